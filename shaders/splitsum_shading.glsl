// ndfmip shading library: each method under an environment the split-sum way (Karis 2013;
// environment_splitsum.h), one source for the CPU renderer (src/env/splitsum_shading.cpp, through
// glsl.h) and the GPU renderer (after render/environment.glsl). Needs brdf.glsl, toksvig.glsl,
// vmf.glsl and splitsum.glsl, and the lighting's lookups, which each side defines on its own data
// (the CPU's prepared chains, the GPU's textures):
//   vec3 ndfmipPrefilteredRadiance(vec3 reflected, float r, float normalVariance)
//       the rule's chain along `reflected` (environment frame) at perceptual roughness r, or for
//       log2sigma at the spread of r's lobe widened by normalVariance
//   float ndfmipSpecularAlbedo(NdfmipMaterial m, float mu, float r)
//       the split sum's second factor at n.v = mu and perceptual roughness r
//   vec2 ndfmipSpecularAlbedoAndSlope(NdfmipMaterial m, float mu, float r)
//       that factor and its slope in n.v, from one lookup (the table's cell)
//   float ndfmipDominantShare(NdfmipMaterial m, float mu, float r)
//       the share of the normal in the lobe's dominant direction at n.v = mu and perceptual
//       roughness r (lobeDominantShare; 0 reads along the reflection)
//   vec3 ndfmipIrradiance(vec3 n, vec3 band)
//       the irradiance about n (environment frame), SH band l scaled by band[l]
//   int ndfmipEnvRule          0 log2sigma, 1 filament, 2 unity, 3 unreal (EnvironmentLod)
//   int ndfmipEnvBandFactors   1: diffuse about a vMF band-attenuated
//   int ndfmipEnvWeightedReflection  1: a spread texel's radiance about its albedo-weighted
//       reflecting normal (ndfmipWeightedReflectingNormal), 0: about its mean normal
// `toEnv` takes tangent-frame directions (z the geometric normal) to the environment frame: its
// columns are the hit's tangent, bitangent and normal there.

// albedo/pi E(n) about the unit tangent-frame normal n.
vec3 ndfmipEnvDiffuse(mat3 toEnv, vec3 albedo, vec3 n, vec3 band) {
    return albedo * (1.0f / NDFMIP_PI) * ndfmipIrradiance(toEnv * n, band);
}

// The mean of the material's albedo E(n.v, albedoR) over the normals of a vMF of mean length `len`
// about the unit n, seen at n.v = mu: a two-point rule in n.v exact in its mean (len mu) and mean
// square (ndfmipMeanSquareCosine), so exact wherever E is quadratic in n.v, as it nearly is over
// [0, 1].
// The nodes are mean -+ the deviation at equal weights; a node past 1 or 0 is put there and the
// other node and the weights moved so both moments still hold (no n.v exceeds 1, and below 0 a
// normal reflects nothing); where no two points in [0, 1] hold them, 0 and 1. One normal: E(mu).
float ndfmipSpreadAlbedo(NdfmipMaterial m, float mu, float len, float albedoR) {
    float mean = clamp(mu, 0.0f, 1.0f) * clamp(len, 0.0f, 1.0f);
    float variance = max(ndfmipMeanSquareCosine(mu, len) - mean * mean, 0.0f);
    if (!(variance > 1e-12f)) return ndfmipSpecularAlbedo(m, mean, albedoR);
    float deviation = sqrt(variance);
    float low = mean - deviation, high = mean + deviation, lowWeight = 0.5f;
    if (variance >= mean * (1.0f - mean)) {
        low = 0.0f;
        high = 1.0f;
        lowWeight = 1.0f - mean;
    } else if (high > 1.0f) {
        high = 1.0f;
        low = mean - variance / (1.0f - mean);
        lowWeight = (1.0f - mean) * (1.0f - mean) / ((1.0f - mean) * (1.0f - mean) + variance);
    } else if (low < 0.0f) {
        low = 0.0f;
        high = mean + variance / mean;
        lowWeight = variance / (mean * mean + variance);
    }
    return lowWeight * ndfmipSpecularAlbedo(m, low, albedoR) + (1.0f - lowWeight) * ndfmipSpecularAlbedo(m, high, albedoR);
}

// Where a spread texel reflects the view on average, weighted as its normals reflect: each normal
// reflects as much as the material's albedo E(n.v) lets it, and E grows with n.v, so the normals
// tilted towards the view (which reflect it higher, towards the zenith) weigh more than those
// tilted away (which reflect it towards the horizon). To first order in the spread the weighted
// mean normal is the unit mean n tilted towards the view, in their plane, by
//   sigma^2 sin(theta_v) E'(n.v) / E(n.v)
// (sigma^2 the spread per axis, (1 - r^2)/(3 - r^2) for a vMF of mean length r by Banerjee's
// kappa), at most to the view itself. Half of it is taken (NDFMIP_ENV_TILT_SCALE, chosen on
// rock and wool seen from 30 degrees): along the whole tilt the widened rows went from 7-8% too
// bright to 5% too dark under venice and from 6-12% too dark to 4-13% too bright under studio;
// with half, within 3% under both (docs/RESULTS.md, "The albedo-weighted reflecting normal").
// One normal (r = 1) or a view along n: no tilt.
#define NDFMIP_ENV_TILT_SCALE 0.5f
vec3 ndfmipWeightedReflectingNormal(NdfmipMaterial m, vec3 n, vec3 view, float len, float albedoR) {
    float mu = clamp(dot(n, view), 0.0f, 1.0f);
    vec3 across = view - mu * n;
    float s = length(across);
    float r = clamp(len, 0.0f, 1.0f);
    if (ndfmipEnvWeightedReflection == 0 || !(s > 1e-4f) || !(r < 1.0f)) return n;
    float sigma2 = (1.0f - r * r) / (3.0f - r * r);
    vec2 e = ndfmipSpecularAlbedoAndSlope(m, mu, albedoR);
    if (!(e.x > 0.0f)) return n;
    float tilt = clamp(NDFMIP_ENV_TILT_SCALE * sigma2 * s * e.y / e.x, 0.0f, atan(s, mu));
    return normalize(cos(tilt) * n + sin(tilt) * (across / s));
}

// The specular term about the unit tangent-frame normal n: m.specular LD(reflect(-v, n), r) times
// the albedo factor. The albedo factor is the mean of the texel's own lobes, not the widened
// lobe's: every normal a filtered texel covers carries the material's lobe (perceptual roughness
// albedoR), so it is the mean of the material's albedo over the normals' n.v, those of a vMF of
// mean length `len` about n (ndfmipSpreadAlbedo). The widened lobe's own albedo at n.v of the mean
// normal lost 13-15% of the truth's energy at large footprints (docs/RESULTS.md): a wide lobe about
// the mean normal loses what falls below its horizon, the texel's narrow lobes do not. Read at the
// root mean square of n.v (exact only for an albedo growing as (n.v)^2), a texel seen 75 degrees
// off its normal read 11.6% too much under a constant environment: the albedo has a linear part,
// whose mean is at the mean n.v. The widened roughness r only blurs the radiance, LD.
// The radiance is read along the lobe's dominant direction: its centroid, which at grazing views
// leaves the mirror direction towards n, where the lobe's cosine weighs its directions and its
// part below the horizon is cut (a plane seen from 22 degrees read its sky 21% too bright under
// venice along the mirror direction, docs/RESULTS.md). The bend is the material's own lobe's, as
// the albedo factor is: each normal of the texel bends its own narrow lobe, and their spread
// blurs about the mean normal rather than bending (with the widened roughness's bend the spread
// texels lost up to 5% more energy under studio, vmf at footprint 64). The radiance's level is
// the widened lobe's as seen at n.v (ndfmipGrazingRoughness; log2sigma: the normals' variance
// scaled the same way).
// One normal (len 1, r = albedoR): the plain split sum.
vec3 ndfmipEnvSpecular(NdfmipMaterial m, mat3 toEnv, vec3 n, vec3 view, float r, float albedoR, float len,
                       float normalVariance) {
    float mu = dot(n, view);
    vec3 weighted = ndfmipWeightedReflectingNormal(m, n, view, len, albedoR);
    float muW = dot(weighted, view);
    vec3 reflected = 2.0f * muW * weighted - view;
    reflected = normalize(mix(reflected, weighted, ndfmipDominantShare(m, muW, albedoR)));
    vec3 ld = ndfmipPrefilteredRadiance(toEnv * reflected, ndfmipGrazingRoughness(r, albedoR, mu),
                                        normalVariance * clamp(mu, 0.0f, 1.0f));
    return m.specular * ld * ndfmipSpreadAlbedo(m, mu, len, albedoR);
}

// Standard mipmap: the filtered normal renormalised, the material's own roughness.
vec3 ndfmipShadeNaiveEnvironment(NdfmipMaterial m, vec3 albedo, vec3 filtered, mat3 toEnv, vec3 view) {
    vec3 n = ndfmipUnitOrFlat(filtered);
    vec3 out3 = ndfmipEnvDiffuse(toEnv, albedo, n, vec3(1.0f));
    if (!ndfmipHasLobe(m)) return out3;
    float r = ndfmipBasePerceptual(m);
    return out3 + ndfmipEnvSpecular(m, toEnv, n, view, r, r, 1.0f, 0.0f);
}

// Roughness mips: the radiance at the stored roughness (perceptual, alpha = stored^2, unless
// isAlpha, as ndfmipShadeRoughnessMips), the albedo factor at the material's over the spread that
// widened it (ndfmipLengthFromRoughness, the ours mapping). Blinn-Phong keeps its exponent: the
// naive shading.
vec3 ndfmipShadeRoughnessMipsEnvironment(NdfmipMaterial m, vec3 albedo, vec3 filtered, float stored, bool isAlpha,
                                         mat3 toEnv, vec3 view) {
    if (!ndfmipHasLobe(m) || m.brdf == NDFMIP_BLINN_PHONG) return ndfmipShadeNaiveEnvironment(m, albedo, filtered, toEnv, view);
    vec3 n = ndfmipUnitOrFlat(filtered);
    vec3 out3 = ndfmipEnvDiffuse(toEnv, albedo, n, vec3(1.0f));
    float base = ndfmipBasePerceptual(m);
    float s = clamp(stored, 0.0f, 1.0f);
    float alpha = max(isAlpha ? s : s * s, 1e-4f);
    float len = ndfmipLengthFromRoughness(alpha, m.roughness);
    return out3 + ndfmipEnvSpecular(m, toEnv, n, view, ndfmipAlphaPerceptual(alpha), base, len, 0.0f);
}

// Toksvig: diffuse about Na/|Na|, irradiance being linear in n in band 1, whose mean over the
// normals is exactly its value at Na (band 1 scaled by |Na|), band 2 as a vMF of that mean length;
// the radiance of the lobe widened as ndfmipShadeToksvig (T eq. 6 or the roughness mapping), or
// for log2sigma the material's spread plus the normals' sigma^2 = (1 - |Na|)/|Na| (T eq. 1), which
// for Blinn-Phong is T eq. 5's 1/s' = 1/s + sigma^2 and for Beckmann/GGX the ours mapping with
// c = 2; the albedo factor the material's over normals of mean length |Na|.
vec3 ndfmipShadeToksvigEnvironment(NdfmipMaterial m, vec3 albedo, vec3 na, mat3 toEnv, vec3 view, int mapping,
                                   float varianceScale) {
    float len = min(length(na), 1.0f);
    vec3 n = ndfmipUnitOrFlat(na);
    vec3 band = vec3(1.0f);
    if (ndfmipEnvBandFactors != 0 && len < 1.0f) band = ndfmipVmfBandFactors(ndfmipToksvigKappa(len));
    if (ndfmipEnvBandFactors != 0) band.y = len;
    vec3 out3 = ndfmipEnvDiffuse(toEnv, albedo, n, band);
    if (!ndfmipHasLobe(m)) return out3;
    float r = m.brdf == NDFMIP_BLINN_PHONG
                  ? ndfmipBlinnPhongPerceptual(ndfmipToksvigFactor(len, m.exponent) * m.exponent)
                  : ndfmipAlphaPerceptual(ndfmipMappedRoughness(mapping, len, m.roughness, varianceScale));
    float base = ndfmipBasePerceptual(m);
    if (ndfmipEnvRule != 0) return out3 + ndfmipEnvSpecular(m, toEnv, n, view, r, base, len, 0.0f);
    return out3 + ndfmipEnvSpecular(m, toEnv, n, view, base, base, len, len > 0.0f ? ndfmipToksvigSigma2(len) : 1e6f);
}

// One vMF lobe, its weight included: diffuse at mu, band-attenuated by the vMF (its Legendre
// moments A(kappa), 1 - 3 A(kappa)/kappa); specular along the reflection about mu at the widened
// lobe's roughness (H eqs. 29-30, as ndfmipVmfWidenedAlpha), the albedo factor at the material's
// roughness over the lobe's normals, whose mean length is A(kappa).
vec3 ndfmipShadeVmfLobeEnvironment(NdfmipMaterial m, vec3 albedo, vec4 lobeTexel, mat3 toEnv, vec3 view) {
    NdfmipLobe lobe = ndfmipUnpackLobe(lobeTexel);
    if (!(lobe.alpha > 0.0f)) return vec3(0.0f);
    vec3 band = ndfmipEnvBandFactors != 0 ? ndfmipVmfBandFactors(lobe.kappa) : vec3(1.0f);
    vec3 term = ndfmipEnvDiffuse(toEnv, albedo, lobe.mu, band);
    if (ndfmipHasLobe(m)) {
        float kappa = max(lobe.kappa, 1e-6f);
        float r = m.brdf == NDFMIP_BLINN_PHONG
                      ? ndfmipBlinnPhongPerceptual(kappa * m.exponent / (kappa + m.exponent))
                      : ndfmipAlphaPerceptual(ndfmipVmfWidenedAlpha(m.roughness, kappa));
        term += ndfmipEnvSpecular(m, toEnv, lobe.mu, view, r, ndfmipBasePerceptual(m), ndfmipVmfBandFactors(kappa).y,
                                  0.0f);
    }
    return lobe.alpha * term;
}
