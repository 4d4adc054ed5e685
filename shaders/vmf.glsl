// ndfmip shading library: mixtures of von Mises-Fisher lobes (Han et al. Sec. 7; needs
// brdf.glsl).
//
// Textures: the vmf bake's planes "lobe0" .. "lobe<J-1>" (RGBA, mipmapped, trilinear), each
// (alpha, alpha r mu) (H eq. 33), and, with --albedo, "color0" .. (RGB, the lobe's colour times
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
    lobe.kappa = min(ndfmipKappaFromLength(len / lobeTexel.x), NDFMIP_KAPPA_MAX);
    return lobe;
}

// The vMF density of concentration k at mu.h = cosH, k / (4 pi sinh k) e^(k cosH), as
// k / (2 pi (1 - e^(-2k))) e^(k (cosH - 1)); e^(-2k) is below float precision beyond k = 10.
float ndfmipVmfDensity(float cosH, float k) {
    float norm = k > 10.0f ? k / (2.0f * NDFMIP_PI)
                           : (k > 1e-3f ? k / (2.0f * NDFMIP_PI * (1.0f - exp(-2.0f * k))) : 1.0f / (4.0f * NDFMIP_PI));
    return norm * exp(k * (cosH - 1.0f));
}

// A GGX lobe's integral over the sphere (not over projected area, which is 1):
// 1 + a^2 atanh(b)/b with b = sqrt(1 - a^2), atanh(b) = ln((1 + b)/a); atan for a > 1.
float ndfmipGgxSphereMass(float a) {
    float a2 = a * a;
    float b2 = 1.0f - a2;
    if (a < 1e-4f) return 1.0f;
    if (b2 > 1e-6f) return 1.0f + a2 * log((1.0f + sqrt(b2)) / a) / sqrt(b2);
    if (b2 < -1e-6f) return 1.0f + a2 * atan(sqrt(-b2)) / sqrt(-b2);
    return 1.0f + a2;
}

// GGX of roughness alpha convolved with a vMF lobe of concentration kappa, as a function of
// mu.h: a closed form fitted to the convolution. By shape the convolution is a widened GGX lobe
// where the material's lobe dominates and the vMF where the normals' spread does, so it is
// written as their blend, each part at the variances' sum (H eq. 30) with a fitted share:
//   mass(alpha) [eta D_GGX(alpha_g) / mass(alpha_g) + (1 - eta) vMF(k_v)],
//   alpha_g^2 = alpha^2 + p_g 2/kappa,  k_v = 2 / (p_b alpha^2 + 2/kappa),
// mass = ndfmipGgxSphereMass, so the integral over the sphere is GGX's, as a convolution with a
// unit-mass lobe keeps it. eta (a logistic), ln p_g and ln p_b are cubics in u = ln(kappa
// alpha^2)/4 and alpha, least-squares fitted to the spherical convolution integrated numerically
// at 136 (alpha, kappa) pairs (alpha 0.02-1, kappa 1-1e5). On 48 other pairs it is within 1.7%
// (relative L2 over mu.h) for alpha <= 0.3 and 3.2% up to alpha = 0.7, where the equivalent
// roughness alpha'^2 = alpha^2 + 2/kappa is off by up to 260% (tests/methods/vmf/
// vmf_ggx_test.cpp). Where the vMF is far narrower than GGX (kappa alpha^2 > 400) that equivalent
// roughness is within 1% and is used.
float ndfmipGgxVmf(float cosH, float alpha, float kappa) {
    float a2 = alpha * alpha;
    if (kappa * a2 > 400.0f) return ndfmipGgx(cosH, sqrt(a2 + 2.0f / kappa));
    float u = clamp(log(kappa * a2), -7.0f, 7.0f) * 0.25f;
    float t = min(alpha, 1.0f);
    vec4 m0 = vec4(1.0f, u, t, u * u);
    vec4 m1 = vec4(u * t, t * t, u * u * u, u * u * t);
    vec2 m2 = vec2(u * t * t, t * t * t);
    float eta = 1.0f / (1.0f + exp(-(dot(m0, vec4(-0.6705204f, 2.941779f, 3.25437f, -0.8071828f))
                                     + dot(m1, vec4(5.843384f, -13.46371f, 1.112313f, -2.557632f))
                                     + dot(m2, vec2(-1.714262f, 7.797084f)))));
    float pg = exp(dot(m0, vec4(0.7520016f, 0.1756101f, -3.112437f, 0.6051188f))
                   + dot(m1, vec4(0.962732f, 4.750122f, -0.4287811f, -3.08418f))
                   + dot(m2, vec2(4.192812f, -5.728739f)));
    float pb = exp(dot(m0, vec4(0.1782638f, -0.9031241f, 1.402742f, 0.4002095f))
                   + dot(m1, vec4(-0.6447222f, -0.5168708f, 0.09645951f, 0.8259958f))
                   + dot(m2, vec2(-0.1635519f, -0.1080919f)));
    float alphaG = sqrt(a2 + pg * 2.0f / kappa);
    float kappaV = 2.0f / (pb * a2 + 2.0f / kappa);
    return ndfmipGgxSphereMass(alpha) * (eta * ndfmipGgx(cosH, alphaG) / ndfmipGgxSphereMass(alphaG)
                                         + (1.0f - eta) * ndfmipVmfDensity(cosH, kappaV));
}

// The material's lobe convolved with one vMF lobe, about mu:
//   Blinn-Phong  s' = kappa s / (kappa + s)                         (H eq. 29)
//   Beckmann     alpha'^2 = alpha^2 + 2/kappa                       (H eq. 30)
//   GGX          the convolution, a fitted closed form (ndfmipGgxVmf)
float ndfmipVmfWidenedLobe(NdfmipMaterial m, vec3 mu, float kappa, vec3 h) {
    float cosH = dot(mu, h);
    if (m.brdf == NDFMIP_BLINN_PHONG) return ndfmipBlinnPhong(cosH, kappa * m.exponent / (kappa + m.exponent));
    float safeKappa = max(kappa, 1e-6f);
    if (m.brdf == NDFMIP_BECKMANN) return ndfmipBeckmann(cosH, sqrt(m.roughness * m.roughness + 2.0f / safeKappa));
    if (m.brdf == NDFMIP_GGX) return ndfmipGgxVmf(cosH, m.roughness, safeKappa);
    return 0.0f;
}

// The GGX or Beckmann alpha of the material's lobe (alpha) widened by a vMF lobe of concentration
// kappa, alpha'^2 = alpha^2 + 2/kappa (H eq. 30), at most 1: the roughness an engine's
// prefiltered environment is read at for that lobe.
float ndfmipVmfWidenedAlpha(float alpha, float kappa) {
    return min(sqrt(alpha * alpha + 2.0f / max(kappa, 1e-6f)), 1.0f);
}

// One lobe's share, given its specular lobe value: alpha (albedo D_diffuse + specular lobe
// cosine), the diffuse term H eq. 29 with s = 1 over l (footnote 9), which carries its cosine.
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
