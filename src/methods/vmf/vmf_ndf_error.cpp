// The smoothed-NDF distance between normals and vMF lobes (see smoothedNdfError in vmf.h).
#include <cmath>

#include "ndfmip/vmf.h"

namespace ndfmip {
namespace {

// Integral over the sphere of gamma(w; mu1, k1) gamma(w; mu2, k2).
double productIntegral(glm::dvec3 mu1, double k1, glm::dvec3 mu2, double k2) {
    const double k3 = glm::length(k1 * mu1 + k2 * mu2);
    return std::exp(vmfLogNormalizer(k1) + vmfLogNormalizer(k2) - vmfLogNormalizer(k3));
}

double seenThrough(double kappa, double s) {
    return kappa > 0 ? kappa * s / (kappa + s) : 0.0;
}

} // namespace

double smoothedNdfError(const glm::vec3* normals, size_t count, std::span<const VmfLobe> lobes,
                        double s) {
    if (count == 0) return 0;
    std::vector<glm::dvec3> n(count);
    for (size_t i = 0; i < count; ++i) n[i] = glm::normalize(glm::dvec3(normals[i]));
    double data = 0; // Integral f_s^2
    for (size_t i = 0; i < count; ++i) {
        double row = 0.5 * productIntegral(n[i], s, n[i], s);
        for (size_t k = i + 1; k < count; ++k) row += productIntegral(n[i], s, n[k], s);
        data += 2 * row;
    }
    data /= double(count) * double(count);
    double cross = 0, fit = 0; // Integral f_s g_s, Integral g_s^2
    for (const VmfLobe& a : lobes) {
        if (!(a.alpha > 0)) continue;
        const glm::dvec3 mu = glm::normalize(glm::dvec3(a.mu));
        const double ka = seenThrough(a.kappa, s);
        double sum = 0;
        for (size_t i = 0; i < count; ++i) sum += productIntegral(n[i], s, mu, ka);
        cross += a.alpha * sum / double(count);
        for (const VmfLobe& b : lobes)
            if (b.alpha > 0)
                fit += double(a.alpha) * b.alpha *
                       productIntegral(mu, ka, glm::normalize(glm::dvec3(b.mu)),
                                       seenThrough(b.kappa, s));
    }
    return std::sqrt(std::max(data - 2 * cross + fit, 0.0) / data);
}

} // namespace ndfmip
