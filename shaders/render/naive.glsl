// Render glue for the naive bake: layer 0 = "normal".
#define NDFMIP_LAYERS 1
#define NDFMIP_SPECULAR_AA
// The material, its alpha (GGX, Beckmann) widened by this lookup's specular anti-aliasing.
NdfmipMaterial ndfmipAaMaterial() {
    NdfmipMaterial m = ndfmipMaterial;
    if (ndfmipAaKernel > 0.0f && (m.brdf == NDFMIP_GGX || m.brdf == NDFMIP_BECKMANN))
        m.roughness = ndfmipSpecularAaAlpha(m.roughness, ndfmipAaKernel);
    return m;
}
vec3 ndfmipShadeTexel(vec4 p[NDFMIP_LAYERS], vec3 albedo, vec3 l, vec3 v) {
    return ndfmipShadeNaive(ndfmipAaMaterial(), albedo, p[0].xyz, l, v);
}
#ifdef NDFMIP_ENVIRONMENT
// Under an environment (render/environment.glsl).
vec3 ndfmipShadeEnvironment(vec4 p[NDFMIP_LAYERS], vec3 albedo, NdfmipHit hit, vec3 view) {
    return ndfmipShadeNaiveEnvironment(ndfmipAaMaterial(), albedo, p[0].xyz, ndfmipTangentFrame(hit), view);
}
#endif
