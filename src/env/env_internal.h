// Sampling shared by the prefilter and the DFG table (src/env).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <glm/glm.hpp>

namespace ndfmip::env {

// Van der Corput radical inverse in base 2: the second coordinate of Hammersley point i.
inline double radicalInverse(uint32_t bits) {
    bits = (bits << 16u) | (bits >> 16u);
    bits = ((bits & 0x55555555u) << 1u) | ((bits & 0xAAAAAAAAu) >> 1u);
    bits = ((bits & 0x33333333u) << 2u) | ((bits & 0xCCCCCCCCu) >> 2u);
    bits = ((bits & 0x0F0F0F0Fu) << 4u) | ((bits & 0xF0F0F0F0u) >> 4u);
    bits = ((bits & 0x00FF00FFu) << 8u) | ((bits & 0xFF00FF00u) >> 8u);
    return double(bits) * 2.3283064365386963e-10; // / 2^32
}

// Half vector i of `count` Hammersley points (i / count, radicalInverse(i)) mapped through the
// inverse CDF of D(h) <n.h> for GGX, n = z: cos^2 theta_h = (1 - u) / (1 + (a^2 - 1) u),
// with a^2 - 1 written (a - 1)(a + 1) for precision at small alpha.
inline glm::dvec3 ggxHalfVector(int i, int count, double alpha) {
    const double phi = 2. * M_PI * i / count, u = radicalInverse(uint32_t(i));
    const double cos2 = (1. - u) / (1. + (alpha + 1.) * ((alpha - 1.) * u));
    const double sinTheta = std::sqrt(std::max(0., 1. - cos2));
    return {sinTheta * std::cos(phi), sinTheta * std::sin(phi), std::sqrt(cos2)};
}

} // namespace ndfmip::env
