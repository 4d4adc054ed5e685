// The GPU renderer (see gpu_render.h).
#include <algorithm>
#include <chrono>
#include <cstring>

#include <epoxy/gl.h>

#include "gpu/gl_context.h"
#include "gpu/gl_program.h"
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
    ~GlTexture() { if (id) glDeleteTextures(1, &id); }
};
struct GlFramebuffer {
    GLuint id = 0;
    ~GlFramebuffer() { if (id) glDeleteFramebuffers(1, &id); }
};
struct GlVertexArray {
    GLuint id = 0;
    ~GlVertexArray() { if (id) glDeleteVertexArrays(1, &id); }
};
struct GlQuery {
    GLuint id = 0;
    ~GlQuery() { if (id) glDeleteQueries(1, &id); }
};

// The layers as one RGBA32F array texture, every level padded to RGBA.
Result<GLuint> uploadLayers(const std::vector<std::vector<const Image*>>& layers, GlTexture& texture) {
    const Image& base = *layers.front().front();
    const int levelCount = int(layers.front().size());
    GLint maxSize = 0, maxLayers = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxSize);
    glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &maxLayers);
    if (base.width > maxSize || base.height > maxSize)
        return Error{"GPU: the bake's " + std::to_string(base.width) + "x" + std::to_string(base.height) +
                     " level 0 exceeds the driver's texture size " + std::to_string(maxSize)};
    if (int(layers.size()) > maxLayers)
        return Error{"GPU: " + std::to_string(layers.size()) + " planes exceed the driver's " + std::to_string(maxLayers) +
                     " array layers"};
    glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &texture.id);
    glTextureStorage3D(texture.id, levelCount, GL_RGBA32F, base.width, base.height, GLsizei(layers.size()));
    std::vector<float> rgba;
    for (int k = 0; k < levelCount; ++k)
        for (size_t layer = 0; layer < layers.size(); ++layer) {
            const Image& image = *layers[layer][size_t(k)];
            rgba.assign(image.texelCount() * 4, 0.f);
            for (size_t i = 0; i < image.texelCount(); ++i)
                for (int c = 0; c < std::min(image.channels, 4); ++c)
                    rgba[4 * i + size_t(c)] = image.pixels[i * size_t(image.channels) + size_t(c)];
            glTextureSubImage3D(texture.id, k, 0, 0, GLint(layer), image.width, image.height, 1, GL_RGBA, GL_FLOAT,
                                rgba.data());
        }
    glTextureParameteri(texture.id, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTextureParameteri(texture.id, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(texture.id, GL_TEXTURE_WRAP_S, GL_REPEAT);
    glTextureParameteri(texture.id, GL_TEXTURE_WRAP_T, GL_REPEAT);
    glTextureParameteri(texture.id, GL_TEXTURE_BASE_LEVEL, 0);
    glTextureParameteri(texture.id, GL_TEXTURE_MAX_LEVEL, levelCount - 1);
    return texture.id;
}

void setUniforms(GLuint program, const std::vector<UniformValue>& uniforms) {
    for (const UniformValue& u : uniforms) {
        const GLint at = glGetUniformLocation(program, u.name.c_str());
        if (at < 0) continue; // not used by this method's shader
        const float* v = u.values.data();
        if (u.integer) glProgramUniform1i(program, at, GLint(v[0]));
        else if (u.values.size() == 1) glProgramUniform1f(program, at, v[0]);
        else if (u.values.size() == 2) glProgramUniform2f(program, at, v[0], v[1]);
        else glProgramUniform3f(program, at, v[0], v[1], v[2]);
    }
}

} // namespace

Result<Image> renderGpu(const Scene& scene, const RenderTextures& textures, const std::string& methodName,
                        const RenderOptions& options, GpuRenderStats* stats, int frames) {
    const auto started = std::chrono::steady_clock::now();
    if (frames < 1 || frames > 10000) return Error{"render --gpu: frames must be in 1 .. 10000"};
    Result<RenderProgram> assembled = renderProgram(scene, textures, methodName, options);
    if (!assembled) return assembled.error();
    const RenderProgram& parts = assembled.value();
    const ShaderSetup& setup = parts.setup;

    Result<GlContext> gl = createHeadlessGl();
    if (!gl) return gl.error();

    ShaderSource fragment = glslVersionHeader();
    for (const auto& [name, text] : parts.fragmentParts) appendShaderText(fragment, name, text);
    ShaderSource vertex = glslVersionHeader();
    appendShaderText(vertex, "<full-screen triangle>", renderVertexShader());
    Result<GlProgram> program = compileProgram({{ShaderStage::Vertex, vertex}, {ShaderStage::Fragment, fragment}});
    if (!program) return program.error();

    GlTexture planes, lut, target;
    if (Result<GLuint> uploaded = uploadLayers(parts.layers, planes); !uploaded) return uploaded.error();
    if (!setup.lut.empty()) {
        glCreateTextures(GL_TEXTURE_2D, 1, &lut.id);
        glTextureStorage2D(lut.id, 1, GL_R32F, setup.lut.width, setup.lut.height);
        glTextureSubImage2D(lut.id, 0, 0, 0, setup.lut.width, setup.lut.height, GL_RED, GL_FLOAT, setup.lut.pixels.data());
        glTextureParameteri(lut.id, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTextureParameteri(lut.id, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glTextureParameteri(lut.id, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTextureParameteri(lut.id, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    }
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

    setUniforms(program->id(), parts.uniforms);

    GlVertexArray vao;
    glCreateVertexArrays(1, &vao.id);
    glBindVertexArray(vao.id);
    glUseProgram(program->id());
    glBindTextureUnit(0, planes.id);
    if (lut.id) glBindTextureUnit(1, lut.id);
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer.id);
    glViewport(0, 0, width, height);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    glFinish();
    if (stats) {
        stats->device = gl->description();
        stats->compileMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
        stats->frameMs.clear();
        stats->frameWallMs.clear();
    }
    GlQuery query;
    glCreateQueries(GL_TIME_ELAPSED, 1, &query.id);
    for (int f = 0; f < frames; ++f) {
        const auto frameStart = std::chrono::steady_clock::now();
        glBeginQuery(GL_TIME_ELAPSED, query.id);
        glDrawArrays(GL_TRIANGLES, 0, 3);
        glEndQuery(GL_TIME_ELAPSED);
        GLuint64 nanoseconds = 0;
        glGetQueryObjectui64v(query.id, GL_QUERY_RESULT, &nanoseconds); // waits for the frame
        glFinish();
        if (stats) {
            stats->frameMs.push_back(double(nanoseconds) * 1e-6);
            stats->frameWallMs.push_back(
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - frameStart).count());
        }
    }
    std::vector<float> rgba(size_t(width) * size_t(height) * 4);
    glReadnPixels(0, 0, width, height, GL_RGBA, GL_FLOAT, GLsizei(rgba.size() * sizeof(float)), rgba.data());
    if (GLenum e = glGetError(); e != GL_NO_ERROR)
        return Error{"GPU: OpenGL error 0x" + [e] { char t[16]; std::snprintf(t, sizeof t, "%04x", e); return std::string(t); }() +
                     " while rendering"};
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
