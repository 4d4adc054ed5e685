// Render glue for the sh bake: layers "sh0" .. (NDFMIP_LAYERS, set by the renderer: four
// coefficients each); the material's A_l as uniforms.
uniform int ndfmipShOrder;
uniform float ndfmipShDiffuse[NDFMIP_SH_MAX_ORDER + 1];
uniform float ndfmipShSpecular[NDFMIP_SH_MAX_ORDER + 1];
vec3 ndfmipShadeTexel(vec4 p[NDFMIP_LAYERS], vec3 albedo, vec3 l, vec3 v) {
    float g[NDFMIP_SH_MAX_COEFFICIENTS];
    for (int k = 0; k < NDFMIP_SH_MAX_COEFFICIENTS; ++k) g[k] = k < 4 * NDFMIP_LAYERS ? p[k / 4][k % 4] : 0.0f;
    return ndfmipShadeSh(ndfmipMaterial, albedo, g, ndfmipShDiffuse, ndfmipShSpecular, ndfmipShOrder, l, v);
}
#ifdef NDFMIP_ENVIRONMENT
// Under an environment (render/environment.glsl, the SH-lighting way).
vec3 ndfmipShadeEnvironment(vec4 p[NDFMIP_LAYERS], vec3 albedo, NdfmipHit hit, vec3 view) {
    float g[NDFMIP_SH_MAX_COEFFICIENTS];
    for (int k = 0; k < NDFMIP_SH_MAX_COEFFICIENTS; ++k) g[k] = k < 4 * NDFMIP_LAYERS ? p[k / 4][k % 4] : 0.0f;
    return ndfmipShadeShEnvironment(ndfmipMaterial, albedo, g, ndfmipShOrder, hit);
}
#endif
