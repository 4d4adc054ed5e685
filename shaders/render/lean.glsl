// Render glue for the lean bake: layer 0 = "lean_moments", layer 1 = "lean_cross".
#define NDFMIP_LAYERS 2
vec3 ndfmipShadeTexel(vec4 p[NDFMIP_LAYERS], vec3 albedo, vec3 l, vec3 v) {
    return ndfmipShadeLean(ndfmipMaterial, albedo, p[0], p[1].x, l, v);
}
