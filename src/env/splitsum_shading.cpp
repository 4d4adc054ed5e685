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

// The split sum's per-texel factors, from the shading library (splitsum.glsl), which the GPU
// renderer's environment.glsl calls too.
static_assert(kVarianceScale == NDFMIP_VARIANCE_SCALE, "splitsum.glsl's variance scale");
bool hasLobe(const Material& m) {
    return glsl().ndfmipHasLobe(glslMaterial(m));
}
float blinnPhongPerceptual(float exponent) {
    return glsl().ndfmipBlinnPhongPerceptual(exponent);
}
float alphaPerceptual(float alpha) {
    return glsl().ndfmipAlphaPerceptual(alpha);
}
float basePerceptual(const Material& m) {
    return glsl().ndfmipBasePerceptual(glslMaterial(m));
}
float rmsCosine(float mu, float r) {
    return glsl().ndfmipRmsCosine(mu, r);
}
float lengthFromRoughness(float widened, float alpha) {
    return glsl().ndfmipLengthFromRoughness(widened, alpha);
}
glm::vec3 unitOrFlat(glm::vec3 v) {
    return glsl().ndfmipUnitOrFlat(v);
}
glm::dvec3 vmfBandFactors(float kappa) {
    return glm::dvec3(glsl().ndfmipVmfBandFactors(kappa));
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

glm::vec3 diffuseTerm(glm::vec3 albedo, glm::vec3 n, const glm::mat3& tangentToEnvironment,
                      const SplitSumLighting& lighting, glm::dvec3 band = glm::dvec3(1.)) {
    return albedo * (1.f / kPi) *
           irradianceAt(lighting, glm::dvec3(tangentToEnvironment * n), band);
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
                                : alphaPerceptual(glsl().ndfmipVmfWidenedAlpha(m.roughness, kappa));
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
