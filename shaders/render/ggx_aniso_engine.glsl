// Render glue for ggx-aniso-khr, ggx-aniso-kulla and ggx-aniso-burley: ggx-aniso's lobe as an
// engine samples its files: layer 0 = "normal", layer 1 = the engine's channels (the roughness,
// the direction's two, the anisotropy), blended by the lookup and decoded after by
// NDFMIP_ENGINE_ANISOTROPY (ggx_aniso.glsl's decoders; KHR_materials_anisotropy's without it).
#define NDFMIP_LAYERS 2
#ifndef NDFMIP_ENGINE_ANISOTROPY
#define NDFMIP_ENGINE_ANISOTROPY ndfmipKhrAnisotropyTensor
#endif
vec3 ndfmipShadeTexel(vec4 p[NDFMIP_LAYERS], vec3 albedo, vec3 l, vec3 v) {
    return ndfmipShadeGgxAniso(ndfmipMaterial, albedo, p[0].xyz, NDFMIP_ENGINE_ANISOTROPY(p[1]), l, v);
}
#ifdef NDFMIP_ENVIRONMENT
// Under an environment (render/environment.glsl): as ggx-aniso, at the decoded tensor's isotropic
// alpha.
vec3 ndfmipShadeEnvironment(vec4 p[NDFMIP_LAYERS], vec3 albedo, NdfmipHit hit, vec3 view) {
    return ndfmipShadeRoughnessMipsEnvironment(ndfmipMaterial, albedo, p[0].xyz,
                                               ndfmipGgxAnisoAlpha(NDFMIP_ENGINE_ANISOTROPY(p[1])), true,
                                               ndfmipTangentFrame(hit), view);
}
#endif
