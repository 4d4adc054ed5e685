// ndfmip shading library: the per-texel factors of the split sum under an environment (needs
// brdf.glsl and vmf.glsl), one source for the CPU renderer (src/env/splitsum_shading.cpp, through
// glsl.h) and the GPU renderer's environment.glsl: which perceptual roughness a lobe reads the
// prefiltered chain and the albedo table at (and, for a widened lobe, at which view), the mean
// square of n.v over a texel's normals, and the SH bands' mean over a vMF's normals.

// The Toksvig variance scale of the ours roughness mapping, alpha'^2 = alpha^2 + c sigma^2
// (roughness.h's kVarianceScale, which glsl.h checks against it).
#define NDFMIP_VARIANCE_SCALE 2.0f

// The perceptual roughness at which a lobe reads the chains: sqrt(alpha), Blinn-Phong through
// alpha^2 = 2/(s + 2) (Walter et al.), so that its GGX-prefiltered level and its albedo table
// row agree with the lobe near its peak.
float ndfmipBlinnPhongPerceptual(float s) { return sqrt(sqrt(2.0f / (max(s, 0.0f) + 2.0f))); }
float ndfmipAlphaPerceptual(float alpha) { return sqrt(clamp(alpha, 0.0f, 1.0f)); }
bool ndfmipHasLobe(NdfmipMaterial m) {
    return m.brdf == NDFMIP_BLINN_PHONG || m.brdf == NDFMIP_BECKMANN || m.brdf == NDFMIP_GGX;
}

// The material's own perceptual roughness (a Blinn-Phong exponent's through Walter et al.).
float ndfmipBasePerceptual(NdfmipMaterial m) {
    return m.brdf == NDFMIP_BLINN_PHONG ? ndfmipBlinnPhongPerceptual(m.exponent) : ndfmipAlphaPerceptual(m.roughness);
}

// The level a widened lobe's radiance is read at, seen at n.v = mu: perceptual roughness r (the
// material's lobe, albedoR, widened by the normals' spread) with the spread's share of alpha^2
// scaled by mu. A spread of normals reflects into a spread of directions twice as wide in the
// plane of incidence but 2 mu as wide across it (dr = 2 (dn.v) n + 2 mu dn), and the
// prefiltered levels hold round lobes: scaled by mu the level's lobe covers the solid angle of the
// stretched one (the geometric mean of its two variances, 4 sigma^2 mu). Read at the full
// widening, a plane seen from 30 degrees was 12-36% too bright under studio with Toksvig's
// roughness, its widened lobes reaching lamps its normals do not (docs/RESULTS.md). The material's
// own lobe is stretched alike; its level is every engine's convention and stays as it is.
float ndfmipGrazingRoughness(float r, float albedoR, float mu) {
    float base = albedoR * albedoR, widened = r * r; // alphas
    if (!(widened > base)) return r;
    float a2 = base * base + (widened * widened - base * base) * clamp(mu, 0.0f, 1.0f);
    return sqrt(sqrt(a2));
}

vec3 ndfmipUnitOrFlat(vec3 v) {
    float len = length(v);
    return len > 0.0f ? v / len : vec3(0.0f, 0.0f, 1.0f);
}

// The mean square of n.v over a texel's normals, read as a vMF of mean length r about the unit
// mean direction m, mu = m.v: E[(n.v)^2] = E[cos^2 t] mu^2 + E[sin^2 t] (1 - mu^2)/2 (t the
// angle to m, the spread even about m), with a vMF's E[sin^2 t] = 2 A(kappa)/kappa, A = r and
// kappa by Banerjee's approximation: 2 (1 - r^2)/(3 - r^2), about 2 (1 - r) near r = 1 (twice
// T eq. 1's sigma^2) and 2/3 (normals over the whole sphere) at r = 0. With their mean r mu it
// gives the two moments the albedo factor's mean over the normals is taken from
// (ndfmipSpreadAlbedo). One normal (r >= 1): mu^2, mu clamped to [0, 1].
float ndfmipMeanSquareCosine(float mu, float r) {
    mu = clamp(mu, 0.0f, 1.0f);
    if (r >= 1.0f) return mu * mu;
    r = clamp(r, 0.0f, 1.0f);
    float sin2 = 2.0f * (1.0f - r * r) / (3.0f - r * r);
    return max(mu * mu * (1.0f - sin2) + 0.5f * sin2 * (1.0f - mu * mu), 0.0f);
}

// The mean length |Na| whose Toksvig variance widens alpha to `widened` under the ours mapping:
// T eq. 1 inverted, 1/(1 + sigma^2), sigma^2 = (widened^2 - alpha^2)/c; 1 where the stored
// roughness is not wider than the material's.
float ndfmipLengthFromRoughness(float widened, float alpha) {
    return 1.0f / (1.0f + max(widened * widened - alpha * alpha, 0.0f) / NDFMIP_VARIANCE_SCALE);
}

// The mean of the SH bands 1 and 2 over normals drawn from a vMF of concentration kappa,
// relative to their value at its mean direction: the Legendre moments E[P_l(cos t)], 1,
// A(kappa) and 1 - 3 A(kappa)/kappa (Langevin's A); the series where float cancels.
vec3 ndfmipVmfBandFactors(float kappa) {
    if (!(kappa < 1e30f)) return vec3(1.0f);
    if (kappa < 0.05f) return vec3(1.0f, kappa / 3.0f - kappa * kappa * kappa / 45.0f, kappa * kappa / 15.0f);
    float a = ndfmipLangevin(kappa);
    return vec3(1.0f, a, 1.0f - 3.0f * a / kappa);
}
