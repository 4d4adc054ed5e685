// ndfmip shading library: Toksvig's 2D lookup table (T eq. 9, phase-out T eqs. 10-11; needs
// brdf.glsl and toksvig.glsl).
//
// Textures: the toksvig bake's "mean" plane (Na, not renormalised) and the table written by
// `ndfmip lut --exponent S --bits 8` (one channel, 256 x 256, linear filtering, clamp to edge,
// no mipmaps). The table holds the lobe relative to the unfiltered highlight, at
// (u, v) = (Na.H, Na.Na) with v = 0 in the first row, as the paper's pseudo-code looks it up.

vec2 ndfmipToksvigLutCoordinates(vec3 na, vec3 h) { return vec2(dot(na, h), dot(na, na)); }

// The table's relative value made absolute by the unfiltered lobe's peak (s + 1)/(2 pi).
float ndfmipToksvigLutLobe(float exponent, float relative) { return (exponent + 1.0f) / (2.0f * NDFMIP_PI) * relative; }

vec3 ndfmipShadeToksvigLut(NdfmipMaterial m, vec3 albedo, vec3 na, float relative, vec3 l, vec3 v) {
    return ndfmipShadeToksvigLobe(m, albedo, na, l, v, ndfmipToksvigLutLobe(m.exponent, relative));
}
