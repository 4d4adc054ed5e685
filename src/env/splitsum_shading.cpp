// Each method's split-sum shading (environment_splitsum.h): what an engine's pixel shader does
// with the method's filtered parameters under a prefiltered environment.
#include <algorithm>
#include <cmath>

#include "ndfmip/environment_splitsum.h"
#include "ndfmip/glsl.h"
#include "ndfmip/shading.h"
#include "ndfmip/toksvig.h"

namespace ndfmip {

namespace {

bool hasLobe(const Material& m) {
    return m.brdf == Brdf::BlinnPhong || m.brdf == Brdf::Beckmann || m.brdf == Brdf::Ggx;
}

// The perceptual roughness at which a lobe reads the chains: sqrt(alpha), Blinn-Phong through
// alpha^2 = 2/(s + 2) (Walter et al.), so that its GGX-prefiltered level and its albedo table row
// agree with the lobe near its peak.
float blinnPhongPerceptual(float exponent) {
    return float(std::sqrt(blinnPhongAlpha(exponent)));
}
float alphaPerceptual(float alpha) {
    return std::sqrt(std::clamp(alpha, 0.f, 1.f));
}

// The root mean square of n.v over a texel's normals, read as a vMF of mean length r about the
// unit mean direction m, mu = m.v: E[(n.v)^2] = E[cos^2 t] mu^2 + E[sin^2 t] (1 - mu^2)/2 (t the
// angle to m, the spread even about m), with a vMF's E[sin^2 t] = 2 A(kappa)/kappa, A = r and
// kappa by Banerjee's approximation (vmfKappaFromLength): 2 (1 - r^2)/(3 - r^2), about 2 (1 - r)
// near r = 1 (twice T eq. 1's sigma^2) and 2/3 (normals over the whole sphere) at r = 0. A lobe's
// albedo grows as (n.v)^2 (4 (n.v)^2 when sharp), so one albedo read here stands for the mean of
// the texel's own. One normal (r >= 1): mu itself, clamped to [0, 1].
float rmsCosine(float mu, float r) {
    mu = std::clamp(mu, 0.f, 1.f);
    if (r >= 1.f) return mu;
    r = std::clamp(r, 0.f, 1.f);
    const float sin2 = 2.f * (1.f - r * r) / (3.f - r * r);
    return std::sqrt(std::max(mu * mu * (1.f - sin2) + 0.5f * sin2 * (1.f - mu * mu), 0.f));
}

// The mean length |Na| whose Toksvig variance widens alpha to `widened` under the ours mapping
// (roughness.h, c = kVarianceScale): T eq. 1 inverted, 1/(1 + sigma^2), sigma^2 = (widened^2 -
// alpha^2)/c; 1 where the stored roughness is not wider than the material's.
float lengthFromRoughness(float widened, float alpha) {
    return 1.f / (1.f + std::max(widened * widened - alpha * alpha, 0.f) / kVarianceScale);
}

// A unit normal n (tangent frame), seen from v: the specular term of a lobe of perceptual
// roughness r about n, m.specular x LD(reflect(-v, n), r) x E(mu, base). The albedo factor is
// the mean of the texel's own lobes, not the widened lobe's: every normal a filtered texel covers
// carries the material's lobe (perceptual roughness `base`), whose albedo grows as (n.v)^2, so it
// is read at the material's roughness and the root mean square of n.v over the normals, a vMF of
// mean length `length` about n (rmsCosine). The widened lobe's own albedo at n.v of the
// mean normal lost 13-15% of the truth's energy at large footprints (docs/RESULTS.md): a wide
// lobe about the mean normal loses what falls below its horizon, the texel's narrow lobes do not.
// The widened roughness r only blurs the radiance, LD. One normal (length 1, r = base): the plain
// split sum.
glm::vec3 specularTerm(const Material& m, glm::vec3 n, glm::vec3 view,
                       const glm::mat3& tangentToEnvironment, const SplitSumLighting& lighting,
                       EnvironmentLod rule, float r, float base, float length = 1.f,
                       double normalVariance = 0.) {
    const float mu = glm::dot(n, view);
    const glm::vec3 reflected = 2.f * mu * n - view;
    const glm::vec3 ld = prefilteredRadiance(
        lighting, rule, glm::dvec3(tangentToEnvironment * reflected), r, normalVariance);
    return m.specular * ld * specularAlbedo(lighting, m.brdf, rmsCosine(mu, length), base);
}

// The material's own perceptual roughness (a Blinn-Phong exponent's through Walter et al.).
float basePerceptual(const Material& m) {
    return m.brdf == Brdf::BlinnPhong ? blinnPhongPerceptual(m.exponent)
                                      : alphaPerceptual(m.roughness);
}

glm::vec3 diffuseTerm(glm::vec3 albedo, glm::vec3 n, const glm::mat3& tangentToEnvironment,
                      const SplitSumLighting& lighting, glm::dvec3 band = glm::dvec3(1.)) {
    return albedo * (1.f / kPi) *
           irradianceAt(lighting, glm::dvec3(tangentToEnvironment * n), band);
}

glm::vec3 unitOrFlat(glm::vec3 v) {
    const float length = glm::length(v);
    return length > 0.f ? v / length : glm::vec3(0.f, 0.f, 1.f);
}

// The mean of the SH bands 1 and 2 over normals drawn from a vMF of concentration kappa, relative
// to their value at its mean direction: the Legendre moments E[P_l(cos t)], A(kappa) and
// 1 - 3 A(kappa)/kappa, A = coth(kappa) - 1/kappa (series below 1e-3, where it cancels).
glm::dvec3 vmfBandFactors(double kappa) {
    if (!(kappa < 1e30)) return glm::dvec3(1.);
    if (kappa < 1e-3) return {1., kappa / 3., kappa * kappa / 15.};
    const double a = (kappa > 20. ? 1. : 1. / std::tanh(kappa)) - 1. / kappa;
    return {1., a, 1. - 3. * a / kappa};
}

} // namespace

glm::vec3 shadeNaiveSplitSum(const Material& m, glm::vec3 albedo, glm::vec3 filtered,
                             glm::vec3 view, const glm::mat3& tangentToEnvironment,
                             const SplitSumLighting& lighting, EnvironmentLod rule) {
    const glm::vec3 n = unitOrFlat(filtered);
    glm::vec3 out = diffuseTerm(albedo, n, tangentToEnvironment, lighting);
    if (!hasLobe(m)) return out;
    const float r = basePerceptual(m);
    return out + specularTerm(m, n, view, tangentToEnvironment, lighting, rule, r, r);
}

glm::vec3 shadeToksvigSplitSum(const Material& m, glm::vec3 albedo, glm::vec3 na, glm::vec3 view,
                               const glm::mat3& tangentToEnvironment,
                               const SplitSumLighting& lighting, EnvironmentLod rule,
                               RoughnessMapping mapping, float varianceScale) {
    const float length = std::min(glm::length(na), 1.f);
    const glm::vec3 n = unitOrFlat(na);
    // Diffuse: irradiance is linear in n in band 1, whose mean over the normals is exactly its
    // value at Na; band 2 as a vMF of the concentration whose mean length is |Na|.
    glm::dvec3 band(1.);
    if (lighting.vmfBandFactors && length < 1.f) band = vmfBandFactors(vmfKappaFromLength(length));
    if (lighting.vmfBandFactors) band.y = length;
    glm::vec3 out = diffuseTerm(albedo, n, tangentToEnvironment, lighting, band);
    if (!hasLobe(m)) return out;

    // The widened lobe exactly as shadeToksvig: s' = ft s (T eq. 6) or the roughness mapping; it
    // blurs the radiance, the albedo factor stays the material's (specularTerm).
    const float r =
        m.brdf == Brdf::BlinnPhong
            ? blinnPhongPerceptual(toksvigFactor(length, m.exponent) * m.exponent)
            : alphaPerceptual(mappedRoughness(mapping, length, m.roughness, varianceScale));
    const float base = basePerceptual(m);
    if (rule != EnvironmentLod::Log2Sigma)
        return out +
               specularTerm(m, n, view, tangentToEnvironment, lighting, rule, r, base, length);
    // Toksvig's own rule: the material's spread plus the normals' sigma^2 = (1 - |Na|)/|Na|
    // (T eq. 1), which for Blinn-Phong is T eq. 5's 1/s' = 1/s + sigma^2 and for Beckmann/GGX the
    // Ours mapping with c = 2.
    return out + specularTerm(m, n, view, tangentToEnvironment, lighting, rule, base, base, length,
                              length > 0.f ? toksvigSigma2(length) : 1e6);
}

glm::vec3 shadeRoughnessMipsSplitSum(const Material& m, glm::vec3 albedo, glm::vec3 filtered,
                                     float stored, bool isAlpha, glm::vec3 view,
                                     const glm::mat3& tangentToEnvironment,
                                     const SplitSumLighting& lighting, EnvironmentLod rule) {
    // Blinn-Phong keeps its exponent: the naive shading.
    if (!hasLobe(m) || m.brdf == Brdf::BlinnPhong)
        return shadeNaiveSplitSum(m, albedo, filtered, view, tangentToEnvironment, lighting, rule);
    const glm::vec3 n = unitOrFlat(filtered);
    const glm::vec3 out = diffuseTerm(albedo, n, tangentToEnvironment, lighting);
    const float s = std::clamp(stored, 0.f, 1.f);
    const float alpha = std::max(isAlpha ? s : s * s, 1e-4f); // as ndfmipShadeRoughnessMips
    // The stored roughness blurs the radiance; the albedo factor is the material's at the normals'
    // spread that widened it, read back through the ours mapping (specularTerm).
    const float length = lengthFromRoughness(alpha, m.roughness);
    return out + specularTerm(m, n, view, tangentToEnvironment, lighting, rule,
                              alphaPerceptual(alpha), basePerceptual(m), length);
}

glm::vec3 shadeVmfSplitSum(const Material& m, glm::vec3 albedo, const float* lobes, int count,
                           const glm::vec3* colors, glm::vec3 view,
                           const glm::mat3& tangentToEnvironment, const SplitSumLighting& lighting,
                           EnvironmentLod rule) {
    glm::vec3 out(0.f);
    for (int j = 0; j < count; ++j) {
        const float* p = lobes + 4 * j;
        const GlslLibrary::NdfmipLobe lobe =
            glsl().ndfmipUnpackLobe(glm::vec4(p[0], p[1], p[2], p[3]));
        if (!(lobe.alpha > 0.f)) continue;
        const glm::vec3 lobeAlbedo = colors ? colors[j] * m.albedo : albedo;
        const glm::dvec3 band =
            lighting.vmfBandFactors ? vmfBandFactors(lobe.kappa) : glm::dvec3(1.);
        glm::vec3 term = diffuseTerm(lobeAlbedo, lobe.mu, tangentToEnvironment, lighting, band);
        if (hasLobe(m)) {
            // H eqs. 29-30 as ndfmipVmfWidenedLobe: the material's lobe convolved with the vMF.
            const float kappa = std::max(lobe.kappa, 1e-6f);
            const float r = m.brdf == Brdf::BlinnPhong
                                ? blinnPhongPerceptual(kappa * m.exponent / (kappa + m.exponent))
                                : alphaPerceptual(std::min(
                                      std::sqrt(m.roughness * m.roughness + 2.f / kappa), 1.f));
            // The albedo factor at the material's roughness over the lobe's normals, whose mean
            // length is A(kappa) (specularTerm).
            term += specularTerm(m, lobe.mu, view, tangentToEnvironment, lighting, rule, r,
                                 basePerceptual(m), float(vmfBandFactors(kappa).y));
        }
        out += lobe.alpha * term;
    }
    return out;
}

} // namespace ndfmip
