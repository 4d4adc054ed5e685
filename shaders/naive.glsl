// ndfmip shading library: the standard mipmap (needs brdf.glsl).
//
// Texture: the naive bake's "normal" plane (RGB, mipmapped, trilinear), the mean normal.

// The filtered normal renormalised, the material unchanged.
vec3 ndfmipShadeNaive(NdfmipMaterial m, vec3 albedo, vec3 filtered, vec3 l, vec3 v) {
    float len = sqrt(dot(filtered, filtered));
    vec3 n = len > 0.0f ? filtered / len : vec3(0.0f, 0.0f, 1.0f);
    return ndfmipShadeNormal(m, albedo, n, l, normalize(l + v));
}

// An engine's inputs: the normal mipmap and a roughness mip chain (`stored`: perceptual,
// alpha = stored^2, unless isAlpha), the material's Beckmann or GGX lobe at that alpha.
vec3 ndfmipShadeRoughnessMips(NdfmipMaterial m, vec3 albedo, vec3 filtered, float stored, bool isAlpha, vec3 l,
                              vec3 v) {
    float r = clamp(stored, 0.0f, 1.0f);
    NdfmipMaterial widened = m;
    widened.roughness = max(isAlpha ? r : r * r, 1e-4f);
    return ndfmipShadeNaive(widened, albedo, filtered, l, v);
}
