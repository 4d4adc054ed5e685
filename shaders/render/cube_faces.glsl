// OpenGL's cube-map face table, as the CPU's cubeFaceDirection (environment.h): faces +x, -x,
// +y, -y, +z, -z. Included before the files that read cube faces: Toksvig's normal cube map's
// LOD (faceted.glsl) and the log2sigma rule's box chain (environment.glsl).

// The point (a, b) in [-1, 1]^2 of face `face` of the cube [-1, 1]^3, a to the right, b down
// (not normalised).
vec3 ndfmipCubeFaceDirection(int face, float a, float b) {
    if (face == 0) return vec3(1.0f, -b, -a);
    if (face == 1) return vec3(-1.0f, -b, a);
    if (face == 2) return vec3(a, 1.0f, b);
    if (face == 3) return vec3(a, -1.0f, -b);
    if (face == 4) return vec3(a, -b, 1.0f);
    return vec3(-a, -b, -1.0f);
}
