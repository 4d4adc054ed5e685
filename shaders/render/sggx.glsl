// Render glue for sggx on the lean bake: layer 0 = "lean_moments", layer 1 = "lean_cross".
#define NDFMIP_LAYERS 2
vec3 ndfmipShadeTexel(vec4 p[NDFMIP_LAYERS], vec3 albedo, vec3 l, vec3 v) {
    return ndfmipShadeSggx(ndfmipMaterial, albedo, p[0], p[1].x, l, v);
}
