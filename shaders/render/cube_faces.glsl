// OpenGL's cube-map face table, faces +x, -x, +y, -y, +z, -z, and its inverse: one source for the
// GPU renderer (included before the files that read cube faces: Toksvig's normal cube map's LOD,
// normal_cube_lod.glsl, and the log2sigma rule's box chain, environment.glsl) and the CPU, which
// compiles it through glsl.h in float (the normal cube map, src/render/normal_cube_map.cpp) and in
// double (the environment's cube faces, src/env/cube_faces.cpp). No `float` is named here, so the
// double build keeps every operation in double.

// The point ab in [-1, 1]^2 of face `face` of the cube [-1, 1]^3, ab.x to the right, ab.y down
// (not normalised).
vec3 ndfmipCubeFaceDirection(int face, vec2 ab) {
    if (face == 0) return vec3(1.0f, -ab.y, -ab.x);
    if (face == 1) return vec3(-1.0f, -ab.y, ab.x);
    if (face == 2) return vec3(ab.x, 1.0f, ab.y);
    if (face == 3) return vec3(ab.x, -1.0f, -ab.y);
    if (face == 4) return vec3(ab.x, -ab.y, 1.0f);
    return vec3(-ab.x, -ab.y, -1.0f);
}

// The face d points into and the point of it d passes through, as ndfmipCubeFaceDirection takes
// them: its inverse for any d but 0. The largest of |x|, |y|, |z| picks the face, ties going to x,
// then y; the zero vector lands on the centre of +z.
struct NdfmipCubeFacePoint {
    int face;
    vec2 ab;
};

NdfmipCubeFacePoint ndfmipCubeFacePoint(vec3 d) {
    vec3 m = abs(d);
    NdfmipCubeFacePoint p;
    if (!(max(m.x, max(m.y, m.z)) > 0.0f)) {
        p.face = 4;
        p.ab = vec2(0.0f);
    } else if (m.x >= m.y && m.x >= m.z) {
        p.face = d.x >= 0.0f ? 0 : 1;
        p.ab = vec2(d.x >= 0.0f ? -d.z : d.z, -d.y) / m.x;
    } else if (m.y >= m.z) {
        p.face = d.y >= 0.0f ? 2 : 3;
        p.ab = vec2(d.x, d.y >= 0.0f ? d.z : -d.z) / m.y;
    } else {
        p.face = d.z >= 0.0f ? 4 : 5;
        p.ab = vec2(d.z >= 0.0f ? d.x : -d.x, -d.y) / m.z;
    }
    return p;
}
