// The GPU renderer's program, API-free (see render_program.h).
#include "render/render_program.h"

#include <algorithm>
#include <cassert>
#include <cmath>

#include "ndfmip/environment_lighting.h"
#include "ndfmip/sh_rotation.h"
#include "ndfmip/spherical_harmonics.h"
#include "render/embedded_shaders.h"

namespace ndfmip {

namespace {

// The library's files in the order they depend on each other, then the ray caster.
const char* const kLibraryFiles[] = {"brdf.glsl",
                                     "naive.glsl",
                                     "toksvig.glsl",
                                     "toksvig_lut.glsl",
                                     "sh.glsl",
                                     "vmf.glsl",
                                     "lean.glsl",
                                     "sggx.glsl",
                                     "ggx_aniso.glsl",
                                     "splitsum.glsl",
                                     "render/raycast.glsl",
                                     "render/ray_geometry.glsl",
                                     "render/specular_aa.glsl"};

Result<std::string> embedded(const std::string& path) {
    for (const EmbeddedShader& s : embeddedShaders())
        if (s.path == path) return std::string(s.text);
    return Error{"GPU: no shader file " + path + " in this build"};
}

void add(std::vector<UniformValue>& u, const std::string& name, int v) {
    u.push_back({name, true, {float(v)}});
}
void add(std::vector<UniformValue>& u, const std::string& name, float v) {
    u.push_back({name, false, {v}});
}
void add(std::vector<UniformValue>& u, const std::string& name, glm::vec2 v) {
    u.push_back({name, false, {v.x, v.y}});
}
void add(std::vector<UniformValue>& u, const std::string& name, glm::vec3 v) {
    u.push_back({name, false, {v.x, v.y, v.z}});
}

// Why a method cannot be drawn under an environment on the GPU; empty when it can.
std::string environmentRefusal(const MethodShader& shader, const std::string& method) {
    if (!shader.shadeEnvironment)
        return "render --gpu: method " + quote(method) + " cannot shade under an environment";
    return {};
}

// The SH lighting as rows (environment.glsl's ndfmipEnvSh), coefficients l <= order: L, then
// its reparameterisedSets (the axes' L' and, for the reflecting normals' cosine, the half
// vector's; or one L'). With `frame` (the columns of a tangent frame in the environment frame)
// every row re-expressed in that frame, f_t(d) = f(T d), as the CPU's shadeShEnvironment does
// (sh_rotation.h).
Image shLightingRows(const ShLighting& lighting, int order, const glm::mat3* frame) {
    const int count = shCount(order), rows = 1 + reparameterisedSets(lighting.cosine);
    std::vector<double> values = interleavedShLighting(lighting, order);
    if (frame)
        rotateSh(glm::transpose(glm::dmat3(*frame)), order, values.data(), values.data(), 3 * rows);
    Image out(count, rows, 3);
    for (int i = 0; i < count; ++i)
        for (int row = 0; row < rows; ++row)
            for (int c = 0; c < 3; ++c)
                out.at(i, row)[c] =
                    float(values[size_t(3 * rows) * size_t(i) + size_t(3 * row + c)]);
    return out;
}

// The same rows in the environment frame, followed by what the shader needs to rotate them into
// each hit's frame itself (a sphere: one frame per hit): a row of the rotation's points d_k (xyz
// in RGB), then per coefficient i = shIndex(l, m) a row of band l's pseudo-inverse, column k in R
// (sh_rotation.h's ShRotationSampling, so the GPU rotates as the CPU's rotateSh does).
Image shLightingRowsToRotate(const ShLighting& lighting, int order) {
    const Image rows = shLightingRows(lighting, order, nullptr);
    const ShRotationSampling& sampling = shRotationSampling(order);
    const int count = shCount(order), points = int(sampling.points.size());
    Image out(std::max(count, points), rows.height + 1 + count, 3);
    for (int row = 0; row < rows.height; ++row)
        for (int i = 0; i < count; ++i)
            for (int c = 0; c < 3; ++c) out.at(i, row)[c] = rows.at(i, row)[c];
    for (int k = 0; k < points; ++k)
        for (int c = 0; c < 3; ++c)
            out.at(k, rows.height)[c] = float(sampling.points[size_t(k)][c]);
    for (int l = 0; l <= order; ++l)
        for (int m = 0; m < 2 * l + 1; ++m)
            for (int k = 0; k < points; ++k)
                out.at(k, rows.height + 1 + l * l + m)[0] =
                    float(sampling.pseudoInverse[size_t(l)][size_t(m * points + k)]);
    return out;
}

// The split sum's second factor for the material (splitsum_lighting.cpp's specularAlbedo: the
// lobe's table of its BRDF, or the DFG table's scale + bias) and the dominant direction's share
// of the normal (dominantShare), as two channels; an empty image for a material without a lobe.
Image albedoChannel(const SplitSumLighting& lighting, Brdf brdf) {
    const bool engine = lighting.albedoKind == SpecularAlbedo::EngineDfg;
    if (brdf != Brdf::BlinnPhong && brdf != Brdf::Beckmann && brdf != Brdf::Ggx)
        return Image(1, 1, 2);
    const Image& table = lighting.albedo[engine ? 0 : size_t(int(brdf) - 1)];
    const Image& dominant = lighting.dominant[size_t(int(brdf) - 1)];
    assert(dominant.width == table.width && dominant.height == table.height);
    const int channel = engine ? 2 : 0;
    Image out(table.width, table.height, 2);
    for (size_t i = 0; i < table.texelCount(); ++i) {
        out.pixels[2 * i] = table.pixels[i * size_t(table.channels) + size_t(channel)];
        out.pixels[2 * i + 1] = dominant.pixels[i];
    }
    return out;
}

// The camera, the object, the material and the lights (raycast.glsl, main.frag and
// interpolated.frag).
void addSceneUniforms(std::vector<UniformValue>& u, const Scene& scene, const CameraFrame& camera) {
    add(u, "ndfmipCameraType", scene.camera.type == CameraType::Orthographic ? 1 : 0);
    add(u, "ndfmipEye", camera.eye);
    add(u, "ndfmipForward", camera.forward);
    add(u, "ndfmipRight", camera.right);
    add(u, "ndfmipUp", camera.up);
    add(u, "ndfmipHalfSize", glm::vec2(camera.halfWidth, camera.halfHeight));
    add(u, "ndfmipImageSize", glm::vec2(camera.width, camera.height));
    const Geometry& g = scene.geometry;
    add(u, "ndfmipGeometryType", g.type == GeometryType::Plane ? 0 : 1);
    add(u, "ndfmipCenter", g.center);
    add(u, "ndfmipNormal", g.normal);
    add(u, "ndfmipTangent", g.tangent);
    add(u, "ndfmipPlaneSize", g.size);
    add(u, "ndfmipTiling", g.tiling);
    add(u, "ndfmipRadius", g.radius);
    const Material& m = scene.material;
    const GlslMaterial material = glslMaterial(m);
    add(u, "ndfmipMaterial.brdf", material.brdf);
    add(u, "ndfmipMaterial.exponent", material.exponent);
    add(u, "ndfmipMaterial.roughness", material.roughness);
    add(u, "ndfmipMaterial.specular", material.specular);
    add(u, "ndfmipMaterialAlbedo", m.albedo);
    add(u, "ndfmipBackground", scene.background);
    add(u, "ndfmipLightCount", int(scene.lights.size()));
    for (size_t i = 0; i < scene.lights.size(); ++i) {
        const Light& light = scene.lights[i];
        // Appended, not "[" + ...: GCC 12 warns falsely (-Wrestrict) on that once inlined here.
        std::string index = "[";
        index += std::to_string(i);
        index += "]";
        add(u, "ndfmipLightType" + index, light.type == LightType::Point ? 1 : 0);
        add(u, "ndfmipLightDirection" + index, light.direction);
        add(u, "ndfmipLightPosition" + index, light.position);
        add(u, "ndfmipLightColor" + index, light.color);
    }
}

} // namespace

const char* renderVertexShader() {
    return R"(// One triangle covering the viewport.
void main() {
    vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
    gl_Position = vec4(2.0 * p - 1.0, 0.0, 1.0);
}
)";
}

namespace {

// A faceted-sphere scene (interpolated.h): the CPU's mesh, every vertex and triangle as it
// builds them, and the method's checks as renderInterpolated's.
Result<RenderProgram> interpolatedProgram(const Scene& scene, const std::string& method,
                                          const RenderOptions& options) {
    if (method == kGroundTruth)
        return Error{"render --gpu: '" + method +
                     "' of a faceted-sphere scene is rendered on the CPU only"};
    if (method != kRenormalized && method != kCubemapToksvig)
        return Error{"render --gpu: unknown method " + quote(method) +
                     " for a faceted-sphere scene (expected " + std::string(kRenormalized) + ", " +
                     kCubemapToksvig + ")"};
    const Geometry& g = scene.geometry;
    if (g.segments < kMinSphereSegments || g.segments > kMaxSphereSegments ||
        g.rings < kMinSphereRings || g.rings > kMaxSphereRings || !(g.radius > 0.f))
        return Error{"render --gpu: a faceted sphere needs " + std::to_string(kMinSphereSegments) +
                     " .. " + std::to_string(kMaxSphereSegments) + " segments, " +
                     std::to_string(kMinSphereRings) + " .. " + std::to_string(kMaxSphereRings) +
                     " rings and a positive radius"};
    if (!scene.environment.path.empty())
        return Error{
            "render --gpu: faceted-sphere scenes are lit by point lights only, not an environment"};
    const Material& m = scene.material;
    if (m.brdf == Brdf::Tabulated || m.factor)
        return Error{"render --gpu: tabulated BRDFs are rendered on the CPU only"};
    if (scene.lights.size() > size_t(kGpuMaxLights))
        return Error{"render --gpu: at most " + std::to_string(kGpuMaxLights) +
                     " lights, the scene has " + std::to_string(scene.lights.size())};
    if (options.spp != 1)
        return Error{
            "render --gpu: methods take one sample per pixel (--spp is the ground truth's)"};
    if (scene.camera.width < 1 || scene.camera.height < 1)
        return Error{"render --gpu: the camera's image is empty"};

    RenderProgram program;
    // The mesh as rows of one texture (faceted.glsl): positions, vertex normals, face normals,
    // triangles' vertex indices.
    const FacetedSphereMesh mesh = facetedSphereMesh(g);
    const int width = int(std::max(mesh.positions.size(), mesh.triangles.size()));
    program.facetedMesh = Image(width, 4, 3);
    for (size_t i = 0; i < mesh.positions.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            program.facetedMesh.at(int(i), 0)[c] = mesh.positions[i][c];
            program.facetedMesh.at(int(i), 1)[c] = mesh.normals[i][c];
        }
    for (size_t k = 0; k < mesh.triangles.size(); ++k)
        for (int c = 0; c < 3; ++c) {
            program.facetedMesh.at(int(k), 2)[c] = mesh.faceNormals[k][c];
            program.facetedMesh.at(int(k), 3)[c] = float(mesh.triangles[k][c]);
        }
    const InterpolatedOptions cube; // the CPU renderer's cube map and LOD bias
    if (method == kCubemapToksvig)
        program.normalCube =
            std::make_shared<const NormalCubeMap>(buildNormalCubeMap(cube.cubeSize));

    std::vector<std::string> files = {"brdf.glsl",
                                      "toksvig.glsl",
                                      "render/raycast.glsl",
                                      "render/ray_geometry.glsl",
                                      "render/cube_faces.glsl",
                                      "render/faceted.glsl",
                                      "render/faceted_trace.glsl",
                                      "render/normal_cube_lod.glsl",
                                      "render/interpolated.frag"};
    program.fragmentParts.emplace_back("<defines>", "");
    for (const std::string& file : files) {
        Result<std::string> text = embedded(file);
        if (!text) return text.error();
        program.fragmentParts.emplace_back(file, std::move(text.value()));
    }
    auto& u = program.uniforms;
    addSceneUniforms(u, scene, cameraFrame(scene.camera));
    add(u, "ndfmipPixelShift", options.pixelShift);
    add(u, "ndfmipInterpolatedMethod", method == kCubemapToksvig ? 1 : 0);
    add(u, "ndfmipMapping", int(options.roughnessMapping));
    add(u, "ndfmipVarianceScale", options.varianceScale);
    add(u, "ndfmipTriangleCount", int(mesh.triangles.size()));
    add(u, "ndfmipNormalCubeSize", cube.cubeSize);
    add(u, "ndfmipNormalCubeLodBias", cube.lodBias);
    // Units of their own (gpu_method.cpp): samplers of two types on one unit make a draw invalid.
    add(u, "ndfmipMesh", 5);
    add(u, "ndfmipNormalCube", 6);
    return program;
}

// What the GPU renderer cannot draw of this scene, method and options: one line each.
Status checkProgramInputs(const Scene& scene, const RenderTextures& textures,
                          const std::string& method, const MethodShader& shader,
                          const RenderOptions& options) {
    const Material& m = scene.material;
    if (m.brdf == Brdf::Tabulated || m.factor)
        return Status::failure("render --gpu: tabulated BRDFs are rendered on the CPU only");
    const bool environment = !scene.environment.path.empty();
    if (environment) {
        if (const std::string refusal = environmentRefusal(shader, method); !refusal.empty())
            return Status::failure(refusal);
        if (!textures.environment)
            return Status::failure("render --gpu: the scene's environment " +
                                   quote(scene.environment.path) + " is not loaded");
        if (options.shViews != 0)
            return Status::failure("render --gpu: --sh-views is rendered on the CPU only");
    }
    if (scene.lights.size() > size_t(kGpuMaxLights))
        return Status::failure("render --gpu: at most " + std::to_string(kGpuMaxLights) +
                               " lights, the scene has " + std::to_string(scene.lights.size()));
    if (options.spp != 1)
        return Status::failure(
            "render --gpu: methods take one sample per pixel (--spp is the ground truth's)");
    if (options.taps < 1 || options.taps > 16)
        return Status::failure("render --gpu: taps must be in 1 .. 16");
    if (options.anisotropy < 1 || options.anisotropy > 64)
        return Status::failure("render --gpu: anisotropy must be in 1 .. 64");
    if (scene.camera.width < 1 || scene.camera.height < 1)
        return Status::failure("render --gpu: the camera's image is empty");
    const Bake& bake = textures.bake;
    if (bake.levels.empty() || bake.method != shader.bake)
        return Status::failure("render --gpu: no bake of method '" +
                               std::string(methodName(shader.bake)) + "' to render with");
    return Status::success();
}

// Under an environment: the SH lighting's rows (returns their order) or the prefiltered levels
// the program reads; 0 without SH lighting.
Result<int> addEnvironmentLighting(RenderProgram& program, const Scene& scene,
                                   const RenderTextures& textures, const std::string& method) {
    const MethodShader& shader = *program.shader;
    const ShaderSetup& setup = program.setup;
    const Material& m = scene.material;
    const bool environment = !scene.environment.path.empty();
    const bool shLighting = environment && setup.shLighting;
    int environmentShOrder = 0;
    if (shLighting) {
        const ShLighting& lighting = *setup.shLighting;
        environmentShOrder = std::min(setup.sh.order, lighting.order);
        if (environmentShOrder > kGpuMaxShOrder)
            return Error{"render --gpu: SH lighting up to order " + std::to_string(kGpuMaxShOrder)};
        // sh: on a plane, its one tangent frame (geometry.cpp's), as the CPU rotates into it; on a
        // sphere the shader rotates into each hit's frame (shLightingRowsToRotate).
        const Geometry& g = scene.geometry;
        const glm::mat3 frame =
            tangentToEnvironment(g.tangent, glm::cross(g.normal, g.tangent), g.normal);
        const int order = environmentShOrder;
        if (!shader.shLightingInTangentFrame)
            program.environmentSh = shLightingRows(lighting, order, nullptr);
        else if (g.type == GeometryType::Plane)
            program.environmentSh = shLightingRows(lighting, order, &frame);
        else
            program.environmentSh = shLightingRowsToRotate(lighting, order);
        program.environment = textures.environment;
        program.environmentVisible = scene.environment.visible;
    } else if (environment) {
        const SplitSumChain* chain =
            setup.splitSum ? findChain(*setup.splitSum, setup.environmentLod) : nullptr;
        if (!chain)
            return Error{"render --gpu: method " + quote(method) +
                         " prepared no environment lighting"};
        // One texture's mips (the log2sigma rule's cube faces: six layers of one): level k must
        // be GL's size of level k.
        const bool cube = !chain->cube.levels.empty();
        const int levels = int(chain->perceptualRoughness.size());
        const Image& base = cube ? chain->cube.levels.front()[0] : chain->levels.front();
        for (int k = 0; k < levels; ++k) {
            const Image& level = cube ? chain->cube.levels[size_t(k)][0] : chain->levels[size_t(k)];
            if (level.width != std::max(base.width >> k, 1) ||
                level.height != std::max(base.height >> k, 1))
                return Error{"render --gpu: level " + std::to_string(k) +
                             " of the prefiltered environment is not a mip level"};
        }
        program.environmentChain = chain;
        program.environmentAlbedo = albedoChannel(*setup.splitSum, m.brdf);
        program.environment = textures.environment;
        program.environmentVisible = scene.environment.visible;
    }
    return environmentShOrder;
}

// The textures' layers: the linear planes, then the method's own (roughness-mips' roughness),
// then the albedo map; returns how many are the method's.
Result<int> addLayers(RenderProgram& program, const RenderTextures& textures) {
    const MethodShader& shader = *program.shader;
    if (shader.planesOf) program.encoded = shader.planesOf(textures.bake);
    const Bake& bake = shader.planesOf ? program.encoded : textures.bake;
    // Layers: the linear planes, then the roughness mips (roughness-mips), then the albedo map.
    auto& layers = program.layers;
    for (size_t p = 0; p < bake.planes.size(); ++p) {
        if (!bake.planes[p].linear) continue;
        if (bake.levels.front()[p]->channels > 4)
            return Error{"render --gpu: planes of more than 4 channels"};
        std::vector<const Image*> chain;
        for (const auto& level : bake.levels) chain.push_back(level[p].get());
        layers.push_back(chain);
    }
    if (shader.gpuLayers)
        if (Status s = shader.gpuLayers(textures, bake.levels.size(), layers); !s)
            return Error{s.error};
    const int methodLayers = int(layers.size());
    const bool albedoMap = !textures.albedo.empty();
    if (albedoMap) {
        if (textures.albedo.size() < bake.levels.size())
            return Error{"render --gpu: the albedo map has fewer levels than the bake"};
        std::vector<const Image*> chain;
        for (size_t k = 0; k < bake.levels.size(); ++k) chain.push_back(textures.albedo[k].get());
        layers.push_back(chain);
    }
    for (const auto& chain : layers)
        for (size_t k = 0; k < chain.size(); ++k)
            if (chain[k]->width != bake.levels[k].front()->width ||
                chain[k]->height != bake.levels[k].front()->height)
                return Error{"render --gpu: level " + std::to_string(k) +
                             " of a texture differs in size from the bake's"};
    return methodLayers;
}

// The fragment shader's parts: defines, the library, the ray caster, the method's glue, the
// main.
Status addFragmentParts(RenderProgram& program, const Scene& scene, int methodLayers,
                        int environmentShOrder) {
    const MethodShader& shader = *program.shader;
    const ShaderSetup& setup = program.setup;
    const bool environment = !scene.environment.path.empty();
    const bool shLighting = environment && setup.shLighting;
    std::string defines = shader.gpuDefines ? shader.gpuDefines(setup, methodLayers) : "";
    if (environment) defines += "#define NDFMIP_ENVIRONMENT\n";
    if (shLighting) defines += "#define NDFMIP_ENVIRONMENT_SH\n";
    if (program.environmentChain && !program.environmentChain->cube.levels.empty())
        defines += "#define NDFMIP_ENVIRONMENT_CUBE\n";
    // Toksvig's log2sigma level (log2SigmaLevel) reads its constants from here, not as literals.
    if (environment)
        defines += "#define NDFMIP_LOG2SIGMA_SPAN " + std::to_string(kLog2SigmaSpan) +
                   "\n#define NDFMIP_LOG2SIGMA_LOBE_LEVELS " +
                   std::to_string(double(kLog2SigmaLobeLevels)) + "\n";
    if (shLighting && shader.shLightingInTangentFrame && scene.geometry.type != GeometryType::Plane)
        defines += "#define NDFMIP_ENVIRONMENT_SH_PER_HIT\n";
    // The SH lighting's order, rows and rotation points as constants (environment.glsl): its
    // loops over bands and coefficients unroll, and llvmpipe's loop limiter no longer counts them.
    if (shLighting) {
        defines += "#define NDFMIP_ENV_SH_ORDER " + std::to_string(environmentShOrder) + "\n";
        defines += "#define NDFMIP_ENV_SH_POINTS " +
                   std::to_string(shRotationSampling(environmentShOrder).points.size()) + "\n";
        if (setup.shLighting->cosine == SpecularCosine::MeanNormal)
            defines += "#define NDFMIP_ENV_SH_AXES\n";
        if (setup.shLighting->cosine == SpecularCosine::Reflecting)
            defines += "#define NDFMIP_ENV_SH_REFLECTING\n";
    }
    program.fragmentParts.emplace_back("<defines>", defines);
    std::vector<std::string> files(std::begin(kLibraryFiles), std::end(kLibraryFiles));
    if (environment)
        files.insert(files.end(), {"render/cube_faces.glsl", "render/environment.glsl",
                                   "splitsum_shading.glsl"});
    if (shLighting) files.push_back("sh_lighting_shading.glsl");
    files.push_back(shader.glsl);
    files.push_back("render/main.frag");
    for (const std::string& file : files) {
        Result<std::string> text = embedded(file);
        if (!text) return Status::failure(text.error().message);
        program.fragmentParts.emplace_back(file, std::move(text.value()));
    }
    return Status::success();
}

// The uniforms: camera, object, material, lights, filtering rule, method, environment.
Status addUniforms(RenderProgram& program, const Scene& scene, const RenderTextures& textures,
                   const RenderOptions& options, const CameraFrame& camera,
                   int environmentShOrder) {
    const MethodShader& shader = *program.shader;
    const ShaderSetup& setup = program.setup;
    const Bake& bake = textures.bake;
    const bool environment = !scene.environment.path.empty();
    const bool shLighting = environment && setup.shLighting;
    const bool albedoMap = !textures.albedo.empty();
    auto& u = program.uniforms;
    addSceneUniforms(u, scene, camera);
    add(u, "ndfmipTaps", options.taps);
    add(u, "ndfmipLodBias", options.lodBias);
    add(u, "ndfmipAnisotropy", options.anisotropy);
    add(u, "ndfmipShadeEachTexel", options.shadeFilter == ShadeFilter::Texel ? 1 : 0);
    add(u, "ndfmipPixelShift", options.pixelShift);
    add(u, "ndfmipSpecularAaVariance", options.specularAntiAliasing.variance);
    add(u, "ndfmipSpecularAaThreshold", options.specularAntiAliasing.threshold);
    add(u, "ndfmipHasAlbedoMap", albedoMap ? 1 : 0);
    add(u, "ndfmipLevelCount", int(bake.levels.size()));
    add(u, "ndfmipPlanes", 0);
    if (shader.gpuUniforms)
        if (Status s = shader.gpuUniforms(setup, u); !s) return s;
    if (environment) {
        // Every sampler on its unit, used or not: two of different types on one unit (0, the
        // planes' array) make the draw invalid.
        add(u, "ndfmipEnvChain", 2);
        add(u, "ndfmipEnvSh", 2);
        add(u, "ndfmipEnvAlbedo", 3);
        add(u, "ndfmipEnvMap", 4);
        add(u, "ndfmipEnvCube", 7);
        add(u, "ndfmipEnvVisible", program.environmentVisible ? 1 : 0);
        const double rotation = -textures.environment->environment.rotation;
        add(u, "ndfmipEnvRotation",
            glm::vec2(float(std::cos(rotation)), float(std::sin(rotation))));
    }
    if (shLighting) {
        for (int l = 0; l <= environmentShOrder; ++l) {
            add(u, "ndfmipEnvShDiffuse[" + std::to_string(l) + "]",
                float(setup.sh.diffuse[size_t(l)]));
            add(u, "ndfmipEnvShSpecular[" + std::to_string(l) + "]",
                float(setup.sh.specular[size_t(l)]));
        }
    } else if (environment) {
        const SplitSumLighting& lighting = *setup.splitSum;
        add(u, "ndfmipEnvLevels", int(program.environmentChain->perceptualRoughness.size()));
        add(u, "ndfmipEnvRule", int(setup.environmentLod));
        add(u, "ndfmipEnvTexelAngle", float(lighting.texelAngle));
        for (size_t k = 0; k < 9; ++k)
            add(u, "ndfmipEnvIrradiance[" + std::to_string(k) + "]",
                glm::vec3(lighting.irradiance[k]));
        add(u, "ndfmipEnvBandFactors", lighting.vmfBandFactors ? 1 : 0);
        add(u, "ndfmipEnvWeightedReflection", lighting.weightedReflection ? 1 : 0);
    }
    return Status::success();
}

} // namespace

Result<RenderProgram> renderProgram(const Scene& scene, const RenderTextures& textures,
                                    const std::string& method, const RenderOptions& options) {
    if (scene.geometry.type == GeometryType::FacetedSphere)
        return interpolatedProgram(scene, method, options);
    RenderProgram program;
    if (method == kGroundTruth || method == kExact)
        return Error{"render --gpu: '" + method + "' is rendered on the CPU only"};
    program.shader = findShader(method);
    if (!program.shader)
        return Error{"render --gpu: unknown method " + quote(method) + " (expected " +
                     renderMethodNames() + ")"};
    if (Status s = checkProgramInputs(scene, textures, method, *program.shader, options); !s)
        return Error{s.error};
    const CameraFrame camera = cameraFrame(scene.camera);
    // As the CPU renderer: the view towards the camera (environment frame) before prepare.
    if (!scene.environment.path.empty())
        program.setup.environmentView = worldToEnvironment(glm::dvec3(-camera.forward));
    if (Status ready = program.shader->prepare(scene.material, textures, options, program.setup);
        !ready)
        return Error{ready.error};
    const Result<int> shOrder = addEnvironmentLighting(program, scene, textures, method);
    if (!shOrder) return shOrder.error();
    const Result<int> methodLayers = addLayers(program, textures);
    if (!methodLayers) return methodLayers.error();
    if (Status s = addFragmentParts(program, scene, methodLayers.value(), shOrder.value()); !s)
        return Error{s.error};
    if (Status s = addUniforms(program, scene, textures, options, camera, shOrder.value()); !s)
        return Error{s.error};
    return program;
}

} // namespace ndfmip
