// ndfmip shading library: Toksvig, "Mipmapping Normal Maps" (needs brdf.glsl).
//
// Texture: the toksvig bake's "mean" plane (RGB, mipmapped, trilinear): Na, NOT renormalised.

// Roughness mappings from |Na| (ndfmipMappedRoughness).
#define NDFMIP_MAPPING_OURS 0     // alpha'^2 = alpha^2 + c (1 - r)/r
#define NDFMIP_MAPPING_HDRP 1     // alpha'^2 = alpha^2 + 0.5 / kappa
#define NDFMIP_MAPPING_FILAMENT 2 // alpha'^2 = alpha^2 + 2 / kappa
#define NDFMIP_MAPPING_GODOT 3    // p'^2 = p^2 + min(0.75 / kappa, 0.16), p = sqrt(alpha)
#define NDFMIP_MAPPING_UNREAL 4   // (alpha^2 + 2V (1 - alpha^2)) / (1 + 2V (1 - alpha^2)), V = (1 - r)/r

// T eq. 1: sigma^2 = (1 - |Na|)/|Na|.
float ndfmipToksvigSigma2(float r) {
    r = clamp(r, 1e-6f, 1.0f);
    return (1.0f - r) / r;
}

// T eq. 6: the factor that scales the exponent, ft = |Na| / (|Na| + s (1 - |Na|)).
float ndfmipToksvigFactor(float r, float s) {
    r = clamp(r, 0.0f, 1.0f);
    float denominator = r + s * (1.0f - r);
    return denominator > 0.0f ? r / denominator : 1.0f;
}

// The vMF concentration whose mean length is |Na| = r (ndfmipKappaFromLength), kept finite
// (about 1e6) for r = 1, where the mappings divide by it.
float ndfmipToksvigKappa(float r) {
    return ndfmipKappaFromLength(min(r, 0.999999f));
}

// alpha' from |Na| = r and the material's alpha; c = varianceScale (2: calibrated on real maps).
float ndfmipMappedRoughness(int mapping, float r, float alpha, float varianceScale) {
    float a2 = alpha * alpha;
    if (mapping == NDFMIP_MAPPING_OURS) a2 += varianceScale * ndfmipToksvigSigma2(r);
    if (mapping == NDFMIP_MAPPING_HDRP) a2 += 0.5f / max(ndfmipToksvigKappa(r), 1e-6f);
    if (mapping == NDFMIP_MAPPING_FILAMENT) a2 += 2.0f / max(ndfmipToksvigKappa(r), 1e-6f);
    if (mapping == NDFMIP_MAPPING_GODOT)
        return min(alpha + min(0.75f / max(ndfmipToksvigKappa(r), 1e-6f), 0.16f), 1.0f); // alpha' = p'^2
    if (mapping == NDFMIP_MAPPING_UNREAL) {
        float b = 2.0f * ndfmipToksvigSigma2(r) * (1.0f - a2);
        a2 = (a2 + b) / (1.0f + b);
    }
    return min(sqrt(a2), 1.0f);
}

// The widened lobe alone about Na/|Na|: Blinn-Phong with exponent ft s (T eq. 8, normalised);
// Beckmann and GGX at the mapped alpha.
float ndfmipToksvigLobe(NdfmipMaterial m, vec3 na, vec3 h, int mapping, float varianceScale) {
    float r = sqrt(dot(na, na));
    float cosH = r > 0.0f ? dot(na, h) / r : 0.0f;
    if (m.brdf == NDFMIP_BLINN_PHONG) return ndfmipBlinnPhong(cosH, ndfmipToksvigFactor(r, m.exponent) * m.exponent);
    if (m.brdf == NDFMIP_BECKMANN) return ndfmipBeckmann(cosH, ndfmipMappedRoughness(mapping, r, m.roughness, varianceScale));
    if (m.brdf == NDFMIP_GGX) return ndfmipGgx(cosH, ndfmipMappedRoughness(mapping, r, m.roughness, varianceScale));
    return 0.0f;
}

// Diffuse with the exact mean cosine Na.l (Lambert is linear in n); the lobe with
// ndfmipSpecularCosine, the NDF read as a vMF of kappa = |Na|/(1 - |Na|) (T eq. 1).
vec3 ndfmipShadeToksvigLobe(NdfmipMaterial m, vec3 albedo, vec3 na, vec3 l, vec3 v, float lobe) {
    float r = sqrt(dot(na, na));
    vec3 h = normalize(l + v);
    vec3 mu = r > 0.0f ? na / r : vec3(0.0f, 0.0f, 1.0f);
    float kappa = r < 1.0f ? r / (1.0f - r) : 1e30f;
    float cosDiffuse = max(dot(na, l), 0.0f);
    float cosSpecular = ndfmipSpecularCosine(mu, kappa, ndfmipLobeConcentration(m), h, l);
    return cosDiffuse * albedo * (1.0f / NDFMIP_PI) + cosSpecular * m.specular * lobe;
}

vec3 ndfmipShadeToksvig(NdfmipMaterial m, vec3 albedo, vec3 na, vec3 l, vec3 v, int mapping, float varianceScale) {
    float lobe = ndfmipToksvigLobe(m, na, normalize(l + v), mapping, varianceScale);
    return ndfmipShadeToksvigLobe(m, albedo, na, l, v, lobe);
}
