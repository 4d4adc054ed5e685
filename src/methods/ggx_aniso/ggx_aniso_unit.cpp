// ggx-aniso as a unit, and its shader: the level's unit normal with the fitted anisotropic GGX
// lobe's tensor, both blended by the lookup (shaders/ggx_aniso.glsl).

#include <nlohmann/json.hpp>

#include "methods/lean/engine_anisotropy.h"
#include "methods/method_unit.h"
#include "ndfmip/roughness.h"

namespace ndfmip {

namespace {

Status prepareGgxAniso(const Material& m, const RenderTextures& textures,
                       const RenderOptions& options, ShaderSetup& setup) {
    if (Status s = checkFittedMaterial("ggx-aniso", m, textures); !s) return s;
    return prepareSplitSumSetup(m, textures, options, setup);
}

glm::vec3 shadeGgxAnisoParams(const ShaderSetup&, const Material& m, const float* p,
                              glm::vec3 albedo, glm::vec3 l, glm::vec3 v) {
    const glm::vec3 h = glm::normalize(l + v);
    return glsl().ndfmipShadeGgxAniso(glslMaterial(m, specularFactor(m, l, h)), albedo,
                                      glm::vec3(p[0], p[1], p[2]), glm::vec3(p[3], p[4], p[5]), l,
                                      v);
}

float ggxAnisoLobe(const ShaderSetup&, const Material&, const float* p, glm::vec3 h) {
    const glm::vec3 n(p[0], p[1], p[2]);
    const float length = glm::length(n);
    if (!(length > 0.f)) return 0.f;
    return glsl().ndfmipGgxAnisoLobe(n / length, glm::vec3(p[3], p[4], p[5]), h);
}

// Under an environment: an engine's split sum at the tensor's isotropic alpha.
glm::vec3 shadeGgxAnisoEnvironment(const ShaderSetup& setup, const Material& m, const float* p,
                                   glm::vec3 albedo, glm::vec3 v, const glm::mat3& toEnvironment,
                                   const EnvironmentLighting&) {
    const float alpha = glsl().ndfmipGgxAnisoAlpha(glm::vec3(p[3], p[4], p[5]));
    return shadeRoughnessMipsSplitSum(m, albedo, glm::vec3(p[0], p[1], p[2]), alpha, true, v,
                                      toEnvironment, *setup.splitSum, setup.environmentLod);
}

void inspectGgxAniso(nlohmann::json& out, const LoadedBake& bake, int x, int y,
                     const InspectOptions&) {
    out["normal"] = jsonVec3(bake.level[requirePlane(bake, "normal")].at(x, y));
    const float* a = bake.level[requirePlane(bake, "alpha_tensor")].at(x, y);
    out["alpha_tensor"] = {{a[0], a[1]}, {a[1], a[2]}};
    const AnisotropicLobe lobe = anisotropicLobe(a[0], a[2], a[1]);
    out["alpha_t"] = lobe.alphaT;
    out["alpha_b"] = lobe.alphaB;
    out["direction"] = {lobe.direction.x, lobe.direction.y};
}

} // namespace

MethodUnit ggxAnisoUnit() {
    MethodUnit u{};
    u.method = Method::GgxAniso;
    u.name = "ggx-aniso";
    u.summary = "one anisotropic GGX lobe per texel (two roughnesses and a direction), fitted to "
                "the texel's filtered NDF (needs --base-roughness)";
    u.bake = bakeGgxAniso;
    u.planes = [](const BakeParameters&, bool) {
        return std::vector<PlaneInfo>{planeOf("normal", 3, true), planeOf("alpha_tensor", 3, true)};
    };
    u.parameters = {materialRoughnessParameter()}; // the shader checks the material's
    // The planes, and with a roughness map its alpha.
    u.bakeBytesPerTexel = [](const BakeOptions& o) {
        return 24.0 * 4.0 / 3.0 + (o.roughnessMap ? 4.0 : 0.0);
    };
    u.describe = [](const BakeParameters&) { return std::string("ggx-aniso bake"); };
    u.inspect = inspectGgxAniso;
    u.levelZeroNormal = [](const float* p) { return glm::vec3(p[0], p[1], p[2]); };
    u.ndfDensity = nullptr;
    u.fitsMaterialRoughness = true;
    return u;
}

std::vector<MethodShader> ggxAnisoShaders() {
    return {{"ggx-aniso", Method::GgxAniso, "render/ggx_aniso.glsl", prepareGgxAniso,
             shadeGgxAnisoParams, ggxAnisoLobe, shadeGgxAnisoEnvironment, nullptr, nullptr, nullptr,
             false}};
}

} // namespace ndfmip
