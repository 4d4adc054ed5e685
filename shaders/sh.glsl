// ndfmip shading library: spherical-harmonic NDFs (Han et al. eq. 17; needs brdf.glsl).
//
// Textures: the sh bake's planes "sh0" .. (RGBA, mipmapped, trilinear), four coefficients
// each in the order l = 0 .. l*, m = -l .. l. Up to order NDFMIP_SH_MAX_ORDER on the GPU.
// The BRDF's A_l (ndfmip's sh_brdf.h: brdfCoefficients, lambertCoefficients) are uniforms.

#define NDFMIP_SH_MAX_ORDER 10
#define NDFMIP_SH_MAX_COEFFICIENTS 121

// Sum over l <= order of A_l Sum_m g_lm Y_lm(w), real Y_lm without the Condon-Shortley phase,
// by the associated Legendre recurrence in P_l^m / sin^m (as spherical_harmonics.cpp) with
// sin^m e^{i m phi} = (x + i y)^m.
float ndfmipShConvolve(float g[NDFMIP_SH_MAX_COEFFICIENTS], float a[NDFMIP_SH_MAX_ORDER + 1], int order, vec3 w) {
    float sum = 0.0f;
    float re = 1.0f;
    float im = 0.0f;
    float pmm = 1.0f;
    for (int m = 0; m <= order; ++m) {
        if (m > 0) {
            float nextRe = re * w.x - im * w.y;
            im = re * w.y + im * w.x;
            re = nextRe;
            pmm *= float(2 * m - 1);
        }
        float previous = 0.0f;
        float current = pmm;
        for (int l = m; l <= order; ++l) {
            if (l == m + 1) {
                previous = current;
                current = float(2 * m + 1) * w.z * current;
            } else if (l > m + 1) {
                float next = (float(2 * l - 1) * w.z * current - float(l + m - 1) * previous) / float(l - m);
                previous = current;
                current = next;
            }
            float ratio = 1.0f; // (l - m)! / (l + m)!
            for (int k = l - m + 1; k <= l + m; ++k) ratio /= float(k);
            float kLm = sqrt((2.0f * float(l) + 1.0f) / (4.0f * NDFMIP_PI) * ratio) * current;
            int centre = l * (l + 1);
            if (m == 0) sum += a[l] * g[centre] * kLm;
            else sum += a[l] * 1.41421356f * kLm * (g[centre + m] * re + g[centre - m] * im);
        }
    }
    return sum;
}

// The mean normal band 1 holds: (g_11, g_1-1, g_10) / sqrt(3 / 4 pi) (footnote 5).
vec3 ndfmipShMeanNormal(float g1m1, float g10, float g11) {
    return vec3(g11, g1m1, g10) / sqrt(3.0f / (4.0f * NDFMIP_PI));
}

// Eq. 17 from the two convolutions: diffuseSum over w = l with the clamped cosine's A_l (it
// carries its own cosine), specularSum over w = h with the lobe's A_l; the lobe's cosine as
// ndfmipSpecularCosine with the NDF read as a vMF of Banerjee's kappa for |Na|. Truncation
// can ring below zero: each term is clamped at 0.
vec3 ndfmipShadeShSums(NdfmipMaterial m, vec3 albedo, float diffuseSum, float specularSum, vec3 na, vec3 l, vec3 v) {
    vec3 h = normalize(l + v);
    float r = sqrt(dot(na, na));
    vec3 mu = r > 0.0f ? na / r : vec3(0.0f, 0.0f, 1.0f);
    float kappa = r >= 1.0f ? 1e30f : (r > 0.0f ? r * (3.0f - r * r) / ((1.0f - r) * (1.0f + r)) : 0.0f);
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
