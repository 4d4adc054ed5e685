// ggx-aniso as a unit, and its shaders: the level's unit normal with the fitted anisotropic GGX
// lobe's tensor stored as moments, both blended by the lookup (shaders/ggx_aniso.glsl); and
// ggx-aniso-khr, ggx-aniso-kulla and ggx-aniso-burley, the same lobe as the engines sample it from
// their files (KHR_materials_anisotropy; Unreal's and Unity HDRP's inputs; Godot's).

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
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

// Where a row's shader reads its lobe: the bake's own moments (ggx-aniso), or an engine's inputs
// (engine_anisotropy.h) for the engine rows: glTF's KHR_materials_anisotropy (three.js, Filament,
// Bevy), Kulla's (Unreal, Unity HDRP), Burley's (Godot).
enum class EngineInputs { Moments, Khr, Kulla, Burley };

// A texel of the engine's files as the row's plane holds it: the perceptual roughness, the
// direction as (d + 1)/2, the anisotropy (KHR's strength or the engine's k).
template <EngineInputs E> glm::vec4 engineTexel(const AnisotropicLobe& lobe) {
    if constexpr (E == EngineInputs::Khr) {
        const KhrAnisotropy khr = khrAnisotropy(lobe);
        float rgba[4];
        khrAnisotropyTexel(khr, rgba);
        return {khr.roughness, rgba[0], rgba[1], rgba[2]};
    } else {
        const RoughnessAnisotropy r =
            E == EngineInputs::Kulla ? kullaAnisotropy(lobe) : burleyAnisotropy(lobe);
        return {r.roughness, 0.5f * (r.direction.x + 1.f), 0.5f * (r.direction.y + 1.f),
                r.anisotropy};
    }
}

// The engine row's planes: the bake's lobes as the engine's files hold them (bake --engine, ndfmip
// gltf): the normal, and per texel the roughness beside the direction and the anisotropy, with
// the files' directions (coherentDirections) and their 8 bits.
template <EngineInputs E> Bake engineAnisotropyPlanes(const Bake& bake) {
    const int normalPlane = findPlane(bake.planes, "normal");
    const int momentsPlaneIndex = findPlane(bake.planes, "alpha_moments");
    if (normalPlane < 0 || momentsPlaneIndex < 0)
        throw std::runtime_error("ggx-aniso: the bake has no normal and alpha_moments planes");
    const size_t momentsPlane = size_t(momentsPlaneIndex);
    std::vector<std::pair<int, int>> sizes;
    for (const auto& level : bake.levels)
        sizes.emplace_back(level[momentsPlane]->width, level[momentsPlane]->height);
    auto lobe = [&bake, momentsPlane, normalPlane](size_t k, size_t i) {
        return anisotropicLobeOfGgxAniso(&bake.levels[k][momentsPlane]->pixels[3 * i],
                                         &bake.levels[k][size_t(normalPlane)]->pixels[3 * i]);
    };
    const StoredDirections directions = coherentDirections(sizes, lobe);
    auto eightBits = [](float v) { return std::round(std::clamp(v, 0.f, 1.f) * 255.f) / 255.f; };
    Bake out;
    out.method = bake.method;
    out.parameters = bake.parameters;
    out.planes = {bake.planes[size_t(normalPlane)],
                  {"engine_anisotropy",
                   {"roughness: perceptual", "direction of alpha_t, tangent x, (d + 1)/2",
                    "direction of alpha_t, bitangent y, (d + 1)/2",
                    E == EngineInputs::Khr ? kKhrAnisotropyChannels[2] : "anisotropy k"},
                   "the lobe as the engine's files hold it, 8-bit",
                   true}};
    for (size_t k = 0; k < bake.levels.size(); ++k) {
        const Image& moments = *bake.levels[k][momentsPlane];
        Image texels(moments.width, moments.height, 4, Image::Uninitialized{});
        for (size_t i = 0; i < moments.texelCount(); ++i) {
            AnisotropicLobe l = lobe(k, i);
            l.direction = directions.at(k, i);
            const glm::vec4 texel = engineTexel<E>(l);
            for (int c = 0; c < 4; ++c) texels.pixels[4 * i + size_t(c)] = eightBits(texel[c]);
        }
        out.levels.push_back({bake.levels[k][size_t(normalPlane)],
                              std::make_shared<const Image>(std::move(texels))});
    }
    return out;
}

// The lobe's tensor from the blended planes: the bake's, from its blended moments and normal, or
// the one the engine decodes from its blended channels (ggx_aniso.glsl).
template <EngineInputs E> glm::vec3 tensorOf(const float* p) {
    if constexpr (E == EngineInputs::Moments)
        return glsl().ndfmipGgxAnisoTensor(glm::vec3(p[3], p[4], p[5]),
                                           glm::vec3(p[0], p[1], p[2]));
    else if constexpr (E == EngineInputs::Khr)
        return glsl().ndfmipKhrAnisotropyTensor(glm::vec4(p[3], p[4], p[5], p[6]));
    else if constexpr (E == EngineInputs::Kulla)
        return glsl().ndfmipKullaAnisotropyTensor(glm::vec4(p[3], p[4], p[5], p[6]));
    else
        return glsl().ndfmipBurleyAnisotropyTensor(glm::vec4(p[3], p[4], p[5], p[6]));
}

template <EngineInputs E>
glm::vec3 shadeAniso(const ShaderSetup&, const Material& m, const float* p, glm::vec3 albedo,
                     glm::vec3 l, glm::vec3 v) {
    const glm::vec3 h = glm::normalize(l + v);
    return glsl().ndfmipShadeGgxAniso(glslMaterial(m, specularFactor(m, l, h)), albedo,
                                      glm::vec3(p[0], p[1], p[2]), tensorOf<E>(p), l, v);
}

template <EngineInputs E>
float anisoLobe(const ShaderSetup&, const Material&, const float* p, glm::vec3 h) {
    const glm::vec3 n(p[0], p[1], p[2]);
    const float length = glm::length(n);
    if (!(length > 0.f)) return 0.f;
    return glsl().ndfmipGgxAnisoLobe(n / length, tensorOf<E>(p), h);
}

// Under an environment: an engine's split sum at the tensor's isotropic alpha.
template <EngineInputs E>
glm::vec3 shadeAnisoEnvironment(const ShaderSetup& setup, const Material& m, const float* p,
                                glm::vec3 albedo, glm::vec3 v, const glm::mat3& toEnvironment,
                                const EnvironmentLighting&) {
    const float alpha = glsl().ndfmipGgxAnisoAlpha(tensorOf<E>(p));
    return shadeRoughnessMipsSplitSum(m, albedo, glm::vec3(p[0], p[1], p[2]), alpha, true, v,
                                      toEnvironment, *setup.splitSum, setup.environmentLod);
}

// The GPU glue's decoder (render/ggx_aniso_engine.glsl; KHR's without a define).
template <EngineInputs E> std::string engineDefines(const ShaderSetup&, int) {
    if constexpr (E == EngineInputs::Kulla)
        return "#define NDFMIP_ENGINE_ANISOTROPY ndfmipKullaAnisotropyTensor\n";
    else if constexpr (E == EngineInputs::Burley)
        return "#define NDFMIP_ENGINE_ANISOTROPY ndfmipBurleyAnisotropyTensor\n";
    else
        return "";
}

// Specular anti-aliasing on the tensor (ndfmipSpecularAaTensor), added to the blended moments,
// which adds it to their tensor. The engine rows' planes are their files' channels, whose engines
// widen no tensor: they take none.
void widenTensor(const ShaderSetup&, Material&, float* p, float kernel) {
    const glm::vec3 widened = glsl().ndfmipSpecularAaTensor(glm::vec3(p[3], p[4], p[5]), kernel);
    p[3] = widened.x;
    p[4] = widened.y;
    p[5] = widened.z;
}

template <EngineInputs E> MethodShader anisoShader(const char* name) {
    MethodShader shader{name,
                        Method::GgxAniso,
                        "render/ggx_aniso.glsl",
                        prepareGgxAniso,
                        shadeAniso<E>,
                        anisoLobe<E>,
                        shadeAnisoEnvironment<E>,
                        nullptr,
                        nullptr,
                        nullptr,
                        false,
                        nullptr,
                        nullptr};
    if constexpr (E != EngineInputs::Moments) {
        shader.glsl = "render/ggx_aniso_engine.glsl";
        shader.gpuDefines = engineDefines<E>;
        shader.planesOf = engineAnisotropyPlanes<E>;
    } else {
        shader.widenRoughness = widenTensor;
    }
    return shader;
}

void inspectGgxAniso(nlohmann::json& out, const LoadedBake& bake, int x, int y,
                     const InspectOptions&) {
    const float* n = bake.level[requirePlane(bake, "normal")].at(x, y);
    out["normal"] = jsonVec3(n);
    const float* m = bake.level[requirePlane(bake, "alpha_moments")].at(x, y);
    out["alpha_moments"] = {{m[0], m[1]}, {m[1], m[2]}};
    const glm::vec3 a =
        glsl().ndfmipGgxAnisoTensor(glm::vec3(m[0], m[1], m[2]), glm::vec3(n[0], n[1], n[2]));
    out["alpha_tensor"] = {{a.x, a.y}, {a.y, a.z}};
    const AnisotropicLobe lobe = anisotropicLobe(a.x, a.z, a.y);
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
        return std::vector<PlaneInfo>{planeOf("normal", 3, true),
                                      planeOf("alpha_moments", 3, true)};
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
    return {anisoShader<EngineInputs::Moments>("ggx-aniso"),
            anisoShader<EngineInputs::Khr>("ggx-aniso-khr"),
            anisoShader<EngineInputs::Kulla>("ggx-aniso-kulla"),
            anisoShader<EngineInputs::Burley>("ggx-aniso-burley")};
}

} // namespace ndfmip
