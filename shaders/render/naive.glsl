// Render glue for the naive bake: layer 0 = "normal".
#define NDFMIP_LAYERS 1
vec3 ndfmipShadeTexel(vec4 p[NDFMIP_LAYERS], vec3 albedo, vec3 l, vec3 v) {
    return ndfmipShadeNaive(ndfmipMaterial, albedo, p[0].xyz, l, v);
}
#ifdef NDFMIP_ENVIRONMENT
// Under an environment (render/environment.glsl).
vec3 ndfmipShadeEnvironment(vec4 p[NDFMIP_LAYERS], vec3 albedo, NdfmipHit hit, vec3 view) {
    return ndfmipShadeNaiveEnvironment(ndfmipMaterial, albedo, p[0].xyz, ndfmipTangentFrame(hit), view);
}
#endif
