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
        return Error{"sh: order " + std::to_string(order) + " is not in 1 .. " +
                     std::to_string(kMaxShOrder)};
    ShShading a;
    a.order = order;
    a.diffuse = lambertCoefficients(order);
    if (m.brdf == Brdf::Lambert) {
        a.specular.assign(order + 1, 0.0);
        return a;
    }
    Result<std::vector<double>> lobe =
        m.brdf == Brdf::Tabulated
            ? (m.table ? tabulatedCoefficients(*m.table, order)
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

glm::vec3 shadeSh(const Material& m, glm::vec3 albedo, const float* g, const ShShading& a,
                  glm::vec3 l, glm::vec3 v) {
    // The convolutions in double to any order (the GPU's ndfmipShConvolve: float, order <= 10),
    // H eq. 17 from them by the GLSL.
    const glm::vec3 h = glm::normalize(l + v);
    const float diffuse = float(convolve(g, a.diffuse, a.order, l));
    const float specular =
        m.brdf == Brdf::Lambert ? 0.f : float(convolve(g, a.specular, a.order, h));
    const glm::vec3 na =
        glsl().ndfmipShMeanNormal(g[shIndex(1, -1)], g[shIndex(1, 0)], g[shIndex(1, 1)]);
    return glsl().ndfmipShadeShSums(glslMaterial(m, specularFactor(m, l, h)), albedo, diffuse,
                                    specular, na, l, v);
}

} // namespace ndfmip
