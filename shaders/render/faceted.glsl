// ndfmip's GPU renderer for faceted-sphere scenes: the mesh and Toksvig's normalisation cube map
// (src/render/normal_cube_map.cpp) as textures. Needs raycast.glsl (the camera); then
// faceted_trace.glsl traces the mesh and normal_cube_lod.glsl gives the cube map's LOD, both
// the CPU's own sources.

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
