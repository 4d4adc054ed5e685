// One method on the GPU: its compiled program, the bake's layers as a mipmapped array texture,
// Toksvig's table and, under an environment, the prefiltered chain (or the box chain on cube
// faces), the albedo table and the map (a faceted-sphere scene: the mesh and Toksvig's normal cube
// map instead of the bake), drawn into whatever framebuffer is bound. The headless renderer
// (gpu_renderer.cpp) draws into a float target and reads it back; the viewer draws into its
// window.
#pragma once

#include <vector>

#include "gpu/gl_program.h"
#include "render/render_program.h"

namespace ndfmip {

class GpuMethod {
  public:
    // Needs a current OpenGL 4.5 context; errors name the shader file and line, or the limit.
    static Result<GpuMethod> create(const RenderProgram& parts);

    GpuMethod() = default;
    GpuMethod(GpuMethod&& other) noexcept;
    GpuMethod& operator=(GpuMethod&& other) noexcept;
    GpuMethod(const GpuMethod&) = delete;
    GpuMethod& operator=(const GpuMethod&) = delete;
    ~GpuMethod();

    // Sets `uniforms` and draws the full-screen triangle into the viewport (x, y, w, h) of the
    // bound framebuffer.
    void draw(const std::vector<UniformValue>& uniforms, int x, int y, int width, int height) const;
    unsigned program() const { return program_.id(); }

  private:
    void release();
    GlProgram program_;
    unsigned planes_ = 0, lut_ = 0, vertexArray_ = 0;
    unsigned environmentChain_ = 0, environmentAlbedo_ = 0, environmentMap_ = 0;
    unsigned environmentCube_ = 0; // the log2 sigma rule's box chain, six faces a level
    unsigned facetedMesh_ = 0, normalCube_ = 0; // faceted-sphere scenes
};

} // namespace ndfmip
