// renderGpu in a build without the OpenGL path (NDFMIP_GPU off, or no libepoxy/EGL).
#ifndef NDFMIP_HAS_GPU
#include "ndfmip/gpu_render.h"

namespace ndfmip {

Result<Image> renderGpu(const Scene&, const RenderTextures&, const std::string&,
                        const RenderOptions&, GpuRenderStats*, int) {
    return Error{
        "GPU: this ndfmip was built without the OpenGL path (NDFMIP_GPU off, or libepoxy-dev / "
        "libegl-dev missing when it was configured)"};
}

} // namespace ndfmip
#endif
