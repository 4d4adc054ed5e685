// Render glue for the toksvig bake: layer 0 = "mean" (Na, not renormalised).
#define NDFMIP_LAYERS 1
uniform int ndfmipMapping;
uniform float ndfmipVarianceScale;
vec3 ndfmipShadeTexel(vec4 p[NDFMIP_LAYERS], vec3 albedo, vec3 l, vec3 v) {
    return ndfmipShadeToksvig(ndfmipMaterial, albedo, p[0].xyz, l, v, ndfmipMapping, ndfmipVarianceScale);
}
#ifdef NDFMIP_ENVIRONMENT
// Under an environment (render/environment.glsl).
vec3 ndfmipShadeEnvironment(vec4 p[NDFMIP_LAYERS], vec3 albedo, NdfmipHit hit, vec3 view) {
    return ndfmipShadeToksvigEnvironment(ndfmipMaterial, albedo, p[0].xyz, ndfmipTangentFrame(hit), view, ndfmipMapping, ndfmipVarianceScale);
}
#endif
