// Each method's shade function: what a pixel shader does with the method's parameters after
// trilinear filtering, in the tangent frame (l, v unit, z = geometric normal). Returns the
// reflected radiance per unit irradiance, like shadeNormal (brdf.h) does for one true normal,
// so that a filtered pixel can be compared with the mean of shadeNormal over its normals.
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include "ndfmip/brdf.h"
#include "ndfmip/image.h"
#include "ndfmip/result.h"
#include "ndfmip/roughness.h"
#include "ndfmip/toksvig.h"

namespace ndfmip {

// Standard mipmap: the filtered normal renormalised, the material unchanged.
// `albedo`, in every shade function below, is the material's albedo times the filtered albedo
// map (or the material's alone).
inline glm::vec3 shadeNaive(const Material& m, glm::vec3 albedo, glm::vec3 filtered, glm::vec3 l,
                            glm::vec3 v) {
    const glm::vec3 h = glm::normalize(l + v);
    if (m.brdf != Brdf::Tabulated)
        return glsl().ndfmipShadeNaive(glslMaterial(m, specularFactor(m, l, h)), albedo, filtered,
                                       l, v);
    const float length = glm::length(filtered);
    return shadeNormal(m, albedo, length > 0.f ? filtered / length : glm::vec3(0.f, 0.f, 1.f), l,
                       h);
}

inline glm::vec3 shadeNaive(const Material& m, glm::vec3 filtered, glm::vec3 l, glm::vec3 v) {
    return shadeNaive(m, m.albedo, filtered, l, v);
}

// An engine's normal mipmap with a roughness mip chain (kRoughnessMips in render.h): the
// filtered normal renormalised, the material's Beckmann or GGX lobe at the filtered roughness
// `stored` (perceptual, alpha = stored^2, unless `isAlpha`).
inline glm::vec3 shadeRoughnessMipsTexel(const Material& m, glm::vec3 albedo, glm::vec3 filtered,
                                         float stored, bool isAlpha, glm::vec3 l, glm::vec3 v) {
    const float factor = specularFactor(m, l, glm::normalize(l + v));
    return glsl().ndfmipShadeRoughnessMips(glslMaterial(m, factor), albedo, filtered, stored,
                                           isAlpha, l, v);
}

// The material's lobe as a function of n about h, read as a vMF concentration: Blinn-Phong
// (n.h)^s ~ exp(s (n.h - 1)), so s; Beckmann and GGX through Walter et al.'s s = 2/alpha^2 - 2;
// 0 where no width is known (tabulated lobes, Lambert).
inline float lobeConcentration(const Material& m) {
    return glsl().ndfmipLobeConcentration(glslMaterial(m));
}

// The cosine of a filtered specular term. The truth averages lobe(n.h) (n.l) over the normals;
// where the NDF is a lobe of concentration kappa about mu, NDF x lobe is (as vMFs) a vMF with
// natural parameter w = kappa mu + lobeKappa h, whose mean normal is A(|w|) w/|w| (Langevin's
// A, H eq. 23): the normals that reflect, on average. Its dot with l is the mean n.l, so the
// cosine is max(A(|w|) l.w/|w|, 0): mu.l for a sharp NDF, h.l for a sharp lobe. kappa may be
// infinite (a single normal).
inline float specularCosine(glm::vec3 mu, float kappa, float lobeKappa, glm::vec3 h, glm::vec3 l) {
    return glsl().ndfmipSpecularCosine(mu, kappa, lobeKappa, h, l);
}

// Toksvig: Na is kept unnormalised. Its length widens the specular lobe (Blinn-Phong: the
// exponent times the Toksvig factor, T eq. 6; Beckmann/GGX: alpha from the roughness mapping).
// The diffuse cosine is Na.l, the exact mean of the covered normals' cosines where none of them
// faces away from the light (Lambertian reflection is linear in n); the specular cosine is
// specularCosine with the NDF read as a vMF of kappa = 1/sigma^2 = |Na|/(1 - |Na|) (T eq. 1).
inline glm::vec3 shadeToksvigLobe(const Material& m, glm::vec3 albedo, glm::vec3 na, glm::vec3 l,
                                  glm::vec3 v, float lobe) {
    const glm::vec3 h = glm::normalize(l + v);
    return glsl().ndfmipShadeToksvigLobe(glslMaterial(m, specularFactor(m, l, h)), albedo, na, l, v,
                                         lobe);
}

// Toksvig's lobe alone (no cosine) about Na/|Na|, widened by |Na|.
inline float toksvigLobe(const Material& m, glm::vec3 na, glm::vec3 h, RoughnessMapping mapping,
                         float varianceScale = kVarianceScale) {
    if (m.brdf != Brdf::Tabulated)
        return glsl().ndfmipToksvigLobe(glslMaterial(m), na, h, int(mapping), varianceScale);
    const float length = glm::length(na); // a table has no widening rule: read about Na/|Na|
    return materialLobe(m, length > 0.f ? glm::dot(na, h) / length : 0.f, 0.f, 0.f);
}

inline glm::vec3 shadeToksvig(const Material& m, glm::vec3 albedo, glm::vec3 na, glm::vec3 l,
                              glm::vec3 v, RoughnessMapping mapping,
                              float varianceScale = kVarianceScale) {
    const float lobe = toksvigLobe(m, na, glm::normalize(l + v), mapping, varianceScale);
    return shadeToksvigLobe(m, albedo, na, l, v, lobe);
}

inline glm::vec3 shadeToksvig(const Material& m, glm::vec3 na, glm::vec3 l, glm::vec3 v,
                              RoughnessMapping mapping, float varianceScale = kVarianceScale) {
    return shadeToksvig(m, m.albedo, na, l, v, mapping, varianceScale);
}

// Toksvig through his lookup table (T eq. 9; kToksvigLut in render.h): `lut` is toksvigLut(...)
// of the material's exponent, read bilinearly at (Na.H, Na.Na) with clamped edges, and turned
// from relative to absolute by the unfiltered lobe's peak (s + 1)/(2 pi). Cosines as
// shadeToksvig. Blinn-Phong materials only.
glm::vec3 shadeToksvigLut(const Material& m, glm::vec3 albedo, glm::vec3 na, const Image& lut,
                          glm::vec3 l, glm::vec3 v);
float toksvigLutLobe(const Material& m, glm::vec3 na, const Image& lut,
                     glm::vec3 h); // the lobe alone

// Spherical harmonics (Han et al. eq. 17): the BRDF's A_l, fixed per material and order.
struct ShShading {
    int order = 0;
    std::vector<double> specular; // A_l of the material's lobe, over the half vector
    std::vector<double> diffuse;  // A_l of the clamped cosine / pi, over the light direction
};

// A_l for l <= order (sh_brdf.h); errors for parameters out of range.
Result<ShShading> shShadingFor(const Material& m, int order);

// r_eff(w) = Sum A_l g_lm Y_lm(w) with w = h for the lobe and w = l for the diffuse term, which
// thereby carries its own cosine; the lobe's cosine comes from the mipmapped normal
// Na = (g_11, g_1-1, g_10) / sqrt(3 / 4 pi) (footnote 5), as specularCosine with the NDF read
// as a vMF of Banerjee's kappa for |Na|. Truncation can ring below zero; each term is clamped
// at 0. `g` holds shCount(order) coefficients.
glm::vec3 shadeSh(const Material& m, glm::vec3 albedo, const float* g, const ShShading& a,
                  glm::vec3 l, glm::vec3 v);
float shLobe(const float* g, const ShShading& a,
             glm::vec3 h); // the lobe alone, Sum A_l g_lm Y_lm(h) >= 0

// LEAN (Olano and Baker 2010): `p` holds the filtered slope moments (E[bx], E[by], E[bx^2],
// E[by^2], E[bx by]) of the lean bake; their covariance plus the material's slope variance
// (Beckmann alpha^2/2 per axis; Blinn-Phong through alpha^2 = 2/(s + 2); GGX as Beckmann) is a
// 2D Gaussian of slopes, the anisotropic Beckmann lobe exp(-d^T S^-1 d / 2) / (2 pi sqrt|S|
// h.z^4) with d = h.xy/h.z - E[b]. Cosines about the mean slope's normal, as shadeToksvig.
glm::vec3 shadeLean(const Material& m, glm::vec3 albedo, const float* p, glm::vec3 l, glm::vec3 v);
float leanLobe(const Material& m, const float* p, glm::vec3 h); // its lobe alone, no cosine

// sggx on the lean bake's planes: one anisotropic GGX lobe whose squared-roughness tensor is the
// material's alpha^2 plus twice the slopes' covariance (shaders/sggx.glsl).
glm::vec3 shadeSggx(const Material& m, glm::vec3 albedo, const float* p, glm::vec3 l, glm::vec3 v);
float sggxLobe(const Material& m, const float* p, glm::vec3 h); // its lobe alone, no cosine

// vMF mixture (Han et al. Sec. 7.2): `lobes` holds J filtered (alpha, alpha r mu) quadruples
// (H eq. 33); each lobe's mu and kappa come back by Algorithm 1 lines 12-13. Per lobe:
//   Blinn-Phong    s' = kappa s / (kappa + s), (s' + 1)/(2 pi) (h.mu)^s'          (H eq. 29)
//   Beckmann       alpha'^2 = alpha^2 + 2/kappa: Torrance-Sparrow's sigma'^2 = sigma^2 + 1/(2
//   kappa)
//                  (H eq. 30) with sigma^2 = alpha^2/4 (the same per-axis spread)
//   GGX            the same alpha' (an equivalent-roughness mapping; its error is measured)
//   tabulated      the table about mu, unwidened
//   diffuse        the Blinn-Phong rule with s = 1 and w = l, which carries the cosine (footnote 9)
// summed with weights alpha_j; each lobe's specular cosine is specularCosine(mu_j, kappa_j, ...).
// `colors`, when not null, holds J lobe colours (H eq. 31) that
// multiply the material's albedo in place of `albedo`.
glm::vec3 shadeVmf(const Material& m, glm::vec3 albedo, const float* lobes, int count,
                   const glm::vec3* colors, glm::vec3 l, glm::vec3 v);
float vmfLobe(const Material& m, const float* lobes, int count,
              glm::vec3 h); // Sum alpha_j lobe_j, no cosine

} // namespace ndfmip
