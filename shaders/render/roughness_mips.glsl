// Render glue for an engine's normal mipmap with roughness mips: layer 0 = the naive bake's
// "normal", layer 1 = the roughness (perceptual unless ndfmipRoughnessIsAlpha).
#define NDFMIP_LAYERS 2
uniform int ndfmipRoughnessIsAlpha; // 1: alpha, 0: perceptual
#define NDFMIP_SPECULAR_AA
// The stored roughness widened by this lookup's specular anti-aliasing, in its own encoding.
float ndfmipAaRoughness(float stored) {
    return ndfmipAaKernel > 0.0f ? ndfmipSpecularAaStored(stored, ndfmipRoughnessIsAlpha != 0, ndfmipAaKernel)
                                 : stored;
}
vec3 ndfmipShadeTexel(vec4 p[NDFMIP_LAYERS], vec3 albedo, vec3 l, vec3 v) {
    return ndfmipShadeRoughnessMips(ndfmipMaterial, albedo, p[0].xyz, ndfmipAaRoughness(p[1].x),
                                    ndfmipRoughnessIsAlpha != 0, l, v);
}
#ifdef NDFMIP_ENVIRONMENT
// Under an environment (render/environment.glsl).
vec3 ndfmipShadeEnvironment(vec4 p[NDFMIP_LAYERS], vec3 albedo, NdfmipHit hit, vec3 view) {
    return ndfmipShadeRoughnessMipsEnvironment(ndfmipMaterial, albedo, p[0].xyz, ndfmipAaRoughness(p[1].x),
                                               ndfmipRoughnessIsAlpha != 0,
                                               ndfmipTangentFrame(hit), view);
}
#endif
