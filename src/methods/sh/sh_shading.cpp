// Shading from spherical-harmonic NDF coefficients (Han et al. eq. 17; see method_shading.h).
#include <cmath>

#include "ndfmip/brdf.h"
#include "ndfmip/method_shading.h"
#include "ndfmip/sh_brdf.h"
#include "ndfmip/spherical_harmonics.h"
#include "ndfmip/vmf.h"

namespace ndfmip {

Result<ShShading> shShadingFor(const Material& m, int order) {
    if (order < 1 || order > kMaxShOrder)
        return Error{"sh: order " + std::to_string(order) + " is not in 1 .. " + std::to_string(kMaxShOrder)};
    ShShading a;
    a.order = order;
    a.diffuse = lambertCoefficients(order);
    if (m.brdf == Brdf::Lambert) {
        a.specular.assign(order + 1, 0.0);
        return a;
    }
    Result<std::vector<double>> lobe =
        m.brdf == Brdf::Tabulated ? (m.table ? tabulatedCoefficients(*m.table, order)
                                             : Result<std::vector<double>>(Error{"sh: tabulated BRDF without a table"}))
                                  : brdfCoefficients(m.brdf, m.exponent, m.roughness, order);
    if (!lobe) return lobe.error();
    a.specular = std::move(lobe.value());
    return a;
}

namespace {

// Sum over l <= order of A_l Sum_m g_lm Y_lm(w).
double convolve(const float* g, const std::vector<double>& A, int order, glm::vec3 w) {
    double y[shCount(kMaxShOrder)];
    evaluateSh(glm::dvec3(glm::normalize(w)), order, y);
    double sum = 0.0;
    for (int l = 0; l <= order; ++l) {
        double band = 0.0;
        for (int i = shIndex(l, -l); i <= shIndex(l, l); ++i) band += double(g[i]) * y[i];
        sum += A[l] * band;
    }
    return sum;
}

} // namespace

float shLobe(const float* g, const ShShading& a, glm::vec3 h) {
    return float(std::max(0.0, convolve(g, a.specular, a.order, h)));
}

glm::vec3 shadeSh(const Material& m, glm::vec3 albedo, const float* g, const ShShading& a, glm::vec3 l,
                  glm::vec3 v) {
    glm::vec3 out(0.f);
    if (albedo != glm::vec3(0.f))
        out += albedo * float(std::max(0.0, convolve(g, a.diffuse, a.order, l)));
    if (m.brdf != Brdf::Lambert && m.specular != glm::vec3(0.f)) {
        const float c = std::sqrt(3.f / (4.f * kPi));
        const glm::vec3 na = glm::vec3(g[shIndex(1, 1)], g[shIndex(1, -1)], g[shIndex(1, 0)]) / c;
        const float length = glm::length(na);
        const glm::vec3 h = glm::normalize(l + v);
        const glm::vec3 mu = length > 0.f ? na / length : glm::vec3(0.f, 0.f, 1.f);
        const float kappa = float(kappaFromMeanLength(length, 1e30));
        const float cosL = specularCosine(mu, kappa, lobeConcentration(m), h, l);
        if (cosL > 0.f)
            out += m.specular * (cosL * specularFactor(m, l, h) *
                                 shLobe(g, a, h));
    }
    return out;
}

} // namespace ndfmip
