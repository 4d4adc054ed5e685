// Render glue for ggx-aniso-khr: ggx-aniso's lobe as a glTF engine samples its
// KHR_materials_anisotropy textures: layer 0 = "normal", layer 1 = "khr_anisotropy" (the
// roughness, the anisotropyTexture's R, G, B), the channels blended by the lookup and decoded after.
#define NDFMIP_LAYERS 2
vec3 ndfmipShadeTexel(vec4 p[NDFMIP_LAYERS], vec3 albedo, vec3 l, vec3 v) {
    return ndfmipShadeGgxAniso(ndfmipMaterial, albedo, p[0].xyz, ndfmipKhrAnisotropyTensor(p[1]), l, v);
}
#ifdef NDFMIP_ENVIRONMENT
// Under an environment (render/environment.glsl): as ggx-aniso, at the decoded tensor's isotropic
// alpha.
vec3 ndfmipShadeEnvironment(vec4 p[NDFMIP_LAYERS], vec3 albedo, NdfmipHit hit, vec3 view) {
    return ndfmipShadeRoughnessMipsEnvironment(ndfmipMaterial, albedo, p[0].xyz,
                                               ndfmipGgxAnisoAlpha(ndfmipKhrAnisotropyTensor(p[1])), true,
                                               ndfmipTangentFrame(hit), view);
}
#endif
