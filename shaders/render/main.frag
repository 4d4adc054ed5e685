// ndfmip's GPU renderer, fragment stage: per pixel the CPU renderer's filtering rule (K x K
// sub-samples, LOD from ray differentials plus a bias, anisotropic probes along the major
// axis), each lookup either the hardware's trilinear filtering of the bake's planes (blend
// parameters over the probes, then shade) or the texels of every probe shaded one by one.
// Needs the library, raycast.glsl and the method's render/<method>.glsl, which defines
// NDFMIP_LAYERS (or the renderer does) and ndfmipShadeTexel(vec4 p[NDFMIP_LAYERS], vec3 albedo, vec3 l, vec3 v).

#define NDFMIP_MAX_LIGHTS 16

uniform vec3 ndfmipBackground;
uniform int ndfmipLightCount;
uniform int ndfmipLightType[NDFMIP_MAX_LIGHTS]; // 0 directional, 1 point
uniform vec3 ndfmipLightDirection[NDFMIP_MAX_LIGHTS];
uniform vec3 ndfmipLightPosition[NDFMIP_MAX_LIGHTS];
uniform vec3 ndfmipLightColor[NDFMIP_MAX_LIGHTS];

uniform int ndfmipTaps;
uniform float ndfmipLodBias;
uniform int ndfmipAnisotropy;
uniform int ndfmipShadeEachTexel; // 1: texel shading, 0: parameter blending
uniform vec2 ndfmipPixelShift;
uniform int ndfmipShowLevel; // 1: the LOD as false colour instead of shading (ndfmip view)
uniform int ndfmipHasAlbedoMap; // 1: its RGB in layer NDFMIP_LAYERS (ints: SPIR-V has no bool uniforms)

// The bake's linear planes, one layer each (RGBA), ndfmip's own levels as the mips.
uniform sampler2DArray ndfmipPlanes;
uniform int ndfmipLevelCount; // its levels (textureQueryLevels is not reliable on every driver)

layout(location = 0) out vec4 ndfmipColour;

vec3 ndfmipShadeLights(vec4 p[NDFMIP_LAYERS], vec3 albedo, NdfmipHit hit, vec3 view) {
    vec3 radiance = vec3(0.0f);
    for (int i = 0; i < ndfmipLightCount; ++i) {
        vec3 direction = ndfmipLightDirection[i];
        vec3 irradiance = ndfmipLightColor[i];
        if (ndfmipLightType[i] == 1) {
            vec3 d = ndfmipLightPosition[i] - hit.position;
            float d2 = dot(d, d);
            if (d2 <= 0.0f) continue;
            direction = d / sqrt(d2);
            irradiance = ndfmipLightColor[i] / d2;
        }
        vec3 l = ndfmipToTangent(hit, direction);
        if (l.z <= 0.0f) continue;
        radiance += irradiance * ndfmipShadeTexel(p, albedo, l, view);
    }
#ifdef NDFMIP_ENVIRONMENT
    radiance += ndfmipShadeEnvironment(p, albedo, hit, view);
#endif
    return radiance;
}

// Repeat wrapping in integers, dividing non-negative numbers only (GLSL leaves % of negative
// ones undefined, and llvmpipe's float mod(13, 1) is 1).
int ndfmipWrap1(int i, int n) {
    int q = i >= 0 ? i / n : -((n - 1 - i) / n);
    return i - q * n;
}
ivec2 ndfmipWrap(ivec2 i, ivec2 n) { return ivec2(ndfmipWrap1(i.x, n.x), ndfmipWrap1(i.y, n.y)); }

// Parameter blending: the probe's planes as the hardware filters them (trilinear at `lod`),
// added with weight `weight` into p and albedo.
void ndfmipAddFiltered(vec2 uv, float lod, float weight, inout vec4 p[NDFMIP_LAYERS], inout vec3 albedo) {
    lod = clamp(lod, 0.0f, float(ndfmipLevelCount - 1));
    for (int k = 0; k < NDFMIP_LAYERS; ++k) p[k] += weight * textureLod(ndfmipPlanes, vec3(uv, float(k)), lod);
    if (ndfmipHasAlbedoMap != 0) albedo += weight * textureLod(ndfmipPlanes, vec3(uv, float(NDFMIP_LAYERS)), lod).rgb;
}

// Texel shading: the eight texels of a trilinear probe at `lod`, each shaded, with weight `weight`.
vec3 ndfmipShadeProbeTexels(NdfmipHit hit, vec3 view, vec2 uv, float lod, float weight) {
    int last = ndfmipLevelCount - 1;
    lod = clamp(lod, 0.0f, float(last));
    int k0 = int(floor(lod));
    int k1 = min(k0 + 1, last);
    float f = lod - float(k0);
    vec4 p[NDFMIP_LAYERS];
    vec3 sum = vec3(0.0f);
    for (int level = 0; level < 2; ++level) {
        float levelWeight = level == 0 ? 1.0f - f : f;
        if (levelWeight == 0.0f) continue;
        int k = level == 0 ? k0 : k1;
        // GL's mip size rule from level 0 (llvmpipe's textureSize takes one lane's level for all).
        ivec2 size = max(textureSize(ndfmipPlanes, 0).xy >> ivec2(k), ivec2(1));
        vec2 x = uv * vec2(size) - 0.5f;
        vec2 x0 = floor(x);
        vec2 fr = x - x0;
        for (int j = 0; j < 4; ++j) {
            ivec2 offset = ivec2(j & 1, j >> 1);
            float w = (offset.x == 1 ? fr.x : 1.0f - fr.x) * (offset.y == 1 ? fr.y : 1.0f - fr.y);
            if (w == 0.0f) continue;
            ivec2 texel = ndfmipWrap(ivec2(x0) + offset, size);
            for (int c = 0; c < NDFMIP_LAYERS; ++c) p[c] = texelFetch(ndfmipPlanes, ivec3(texel, c), k);
            vec3 albedo = ndfmipMaterialAlbedo;
            if (ndfmipHasAlbedoMap != 0) albedo *= texelFetch(ndfmipPlanes, ivec3(texel, NDFMIP_LAYERS), k).rgb;
            sum += (weight * levelWeight * w) * ndfmipShadeLights(p, albedo, hit, view);
        }
    }
    return sum;
}

// The number of anisotropic probes along the footprint's major axis (as the CPU's filteredTaps:
// within 1% of square is square).
int ndfmipProbes(vec2 dx, vec2 dy) {
    vec2 size = vec2(textureSize(ndfmipPlanes, 0).xy);
    float lx = length(dx * size);
    float ly = length(dy * size);
    float minor = min(lx, ly);
    if (ndfmipAnisotropy > 1 && minor > 0.0f) return clamp(int(ceil(max(lx, ly) / minor - 0.01f)), 1, ndfmipAnisotropy);
    return 1;
}

// Each probe's LOD: log2 of the longer axis in level-0 texels over the probes, plus the bias.
float ndfmipLod(vec2 dx, vec2 dy, int probes) {
    vec2 size = vec2(textureSize(ndfmipPlanes, 0).xy);
    float major = max(length(dx * size), length(dy * size));
    return (probes == 1 ? (major > 0.0f ? log2(major) : 0.0f) : log2(major / float(probes))) + ndfmipLodBias;
}

// The viewer's false colour of a LOD: one hue per level, blended between levels.
vec3 ndfmipLevelColour(float lod) {
    lod = clamp(lod, 0.0f, float(ndfmipLevelCount - 1));
    float k = floor(lod);
    vec3 a = 0.5f + 0.5f * cos(6.2831853f * (k / 7.0f + vec3(0.0f, 0.33f, 0.67f)));
    vec3 b = 0.5f + 0.5f * cos(6.2831853f * ((k + 1.0f) / 7.0f + vec3(0.0f, 0.33f, 0.67f)));
    return mix(a, b, lod - k);
}

#ifdef NDFMIP_SPECULAR_AA
// Layer 0's unit normal as the lookup at `uv` filters it (its probes along `axis`, its LOD): what
// the engine's derivatives of the shading normal read at the neighbouring pixels.
vec3 ndfmipFilteredNormal(vec2 uv, vec2 axis, int probes, float lod) {
    lod = clamp(lod, 0.0f, float(ndfmipLevelCount - 1));
    vec3 n = vec3(0.0f);
    for (int i = 0; i < probes; ++i) {
        vec2 at = probes == 1 ? uv : uv + ((float(i) + 0.5f) / float(probes) - 0.5f) * axis;
        n += (1.0f / float(probes)) * textureLod(ndfmipPlanes, vec3(at, 0.0f), lod).xyz;
    }
    float length3 = length(n);
    return length3 > 0.0f ? n / length3 : vec3(0.0f, 0.0f, 1.0f);
}
#endif

// The lookup at a hit with footprint (dx, dy) in uv: one trilinear probe, or anisotropic probes
// along the major axis; parameters blended over all of them and shaded once, or every texel
// shaded.
vec3 ndfmipLookup(NdfmipHit hit, vec3 view, vec2 dx, vec2 dy) {
#ifdef NDFMIP_ENVIRONMENT_SH_PER_HIT
    // The SH lighting into this hit's frame, here once: called from the shading, which is inlined
    // at both of this function's call sites, the unrolled rotation was compiled twice.
    ndfmipEnvShRotate(hit);
#endif
    vec2 size = vec2(textureSize(ndfmipPlanes, 0).xy);
    int probes = ndfmipProbes(dx, dy);
    vec2 axis = length(dx * size) >= length(dy * size) ? dx : dy;
    float lod = ndfmipLod(dx, dy, probes);
#ifdef NDFMIP_SPECULAR_AA
    ndfmipAaKernel = 0.0f;
    if (ndfmipSpecularAaVariance > 0.0f) {
        vec3 n = ndfmipFilteredNormal(hit.uv, axis, probes, lod);
        ndfmipAaKernel = ndfmipSpecularAaKernel(ndfmipFilteredNormal(hit.uv + dx, axis, probes, lod) - n,
                                                ndfmipFilteredNormal(hit.uv + dy, axis, probes, lod) - n,
                                                ndfmipSpecularAaVariance, ndfmipSpecularAaThreshold);
    }
#endif
    vec4 p[NDFMIP_LAYERS];
    for (int k = 0; k < NDFMIP_LAYERS; ++k) p[k] = vec4(0.0f);
    vec3 albedo = vec3(0.0f);
    vec3 sum = vec3(0.0f);
    for (int i = 0; i < probes; ++i) {
        vec2 uv = probes == 1 ? hit.uv : hit.uv + ((float(i) + 0.5f) / float(probes) - 0.5f) * axis;
        if (ndfmipShadeEachTexel != 0) sum += ndfmipShadeProbeTexels(hit, view, uv, lod, 1.0f / float(probes));
        else ndfmipAddFiltered(uv, lod, 1.0f / float(probes), p, albedo);
    }
    if (ndfmipShadeEachTexel != 0) return sum;
    return ndfmipShadeLights(p, ndfmipHasAlbedoMap != 0 ? ndfmipMaterialAlbedo * albedo : ndfmipMaterialAlbedo, hit, view);
}

void main() {
    // The CPU renderer's pixel (x, y) from the top-left, sampled at its centre.
    float px = gl_FragCoord.x + ndfmipPixelShift.x;
    float py = ndfmipImageSize.y - gl_FragCoord.y + ndfmipPixelShift.y;
    int k = ndfmipTaps;
    float stepSize = 1.0f / float(k);
    vec3 sum = vec3(0.0f);
    for (int j = 0; j < k; ++j) {
        for (int i = 0; i < k; ++i) {
            float qx = k == 1 ? px : px + (float(i) + 0.5f) * stepSize - 0.5f;
            float qy = k == 1 ? py : py + (float(j) + 0.5f) * stepSize - 0.5f;
            NdfmipRay ray = ndfmipCameraRay(qx, qy);
            NdfmipHit hit = ndfmipIntersect(ray);
            if (!hit.hit) {
#ifdef NDFMIP_ENVIRONMENT
                if (ndfmipEnvVisible != 0) {
                    sum += ndfmipEnvironmentBackground(ray.direction);
                    continue;
                }
#endif
                sum += ndfmipBackground;
                continue;
            }
            vec3 view = ndfmipToTangent(hit, -ray.direction);
            if (view.z <= 0.0f) continue;
            vec2 dx = ndfmipUvOffset(hit, qx + 1.0f, qy) * stepSize;
            vec2 dy = ndfmipUvOffset(hit, qx, qy + 1.0f) * stepSize;
            if (ndfmipShowLevel != 0) sum += ndfmipLevelColour(ndfmipLod(dx, dy, ndfmipProbes(dx, dy)));
            else sum += ndfmipLookup(hit, view, dx, dy);
        }
    }
    ndfmipColour = vec4(sum * (stepSize * stepSize), 1.0f);
}
