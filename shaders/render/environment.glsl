// The GPU renderer under an environment: the split sum's lookups (environment_splitsum.h; Karis
// 2013), the same as src/env/splitsum_lighting.cpp's, in float, which the shading of
// splitsum_shading.glsl (one source with the CPU's) reads; and the SH lighting's rows, which
// sh_lighting_shading.glsl (one source with the CPU's) reads. Included by the renderer (with
// #define NDFMIP_ENVIRONMENT) after raycast.glsl and before splitsum_shading.glsl (and
// sh_lighting_shading.glsl) and the method's glue, whose ndfmipShadeEnvironment(p, albedo, hit,
// view) calls them.
//
// Textures, all read with texelFetch so the filtering is the CPU's to rounding:
//   ndfmipEnvChain   the rule's prefiltered chain, equirect (environment frame, rotation
//                    applied), its level k the texture's mip k
//   ndfmipEnvCube    instead, with NDFMIP_ENVIRONMENT_CUBE, the log2sigma rule's chain on
//                    cube faces: six layers, its level k the mip k
//   ndfmipEnvAlbedo  the split sum's second factor (R) and the dominant direction's share of the
//                    normal (G): column n.v, row perceptual roughness
//   ndfmipEnvMap     the map itself (the background where it is visible)

uniform sampler2D ndfmipEnvChain;
uniform int ndfmipEnvLevels;
uniform int ndfmipEnvRule;          // 0 log2sigma, 1 filament, 2 unity, 3 unreal (EnvironmentLod)
uniform float ndfmipEnvTexelAngle;  // a level-0 texel's angular height (log2sigma)
uniform sampler2D ndfmipEnvAlbedo;
uniform vec3 ndfmipEnvIrradiance[9]; // E_lm of order 2 (projectEnvironmentSh)
uniform int ndfmipEnvBandFactors;    // 1: diffuse about a vMF band-attenuated
uniform int ndfmipEnvWeightedReflection; // 1: radiance about the albedo-weighted reflecting normal
uniform int ndfmipEnvVisible;        // 1: rays that miss the object see the map
uniform sampler2D ndfmipEnvMap;
uniform vec2 ndfmipEnvRotation;      // cos, sin of -Environment::rotation

// Repeat wrapping for i >= -n (main.frag's ndfmipWrap1 comes after this file).
int ndfmipEnvWrap(int i, int n) { return i < 0 ? i + n : (i >= n ? i - n : i); }

// World (+Z up) to environment (+Y up): e = (-w.x, w.z, w.y) (environment_lighting.h).
vec3 ndfmipWorldToEnvironment(vec3 w) { return vec3(-w.x, w.z, w.y); }

// A tangent-frame direction in the environment frame (tangentToEnvironment).
vec3 ndfmipTangentToEnvironment(NdfmipHit hit, vec3 t) {
    return ndfmipWorldToEnvironment(t.x * hit.tangent + t.y * hit.bitangent + t.z * hit.normal);
}

// The hit's tangent frame in the environment frame, as splitsum_shading.glsl takes it (toEnv).
mat3 ndfmipTangentFrame(NdfmipHit hit) {
    return mat3(ndfmipWorldToEnvironment(hit.tangent), ndfmipWorldToEnvironment(hit.bitangent),
                ndfmipWorldToEnvironment(hit.normal));
}

// equirectCoordinates: u in [0, 1), v in [0, 1].
vec2 ndfmipEquirectCoordinates(vec3 d) {
    float u = 0.5f + atan(-d.x, d.z) / (2.0f * NDFMIP_PI);
    if (u >= 1.0f) u -= 1.0f;
    float v = 0.5f - asin(clamp(d.y / length(d), -1.0f, 1.0f)) / NDFMIP_PI;
    return vec2(u, v);
}

// sampleEquirect on mip `k`: bilinear, longitude wrapping, past a pole the far side's row.
vec3 ndfmipSampleEquirect(int k, vec3 d) {
    // GL's mip size from level 0 (llvmpipe's textureSize takes one lane's level for all).
    ivec2 size = max(textureSize(ndfmipEnvChain, 0) >> ivec2(k), ivec2(1));
    vec2 uv = ndfmipEquirectCoordinates(d);
    vec2 s = uv * vec2(size) - 0.5f;
    vec2 s0 = floor(s);
    vec2 f = s - s0;
    vec3 sum = vec3(0.0f);
    for (int j = 0; j < 2; ++j) {
        for (int i = 0; i < 2; ++i) {
            int x = int(s0.x) + i;
            int y = int(s0.y) + j;
            if (y < 0 || y >= size.y) {
                y = y < 0 ? -1 - y : 2 * size.y - 1 - y;
                x += size.x / 2;
            }
            x = ndfmipEnvWrap(x, size.x);
            float w = (i == 1 ? f.x : 1.0f - f.x) * (j == 1 ? f.y : 1.0f - f.y);
            sum += w * texelFetch(ndfmipEnvChain, ivec2(x, y), k).rgb;
        }
    }
    return sum;
}

#ifdef NDFMIP_ENVIRONMENT_CUBE
// The log2sigma rule's chain on cube faces (SplitSumChain, environment_splitsum.h): layer f of mip k is
// face f of level k, read as sampleCubeLevel reads it.
uniform sampler2DArray ndfmipEnvCube;

// cubeFaceCoordinates: the face d points into and (s, t) on it, clamped to [0, 1].
int ndfmipCubeFaceCoordinates(vec3 d, out vec2 st) {
    NdfmipCubeFacePoint p = ndfmipCubeFacePoint(d);
    st = clamp(0.5f * (p.ab + 1.0f), vec2(0.0f), vec2(1.0f));
    return p.face;
}

// cube_mip_chain.cpp's texelAt: texel (x, y) of `face` at mip k (n wide); one past an edge, the
// adjacent face's texel under the extended plane's texel centre.
vec3 ndfmipCubeTexel(int k, int n, int face, int x, int y) {
    if (x < 0 || x >= n || y < 0 || y >= n) {
        vec2 st;
        vec2 ab = 2.0f * ((vec2(x, y) + 0.5f) / float(n)) - 1.0f; // the texel centre on the extended face
        face = ndfmipCubeFaceCoordinates(normalize(ndfmipCubeFaceDirection(face, ab)), st);
        x = clamp(int(st.x * float(n)), 0, n - 1);
        y = clamp(int(st.y * float(n)), 0, n - 1);
    }
    return texelFetch(ndfmipEnvCube, ivec3(x, y, face), k).rgb;
}

// sampleCubeLevel: bilinear on mip k; past a cube corner the other three texels' mean stands in
// for the missing fourth.
vec3 ndfmipSampleCubeLevel(int k, vec3 d) {
    int n = max(textureSize(ndfmipEnvCube, 0).x >> k, 1);
    vec2 st;
    int face = ndfmipCubeFaceCoordinates(d, st);
    vec2 p = st * float(n) - 0.5f;
    ivec2 x0 = ivec2(floor(p));
    vec2 f = p - vec2(x0);
    vec3 t00 = ndfmipCubeTexel(k, n, face, x0.x, x0.y);
    vec3 t10 = ndfmipCubeTexel(k, n, face, x0.x + 1, x0.y);
    vec3 t01 = ndfmipCubeTexel(k, n, face, x0.x, x0.y + 1);
    vec3 t11 = ndfmipCubeTexel(k, n, face, x0.x + 1, x0.y + 1);
    bool outX0 = x0.x < 0;
    bool outX1 = x0.x + 1 >= n;
    bool outY0 = x0.y < 0;
    bool outY1 = x0.y + 1 >= n;
    if (outX0 && outY0) t00 = (t10 + t01 + t11) / 3.0f;
    if (outX1 && outY0) t10 = (t00 + t11 + t01) / 3.0f;
    if (outX0 && outY1) t01 = (t11 + t00 + t10) / 3.0f;
    if (outX1 && outY1) t11 = (t01 + t10 + t00) / 3.0f;
    return (1.0f - f.y) * ((1.0f - f.x) * t00 + f.x * t10) + f.y * ((1.0f - f.x) * t01 + f.x * t11);
}
#endif

// One level of the chain: the equirect mip, or the cube faces' mip.
vec3 ndfmipSampleLevel(int k, vec3 d) {
#ifdef NDFMIP_ENVIRONMENT_CUBE
    return ndfmipSampleCubeLevel(k, d);
#else
    return ndfmipSampleEquirect(k, d);
#endif
}

// sampleChain: the two levels about `lod`, blended.
vec3 ndfmipSampleChain(float lod, vec3 d) {
    lod = clamp(lod, 0.0f, float(ndfmipEnvLevels - 1));
    int k0 = int(lod);
    int k1 = min(k0 + 1, ndfmipEnvLevels - 1);
    float f = lod - float(k0);
    vec3 a = ndfmipSampleLevel(k0, d);
    if (f > 0.0f && k1 != k0) return (1.0f - f) * a + f * ndfmipSampleLevel(k1, d);
    return a;
}

// prefilteredRadiance: the rule's level for perceptual roughness r (environmentLodLevel), or
// Toksvig's log2(2 sigma / theta0) - 2 with sigma = 2 sqrt(alpha^2/2 + normalVariance)
// (reflectedSpread, log2SigmaLevel: the level whose lobe has that spread).
vec3 ndfmipPrefilteredRadiance(vec3 reflected, float r, float normalVariance) {
    float last = float(ndfmipEnvLevels - 1);
    float lod = 0.0f;
    if (ndfmipEnvRule == 0) {
        float alpha = r * r;
        float sigma = 2.0f * sqrt(max(alpha * alpha / 2.0f, 0.0f) + max(normalVariance, 0.0f));
        // kLog2SigmaSpan and kLog2SigmaLobeLevels (environment_splitsum.h), defined by the renderer.
        lod = sigma > 0.0f ? clamp(log2(NDFMIP_LOG2SIGMA_SPAN * sigma / ndfmipEnvTexelAngle) -
                                       NDFMIP_LOG2SIGMA_LOBE_LEVELS,
                                   0.0f, last)
                           : 0.0f;
    } else {
        r = clamp(r, 0.0f, 1.0f);
        if (ndfmipEnvRule == 1) lod = r * (2.0f - r) * last;
        if (ndfmipEnvRule == 2) lod = r * (1.7f - 0.7f * r) * 6.0f; // kUnitySpecCubeLodSteps
        if (ndfmipEnvRule == 3) lod = last - (1.0f - 1.2f * log2(max(r, 0.001f)));
        lod = clamp(lod, 0.0f, last);
    }
    return ndfmipSampleChain(lod, normalize(reflected));
}

// The material's table bilinear with clamped edges at (n.v, r): the split sum's second factor
// (specularAlbedo) in R, the dominant direction's share of the normal (dominantShare) in G, and
// R's slope in n.v, the interpolant's (the cell's, the last cell's at n.v = 1).
vec3 ndfmipEnvTable(float mu, float r) {
    ivec2 size = textureSize(ndfmipEnvAlbedo, 0);
    float x = clamp(mu, 0.0f, 1.0f) * float(size.x - 1);
    float y = clamp(clamp(r, 0.0f, 1.0f) * float(size.y) - 0.5f, 0.0f, float(size.y - 1));
    int x0 = min(int(x), size.x - 2), y0 = int(y);
    int y1 = min(y0 + 1, size.y - 1);
    vec2 f = vec2(x - float(x0), y - float(y0));
    vec2 a = texelFetch(ndfmipEnvAlbedo, ivec2(x0, y0), 0).rg;
    vec2 b = texelFetch(ndfmipEnvAlbedo, ivec2(x0 + 1, y0), 0).rg;
    vec2 c = texelFetch(ndfmipEnvAlbedo, ivec2(x0, y1), 0).rg;
    vec2 e = texelFetch(ndfmipEnvAlbedo, ivec2(x0 + 1, y1), 0).rg;
    vec2 value = (1.0f - f.y) * ((1.0f - f.x) * a + f.x * b) + f.y * ((1.0f - f.x) * c + f.x * e);
    return vec3(value, float(size.x - 1) * ((1.0f - f.y) * (b.x - a.x) + f.y * (e.x - c.x)));
}

float ndfmipSpecularAlbedo(NdfmipMaterial m, float mu, float r) { return ndfmipEnvTable(mu, r).x; }
vec2 ndfmipSpecularAlbedoAndSlope(NdfmipMaterial m, float mu, float r) { return ndfmipEnvTable(mu, r).xz; }
float ndfmipDominantShare(NdfmipMaterial m, float mu, float r) { return ndfmipEnvTable(mu, r).y; }

// irradianceAt: Sum band_l E_lm Y_lm(n), clamped at 0 (truncation rings).
vec3 ndfmipIrradiance(vec3 n, vec3 band) {
    float g[NDFMIP_SH_MAX_COEFFICIENTS];
    float a[NDFMIP_SH_MAX_ORDER + 1];
    for (int l = 0; l <= NDFMIP_SH_MAX_ORDER; ++l) a[l] = 0.0f;
    a[0] = band.x;
    a[1] = band.y;
    a[2] = band.z;
    vec3 e = vec3(0.0f);
    n = normalize(n);
    for (int c = 0; c < 3; ++c) {
        for (int k = 0; k < NDFMIP_SH_MAX_COEFFICIENTS; ++k) g[k] = k < 9 ? ndfmipEnvIrradiance[k][c] : 0.0f;
        e[c] = ndfmipShConvolve(g, a, 2, n);
    }
    return max(e, vec3(0.0f));
}

// environmentRadiance: the map's texel along world direction w (nearest, as stored).
vec3 ndfmipEnvironmentBackground(vec3 w) {
    vec3 d = ndfmipWorldToEnvironment(w);
    float c = ndfmipEnvRotation.x;
    float s = ndfmipEnvRotation.y;
    d = vec3(c * d.x + s * d.z, d.y, -s * d.x + c * d.z); // rotateAboutY(d, -rotation)
    ivec2 size = textureSize(ndfmipEnvMap, 0);
    vec2 uv = ndfmipEquirectCoordinates(d);
    ivec2 t = clamp(ivec2(uv * vec2(size)), ivec2(0), size - 1);
    return texelFetch(ndfmipEnvMap, t, 0).rgb;
}

// ---- the SH-lighting way (environment_sh_shading.h; Han et al. Sec. 8, eqs. 35 and 37) -------
// The lighting's rows and basis as sh_lighting_shading.glsl reads them. ndfmipEnvSh holds the prepared lighting's coefficients of order NDFMIP_ENV_SH_ORDER, one
// column per coefficient: row 0 L_lm, rows 1 .. 3 L'_lm of the axes x, y, z (the mean-normal
// cosine: NDFMIP_ENV_SH_AXES; the reflecting normals' cosine: NDFMIP_ENV_SH_REFLECTING, with row
// 4 the half vector's L'_lm) or row 1 L'_lm alone. For vmf they are in the environment frame;
// for sh on a plane in its tangent frame (rotated on the CPU, sh_rotation.h, once per frame); for
// sh on a sphere (NDFMIP_ENVIRONMENT_SH_PER_HIT) in the environment frame, followed by a row of
// the rotation's points and its pseudo-inverse, and rotated here into each hit's frame.
//
// The order, the rows and the rotation's points are the renderer's #defines, not uniforms: with
// constant bounds the compiler unrolls the loops over bands and coefficients. That matters on
// Mesa's llvmpipe, whose loop limiter ends a fragment's loops after 65535 iterations in all:
// only the loops left (the rotation's points, the taps, the probes' texels) count against it.
#ifdef NDFMIP_ENVIRONMENT_SH
#if defined(NDFMIP_ENV_SH_REFLECTING)
#define NDFMIP_ENV_SH_ROWS 5
#elif defined(NDFMIP_ENV_SH_AXES)
#define NDFMIP_ENV_SH_ROWS 4
#else
#define NDFMIP_ENV_SH_ROWS 2
#endif
#define NDFMIP_ENV_SH_COUNT ((NDFMIP_ENV_SH_ORDER + 1) * (NDFMIP_ENV_SH_ORDER + 1))

uniform sampler2D ndfmipEnvSh;
uniform float ndfmipEnvShDiffuse[NDFMIP_SH_MAX_ORDER + 1];  // the material's A_l (ShShading)
uniform float ndfmipEnvShSpecular[NDFMIP_SH_MAX_ORDER + 1];

vec3 ndfmipEnvShPrepared(int i, int row) { return texelFetch(ndfmipEnvSh, ivec2(i, row), 0).rgb; }

// sh_lighting_shading.glsl's hooks: float scalars, sh.glsl's basis, the order and cosine constants.
#define NdfmipReal float
#define NDFMIP_ENV_SH_BANDS (NDFMIP_SH_MAX_ORDER + 1)
#define NDFMIP_ENV_SH_COEFFICIENTS NDFMIP_SH_MAX_COEFFICIENTS
#define NdfmipEnvShBasis NdfmipShBasis
const int ndfmipEnvShOrder = NDFMIP_ENV_SH_ORDER;
#if defined(NDFMIP_ENV_SH_REFLECTING)
const int ndfmipEnvShAxes = 2;
#elif defined(NDFMIP_ENV_SH_AXES)
const int ndfmipEnvShAxes = 1;
#else
const int ndfmipEnvShAxes = 0;
#endif
NdfmipShBasis ndfmipEnvShBasisAt(vec3 w) { return ndfmipShBasisAt(w, NDFMIP_ENV_SH_ORDER); }

#ifdef NDFMIP_ENVIRONMENT_SH_PER_HIT
// sh on a sphere: each hit has its own tangent frame T, so the lighting is rotated into it here,
// L_t(d) = L(T d), as the CPU's shadeShEnvironment does (rotateSh, sh_rotation.h): band l of each
// row read at T d_k and fitted back by the pseudo-inverse, exact to float rounding. Once per hit,
// not per texel: texel shading shades the 8 texels of a probe against one rotated lighting, so
// rotating the 2 or 4 RGB rows per hit costs less than rotating each texel's g (one channel, but
// 8 times). NDFMIP_ENV_SH_POINTS (4 order + 4) points.
vec3 ndfmipEnvShRotated[NDFMIP_ENV_SH_ROWS * NDFMIP_ENV_SH_COUNT]; // row r of coefficient i at ROWS i + r

vec3 ndfmipEnvShRow(int i, int row) { return ndfmipEnvShRotated[NDFMIP_ENV_SH_ROWS * i + row]; }

void ndfmipEnvShRotate(NdfmipHit hit) {
    for (int k = 0; k < NDFMIP_ENV_SH_POINTS; ++k) {
        vec3 d = normalize(ndfmipTangentToEnvironment(hit, ndfmipEnvShPrepared(k, NDFMIP_ENV_SH_ROWS)));
        NdfmipShBasis basis = ndfmipShBasisAt(d, NDFMIP_ENV_SH_ORDER);
        for (int l = 0; l <= NDFMIP_ENV_SH_ORDER; ++l) {
            // Band l of each row at T d_k: Sum_m L_lm Y_lm(T d_k).
            vec3 band[NDFMIP_ENV_SH_ROWS];
            for (int row = 0; row < NDFMIP_ENV_SH_ROWS; ++row) {
                band[row] = vec3(0.0f);
                for (int m = -NDFMIP_ENV_SH_ORDER; m <= NDFMIP_ENV_SH_ORDER; ++m) { // unrolled (sh.glsl)
                    if (m * m <= l * l) {
                        int i = l * (l + 1) + m;
                        band[row] += basis.y[i] * ndfmipEnvShPrepared(i, row);
                    }
                }
            }
            // L_t,lm = Sum_k pseudoInverse_l[m, k] (band l at T d_k); a loop per row keeps each
            // body small enough to unroll.
            float w[2 * NDFMIP_ENV_SH_ORDER + 1];
            for (int m = -NDFMIP_ENV_SH_ORDER; m <= NDFMIP_ENV_SH_ORDER; ++m) {
                ivec2 at = ivec2(k, NDFMIP_ENV_SH_ROWS + 1 + l * (l + 1) + m);
                w[m + NDFMIP_ENV_SH_ORDER] = m * m <= l * l ? texelFetch(ndfmipEnvSh, at, 0).r : 0.0f;
            }
            for (int row = 0; row < NDFMIP_ENV_SH_ROWS; ++row) {
                for (int m = -NDFMIP_ENV_SH_ORDER; m <= NDFMIP_ENV_SH_ORDER; ++m) {
                    if (m * m <= l * l) {
                        int at = NDFMIP_ENV_SH_ROWS * (l * (l + 1) + m) + row;
                        ndfmipEnvShRotated[at] = (k == 0 ? vec3(0.0f) : ndfmipEnvShRotated[at]) +
                                                 w[m + NDFMIP_ENV_SH_ORDER] * band[row];
                    }
                }
            }
        }
    }
}
#else
vec3 ndfmipEnvShRow(int i, int row) { return ndfmipEnvShPrepared(i, row); }
#endif

#endif // NDFMIP_ENVIRONMENT_SH
