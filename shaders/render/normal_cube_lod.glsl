// The LOD of Toksvig's normalisation cube map at an interpolated normal: one source for the CPU
// renderer (src/render/normal_cube_map.cpp, through glsl.h) and the GPU renderer (after
// faceted.glsl). Needs cube_faces.glsl and int ndfmipNormalCubeSize, level 0's face side in
// texels (the CPU's map, the GPU's uniform).

// A neighbour d projected onto the face whose centre is `axis` (its plane extended), in the face's
// coordinates (right, down); behind the face, a huge offset from `centre`.
vec2 ndfmipCubeFaceOffset(vec3 d, vec3 axis, vec3 right, vec3 down, vec2 centre) {
    float ma = dot(d, axis);
    if (!(ma > 0.0f)) return vec2(1e6f);
    return vec2(dot(d, right), dot(d, down)) / ma - centre;
}

// n and its neighbours one pixel right (nx) and down (ny) projected onto n's face, as a GPU
// differentiates the face coordinates of the pixel quad within the face the centre selects; the
// footprint's longer axis in level-0 texels rho, log2(rho) (0 when rho <= 1). A GPU's own cube
// LOD (implicit derivatives) differs by driver; this one is the same on both sides to rounding.
float ndfmipNormalCubeLod(vec3 n, vec3 nx, vec3 ny) {
    int face = ndfmipCubeFacePoint(n).face;
    vec3 axis = ndfmipCubeFaceDirection(face, vec2(0.0f));
    vec3 right = ndfmipCubeFaceDirection(face, vec2(1.0f, 0.0f)) - axis;
    vec3 down = ndfmipCubeFaceDirection(face, vec2(0.0f, 1.0f)) - axis;
    float ma = dot(n, axis);
    vec2 centre = ma > 0.0f ? vec2(dot(n, right), dot(n, down)) / ma : vec2(0.0f);
    float texels = 0.5f * float(ndfmipNormalCubeSize); // per unit of face coordinate
    float rho = texels * max(length(ndfmipCubeFaceOffset(nx, axis, right, down, centre)),
                             length(ndfmipCubeFaceOffset(ny, axis, right, down, centre)));
    return rho > 1.0f ? log2(rho) : 0.0f;
}
