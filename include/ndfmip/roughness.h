// Roughness for today's microfacet engines, from the normal variance that Toksvig's |Na|
// measures. A Blinn-Phong exponent s matches Beckmann roughness alpha by s = 2/alpha^2 - 2
// (Walter et al. 2007, sec. 5.2), so 1/s ~ alpha^2/2; Toksvig widens a lobe by
// 1/s' = 1/s + sigma^2 (eq. 5). Together:
//     alpha'^2 = alpha0^2 + 2 sigma^2,   sigma^2 = (1 - |Na|)/|Na|   (Toksvig eq. 1),
// capped at alpha' = 1. GGX uses the same alpha: GGX and Beckmann lobes of equal alpha have
// the same peak 1/(pi alpha^2) and agree near it. docs/METHODS.md has the details.
#pragma once

#include <glm/glm.hpp>

#include "ndfmip/toksvig.h"

namespace ndfmip {

inline float varianceRoughness(float length, float baseAlpha) {
    float alpha2 = baseAlpha * baseAlpha + 2.f * toksvigSigma2(length);
    return glm::min(glm::sqrt(alpha2), 1.f);
}

// Engines store "perceptual" roughness, alpha = perceptual^2 (Burley 2012; glTF, Unreal,
// Unity, Filament).
inline float perceptualRoughness(float alpha) { return glm::sqrt(glm::max(alpha, 0.f)); }

} // namespace ndfmip
