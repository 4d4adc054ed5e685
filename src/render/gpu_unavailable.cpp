// renderGpu and GpuWindowDrawer in a build without the OpenGL path (NDFMIP_GPU off, or no
// libepoxy/EGL): each says so in one line.
#ifndef NDFMIP_HAS_GPU
#include "ndfmip/gpu_render.h"

namespace ndfmip {

namespace {
const char* kNoOpenGl =
    "GPU: this ndfmip was built without the OpenGL path (NDFMIP_GPU off, or libepoxy-dev / "
    "libegl-dev missing when it was configured)";
}

Result<Image> renderGpu(const Scene&, const RenderTextures&, const std::string&,
                        const RenderOptions&, GpuRenderStats*, int) {
    return Error{kNoOpenGl};
}

struct GpuWindowDrawer::Programs {};
GpuWindowDrawer::GpuWindowDrawer() = default;
GpuWindowDrawer::GpuWindowDrawer(GpuWindowDrawer&&) noexcept = default;
GpuWindowDrawer& GpuWindowDrawer::operator=(GpuWindowDrawer&&) noexcept = default;
GpuWindowDrawer::~GpuWindowDrawer() = default;

Status GpuWindowDrawer::draw(const Scene&, const RenderTextures&, const std::string&,
                             const RenderOptions&, const std::string&, bool, int, int, int, int) {
    return Status::failure(kNoOpenGl);
}

} // namespace ndfmip
#endif
