// ndfmip shading library: the sh and vmf methods under SH lighting (Han et al. Sec. 8, H eqs. 35
// and 37; environment_sh_shading.h), one source for the GPU renderer (after render/environment.glsl,
// in float, up to order 10) and the CPU renderer (src/env/sh_lighting_shading.cpp, through glsl.h,
// in double, up to order 30). No `float` is named here: scalars are NdfmipReal, which the GPU
// defines as float and the CPU as double. Each side defines on its own data:
//   int ndfmipEnvShOrder                  the bands summed (the GPU's constant NDFMIP_ENV_SH_ORDER)
//   int ndfmipEnvShAxes                   the cosine (environment_sh_shading.h): 0 one L' (the
//                                         half vector's or none); 1 MeanNormal, the three axes'
//                                         L'; 2 Reflecting, the axes' and the half vector's L'
//   vec3 ndfmipEnvShRow(int i, int row)   coefficient i of the lighting in the frame shading is
//                                         in: row 0 L_lm; row 1 L'_lm, or with axes rows 1 .. 3
//                                         L'_lm of the axes x, y, z and with 2 row 4 the half
//                                         vector's
//   ndfmipEnvShDiffuse[l], ndfmipEnvShSpecular[l]   the material's A_l (ShShading)
//   NdfmipEnvShBasis ndfmipEnvShBasisAt(vec3 w)     Y_lm(w) for l <= ndfmipEnvShOrder at
//                                         .y[l (l + 1) + m] (sh.glsl's basis)
//   NDFMIP_ENV_SH_BANDS, NDFMIP_ENV_SH_COEFFICIENTS the arrays' lengths (at least the order's)

// The specular cosine c = normal.w_i + halfVector h.w_i (environment frame) of an NDF lobe of
// concentration kappa about unit mu whose mean normal is meanLength mu, under the material's lobe
// of concentration lobeKappa (brdf.glsl's ndfmipLobeConcentration). MeanNormal: the mean normal's
// cosine. Reflecting: the normals' that reflect, A(kappa + s) (share mu + (1 - share) h) with
// share = kappa / (kappa + s) (environment_sh_shading.h; brdf.glsl's ndfmipSpecularCosine with
// the product lobe's length and direction taken at h = mu). kappa >= 1e30 is a single normal.
struct NdfmipEnvCosine {
    vec3 normal;
    NdfmipReal halfVector;
};

NdfmipEnvCosine ndfmipEnvCosine(vec3 mu, NdfmipReal kappa, NdfmipReal meanLength, NdfmipReal lobeKappa) {
    NdfmipEnvCosine c;
    c.normal = meanLength * mu;
    c.halfVector = 0.0f;
    if (ndfmipEnvShAxes != 2 || !(kappa < 1e30f)) return c;
    NdfmipReal k = kappa + lobeKappa;
    // Langevin's A(k) = coth k - 1/k (brdf.glsl's ndfmipLangevin, in NdfmipReal).
    NdfmipReal a = k < 1e-3f ? k / 3.0f : (k > 20.0f ? 1.0f : 1.0f / tanh(k)) - 1.0f / k;
    NdfmipReal share = k > 0.0f ? kappa / k : 1.0f;
    c.normal = (a * share) * mu;
    c.halfVector = a * (1.0f - share);
    return c;
}

// L'_lm for the cosine c (environment frame): the prepared L' alone, or Sum_k c.normal_k L'_k
// over the axes, with Reflecting plus c.halfVector L'_h.
vec3 ndfmipEnvReparameterised(int i, NdfmipEnvCosine c) {
    if (ndfmipEnvShAxes == 0) return ndfmipEnvShRow(i, 1);
    vec3 axes = c.normal.x * ndfmipEnvShRow(i, 1) + c.normal.y * ndfmipEnvShRow(i, 2) +
                c.normal.z * ndfmipEnvShRow(i, 3);
    if (ndfmipEnvShAxes == 1) return axes;
    return axes + c.halfVector * ndfmipEnvShRow(i, 4);
}

// The sh bake's texel g (coefficients in the frame of the lighting's rows) with its mean normal
// (footnote 5's mipmapped normal, environment frame) read as a lobe of concentration kappa
// (Banerjee's, for its length): diffuse Sum A_l^diffuse g_lm L_lm (H eq. 35), specular
// Sum A_l^specular g_lm L'_lm (H eq. 37), each clamped at 0 per channel.
vec3 ndfmipShadeShLighting(int brdf, vec3 albedo, vec3 specularColour, NdfmipReal g[NDFMIP_ENV_SH_COEFFICIENTS],
                           vec3 meanNormal, NdfmipReal kappa, NdfmipReal lobeKappa) {
    NdfmipReal meanLength = length(meanNormal);
    vec3 mu = meanLength > 0.0f ? meanNormal / meanLength : vec3(0.0f, 0.0f, 1.0f);
    NdfmipEnvCosine cosine = ndfmipEnvCosine(mu, kappa, meanLength, lobeKappa);
    vec3 diffuse = vec3(0.0f);
    vec3 specular = vec3(0.0f);
    for (int l = 0; l <= ndfmipEnvShOrder; ++l) {
        vec3 d = vec3(0.0f);
        vec3 s = vec3(0.0f);
        // Not unrolled: per texel this is 90 iterations at order 8, and unrolled at each of
        // main.frag's call sites it made llvmpipe's compile several times slower.
        for (int i = l * l; i <= l * (l + 2); ++i) {
            d += g[i] * ndfmipEnvShRow(i, 0);
            s += g[i] * ndfmipEnvReparameterised(i, cosine);
        }
        diffuse += ndfmipEnvShDiffuse[l] * d;
        specular += ndfmipEnvShSpecular[l] * s;
    }
    if (brdf == NDFMIP_LAMBERT) return albedo * max(diffuse, vec3(0.0f));
    return albedo * max(diffuse, vec3(0.0f)) + specularColour * max(specular, vec3(0.0f));
}

// vmfBandFactors: A_l of the normalised vMF, i_l(kappa) / i_0(kappa), l <= order. From kappa = 32
// the terminating series of i_l in e^-2kappa, i_n(k) = (e^k S_-(n) - (-1)^n e^-k S_+(n)) / (2k),
// S_-+ = Sum_j (-+1)^j (n+j)! / (j! (n-j)! (2k)^j), and i_0 = sinh(k)/k, which cannot overflow
// (in double it cancels most at k = 32, n = 30: 3.5e-12). Below, Miller's backward recurrence
// r_l = i_l / i_(l-1) = 1 / ((2l + 1)/kappa + r_(l+1)) from 0 at order + ceil(kappa) + 4, where the
// start's error has died out to 1e-17 (the ratios fall below 1/2 past l ~ kappa), A_l = A_(l-1) r_l.
// Loop counts matter: llvmpipe's loop limiter (65535 iterations per invocation, all loops
// together) cut a longer start short under texel shading, which runs this per texel and lobe.
struct NdfmipVmfBands {
    NdfmipReal a[NDFMIP_ENV_SH_BANDS];
};

NdfmipVmfBands ndfmipVmfBands(NdfmipReal kappa, int order) {
    NdfmipVmfBands bands;
    for (int l = 0; l < NDFMIP_ENV_SH_BANDS; ++l) bands.a[l] = l == 0 ? 1.0f : 0.0f;
    if (kappa == 0.0f) return bands;
    if (kappa >= 32.0f) {
        NdfmipReal decay = exp(-2.0f * kappa);
        for (int n = 1; n <= order; ++n) {
            NdfmipReal term = 1.0f;
            NdfmipReal minus = 1.0f;
            NdfmipReal plus = 1.0f;
            for (int j = 0; j < n; ++j) {
                term *= NdfmipReal(n + j + 1) * NdfmipReal(n - j) / (NdfmipReal(j + 1) * 2.0f * kappa);
                minus += j % 2 == 0 ? -term : term;
                plus += term;
            }
            bands.a[n] = (minus - (n % 2 == 0 ? 1.0f : -1.0f) * decay * plus) / (1.0f - decay);
        }
        return bands;
    }
    NdfmipReal ratio = 0.0f;
    for (int l = order + int(ceil(kappa)) + 4; l >= 1; --l) {
        ratio = 1.0f / ((2.0f * NdfmipReal(l) + 1.0f) / kappa + ratio);
        if (l <= order) bands.a[l] = ratio;
    }
    for (int l = 1; l <= order; ++l) bands.a[l] *= bands.a[l - 1];
    return bands;
}

// One vMF lobe's A_l: diffuse A_l^vMF A_l^diffuse (H eq. 35); specular, for Blinn-Phong with
// `widen`, the widened lobe of exponent s = kappa e / (kappa + e) (H eq. 29; blinnPhongCoefficients:
// A_0 = 1, A_1 = (s + 1)/(s + 2), A_l+2 = A_l (s - l)/(s + l + 3)), otherwise the exact convolution
// A_l^vMF A_l^specular.
struct NdfmipEnvShTransfer {
    NdfmipReal diffuse[NDFMIP_ENV_SH_BANDS];
    NdfmipReal specular[NDFMIP_ENV_SH_BANDS];
};

NdfmipEnvShTransfer ndfmipVmfLobeTransfer(int brdf, NdfmipReal exponent, NdfmipReal kappa, NdfmipVmfBands bands,
                                          bool widen) {
    NdfmipEnvShTransfer t;
    NdfmipReal s = kappa * exponent / (kappa + exponent);
    NdfmipReal widened = 1.0f;
    NdfmipReal widenedOdd = (s + 1.0f) / (s + 2.0f);
    for (int l = 0; l <= ndfmipEnvShOrder; ++l) {
        t.diffuse[l] = bands.a[l] * ndfmipEnvShDiffuse[l];
        t.specular[l] = bands.a[l] * ndfmipEnvShSpecular[l];
        if (widen && brdf == NDFMIP_BLINN_PHONG) {
            t.specular[l] = l % 2 == 0 ? widened : widenedOdd;
            if (l % 2 == 0) widened *= (s - NdfmipReal(l)) / (s + NdfmipReal(l) + 3.0f);
            else widenedOdd *= (s - NdfmipReal(l)) / (s + NdfmipReal(l) + 3.0f);
        }
    }
    return t;
}

// One lobe of weight alpha and concentration kappa about unit mu (environment frame), its mean
// normal A(kappa) mu = meanLength mu (bands.a[1]) for the cosine: no rotation of the lighting,
// only Y_lm(mu) (footnote 10). Diffuse Sum_l t.diffuse_l Sum_m L_lm Y_lm(mu) (H eq. 35), specular
// Sum_l t.specular_l Sum_m L'_lm Y_lm(mu) (H eq. 37), each clamped at 0 per channel.
vec3 ndfmipShadeVmfLobeShLighting(int brdf, vec3 albedo, vec3 specularColour, vec3 mu, NdfmipReal alpha,
                                  NdfmipReal kappa, NdfmipReal meanLength, NdfmipReal lobeKappa,
                                  NdfmipEnvShTransfer t) {
    NdfmipEnvShBasis basis = ndfmipEnvShBasisAt(mu);
    NdfmipEnvCosine cosine = ndfmipEnvCosine(mu, kappa, meanLength, lobeKappa);
    vec3 diffuse = vec3(0.0f);
    vec3 specular = vec3(0.0f);
    for (int l = 0; l <= ndfmipEnvShOrder; ++l) {
        vec3 radiance = vec3(0.0f);
        vec3 reparameterised = vec3(0.0f);
        for (int m = -ndfmipEnvShOrder; m <= ndfmipEnvShOrder; ++m) { // unrolled (sh.glsl)
            if (m * m <= l * l) {
                int i = l * (l + 1) + m;
                radiance += basis.y[i] * ndfmipEnvShRow(i, 0);
                reparameterised += basis.y[i] * ndfmipEnvReparameterised(i, cosine);
            }
        }
        diffuse += t.diffuse[l] * radiance;
        specular += t.specular[l] * reparameterised;
    }
    vec3 shaded = albedo * max(diffuse, vec3(0.0f));
    if (brdf != NDFMIP_LAMBERT) shaded += specularColour * max(specular, vec3(0.0f));
    return alpha * shaded;
}
