// ggx-aniso as a unit, and its shaders: the level's unit normal with the fitted anisotropic GGX
// lobe's tensor, both blended by the lookup (shaders/ggx_aniso.glsl); and ggx-aniso-khr, the same
// lobe as a glTF engine samples it from its KHR_materials_anisotropy textures.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <utility>
#include <vector>

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

// ggx-aniso-khr's planes: the bake's lobes as the glTF files hold them (bake --engine gltf and
// ndfmip gltf, engine_anisotropy.h): the normal, and per texel the roughness (metallicRoughness
// G) beside the anisotropyTexture's R, G, B, with the files' direction signs and their 8 bits.
Bake khrAnisotropyPlanes(const Bake& bake) {
    const int normalPlane = findPlane(bake.planes, "normal");
    const int tensorPlaneIndex = findPlane(bake.planes, "alpha_tensor");
    if (normalPlane < 0 || tensorPlaneIndex < 0)
        throw std::runtime_error("ggx-aniso-khr: the bake has no normal and alpha_tensor planes");
    const size_t tensorPlane = size_t(tensorPlaneIndex);
    std::vector<std::pair<int, int>> sizes;
    for (const auto& level : bake.levels)
        sizes.emplace_back(level[tensorPlane]->width, level[tensorPlane]->height);
    auto lobe = [&bake, tensorPlane](size_t k, size_t i) {
        const float* a = &bake.levels[k][tensorPlane]->pixels[3 * i];
        return anisotropicLobe(a[0], a[2], a[1]);
    };
    const std::vector<std::vector<int8_t>> signs = coherentDirectionSigns(sizes, lobe);
    auto eightBits = [](float v) { return std::round(std::clamp(v, 0.f, 1.f) * 255.f) / 255.f; };
    Bake out;
    out.method = bake.method;
    out.parameters = bake.parameters;
    out.planes = {
        bake.planes[size_t(normalPlane)],
        {"khr_anisotropy",
         {"roughness", kKhrAnisotropyChannels[0], kKhrAnisotropyChannels[1],
          kKhrAnisotropyChannels[2]},
         "the lobe as KHR_materials_anisotropy's inputs: the roughness (metallicRoughness "
         "G), then the anisotropyTexture's R, G, B; 8-bit",
         true}};
    for (size_t k = 0; k < bake.levels.size(); ++k) {
        const Image& tensor = *bake.levels[k][tensorPlane];
        Image khr(tensor.width, tensor.height, 4, Image::Uninitialized{});
        for (size_t i = 0; i < tensor.texelCount(); ++i) {
            AnisotropicLobe l = lobe(k, i);
            if (signs[k][i] < 0) l.direction = -l.direction;
            const KhrAnisotropy engine = khrAnisotropy(l);
            float rgba[4];
            khrAnisotropyTexel(engine, rgba);
            float* out4 = &khr.pixels[4 * i];
            out4[0] = eightBits(engine.roughness);
            for (int c = 0; c < 3; ++c) out4[c + 1] = eightBits(rgba[c]);
        }
        out.levels.push_back(
            {bake.levels[k][size_t(normalPlane)], std::make_shared<const Image>(std::move(khr))});
    }
    return out;
}

glm::vec3 khrTensor(const float* p) {
    return glsl().ndfmipKhrAnisotropyTensor(glm::vec4(p[3], p[4], p[5], p[6]));
}

glm::vec3 shadeGgxAnisoKhr(const ShaderSetup&, const Material& m, const float* p, glm::vec3 albedo,
                           glm::vec3 l, glm::vec3 v) {
    const glm::vec3 h = glm::normalize(l + v);
    return glsl().ndfmipShadeGgxAniso(glslMaterial(m, specularFactor(m, l, h)), albedo,
                                      glm::vec3(p[0], p[1], p[2]), khrTensor(p), l, v);
}

float ggxAnisoKhrLobe(const ShaderSetup&, const Material&, const float* p, glm::vec3 h) {
    const glm::vec3 n(p[0], p[1], p[2]);
    const float length = glm::length(n);
    if (!(length > 0.f)) return 0.f;
    return glsl().ndfmipGgxAnisoLobe(n / length, khrTensor(p), h);
}

glm::vec3 shadeGgxAnisoKhrEnvironment(const ShaderSetup& setup, const Material& m, const float* p,
                                      glm::vec3 albedo, glm::vec3 v, const glm::mat3& toEnvironment,
                                      const EnvironmentLighting&) {
    const float alpha = glsl().ndfmipGgxAnisoAlpha(khrTensor(p));
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
             false, nullptr},
            {"ggx-aniso-khr", Method::GgxAniso, "render/ggx_aniso_khr.glsl", prepareGgxAniso,
             shadeGgxAnisoKhr, ggxAnisoKhrLobe, shadeGgxAnisoKhrEnvironment, nullptr, nullptr,
             nullptr, false, khrAnisotropyPlanes}};
}

} // namespace ndfmip
