// One anisotropic GGX lobe per texel in each engine's own inputs. The lobe has alpha_t >= alpha_b,
// alpha_t along a direction of the tangent frame (x the tangent, y the bitangent, +Y up as the
// normals are decoded). The engines parametrise it three ways (docs/ENGINES.md has the sources):
//  - glTF's KHR_materials_anisotropy (three.js, Filament's glTF loader, Bevy): the roughness in
//    metallicRoughness G is sqrt(alpha_b), a strength s gives alpha_t = mix(alpha_b, 1, s^2);
//  - Kulla and Conty 2017 (Unreal's GetAnisotropicRoughness, Unity HDRP's
//    ConvertAnisotropyToRoughness): alpha_t = alpha (1 + k), alpha_b = alpha (1 - k), so alpha =
//    (alpha_t + alpha_b) / 2 and k = (alpha_t - alpha_b) / (alpha_t + alpha_b), exactly;
//  - Burley 2012 (Godot 4's light_compute): aspect = sqrt(1 - 0.9 k), alpha_t = alpha / aspect,
//    alpha_b = alpha aspect, so alpha = sqrt(alpha_t alpha_b) and k = (1 - alpha_b / alpha_t) /
//    0.9, exact up to a 10:1 stretch (k = 1), beyond which alpha_t comes out shorter.
// Each engine's roughness is perceptual (alpha = roughness^2).
#pragma once

#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

namespace ndfmip {

struct AnisotropicLobe {
    float alphaT = 0.f, alphaB = 0.f; // alpha_t >= alpha_b, each at most 1
    // Unit, the axis of alpha_t; a lobe has no sign: x >= 0 from anisotropicLobe, the engine
    // files' from coherentDirections.
    glm::vec2 direction{1.f, 0.f};
};

// The lobe of squared-roughness tensor A = [[axx, axy], [axy, ayy]] (slope space, as sggx.glsl
// shades it): alpha_t^2 and alpha_b^2 its eigenvalues, each alpha at most 1 (no engine input
// stores a wider lobe).
AnisotropicLobe anisotropicLobe(float axx, float ayy, float axy);

// The lobe of one texel of a lean bake (sggx.glsl): `moments` its lean_moments (E[bx], E[by],
// E[bx^2], E[by^2]), `cross` its lean_cross (E[bx by]), `alpha2` the material's mean alpha^2;
// the tensor alpha2 I + 2 Sigma, Sigma the slopes' covariance (lean.glsl's).
AnisotropicLobe anisotropicLobeOfMoments(const float* moments, float cross, float alpha2);

// The lobe of one texel of a ggx-aniso bake: its alpha_moments less twice its unit normal's x and
// y second moment (ggx_aniso.glsl's ndfmipGgxAnisoTensor), the fitted tensor A.
AnisotropicLobe anisotropicLobeOfGgxAniso(const float* alphaMoments, const float* normal);

// ---- Directions that blend ---------------------------------------------------------------------

// The directions an engine's direction texture stores, chosen so that its sampler's blends keep
// them. A lobe's direction has no sign (d and -d are the same lobe), but the sampler blends the
// stored channels: neighbours at +89 and -89 degrees, each stored with x >= 0, blend to a
// direction across both. So each texel's sign agrees with the signed directions of the texels
// already chosen around it (in its level the one to the left and the three above; its parent in
// the level above), each weighted by its anisotropy (alpha_t - alpha_b) / (alpha_t + alpha_b),
// the coarsest level first; a field that turns by half a turn about a point cannot agree all
// round it, and the scan puts that seam where it meets it. A texel with no anisotropy (an
// isotropic lobe, or one that is not finite) has no direction of its own to keep: it stores its
// parent's, so a blend of the two levels keeps the parent's direction too (ggx-aniso's and lean's
// level 0 is isotropic everywhere).
// `sizes` the levels' (width, height), level 0 the finest; `lobe(k, i)` level k's texel i, row by
// row, called in parallel.
struct StoredDirections {
    std::vector<std::vector<int16_t>> levels; // per level, x and y per texel, times 32767
    glm::vec2 at(size_t k, size_t i) const {
        return {float(levels[k][2 * i]) / 32767.f, float(levels[k][2 * i + 1]) / 32767.f};
    }
};
StoredDirections coherentDirections(const std::vector<std::pair<int, int>>& sizes,
                                    const std::function<AnisotropicLobe(size_t k, size_t i)>& lobe);

// ---- glTF KHR_materials_anisotropy --------------------------------------------------------------

struct KhrAnisotropy {
    float roughness = 0.f;         // perceptual: sqrt(alpha_b)
    glm::vec2 direction{1.f, 0.f}; // the lobe's
    float strength = 0.f;          // s in [0, 1]
};
KhrAnisotropy khrAnisotropy(const AnisotropicLobe& lobe);
KhrAnisotropy khrAnisotropy(float axx, float ayy, float axy); // of anisotropicLobe
KhrAnisotropy khrAnisotropyOfMoments(const float* moments, float cross, float alpha2);

// The lobe's anisotropyTexture texel (RGBA): the direction as (d + 1)/2, the strength, 1.
void khrAnisotropyTexel(const KhrAnisotropy& lobe, float* rgba);

// What the anisotropyTexture's R, G, B hold, for the files' own descriptions.
constexpr const char* kKhrAnisotropyChannels[3] = {"direction of alpha_t, tangent x, (d + 1)/2",
                                                   "direction of alpha_t, bitangent y, (d + 1)/2",
                                                   "strength s: alpha_t = mix(alpha_b, 1, s^2)"};

// ---- Kulla's and Burley's parametrisations ------------------------------------------------------

// An engine's perceptual roughness and anisotropy k in [0, 1], alpha_t along `direction`.
struct RoughnessAnisotropy {
    float roughness = 0.f;
    float anisotropy = 0.f;
    glm::vec2 direction{1.f, 0.f};
};
RoughnessAnisotropy kullaAnisotropy(const AnisotropicLobe& lobe);  // Unreal, Unity HDRP
RoughnessAnisotropy burleyAnisotropy(const AnisotropicLobe& lobe); // Godot 4

} // namespace ndfmip
