// ndfmip's GPU renderer for faceted-sphere scenes: the mesh as faceted_trace.glsl (the CPU's own
// source) traces it, and Toksvig's normalisation cube map looked up at the CPU's LOD
// (src/render/normal_cube_map.cpp). Needs raycast.glsl (the camera); faceted_trace.glsl follows.

// The mesh as the CPU builds it, one RGBA32F texel per item: row 0 the vertices' positions,
// row 1 their unit normals, row 2 the triangles' face normals, row 3 the triangles' vertex
// indices (exact in floats). Read with texelFetch, so nothing is re-derived with the GPU's
// own trigonometry.
uniform sampler2D ndfmipMesh;
uniform int ndfmipTriangleCount;

// Toksvig's cube map, ndfmip's levels as its mips (not renormalised), and its LOD bias.
uniform samplerCube ndfmipNormalCube;
uniform int ndfmipNormalCubeSize; // level 0's face side in texels
uniform float ndfmipNormalCubeLodBias;

ivec3 ndfmipTriangle(int k) { return ivec3(texelFetch(ndfmipMesh, ivec2(k, 3), 0).xyz); }
vec3 ndfmipVertex(int i) { return texelFetch(ndfmipMesh, ivec2(i, 0), 0).xyz; }
vec3 ndfmipVertexNormal(int i) { return texelFetch(ndfmipMesh, ivec2(i, 1), 0).xyz; }
vec3 ndfmipFaceNormal(int k) { return texelFetch(ndfmipMesh, ivec2(k, 2), 0).xyz; }

// The face d points into, as the CPU's cubeFaceCoordinates (ndfmipCubeFaceDirection's table:
// cube_faces.glsl).
int ndfmipCubeFace(vec3 d) {
    vec3 m = abs(d);
    if (m.x >= m.y && m.x >= m.z) return d.x >= 0.0f ? 0 : 1;
    if (m.y >= m.z) return d.y >= 0.0f ? 2 : 3;
    return d.z >= 0.0f ? 4 : 5;
}

// The CPU's normalCubeMapLod: n and its neighbours one pixel right (nx) and down (ny)
// projected onto n's face (its plane extended), the footprint's longer axis in level-0 texels
// rho, log2(rho) (0 when rho <= 1). A GPU's own cube LOD (implicit derivatives) differs by
// driver; this one is the CPU's to rounding.
float ndfmipNormalCubeLod(vec3 n, vec3 nx, vec3 ny) {
    int face = ndfmipCubeFace(n);
    vec3 axis = ndfmipCubeFaceDirection(face, 0.0f, 0.0f);
    vec3 right = ndfmipCubeFaceDirection(face, 1.0f, 0.0f) - axis;
    vec3 down = ndfmipCubeFaceDirection(face, 0.0f, 1.0f) - axis;
    float ma = dot(n, axis);
    vec2 centre = ma > 0.0f ? vec2(dot(n, right), dot(n, down)) / ma : vec2(0.0f);
    vec2 offsets[2];
    vec3 neighbours[2] = vec3[2](nx, ny);
    for (int i = 0; i < 2; ++i) {
        float mi = dot(neighbours[i], axis);
        // Behind the face: a huge footprint.
        offsets[i] = mi > 0.0f ? vec2(dot(neighbours[i], right), dot(neighbours[i], down)) / mi - centre : vec2(1e6f);
    }
    float texels = 0.5f * float(ndfmipNormalCubeSize); // per unit of face coordinate
    float rho = texels * max(length(offsets[0]), length(offsets[1]));
    return rho > 1.0f ? log2(rho) : 0.0f;
}
