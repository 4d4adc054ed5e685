// KHR_materials_anisotropy's texel of an anisotropic GGX lobe (khr_anisotropy.h).
#include "methods/lean/khr_anisotropy.h"

#include <algorithm>
#include <cmath>

namespace ndfmip {

KhrAnisotropy khrAnisotropy(float axx, float ayy, float axy) {
    // Eigenvalues of the symmetric 2x2 tensor: mean +- the half difference's length.
    const double mean = 0.5 * (double(axx) + double(ayy));
    const double half = 0.5 * (double(axx) - double(ayy));
    const double spread = std::hypot(half, double(axy));
    const double alphaT = std::clamp(std::sqrt(std::max(mean + spread, 0.0)), 0.0, 1.0);
    const double alphaB = std::clamp(std::sqrt(std::max(mean - spread, 0.0)), 0.0, alphaT);
    KhrAnisotropy out;
    out.roughness = float(std::sqrt(alphaB));
    // alpha_t = alpha_b + s^2 (1 - alpha_b).
    out.strength = alphaB < 1.0 ? float(std::sqrt((alphaT - alphaB) / (1.0 - alphaB))) : 0.f;
    // The major axis at angle atan2(2 axy, axx - ayy) / 2, in (-90, 90] degrees: x >= 0.
    const double angle = spread > 0.0 ? 0.5 * std::atan2(double(axy), half) : 0.0;
    out.direction = glm::vec2(float(std::cos(angle)), float(std::sin(angle)));
    return out;
}

KhrAnisotropy khrAnisotropyOfMoments(const float* m, float cross, float alpha2) {
    const float sxx = std::max(m[2] - m[0] * m[0], 0.f);
    const float syy = std::max(m[3] - m[1] * m[1], 0.f);
    const float sxy = cross - m[0] * m[1];
    return khrAnisotropy(alpha2 + 2.f * sxx, alpha2 + 2.f * syy, 2.f * sxy);
}

} // namespace ndfmip
