// Toksvig, "Mipmapping Normal Maps": the shortening of the averaged normal |Na| estimates the
// variance of the normals it averages, and that variance widens the specular lobe.
// Equation numbers refer to that paper.
#pragma once

#include <glm/glm.hpp>

#include "ndfmip/image.h"
#include "ndfmip/shading.h"

namespace ndfmip {

// T eq. 1: variance of the angular deviation from the mean normal length, sigma^2 = (1-|Na|)/|Na|.
inline float toksvigSigma2(float length) {
    return glsl().ndfmipToksvigSigma2(length);
}

// T eq. 6: factor that scales the exponent s, ft = |Na| / (|Na| + s (1 - |Na|)).
inline float toksvigFactor(float length, float s) {
    return glsl().ndfmipToksvigFactor(length, s);
}

// T eq. 8 in the normalised form: the Blinn-Phong lobe of exponent ft*s about Na/|Na|,
// scaled so that it keeps unit energy, (ft s + 1)/(2 pi) (Na.H/|Na|)^(ft s).
inline float toksvigSpecular(glm::vec3 meanNormal, glm::vec3 h, float s) {
    float length = glm::length(meanNormal);
    if (length <= 0.f) return 1.f / (2.f * kPi); // every direction equally likely: exponent 0
    float sPrime = toksvigFactor(length, s) * s;
    return blinnPhong(glm::dot(meanNormal, h) / length, sPrime);
}

// The standard mipmap's specular: the renormalised mean normal with the unchanged exponent.
inline float naiveSpecular(glm::vec3 normal, glm::vec3 h, float s) {
    float length = glm::length(normal);
    if (length <= 0.f) return 0.f;
    return blinnPhong(glm::dot(normal, h) / length, s);
}

// ---- Toksvig's 2D lookup table (T eq. 9) ------------------------------------------------------

struct ToksvigLutOptions {
    float exponent = 32.f; // s
    int size = 256;        // N x N texels
    // Phase-out of T eqs. 10-11: where the intensity error caused by the quantisation of
    // |Na| exceeds `threshold`, blend towards the aliased lookup. bitDepth 0 disables it.
    int bitDepth = 0;
    float threshold = 0.05f;
};

// T eq. 9 relative to the unfiltered highlight: ((1 + ft s)/(1 + s)) (Na.H / |Na|)^(ft s),
// written in terms of the two lookups x = Na.H and y = Na.Na of the paper's pseudo-code.
// x is clamped to [0, sqrt(y)] (larger values never occur for a real Na).
float toksvigLutValue(float naDotH, float naDotNa, float s);

// T eq. 10: d(relative intensity)/d|Na| = s^2 / ((1+s)(|Na| + s(1-|Na|))^2).
float toksvigIntensitySensitivity(float length, float s);

// Error in |Na| from b-bit signed components: half a quantisation step in each of the three
// components, sqrt(3) / (2 (2^(b-1) - 1)) (the paper's 0.0068 for b = 8).
float lengthQuantisationError(int bitDepth);

// One value of the table, phase-out (T eq. 11) included when options.bitDepth > 0.
float toksvigLutEntry(float naDotH, float naDotNa, const ToksvigLutOptions& options);

// The N x N table, one channel: column i samples Na.H = (i + 0.5)/N, row j samples
// Na.Na = (j + 0.5)/N with row 0 at the top of the image (Na.Na = 0 side).
Image toksvigLut(const ToksvigLutOptions& options);

// ---- Free gloss maps (T eq. 12) ---------------------------------------------------------------

// Length to give a unit normal so that Toksvig's factor turns the maximum exponent s0 into
// the exponent s (0 < s <= s0): s s0 / (s s0 + s0 - s).
float glossLength(float s, float s0);

// Shortens every normal of `normals` (3 channels) in place; gloss has one channel in [0,1]
// and sets s = max(gloss, 1e-4) * s0 per texel. Both images have the same size.
void applyGlossMap(Image& normals, const Image& gloss, float s0);

} // namespace ndfmip
