// ggx-fit as a unit, and its shader: the level's unit normal with the fitted GGX roughness, both
// blended by the lookup as an engine blends its normal and roughness maps.
#include <cstdio>

#include <nlohmann/json.hpp>

#include "methods/method_unit.h"
#include "ndfmip/roughness.h"

namespace ndfmip {

namespace {

Status prepareGgxFit(const Material& m, const RenderTextures& textures,
                     const RenderOptions& options, ShaderSetup& setup) {
    if (m.brdf != Brdf::Ggx)
        return Status::failure(
            std::string("render: ggx-fit stores a GGX roughness fitted to a GGX material, the "
                        "material is ") +
            brdfName(m.brdf));
    // Fitted to one material roughness (not to a roughness map): the material must be it.
    const auto base = textures.bake.parameters.find("base_roughness");
    if (!textures.bake.parameters.count("roughness_map") &&
        base != textures.bake.parameters.end() &&
        std::abs(float(base->second) - m.roughness) > 1e-4f) {
        char text[256];
        std::snprintf(text, sizeof text,
                      "render: the ggx-fit bake was fitted to GGX alpha %g, the material's is %g: "
                      "bake it with --base-roughness %g",
                      base->second, double(m.roughness), double(m.roughness));
        return Status::failure(text);
    }
    setup.roughnessIsAlpha = true;
    return prepareSplitSumSetup(m, textures, options, setup);
}

// The normal's three channels, then the fitted alpha.
glm::vec3 shadeGgxFit(const ShaderSetup&, const Material& m, const float* p, glm::vec3 albedo,
                      glm::vec3 l, glm::vec3 v) {
    return shadeRoughnessMipsTexel(m, albedo, glm::vec3(p[0], p[1], p[2]), p[3], true, l, v);
}

float ggxFitLobe(const ShaderSetup&, const Material& m, const float* p, glm::vec3 h) {
    const glm::vec3 n(p[0], p[1], p[2]);
    const float length = glm::length(n);
    const float alpha = glm::clamp(p[3], 1e-4f, 1.f);
    return length > 0.f ? specularLobe(m.brdf, glm::dot(n, h) / length, m.exponent, alpha) : 0.f;
}

glm::vec3 shadeGgxFitEnvironment(const ShaderSetup& setup, const Material& m, const float* p,
                                 glm::vec3 albedo, glm::vec3 v, const glm::mat3& toEnvironment,
                                 const EnvironmentLighting&) {
    return shadeRoughnessMipsSplitSum(m, albedo, glm::vec3(p[0], p[1], p[2]), p[3], true, v,
                                      toEnvironment, *setup.splitSum, setup.environmentLod);
}

void inspectGgxFit(nlohmann::json& out, const LoadedBake& bake, int x, int y,
                   const InspectOptions&) {
    out["normal"] = jsonVec3(bake.level[requirePlane(bake, "normal")].at(x, y));
    const float alpha = bake.level[requirePlane(bake, "roughness_ggx")].at(x, y)[0];
    out["roughness_ggx"] = alpha;
    out["perceptual_roughness"] = perceptualRoughness(alpha);
}

} // namespace

MethodUnit ggxFitUnit() {
    MethodUnit u{};
    u.method = Method::GgxFit;
    u.name = "ggx-fit";
    u.summary = "one GGX lobe per texel, its roughness fitted to the texel's filtered NDF "
                "(needs --base-roughness)";
    u.bake = bakeGgxFit;
    u.planes = [](const BakeParameters&, bool) {
        return std::vector<PlaneInfo>{planeOf("normal", 3, true),
                                      planeOf("roughness_ggx", 1, true)};
    };
    u.parameters = {materialRoughnessParameter()}; // the shader checks the material's
    // The planes, and with a roughness map its alpha.
    u.bakeBytesPerTexel = [](const BakeOptions& o) {
        return 16.0 * 4.0 / 3.0 + (o.roughnessMap ? 4.0 : 0.0);
    };
    u.describe = [](const BakeParameters&) { return std::string("ggx-fit bake"); };
    u.inspect = inspectGgxFit;
    u.levelZeroNormal = [](const float* p) { return glm::vec3(p[0], p[1], p[2]); };
    u.ndfDensity = nullptr;
    u.fitsMaterialRoughness = true;
    return u;
}

std::vector<MethodShader> ggxFitShaders() {
    return {{"ggx-fit", Method::GgxFit, "render/ggx_fit.glsl", prepareGgxFit, shadeGgxFit,
             ggxFitLobe, shadeGgxFitEnvironment, nullptr, nullptr, nullptr, false}};
}

} // namespace ndfmip
