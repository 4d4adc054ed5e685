// The standard mipmap as a unit, and its two shaders: the renormalised mean normal with the
// material unchanged, and the same normals with an engine's roughness mips (kRoughnessMips).
#include <nlohmann/json.hpp>

#include "methods/method_unit.h"
#include "ndfmip/glsl.h"

namespace ndfmip {

namespace {

glm::vec3 shadeNaiveParams(const ShaderSetup&, const Material& m, const float* p, glm::vec3 albedo,
                           glm::vec3 l, glm::vec3 v) {
    return shadeNaive(m, albedo, glm::vec3(p[0], p[1], p[2]), l, v);
}

Status prepareRoughnessMips(const Material& m, const RenderTextures& textures,
                            const RenderOptions& options, ShaderSetup& setup) {
    if (m.brdf != Brdf::Ggx && m.brdf != Brdf::Beckmann)
        return Status::failure(
            std::string(
                "render: roughness-mips needs a GGX or Beckmann material, the material is ") +
            brdfName(m.brdf));
    setup.roughnessIsAlpha = textures.roughnessIsAlpha;
    return prepareSplitSumSetup(m, textures, options, setup);
}

// The normal's three channels, then the roughness channel(s) appended by the renderer.
glm::vec3 shadeRoughnessMips(const ShaderSetup& setup, const Material& m, const float* p,
                             glm::vec3 albedo, glm::vec3 l, glm::vec3 v) {
    return shadeRoughnessMipsTexel(m, albedo, glm::vec3(p[0], p[1], p[2]), p[3],
                                   setup.roughnessIsAlpha, l, v);
}

// Under an environment: the prefiltered levels along the reflection about the renormalised normal.
Status prepareNaive(const Material& m, const RenderTextures& textures, const RenderOptions& options,
                    ShaderSetup& setup) {
    return prepareSplitSumSetup(m, textures, options, setup);
}

glm::vec3 shadeNaiveEnvironment(const ShaderSetup& setup, const Material& m, const float* p,
                                glm::vec3 albedo, glm::vec3 v, const glm::mat3& toEnvironment,
                                const EnvironmentLighting&) {
    return shadeNaiveSplitSum(m, albedo, glm::vec3(p[0], p[1], p[2]), v, toEnvironment,
                              *setup.splitSum, setup.environmentLod);
}

glm::vec3 shadeRoughnessMipsEnvironment(const ShaderSetup& setup, const Material& m, const float* p,
                                        glm::vec3 albedo, glm::vec3 v,
                                        const glm::mat3& toEnvironment,
                                        const EnvironmentLighting&) {
    return shadeRoughnessMipsSplitSum(m, albedo, glm::vec3(p[0], p[1], p[2]), p[3],
                                      setup.roughnessIsAlpha, v, toEnvironment, *setup.splitSum,
                                      setup.environmentLod);
}

// Specular anti-aliasing: the material's alpha (GGX, Beckmann) widened; Blinn-Phong's exponent
// has no alpha, and is left as it is.
void widenMaterial(const ShaderSetup&, Material& m, float*, float kernel) {
    if (m.brdf == Brdf::Ggx || m.brdf == Brdf::Beckmann)
        m.roughness = glsl().ndfmipSpecularAaAlpha(m.roughness, kernel);
}

// Specular anti-aliasing: the stored roughness (after the normal), kept in its own encoding.
void widenStoredRoughness(const ShaderSetup& setup, Material&, float* p, float kernel) {
    p[3] = glsl().ndfmipSpecularAaStored(p[3], setup.roughnessIsAlpha, kernel);
}

} // namespace

MethodUnit naiveUnit() {
    MethodUnit u{};
    u.method = Method::Naive;
    u.name = "naive";
    u.summary = "standard mipmap: the mean normal, renormalised";
    u.bake = bakeNaive;
    u.planes = [](const BakeParameters&, bool) {
        return std::vector<PlaneInfo>{planeOf("normal", 3, true)};
    };
    u.bakeBytesPerTexel = [](const BakeOptions&) { return 12.0 * 4.0 / 3.0; };
    u.describe = [](const BakeParameters&) { return std::string("naive bake"); };
    u.inspect = [](nlohmann::json& out, const LoadedBake& bake, int x, int y,
                   const InspectOptions&) {
        out["normal"] = jsonVec3(bake.level[requirePlane(bake, "normal")].at(x, y));
    };
    u.levelZeroNormal = [](const float* p) { return glm::vec3(p[0], p[1], p[2]); };
    u.ndfDensity = nullptr;
    return u;
}

std::vector<MethodShader> naiveShaders() {
    auto lobe = [](const ShaderSetup&, const Material& m, const float* p, glm::vec3 h) {
        const glm::vec3 n(p[0], p[1], p[2]);
        const float length = glm::length(n);
        return length > 0.f ? materialLobe(m, glm::dot(n, h) / length, m.exponent, m.roughness)
                            : 0.f;
    };
    auto roughLobe = [](const ShaderSetup& setup, const Material& m, const float* p, glm::vec3 h) {
        const glm::vec3 n(p[0], p[1], p[2]);
        const float length = glm::length(n), r = glm::clamp(p[3], 0.f, 1.f);
        const float alpha = glm::max(setup.roughnessIsAlpha ? r : r * r, 1e-4f);
        return length > 0.f ? specularLobe(m.brdf, glm::dot(n, h) / length, m.exponent, alpha)
                            : 0.f;
    };
    // roughness-mips reads an engine's roughness per level after the mean normals.
    auto roughnessLayers = [](const RenderTextures& textures, size_t levels,
                              std::vector<std::vector<const Image*>>& layers) {
        if (textures.roughness.size() != levels)
            return Status::failure(
                "render --gpu: roughness-mips needs a roughness image per level");
        std::vector<const Image*> chain;
        for (const SharedImage& r : textures.roughness) chain.push_back(r.get());
        layers.push_back(chain);
        return Status::success();
    };
    auto roughnessUniforms = [](const ShaderSetup& setup, std::vector<UniformValue>& u) {
        addUniform(u, "ndfmipRoughnessIsAlpha", setup.roughnessIsAlpha ? 1 : 0);
        return Status::success();
    };
    return {{"naive", Method::Naive, "render/naive.glsl", prepareNaive, shadeNaiveParams, lobe,
             shadeNaiveEnvironment, nullptr, nullptr, nullptr, false, nullptr, widenMaterial},
            {kRoughnessMips, Method::Naive, "render/roughness_mips.glsl", prepareRoughnessMips,
             shadeRoughnessMips, roughLobe, shadeRoughnessMipsEnvironment, roughnessLayers, nullptr,
             roughnessUniforms, false, nullptr, widenStoredRoughness}};
}

} // namespace ndfmip
