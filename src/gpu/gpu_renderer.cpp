// The GPU renderer (see gpu_render.h).
#include <algorithm>
#include <chrono>
#include <cstring>

#include <epoxy/gl.h>

#include "gpu/embedded_shaders.h"
#include "gpu/gl_context.h"
#include "gpu/gl_program.h"
#include "methods/method_unit.h"
#include "ndfmip/gpu_render.h"

namespace ndfmip {

namespace {

constexpr int kMaxLights = 16; // NDFMIP_MAX_LIGHTS in render/main.frag

// The library's files in the order they depend on each other, then the renderer's.
const char* const kLibraryFiles[] = {"brdf.glsl", "naive.glsl", "toksvig.glsl", "toksvig_lut.glsl",
                                     "sh.glsl",   "vmf.glsl",   "lean.glsl",    "render/raycast.glsl"};

Result<std::string_view> embedded(std::string_view path) {
    for (const EmbeddedShader& s : embeddedShaders())
        if (s.path == path) return s.text;
    return Error{"GPU: no shader file " + std::string(path) + " in this build"};
}

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

// One layer per image chain, every level padded to RGBA.
struct LayerChain {
    std::vector<const Image*> levels;
};

Result<GLuint> uploadLayers(const std::vector<LayerChain>& layers, GlTexture& texture) {
    const Image& base = *layers.front().levels.front();
    const int levelCount = int(layers.front().levels.size());
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
            const Image& image = *layers[layer].levels[size_t(k)];
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

struct Uniforms {
    GLuint program;
    GLint at(const char* name) const { return glGetUniformLocation(program, name); }
    void set(const char* name, int v) const { glProgramUniform1i(program, at(name), v); }
    void set(const char* name, float v) const { glProgramUniform1f(program, at(name), v); }
    void set(const char* name, glm::vec2 v) const { glProgramUniform2f(program, at(name), v.x, v.y); }
    void set(const char* name, glm::vec3 v) const { glProgramUniform3f(program, at(name), v.x, v.y, v.z); }
    void set(const std::string& name, glm::vec3 v) const { set(name.c_str(), v); }
    void set(const std::string& name, int v) const { set(name.c_str(), v); }
};

const char* kVertexShader = R"(#version 450 core
// One triangle covering the viewport.
void main() {
    vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
    gl_Position = vec4(2.0 * p - 1.0, 0.0, 1.0);
}
)";

} // namespace

Result<Image> renderGpu(const Scene& scene, const RenderTextures& textures, const std::string& methodName,
                        const RenderOptions& options, GpuRenderStats* stats, int frames) {
    const auto started = std::chrono::steady_clock::now();
    if (methodName == kGroundTruth || methodName == kExact)
        return Error{"render --gpu: '" + methodName + "' is rendered on the CPU only"};
    const MethodShader* shader = findShader(methodName);
    if (!shader) return Error{"render --gpu: unknown method " + quote(methodName) + " (expected " + renderMethodNames() + ")"};
    const Material& m = scene.material;
    if (m.brdf == Brdf::Tabulated || m.factor)
        return Error{"render --gpu: tabulated BRDFs are rendered on the CPU only"};
    if (scene.lights.size() > size_t(kMaxLights))
        return Error{"render --gpu: at most " + std::to_string(kMaxLights) + " lights, the scene has " +
                     std::to_string(scene.lights.size())};
    if (options.spp != 1) return Error{"render --gpu: methods take one sample per pixel (--spp is the ground truth's)"};
    if (options.taps < 1 || options.taps > 16) return Error{"render --gpu: taps must be in 1 .. 16"};
    if (options.anisotropy < 1 || options.anisotropy > 64) return Error{"render --gpu: anisotropy must be in 1 .. 64"};
    if (frames < 1 || frames > 10000) return Error{"render --gpu: frames must be in 1 .. 10000"};
    if (scene.camera.width < 1 || scene.camera.height < 1) return Error{"render --gpu: the camera's image is empty"};
    const Bake& bake = textures.bake;
    if (bake.levels.empty() || bake.method != shader->bake)
        return Error{"render --gpu: no bake of method '" + std::string(ndfmip::methodName(shader->bake)) +
                     "' to render with"};
    ShaderSetup setup;
    if (Status ready = shader->prepare(m, textures, options, setup); !ready) return Error{ready.error};

    // Layers: the linear planes, then the roughness mips (roughness-mips), then the albedo map.
    std::vector<LayerChain> layers;
    for (size_t p = 0; p < bake.planes.size(); ++p) {
        if (!bake.planes[p].linear) continue;
        LayerChain chain;
        for (const auto& level : bake.levels) chain.levels.push_back(level[p].get());
        const int channels = chain.levels.front()->channels;
        for (int offset = 0; offset < channels; offset += 4) { // planes are at most 4 channels
            if (offset > 0) return Error{"render --gpu: planes of more than 4 channels"};
            layers.push_back(chain);
        }
    }
    const int methodLayers = int(layers.size()) + (methodName == kRoughnessMips ? 1 : 0);
    if (methodName == kRoughnessMips) {
        if (textures.roughness.size() != bake.levels.size())
            return Error{"render --gpu: roughness-mips needs a roughness image per level"};
        LayerChain chain;
        for (const SharedImage& r : textures.roughness) chain.levels.push_back(r.get());
        layers.push_back(chain);
    }
    const bool albedoMap = !textures.albedo.empty();
    if (albedoMap) {
        if (textures.albedo.size() < bake.levels.size()) return Error{"render --gpu: the albedo map has fewer levels than the bake"};
        LayerChain chain;
        for (size_t k = 0; k < bake.levels.size(); ++k) chain.levels.push_back(textures.albedo[k].get());
        layers.push_back(chain);
    }
    for (const LayerChain& chain : layers)
        for (size_t k = 0; k < chain.levels.size(); ++k)
            if (chain.levels[k]->width != bake.levels[k].front()->width ||
                chain.levels[k]->height != bake.levels[k].front()->height)
                return Error{"render --gpu: level " + std::to_string(k) + " of a texture differs in size from the bake's"};

    Result<GlContext> gl = createHeadlessGl();
    if (!gl) return gl.error();

    // The fragment shader: defines, the library, the ray caster, the method's glue, the main.
    ShaderSource fragment = glslVersionHeader();
    std::string defines;
    if (shader->bake == Method::Sh || shader->bake == Method::Vmf)
        defines += "#define NDFMIP_LAYERS " + std::to_string(methodLayers) + "\n";
    if (shader->bake == Method::Vmf) {
        defines += "#define NDFMIP_LOBES " + std::to_string(setup.vmfLobes) + "\n";
        if (setup.vmfColors) defines += "#define NDFMIP_LOBE_COLOURS\n";
    }
    if (shader->bake == Method::Sh && setup.sh.order > 10)
        return Error{"render --gpu: sh bakes up to order 10 (this one is " + std::to_string(setup.sh.order) + ")"};
    appendShaderText(fragment, "<defines>", defines);
    std::vector<std::string> files(std::begin(kLibraryFiles), std::end(kLibraryFiles));
    files.push_back(shader->glsl);
    files.push_back("render/main.frag");
    for (const std::string& file : files) {
        Result<std::string_view> text = embedded(file);
        if (!text) return text.error();
        appendShaderText(fragment, file, text.value());
    }
    ShaderSource vertex;
    appendShaderText(vertex, "<full-screen triangle>", kVertexShader);
    Result<GlProgram> program = compileProgram({{ShaderStage::Vertex, vertex}, {ShaderStage::Fragment, fragment}});
    if (!program) return program.error();
    const Uniforms u{program->id()};

    GlTexture planes, lut, target;
    if (Result<GLuint> uploaded = uploadLayers(layers, planes); !uploaded) return uploaded.error();
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

    // Uniforms: camera, object, material, lights, filtering rule, method.
    const CameraFrame camera = cameraFrame(scene.camera);
    u.set("ndfmipCameraType", scene.camera.type == CameraType::Orthographic ? 1 : 0);
    u.set("ndfmipEye", camera.eye);
    u.set("ndfmipForward", camera.forward);
    u.set("ndfmipRight", camera.right);
    u.set("ndfmipUp", camera.up);
    u.set("ndfmipHalfSize", glm::vec2(camera.halfWidth, camera.halfHeight));
    u.set("ndfmipImageSize", glm::vec2(camera.width, camera.height));
    const Geometry& g = scene.geometry;
    u.set("ndfmipGeometryType", g.type == GeometryType::Plane ? 0 : 1);
    u.set("ndfmipCenter", g.center);
    u.set("ndfmipNormal", g.normal);
    u.set("ndfmipTangent", g.tangent);
    u.set("ndfmipPlaneSize", g.size);
    u.set("ndfmipTiling", g.tiling);
    u.set("ndfmipRadius", g.radius);
    const GlslMaterial material = glslMaterial(m);
    u.set("ndfmipMaterial.brdf", material.brdf);
    u.set("ndfmipMaterial.exponent", material.exponent);
    u.set("ndfmipMaterial.roughness", material.roughness);
    u.set("ndfmipMaterial.specular", material.specular);
    u.set("ndfmipMaterialAlbedo", m.albedo);
    u.set("ndfmipBackground", scene.background);
    u.set("ndfmipLightCount", int(scene.lights.size()));
    for (size_t i = 0; i < scene.lights.size(); ++i) {
        const Light& light = scene.lights[i];
        const std::string index = "[" + std::to_string(i) + "]";
        u.set("ndfmipLightType" + index, light.type == LightType::Point ? 1 : 0);
        u.set("ndfmipLightDirection" + index, light.direction);
        u.set("ndfmipLightPosition" + index, light.position);
        u.set("ndfmipLightColor" + index, light.color);
    }
    u.set("ndfmipTaps", options.taps);
    u.set("ndfmipLodBias", options.lodBias);
    u.set("ndfmipAnisotropy", options.anisotropy);
    u.set("ndfmipShadeEachTexel", options.shadeFilter == ShadeFilter::Texel ? 1 : 0);
    u.set("ndfmipPixelShift", options.pixelShift);
    u.set("ndfmipHasAlbedoMap", albedoMap ? 1 : 0);
    u.set("ndfmipPlanes", 0);
    u.set("ndfmipLevelCount", int(bake.levels.size()));
    u.set("ndfmipLut", 1);
    u.set("ndfmipMapping", int(setup.mapping));
    u.set("ndfmipVarianceScale", setup.varianceScale);
    u.set("ndfmipRoughnessIsAlpha", setup.roughnessIsAlpha ? 1 : 0);
    if (shader->bake == Method::Sh) {
        u.set("ndfmipShOrder", setup.sh.order);
        for (int l = 0; l <= setup.sh.order; ++l) {
            const std::string index = "[" + std::to_string(l) + "]";
            u.set(("ndfmipShDiffuse" + index).c_str(), float(setup.sh.diffuse[size_t(l)]));
            u.set(("ndfmipShSpecular" + index).c_str(), float(setup.sh.specular[size_t(l)]));
        }
    }

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
