// Roughness for today's microfacet engines, from the normal variance that Toksvig's |Na|
// measures. A Blinn-Phong exponent s matches Beckmann roughness alpha by s = 2/alpha^2 - 2
// (Walter et al. 2007, sec. 5.2), so 1/s ~ alpha^2/2; Toksvig widens a lobe by
// 1/s' = 1/s + sigma^2 (T eq. 5). Together alpha'^2 = alpha0^2 + 2 sigma^2 with
// sigma^2 = (1 - |Na|)/|Na| (Toksvig eq. 1). Measured against GGX ground truth on real maps
// (ndfmip eval --calibrate, docs/RESULTS.md), with the truth the pyramid averages (the box
// surface, integrated exactly), the derived constant 2 is also the closest, so
//     alpha'^2 = alpha0^2 + c sigma^2,   c = kVarianceScale = 2,
// capped at alpha' = 1. GGX uses the same alpha: GGX and Beckmann lobes of equal alpha have
// the same peak 1/(pi alpha^2) and agree near it. docs/METHODS.md has the details.
#pragma once

#include <string>

#include <glm/glm.hpp>

#include "ndfmip/toksvig.h"

namespace ndfmip {

// The constant c of alpha'^2 = alpha0^2 + c sigma^2, checked against GGX ground truth (c = 0.25
// ... 4 tried on three maps, footprints 4-64, alpha0 = 0.05 ... 0.5: 2 has the lowest error,
// and holds on the six maps not used to choose it; docs/RESULTS.md).
constexpr float kVarianceScale = 2.f;

inline float varianceRoughness(float length, float baseAlpha, float scale = kVarianceScale) {
    return glsl().ndfmipMappedRoughness(NDFMIP_MAPPING_OURS, length, baseAlpha, scale);
}

// Engines store "perceptual" roughness, alpha = perceptual^2 (Burley 2012; glTF, Unreal,
// Unity, Filament).
inline float perceptualRoughness(float alpha) {
    return glm::sqrt(glm::max(alpha, 0.f));
}

// ---- The mappings shipped engines use, for the calibration against ground truth -----------
// r = |Na|. kappa = (3r - r^3)/(1 - r^2) is the von Mises-Fisher concentration whose mean
// length is r (Banerjee et al. 2005); 1/kappa plays the part of sigma^2 for a vMF lobe.

enum class RoughnessMapping {
    Ours,     // alpha'^2 = alpha^2 + c (1 - r)/r, c = kVarianceScale unless given
    Hdrp,     // alpha'^2 = alpha^2 + 0.5 / kappa
    Filament, // alpha'^2 = alpha^2 + 2 / kappa
    Godot,    // p'^2 = p^2 + min(0.75 / kappa, 0.16) on perceptual roughness p = sqrt(alpha)
    Unreal,   // alpha'^2 = (alpha^2 + 2V (1 - alpha^2)) / (1 + 2V (1 - alpha^2)), V = (1 - r)/r
              // (Unreal Engine's texture compressor: a Toksvig variance with c = 2 that keeps
              // alpha' below 1)
};

inline float vmfKappaFromLength(float r) {
    return glsl().ndfmipToksvigKappa(r);
}

// "ours", "hdrp", "filament", "godot", "unreal"; and back (false for any other name).
const char* roughnessMappingName(RoughnessMapping mapping);
bool roughnessMappingFromString(const std::string& name, RoughnessMapping& out);

inline float mappedRoughness(RoughnessMapping mapping, float r, float alpha,
                             float scale = kVarianceScale) {
    return glsl().ndfmipMappedRoughness(int(mapping), r, alpha, scale);
}
static_assert(int(RoughnessMapping::Ours) == NDFMIP_MAPPING_OURS &&
              int(RoughnessMapping::Hdrp) == NDFMIP_MAPPING_HDRP &&
              int(RoughnessMapping::Filament) == NDFMIP_MAPPING_FILAMENT &&
              int(RoughnessMapping::Godot) == NDFMIP_MAPPING_GODOT &&
              int(RoughnessMapping::Unreal) == NDFMIP_MAPPING_UNREAL);

} // namespace ndfmip
