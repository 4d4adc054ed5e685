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

// A Beckmann lobe of squared roughness b2 convolved with a vMF lobe of concentration kappa: the
// slopes' variances add, b2 + 2/kappa (H eq. 30), but the shape is the wider of the two: a
// Beckmann lobe where the material's lobe dominates, the vMF itself (concentration 2/(b2 +
// 2/kappa), H eq. 29's s' = kappa s/(kappa + s) with s = 2/b2) where the normals' spread does.
// The two shapes are blended by the material's share of the variance; a share below 1e-4 is
// skipped.
float ndfmipBeckmannVmf(float cosH, float b2, float kappa) {
    float variance = b2 + 2.0f / kappa;
    float share = b2 / variance;
    float result = 0.0f;
    if (share > 1e-4f && cosH > 0.0f) {
        float c2 = cosH * cosH;
        result = share * exp((c2 - 1.0f) / (c2 * variance)) / (NDFMIP_PI * variance * c2 * c2);
    }
    if (share < 0.9999f) {
        // The vMF density k / (4 pi sinh k) e^(k cos) as k / (2 pi (1 - e^(-2k))) e^(k (cos - 1));
        // e^(-2k) is below float precision beyond k = 10.
        float k = 2.0f / variance;
        float norm = k > 10.0f ? k / (2.0f * NDFMIP_PI)
                               : (k > 1e-3f ? k / (2.0f * NDFMIP_PI * (1.0f - exp(-2.0f * k))) : 1.0f / (4.0f * NDFMIP_PI));
        result += (1.0f - share) * norm * exp(k * (cosH - 1.0f));
    }
    return result;
}

// GGX of roughness alpha convolved with a vMF lobe of concentration kappa, as a function of
// mu.h. GGX is a scale mixture of Beckmann lobes: D_GGX(alpha) = E[D_Beckmann(alpha / sqrt(tau))]
// over tau ~ Exp(1) (GGX's slopes are Student-t, a Gaussian whose variance is drawn), so the
// convolution is that mixture of Beckmann-vMF convolutions. The expectation is a trapezoid rule
// in log tau, step 1, tau = e^-9 .. e^2, each term's weight tau e^-tau and 1/tau written out:
// within 0.4% of a fine rule, within 2% (alpha <= 0.1) to 10% (alpha 0.3, kappa 3) of the
// spherical convolution integrated numerically, where the equivalent roughness alpha'^2 =
// alpha^2 + 2/kappa is off by 6-63%. Where the vMF is far narrower than GGX (kappa alpha^2 >
// 400) that equivalent roughness is within 1% and is used.
float ndfmipGgxVmf(float cosH, float alpha, float kappa) {
    float a2 = alpha * alpha;
    if (kappa * a2 > 400.0f) return ndfmipGgx(cosH, sqrt(a2 + 2.0f / kappa));
    return 1.23394575e-4f * ndfmipBeckmannVmf(cosH, a2 * 8103.08393f, kappa)
         + 3.35350112e-4f * ndfmipBeckmannVmf(cosH, a2 * 2980.95799f, kappa)
         + 9.11050816e-4f * ndfmipBeckmannVmf(cosH, a2 * 1096.63316f, kappa)
         + 2.47261557e-3f * ndfmipBeckmannVmf(cosH, a2 * 403.428793f, kappa)
         + 6.69269968e-3f * ndfmipBeckmannVmf(cosH, a2 * 148.413159f, kappa)
         + 1.79832297e-2f * ndfmipBeckmannVmf(cosH, a2 * 54.5981500f, kappa)
         + 4.73690097e-2f * ndfmipBeckmannVmf(cosH, a2 * 20.0855369f, kappa)
         + 1.18204952e-1f * ndfmipBeckmannVmf(cosH, a2 * 7.38905610f, kappa)
         + 2.54646380e-1f * ndfmipBeckmannVmf(cosH, a2 * 2.71828183f, kappa)
         + 3.67879441e-1f * ndfmipBeckmannVmf(cosH, a2, kappa)
         + 1.79374079e-1f * ndfmipBeckmannVmf(cosH, a2 * 0.367879441f, kappa)
         + 4.56628142e-3f * ndfmipBeckmannVmf(cosH, a2 * 0.135335283f, kappa);
}

// The material's lobe convolved with one vMF lobe, about mu:
//   Blinn-Phong  s' = kappa s / (kappa + s)                         (H eq. 29)
//   Beckmann     alpha'^2 = alpha^2 + 2/kappa                       (H eq. 30)
//   GGX          the scale mixture of Beckmann lobes, each convolved (ndfmipGgxVmf)
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
