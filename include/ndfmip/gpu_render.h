// The GPU renderer: the same scenes, bakes and filtering rule as render() (render.h), drawn by
// OpenGL 4.5 through EGL without a display (Mesa's llvmpipe where there is no GPU), with the
// GLSL shading library of shaders/. Each pixel traces the camera ray as the CPU renderer does;
// the bake's own levels are the mip levels of one RGBA32F array texture (a layer per linear
// plane); a lookup is the hardware's trilinear filtering (parameter blending) or the eight
// texels of the trilinear footprint shaded one by one (texel shading).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "ndfmip/render.h"

namespace ndfmip {

struct GpuRenderStats {
    std::string device;          // "GL_RENDERER, GL_VERSION"
    std::vector<double> frameMs; // GPU time of each drawn frame (GL timer queries, no readback)
    std::vector<double>
        frameWallMs;        // the same frames on the wall clock, draw to glFinish (llvmpipe's
                            // timer queries do not measure its rendering threads)
    double compileMs = 0.0; // shader compilation and texture upload, wall clock
};

// Renders `scene` with `method` (a method or shader name: naive, toksvig, toksvig-lut,
// roughness-mips, sh, vmf, lean; a faceted-sphere scene: renormalized or cubemap-toksvig, no
// textures, see docs/RENDERING.md), drawing it `frames` times (the image of the last; every
// frame timed in `stats`). Errors, one line: no GL or EGL ("GPU: ..."), a shader that does not
// compile (file and line), the ground truth or `exact` (CPU only), tabulated BRDFs or factors
// (CPU only), more than 16 lights, spp > 1, a bake of another method or size, textures beyond
// the driver's limits; under an environment (textures.environment loaded), the methods without
// an environment shading (lean, toksvig-lut), naming the method.
Result<Image> renderGpu(const Scene& scene, const RenderTextures& textures,
                        const std::string& method, const RenderOptions& options,
                        GpuRenderStats* stats = nullptr, int frames = 1);

// Draws scenes into the framebuffer bound in the caller's current OpenGL 4.5 context (an
// interactive viewer's window), with the renderer's programs: each is compiled once per
// `programKey` (name the shader and its bake, e.g. "vmf/vmf:4") and kept for later frames, whose
// camera, light and uniforms may change. Not thread-safe; the context must outlive the drawer.
class GpuWindowDrawer {
  public:
    GpuWindowDrawer();
    GpuWindowDrawer(GpuWindowDrawer&&) noexcept;
    GpuWindowDrawer& operator=(GpuWindowDrawer&&) noexcept;
    ~GpuWindowDrawer();

    // Draws `scene` with `shader` (as renderGpu's method) into the viewport (x, y, width,
    // height); showLevel paints the mip level read as false colour. Errors as renderGpu's, one
    // line ("GPU: ..." in a build without the OpenGL path).
    Status draw(const Scene& scene, const RenderTextures& textures, const std::string& shader,
                const RenderOptions& options, const std::string& programKey, bool showLevel, int x,
                int y, int width, int height);

  private:
    struct Programs;
    std::unique_ptr<Programs> programs_;
};

} // namespace ndfmip
