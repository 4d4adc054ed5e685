// Helpers shared by the vMF tests: directions, angles and exact vMF sampling.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include <glm/glm.hpp>

#include "ndfmip/image.h"
#include "ndfmip/vmf.h"
#include "test_support.h"

namespace ndfmip::vmftest {

constexpr double kPi = 3.14159265358979323846;

inline double angleBetween(glm::vec3 a, glm::vec3 b) {
    glm::dvec3 u = glm::normalize(glm::dvec3(a)), v = glm::normalize(glm::dvec3(b));
    return 2 * std::asin(std::min(1.0, glm::length(u - v) / 2));
}

inline double degrees(double radians) {
    return radians * 180 / kPi;
}

inline glm::vec3 direction(double thetaDegrees, double phiDegrees) {
    double t = thetaDegrees * kPi / 180, p = phiDegrees * kPi / 180;
    return glm::vec3(float(std::sin(t) * std::cos(p)), float(std::sin(t) * std::sin(p)),
                     float(std::cos(t)));
}

// Exact vMF sampling on S^2 (Wood 1994): w = mu.n has density ~ e^(kappa w) on [-1, 1], inverted
// in closed form, w = 1 + log(u + (1 - u) e^(-2 kappa)) / kappa; the azimuth is uniform.
inline glm::vec3 sampleVmf(glm::vec3 mu, double kappa, std::mt19937_64& rng) {
    std::uniform_real_distribution<double> uniform(0, 1);
    double u = uniform(rng), w;
    if (kappa < 1e-8)
        w = 2 * u - 1;
    else
        w = 1 + std::log(u + (1 - u) * std::exp(-2 * kappa)) / kappa;
    w = std::clamp(w, -1.0, 1.0);
    double phi = 2 * kPi * uniform(rng), s = std::sqrt(1 - w * w);
    glm::dvec3 m = glm::normalize(glm::dvec3(mu));
    glm::dvec3 helper = std::abs(m.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0);
    glm::dvec3 e1 = glm::normalize(glm::cross(m, helper)), e2 = glm::cross(m, e1);
    return glm::vec3(glm::normalize(w * m + s * (std::cos(phi) * e1 + std::sin(phi) * e2)));
}

inline std::vector<glm::vec3> sampleMixture(const std::vector<VmfLobe>& lobes, size_t count,
                                            uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::vector<double> alphas;
    for (const VmfLobe& l : lobes) alphas.push_back(l.alpha);
    std::discrete_distribution<int> pick(alphas.begin(), alphas.end());
    std::vector<glm::vec3> normals(count);
    for (glm::vec3& n : normals) {
        const VmfLobe& l = lobes[size_t(pick(rng))];
        n = sampleVmf(l.mu, l.kappa, rng);
    }
    return normals;
}

inline VmfLobe lobe(float alpha, glm::vec3 mu, float kappa) {
    return VmfLobe{alpha, mu, kappa, glm::vec3(0.f)};
}

// A 23 x 13 map (odd sizes: footprints of 2 and 3 texels) of normals drawn from vMF lobes whose
// centres turn across the map.
inline Image oddClusteredMap(uint64_t seed) {
    Image map(23, 13, 3);
    std::mt19937_64 rng(seed);
    for (int y = 0; y < map.height; ++y)
        for (int x = 0; x < map.width; ++x) {
            glm::vec3 n = sampleVmf(direction(20, (x / 3) * 70.0 + y * 5), 80, rng);
            test::setNormal(map, x, y, n.x, n.y, n.z);
        }
    return map;
}

} // namespace ndfmip::vmftest
