// Each method's shade function: what a pixel shader does with the method's parameters after
// trilinear filtering, in the tangent frame (l, v unit, z = geometric normal). Returns the
// reflected radiance per unit irradiance, like shadeNormal (brdf.h) does for one true normal,
// so that a filtered pixel can be compared with the mean of shadeNormal over its normals.
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include "ndfmip/brdf.h"
#include "ndfmip/result.h"
#include "ndfmip/roughness.h"
#include "ndfmip/toksvig.h"

namespace ndfmip {

// Standard mipmap: the filtered normal renormalised, the material unchanged.
// `albedo`, in every shade function below, is the material's albedo times the filtered albedo
// map (or the material's alone).
inline glm::vec3 shadeNaive(const Material& m, glm::vec3 albedo, glm::vec3 filtered, glm::vec3 l, glm::vec3 v) {
    float length = glm::length(filtered);
    glm::vec3 n = length > 0.f ? filtered / length : glm::vec3(0.f, 0.f, 1.f);
    return shadeNormal(m, albedo, n, l, glm::normalize(l + v));
}

inline glm::vec3 shadeNaive(const Material& m, glm::vec3 filtered, glm::vec3 l, glm::vec3 v) {
    return shadeNaive(m, m.albedo, filtered, l, v);
}

// Toksvig: Na is kept unnormalised. Its length widens the specular lobe (Blinn-Phong: the
// exponent times the Toksvig factor, eq. 6; Beckmann/GGX: alpha from the roughness mapping),
// and the cosine is Na.l, the exact mean of the covered normals' cosines where none of them
// faces away from the light (Lambertian reflection is linear in n).
inline glm::vec3 shadeToksvig(const Material& m, glm::vec3 albedo, glm::vec3 na, glm::vec3 l, glm::vec3 v,
                              RoughnessMapping mapping, float varianceScale = kVarianceScale) {
    float cosL = glm::max(glm::dot(na, l), 0.f);
    if (cosL <= 0.f) return glm::vec3(0.f);
    float length = glm::length(na);
    glm::vec3 h = glm::normalize(l + v);
    float cosH = length > 0.f ? glm::dot(na, h) / length : 0.f;
    float lobe = 0.f;
    switch (m.brdf) {
    case Brdf::BlinnPhong:
        lobe = blinnPhong(cosH, toksvigFactor(length, m.exponent) * m.exponent);
        break;
    case Brdf::Beckmann: lobe = beckmannD(cosH, mappedRoughness(mapping, length, m.roughness, varianceScale)); break;
    case Brdf::Ggx: lobe = ggxD(cosH, mappedRoughness(mapping, length, m.roughness, varianceScale)); break;
    case Brdf::Tabulated: lobe = materialLobe(m, cosH, 0.f, 0.f); break; // no widening rule
    case Brdf::Lambert: break;
    }
    lobe *= specularFactor(m, l, h);
    return cosL * (albedo * (1.f / kPi) + m.specular * lobe);
}

inline glm::vec3 shadeToksvig(const Material& m, glm::vec3 na, glm::vec3 l, glm::vec3 v, RoughnessMapping mapping,
                              float varianceScale = kVarianceScale) {
    return shadeToksvig(m, m.albedo, na, l, v, mapping, varianceScale);
}

// Spherical harmonics (Han et al. eq. 17): the BRDF's A_l, fixed per material and order.
struct ShShading {
    int order = 0;
    std::vector<double> specular; // A_l of the material's lobe, over the half vector
    std::vector<double> diffuse;   // A_l of the clamped cosine / pi, over the light direction
};

// A_l for l <= order (sh_brdf.h); errors for parameters out of range.
Result<ShShading> shShadingFor(const Material& m, int order);

// r_eff(w) = Sum A_l g_lm Y_lm(w) with w = h for the lobe and w = l for the diffuse term, which
// thereby carries its own cosine; the lobe's cosine comes from the mipmapped normal
// Na = (g_11, g_1-1, g_10) / sqrt(3 / 4 pi) (footnote 5), as max(Na.l, 0). Truncation can
// ring below zero; each term is clamped at 0. `g` holds shCount(order) coefficients.
glm::vec3 shadeSh(const Material& m, glm::vec3 albedo, const float* g, const ShShading& a, glm::vec3 l,
                  glm::vec3 v);

// vMF mixture (Han et al. Sec. 7.2): `lobes` holds J filtered (alpha, alpha r mu) quadruples
// (eq. 33); each lobe's mu and kappa come back by Algorithm 1 lines 12-13. Per lobe, with the
// cosine to the lobe's centre (footnote 5):
//   Blinn-Phong    s' = kappa s / (kappa + s), (s' + 1)/(2 pi) (h.mu)^s'          (eq. 29)
//   Beckmann       alpha'^2 = alpha^2 + 2/kappa: Torrance-Sparrow's sigma'^2 = sigma^2 + 1/(2 kappa)
//                  (eq. 30) with sigma^2 = alpha^2/4 (the same per-axis spread)
//   GGX            the same alpha' (an equivalent-roughness mapping; its error is measured)
//   tabulated      the table about mu, unwidened
//   diffuse        the Blinn-Phong rule with s = 1 and w = l, which carries the cosine (footnote 9)
// summed with weights alpha_j. `colors`, when not null, holds J lobe colours (eq. 31) that
// multiply the material's albedo in place of `albedo`.
glm::vec3 shadeVmf(const Material& m, glm::vec3 albedo, const float* lobes, int count, const glm::vec3* colors,
                   glm::vec3 l, glm::vec3 v);

} // namespace ndfmip
