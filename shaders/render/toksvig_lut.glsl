// Render glue for Toksvig's table: layer 0 = the toksvig bake's "mean"; ndfmipLut = the table
// of the material's exponent (linear, clamped, no mips).
#define NDFMIP_LAYERS 1
uniform sampler2D ndfmipLut;
vec3 ndfmipShadeTexel(vec4 p[NDFMIP_LAYERS], vec3 albedo, vec3 l, vec3 v) {
    vec3 na = p[0].xyz;
    float relative = textureLod(ndfmipLut, ndfmipToksvigLutCoordinates(na, normalize(l + v)), 0.0f).r;
    return ndfmipShadeToksvigLut(ndfmipMaterial, albedo, na, relative, l, v);
}
