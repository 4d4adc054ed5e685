// Render glue for ggx-aniso: layer 0 = "normal", layer 1 = "alpha_moments".
#define NDFMIP_LAYERS 2
#define NDFMIP_SPECULAR_AA
// The blended lookup's tensor (ndfmipGgxAnisoTensor), with this lookup's specular anti-aliasing
// added along every direction.
vec3 ndfmipLookupTensor(vec4 p[NDFMIP_LAYERS]) {
    vec3 a = ndfmipGgxAnisoTensor(p[1].xyz, p[0].xyz);
    return ndfmipAaKernel > 0.0f ? ndfmipSpecularAaTensor(a, ndfmipAaKernel) : a;
}
vec3 ndfmipShadeTexel(vec4 p[NDFMIP_LAYERS], vec3 albedo, vec3 l, vec3 v) {
    return ndfmipShadeGgxAniso(ndfmipMaterial, albedo, p[0].xyz, ndfmipLookupTensor(p), l, v);
}
#ifdef NDFMIP_ENVIRONMENT
// Under an environment (render/environment.glsl): an engine's split sum at the tensor's
// isotropic alpha.
vec3 ndfmipShadeEnvironment(vec4 p[NDFMIP_LAYERS], vec3 albedo, NdfmipHit hit, vec3 view) {
    return ndfmipShadeRoughnessMipsEnvironment(ndfmipMaterial, albedo, p[0].xyz,
                                               ndfmipGgxAnisoAlpha(ndfmipLookupTensor(p)), true,
                                               ndfmipTangentFrame(hit), view);
}
#endif
