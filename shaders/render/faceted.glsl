// ndfmip's GPU renderer for faceted-sphere scenes: the mesh traced per pixel exactly as the CPU
// does (src/render/faceted_sphere.cpp), and Toksvig's normalisation cube map looked up at the
// CPU's LOD (src/render/normal_cube_map.cpp). Needs raycast.glsl (the camera).

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

struct NdfmipFacetedHit {
    bool hit;
    vec3 position;
    int triangle;
    vec3 faceNormal;
    vec3 interpolated; // b0 n0 + b1 n1 + b2 n2, not renormalised
};

ivec3 ndfmipTriangle(int k) { return ivec3(texelFetch(ndfmipMesh, ivec2(k, 3), 0).xyz); }
vec3 ndfmipVertex(int i) { return texelFetch(ndfmipMesh, ivec2(i, 0), 0).xyz; }
vec3 ndfmipVertexNormal(int i) { return texelFetch(ndfmipMesh, ivec2(i, 1), 0).xyz; }

// Moller-Trumbore, operation for operation as the CPU's rayPlaneBarycentrics: t and the
// barycentrics (u, v) of the triangle's second and third vertices, no bounds on u, v.
bool ndfmipRayPlaneBarycentrics(int triangle, NdfmipRay ray, out float t, out float u, out float v) {
    ivec3 tri = ndfmipTriangle(triangle);
    vec3 p0 = ndfmipVertex(tri.x);
    vec3 e1 = ndfmipVertex(tri.y) - p0;
    vec3 e2 = ndfmipVertex(tri.z) - p0;
    vec3 p = cross(ray.direction, e2);
    float det = dot(e1, p);
    t = u = v = 0.0f;
    if (abs(det) < 1e-20f) return false;
    float inv = 1.0f / det;
    vec3 s = ray.origin - p0;
    u = dot(s, p) * inv;
    vec3 q = cross(s, e1);
    v = dot(ray.direction, q) * inv;
    t = dot(e2, q) * inv;
    return true;
}

vec3 ndfmipInterpolate(int triangle, float u, float v) {
    ivec3 tri = ndfmipTriangle(triangle);
    return (1.0f - u - v) * ndfmipVertexNormal(tri.x) + u * ndfmipVertexNormal(tri.y) + v * ndfmipVertexNormal(tri.z);
}

// The nearest triangle the ray meets (t > 0), the first in the CPU's order on a tie.
NdfmipFacetedHit ndfmipIntersectFaceted(NdfmipRay ray) {
    NdfmipFacetedHit hit;
    hit.hit = false;
    hit.triangle = -1;
    // Every facet lies inside the circumscribed sphere: rays that miss it miss them all.
    vec3 oc = ray.origin - ndfmipCenter;
    float b = dot(oc, ray.direction);
    float c = dot(oc, oc) - ndfmipRadius * ndfmipRadius;
    if (c > 0.0f && (b > 0.0f || b * b - c * dot(ray.direction, ray.direction) < 0.0f)) return hit;
    float best = uintBitsToFloat(0x7F800000u); // +infinity
    float bestU = 0.0f, bestV = 0.0f;
    for (int k = 0; k < ndfmipTriangleCount; ++k) {
        float t, u, v;
        if (!ndfmipRayPlaneBarycentrics(k, ray, t, u, v)) continue;
        // The CPU's tolerance on the edges: rays through a shared edge do not slip between.
        const float edge = -1e-6f;
        if (u < edge || v < edge || u + v > 1.0f - edge || !(t > 0.0f) || t >= best) continue;
        best = t;
        hit.triangle = k;
        bestU = u;
        bestV = v;
    }
    if (hit.triangle < 0) return hit;
    hit.hit = true;
    hit.position = ray.origin + best * ray.direction;
    hit.faceNormal = texelFetch(ndfmipMesh, ivec2(hit.triangle, 2), 0).xyz;
    hit.interpolated = ndfmipInterpolate(hit.triangle, bestU, bestV);
    return hit;
}

// The interpolated normal where `ray` meets the plane of `triangle`, barycentrics extrapolated
// beyond its edges (the CPU's interpolatedNormalOnPlane); `fallback` for a parallel ray.
vec3 ndfmipInterpolatedOnPlane(int triangle, NdfmipRay ray, vec3 fallback) {
    float t, u, v;
    if (!ndfmipRayPlaneBarycentrics(triangle, ray, t, u, v) || isinf(u) || isnan(u) || isinf(v) || isnan(v))
        return fallback;
    return ndfmipInterpolate(triangle, u, v);
}

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
