// ndfmip shading library: mixtures of von Mises-Fisher lobes (Han et al. Sec. 7; needs
// brdf.glsl).
//
// Textures: the vmf bake's planes "lobe0" .. "lobe<J-1>" (RGBA, mipmapped, trilinear), each
// (alpha, alpha r mu) (eq. 33), and, with --albedo, "color0" .. (RGB, the lobe's colour times
// alpha). Shade each lobe with ndfmipShadeVmfLobe and add the results.

#define NDFMIP_KAPPA_MAX 1e5f

struct NdfmipLobe {
    float alpha; // weight
    vec3 mu;     // mean direction
    float kappa; // concentration
};

// Algorithm 1, lines 12-13: r = |alpha r mu| / alpha, mu = its direction, kappa from r by
// Banerjee's approximation, at most NDFMIP_KAPPA_MAX.
NdfmipLobe ndfmipUnpackLobe(vec4 lobeTexel) {
    NdfmipLobe lobe;
    lobe.alpha = 0.0f;
    lobe.mu = vec3(0.0f, 0.0f, 1.0f);
    lobe.kappa = 0.0f;
    if (!(lobeTexel.x > 0.0f)) return lobe;
    vec3 scaled = vec3(lobeTexel.y, lobeTexel.z, lobeTexel.w);
    float len = sqrt(dot(scaled, scaled));
    lobe.alpha = lobeTexel.x;
    if (len > 0.0f) lobe.mu = scaled / len;
    float r = len / lobeTexel.x;
    if (!(r > 0.0f)) lobe.kappa = 0.0f;
    else if (r >= 1.0f) lobe.kappa = NDFMIP_KAPPA_MAX;
    else lobe.kappa = min(r * (3.0f - r * r) / ((1.0f - r) * (1.0f + r)), NDFMIP_KAPPA_MAX);
    return lobe;
}

// The material's lobe convolved with one vMF lobe, about mu:
//   Blinn-Phong  s' = kappa s / (kappa + s)                         (eq. 29)
//   Beckmann     alpha'^2 = alpha^2 + 2/kappa                       (eq. 30)
//   GGX          the same alpha' (an equivalent roughness)
float ndfmipVmfWidenedLobe(NdfmipMaterial m, vec3 mu, float kappa, vec3 h) {
    float cosH = dot(mu, h);
    if (m.brdf == NDFMIP_BLINN_PHONG) return ndfmipBlinnPhong(cosH, kappa * m.exponent / (kappa + m.exponent));
    float alpha = sqrt(m.roughness * m.roughness + 2.0f / max(kappa, 1e-6f));
    if (m.brdf == NDFMIP_BECKMANN) return ndfmipBeckmann(cosH, alpha);
    if (m.brdf == NDFMIP_GGX) return ndfmipGgx(cosH, alpha);
    return 0.0f;
}

// One lobe's share, given its specular lobe value: alpha (albedo D_diffuse + specular lobe
// cosine), the diffuse term eq. 29 with s = 1 over l (footnote 9), which carries its cosine.
vec3 ndfmipVmfLobeTerm(NdfmipMaterial m, vec3 albedo, NdfmipLobe lobe, float specular, vec3 l, vec3 v) {
    if (!(lobe.alpha > 0.0f)) return vec3(0.0f);
    float sd = lobe.kappa / (lobe.kappa + 1.0f);
    float diffuse = (sd + 1.0f) / (2.0f * NDFMIP_PI) * pow(max(dot(lobe.mu, l), 0.0f), sd);
    float cosSpecular = ndfmipSpecularCosine(lobe.mu, lobe.kappa, ndfmipLobeConcentration(m), normalize(l + v), l);
    return lobe.alpha * (albedo * diffuse + m.specular * (specular * cosSpecular));
}

// One filtered lobe texel (alpha, alpha r mu); `albedo` is the lobe's colour (colour plane /
// alpha) times the material's, or the material's.
vec3 ndfmipShadeVmfLobe(NdfmipMaterial m, vec3 albedo, vec4 lobeTexel, vec3 l, vec3 v) {
    NdfmipLobe lobe = ndfmipUnpackLobe(lobeTexel);
    float specular = ndfmipVmfWidenedLobe(m, lobe.mu, lobe.kappa, normalize(l + v));
    return ndfmipVmfLobeTerm(m, albedo, lobe, specular, l, v);
}
