// A headless OpenGL 4.5 core context over EGL, with no window and no display server: Mesa's
// surfaceless platform (llvmpipe on machines without a GPU), or the driver's default display
// or first EGL device (NVIDIA). GL functions are loaded by libepoxy.
#pragma once

#include "ndfmip/result.h"

#include <string>

namespace ndfmip {

// Owns one EGL context and its display reference. Move-only; the context is current on the
// thread that created it, and GL calls made through it must come from that thread.
class GlContext {
  public:
    GlContext() = default;
    GlContext(GlContext&& other) noexcept;
    GlContext& operator=(GlContext&& other) noexcept;
    GlContext(const GlContext&) = delete;
    GlContext& operator=(const GlContext&) = delete;
    ~GlContext();

    bool valid() const { return context_ != nullptr; }
    // "GL_RENDERER, GL_VERSION", e.g. "llvmpipe (LLVM 15.0.6, 256 bits), 4.5 (Core Profile)
    // Mesa 22.3.6".
    const std::string& description() const { return description_; }
    void* eglDisplay() const { return display_; }
    void* eglContext() const { return context_; }

  private:
    friend Result<GlContext> createHeadlessGl();
    void release();

    void* display_ = nullptr; // EGLDisplay
    void* context_ = nullptr; // EGLContext
    std::string description_;
};

// Creates a context and makes it current on this thread (no surface: render into FBOs). The
// error names what is missing, in one line ("GPU: no EGL display (...)").
Result<GlContext> createHeadlessGl();

// Makes `gl` current on the calling thread (a no-op when it already is); fails when it is
// current on another thread.
Status makeCurrent(const GlContext& gl);

// The context's GL version as major * 10 + minor (45 for 4.5); 0 when no context is current.
int glVersion();

} // namespace ndfmip
