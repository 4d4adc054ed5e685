// The GPU renderer (see gpu_render.h).
#include <algorithm>
#include <chrono>
#include <cstring>

#include <epoxy/gl.h>

#include "gpu/gl_context.h"
#include "gpu/gl_program.h"
#include "gpu/gpu_method.h"
#include "ndfmip/gpu_render.h"
#include "render/render_program.h"

namespace ndfmip {

namespace {

// GL names that delete themselves.
struct GlTexture {
    GLuint id = 0;
    GlTexture() = default;
    GlTexture(const GlTexture&) = delete;
    GlTexture& operator=(const GlTexture&) = delete;
    ~GlTexture() {
        if (id) glDeleteTextures(1, &id);
    }
};
struct GlFramebuffer {
    GLuint id = 0;
    ~GlFramebuffer() {
        if (id) glDeleteFramebuffers(1, &id);
    }
};
struct GlQuery {
    GLuint id = 0;
    ~GlQuery() {
        if (id) glDeleteQueries(1, &id);
    }
};

} // namespace

Result<Image> renderGpu(const Scene& scene, const RenderTextures& textures,
                        const std::string& methodName, const RenderOptions& options,
                        GpuRenderStats* stats, int frames) {
    const auto started = std::chrono::steady_clock::now();
    if (frames < 1 || frames > 10000) return Error{"render --gpu: frames must be in 1 .. 10000"};
    Result<RenderProgram> assembled = renderProgram(scene, textures, methodName, options);
    if (!assembled) return assembled.error();
    const RenderProgram& parts = assembled.value();

    Result<GlContext> gl = createHeadlessGl();
    if (!gl) return gl.error();

    Result<GpuMethod> method = GpuMethod::create(parts);
    if (!method) return method.error();
    GlTexture target;
    const int width = scene.camera.width, height = scene.camera.height;
    GLint maxSize = 0;
    glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &maxSize);
    if (width > maxSize || height > maxSize)
        return Error{"render --gpu: a " + std::to_string(width) + "x" + std::to_string(height) +
                     " image exceeds the driver's " + std::to_string(maxSize)};
    glCreateTextures(GL_TEXTURE_2D, 1, &target.id);
    glTextureStorage2D(target.id, 1, GL_RGBA32F, width, height);
    GlFramebuffer framebuffer;
    glCreateFramebuffers(1, &framebuffer.id);
    glNamedFramebufferTexture(framebuffer.id, GL_COLOR_ATTACHMENT0, target.id, 0);
    if (glCheckNamedFramebufferStatus(framebuffer.id, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        return Error{"GPU: the RGBA32F render target is not supported"};

    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer.id);
    glFinish();
    if (stats) {
        stats->device = gl->description();
        stats->compileMs =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started)
                .count();
        stats->frameMs.clear();
        stats->frameWallMs.clear();
    }
    GlQuery query;
    glCreateQueries(GL_TIME_ELAPSED, 1, &query.id);
    for (int f = 0; f < frames; ++f) {
        const auto frameStart = std::chrono::steady_clock::now();
        glBeginQuery(GL_TIME_ELAPSED, query.id);
        method->draw(parts.uniforms, 0, 0, width, height);
        glEndQuery(GL_TIME_ELAPSED);
        GLuint64 nanoseconds = 0;
        glGetQueryObjectui64v(query.id, GL_QUERY_RESULT, &nanoseconds); // waits for the frame
        glFinish();
        if (stats) {
            stats->frameMs.push_back(double(nanoseconds) * 1e-6);
            stats->frameWallMs.push_back(std::chrono::duration<double, std::milli>(
                                             std::chrono::steady_clock::now() - frameStart)
                                             .count());
        }
    }
    std::vector<float> rgba(size_t(width) * size_t(height) * 4);
    glReadnPixels(0, 0, width, height, GL_RGBA, GL_FLOAT, GLsizei(rgba.size() * sizeof(float)),
                  rgba.data());
    if (GLenum e = glGetError(); e != GL_NO_ERROR)
        return Error{"GPU: OpenGL error 0x" + [e] {
            char t[16];
            std::snprintf(t, sizeof t, "%04x", e);
            return std::string(t);
        }() + " while rendering"};
    Image out(width, height, 3);
    for (int y = 0; y < height; ++y) // GL's first row is the bottom one
        for (int x = 0; x < width; ++x) {
            const float* s = &rgba[(size_t(height - 1 - y) * size_t(width) + size_t(x)) * 4];
            float* d = out.at(x, y);
            d[0] = s[0], d[1] = s[1], d[2] = s[2];
        }
    return out;
}

} // namespace ndfmip
