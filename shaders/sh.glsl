// ndfmip shading library: spherical-harmonic NDFs (Han et al. eq. 17; needs brdf.glsl).
//
// Textures: the sh bake's planes "sh0" .. (RGBA, mipmapped, trilinear), four coefficients
// each in the order l = 0 .. l*, m = -l .. l. Up to order NDFMIP_SH_MAX_ORDER on the GPU.
// The BRDF's A_l (ndfmip's sh_brdf.h: brdfCoefficients, lambertCoefficients) are uniforms.

#define NDFMIP_SH_MAX_ORDER 10
#define NDFMIP_SH_MAX_COEFFICIENTS 121

// The real basis Y_lm(w) (spherical_harmonics.cpp's convention: no Condon-Shortley phase) for
// l <= order at y[l (l + 1) + m]; the others are left unset. One recurrence for every SH sum
// of the library and the renderer: the associated Legendre functions already normalised,
// Pbar_lm = K_lm P_lm / sin^m with K_lm = sqrt((2l + 1)/(4 pi) (l - m)!/(l + m)!), so no
// factorial is formed (P_mm alone would reach 19!! = 6.5e8 at order 10):
//   Pbar_00 = 1/sqrt(4 pi),  Pbar_mm = sqrt((2m + 1)/(2m)) Pbar_m-1,m-1,
//   Pbar_m+1,m = sqrt(2m + 3) z Pbar_mm,
//   Pbar_lm = sqrt((4l^2 - 1)/(l^2 - m^2)) (z Pbar_l-1,m - sqrt(((l-1)^2 - m^2)/(4(l-1)^2 - 1)) Pbar_l-2,m),
// and sin^m e^{i m phi} = (x + i y)^m for the azimuth: Y_l,+-m = sqrt2 Pbar_lm (Re, Im), m > 0.
// With a compile-time `order` (the environment's NDFMIP_ENV_SH_ORDER) the inner loops have constant
// bounds, so a GLSL compiler can unroll them: Mesa's unrolls loops of constant trip count (at
// most 32) and small bodies, and not those with a `continue`; hence inner loops over all l (or
// all m) that test for the band's own, not bounds that depend on the outer loop's variable. That matters on llvmpipe, whose loop
// limiter ends a fragment's loops after 65535 iterations in all (render/environment.glsl).
struct NdfmipShBasis {
    float y[NDFMIP_SH_MAX_COEFFICIENTS];
};

NdfmipShBasis ndfmipShBasisAt(vec3 w, int order) {
    NdfmipShBasis basis;
    float re = 1.0f;
    float im = 0.0f;
    float pmm = 0.28209479f; // 1/sqrt(4 pi)
    for (int m = 0; m <= order; ++m) {
        if (m > 0) {
            float nextRe = re * w.x - im * w.y;
            im = re * w.y + im * w.x;
            re = nextRe;
            pmm *= sqrt(float(2 * m + 1) / float(2 * m));
        }
        float previous = 0.0f;
        float current = pmm;
        for (int l = 0; l <= order; ++l) { // from 0, not m, and no `continue`: so that it unrolls
            if (l >= m) {
                if (l == m + 1) {
                    previous = current;
                    current = sqrt(float(2 * m + 3)) * w.z * current;
                } else if (l > m + 1) {
                    float a = sqrt(float(4 * l * l - 1) / float(l * l - m * m));
                    float b = sqrt(float((l - 1) * (l - 1) - m * m) / float(4 * (l - 1) * (l - 1) - 1));
                    float next = a * (w.z * current - b * previous);
                    previous = current;
                    current = next;
                }
                int centre = l * (l + 1);
                if (m == 0) {
                    basis.y[centre] = current;
                } else {
                    basis.y[centre + m] = 1.41421356f * current * re;
                    basis.y[centre - m] = 1.41421356f * current * im;
                }
            }
        }
    }
    return basis;
}

// Sum over l <= order of A_l Sum_m g_lm Y_lm(w).
float ndfmipShConvolve(float g[NDFMIP_SH_MAX_COEFFICIENTS], float a[NDFMIP_SH_MAX_ORDER + 1], int order, vec3 w) {
    NdfmipShBasis basis = ndfmipShBasisAt(w, order);
    float sum = 0.0f;
    for (int l = 0; l <= order; ++l) {
        float band = 0.0f;
        for (int m = -order; m <= order; ++m) // as ndfmipShBasisAt: bounds that do not depend on l
            if (m * m <= l * l) band += g[l * (l + 1) + m] * basis.y[l * (l + 1) + m];
        sum += a[l] * band;
    }
    return sum;
}

// The mean normal band 1 holds: (g_11, g_1-1, g_10) / sqrt(3 / 4 pi) (footnote 5).
vec3 ndfmipShMeanNormal(float g1m1, float g10, float g11) {
    return vec3(g11, g1m1, g10) / sqrt(3.0f / (4.0f * NDFMIP_PI));
}

// H eq. 17 from the two convolutions: diffuseSum over w = l with the clamped cosine's A_l (it
// carries its own cosine), specularSum over w = h with the lobe's A_l; the lobe's cosine as
// ndfmipSpecularCosine with the NDF read as a vMF of Banerjee's kappa for |Na|. Truncation
// can ring below zero: each term is clamped at 0.
vec3 ndfmipShadeShSums(NdfmipMaterial m, vec3 albedo, float diffuseSum, float specularSum, vec3 na, vec3 l, vec3 v) {
    vec3 h = normalize(l + v);
    float r = sqrt(dot(na, na));
    vec3 mu = r > 0.0f ? na / r : vec3(0.0f, 0.0f, 1.0f);
    float kappa = ndfmipKappaFromLength(r);
    float cosL = ndfmipSpecularCosine(mu, kappa, ndfmipLobeConcentration(m), h, l);
    return albedo * max(diffuseSum, 0.0f) + m.specular * (cosL * max(specularSum, 0.0f));
}

vec3 ndfmipShadeSh(NdfmipMaterial m, vec3 albedo, float g[NDFMIP_SH_MAX_COEFFICIENTS],
                   float diffuseA[NDFMIP_SH_MAX_ORDER + 1], float specularA[NDFMIP_SH_MAX_ORDER + 1], int order,
                   vec3 l, vec3 v) {
    float diffuseSum = ndfmipShConvolve(g, diffuseA, order, l);
    float specularSum = ndfmipShConvolve(g, specularA, order, normalize(l + v));
    return ndfmipShadeShSums(m, albedo, diffuseSum, specularSum, ndfmipShMeanNormal(g[1], g[2], g[3]), l, v);
}
