// Render glue for ggx-fit: layer 0 = the bake's "normal", layer 1 = "roughness_ggx" (GGX alpha),
// both blended by the lookup as an engine blends its normal and roughness maps.
#define NDFMIP_LAYERS 2
vec3 ndfmipShadeTexel(vec4 p[NDFMIP_LAYERS], vec3 albedo, vec3 l, vec3 v) {
    return ndfmipShadeRoughnessMips(ndfmipMaterial, albedo, p[0].xyz, p[1].x, true, l, v);
}
#ifdef NDFMIP_ENVIRONMENT
// Under an environment (render/environment.glsl).
vec3 ndfmipShadeEnvironment(vec4 p[NDFMIP_LAYERS], vec3 albedo, NdfmipHit hit, vec3 view) {
    return ndfmipShadeRoughnessMipsEnvironment(ndfmipMaterial, albedo, p[0].xyz, p[1].x, true, hit, view);
}
#endif
