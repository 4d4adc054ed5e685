// A faceted UV sphere traced per ray: Moller-Trumbore on each triangle and the interpolated
// (Phong) vertex normal. One source for the CPU renderer (src/render/faceted_sphere.cpp, through
// glsl.h) and the GPU renderer (after faceted.glsl). Needs NdfmipRay (origin, direction) and the
// mesh as each side holds it (the CPU's FacetedSphereMesh, the GPU's texture):
//   ivec3 ndfmipTriangle(int k)      triangle k's vertex indices
//   vec3 ndfmipVertex(int i)         vertex i's position
//   vec3 ndfmipVertexNormal(int i)   vertex i's unit normal
//   vec3 ndfmipFaceNormal(int k)     triangle k's unit normal, away from the centre
//   int ndfmipTriangleCount; vec3 ndfmipCenter; float ndfmipRadius (the circumscribed sphere)

struct NdfmipFacetedHit {
    bool hit;
    float t;
    vec3 position;
    int triangle;
    vec3 faceNormal;
    vec3 interpolated; // b0 n0 + b1 n1 + b2 n2, not renormalised
};

// Where a ray meets a triangle's plane: t and the barycentrics (u, v) of its second and third
// vertices, no bounds on u, v; not valid for a ray parallel to the plane.
struct NdfmipPlaneCrossing {
    bool valid;
    float t;
    float u;
    float v;
};

// Moller-Trumbore.
NdfmipPlaneCrossing ndfmipRayPlaneBarycentrics(int triangle, NdfmipRay ray) {
    NdfmipPlaneCrossing x;
    x.valid = false;
    x.t = 0.0f;
    x.u = 0.0f;
    x.v = 0.0f;
    ivec3 tri = ndfmipTriangle(triangle);
    vec3 p0 = ndfmipVertex(tri.x);
    vec3 e1 = ndfmipVertex(tri.y) - p0;
    vec3 e2 = ndfmipVertex(tri.z) - p0;
    vec3 p = cross(ray.direction, e2);
    float det = dot(e1, p);
    if (abs(det) < 1e-20f) return x;
    float inv = 1.0f / det;
    vec3 s = ray.origin - p0;
    x.u = dot(s, p) * inv;
    vec3 q = cross(s, e1);
    x.v = dot(ray.direction, q) * inv;
    x.t = dot(e2, q) * inv;
    x.valid = true;
    return x;
}

vec3 ndfmipInterpolate(int triangle, float u, float v) {
    ivec3 tri = ndfmipTriangle(triangle);
    return (1.0f - u - v) * ndfmipVertexNormal(tri.x) + u * ndfmipVertexNormal(tri.y) + v * ndfmipVertexNormal(tri.z);
}

// The nearest triangle the ray meets (t > 0), the first in the mesh's order on a tie.
NdfmipFacetedHit ndfmipIntersectFaceted(NdfmipRay ray) {
    NdfmipFacetedHit hit;
    hit.hit = false;
    hit.t = 0.0f;
    hit.position = vec3(0.0f);
    hit.triangle = -1;
    hit.faceNormal = vec3(0.0f, 0.0f, 1.0f);
    hit.interpolated = vec3(0.0f, 0.0f, 1.0f);
    // Every facet lies inside the circumscribed sphere: rays that miss it miss them all.
    vec3 oc = ray.origin - ndfmipCenter;
    float b = dot(oc, ray.direction);
    float c = dot(oc, oc) - ndfmipRadius * ndfmipRadius;
    if (c > 0.0f && (b > 0.0f || b * b - c * dot(ray.direction, ray.direction) < 0.0f)) return hit;
    float best = uintBitsToFloat(0x7F800000u); // +infinity
    float bestU = 0.0f;
    float bestV = 0.0f;
    for (int k = 0; k < ndfmipTriangleCount; ++k) {
        NdfmipPlaneCrossing x = ndfmipRayPlaneBarycentrics(k, ray);
        if (!x.valid) continue;
        // A small tolerance on the edges keeps rays through a shared edge from slipping between.
        const float edge = -1e-6f;
        if (x.u < edge || x.v < edge || x.u + x.v > 1.0f - edge || !(x.t > 0.0f) || x.t >= best) continue;
        best = x.t;
        hit.triangle = k;
        bestU = x.u;
        bestV = x.v;
    }
    if (hit.triangle < 0) return hit;
    hit.hit = true;
    hit.t = best;
    hit.position = ray.origin + best * ray.direction;
    hit.faceNormal = ndfmipFaceNormal(hit.triangle);
    hit.interpolated = ndfmipInterpolate(hit.triangle, bestU, bestV);
    return hit;
}

// The interpolated normal (not renormalised) where `ray` meets the plane of `triangle`, with
// barycentrics extrapolated beyond its edges: what a GPU's screen-space derivative of the
// interpolated attribute sees at a neighbouring pixel. `fallback` for a ray parallel to the plane.
vec3 ndfmipInterpolatedOnPlane(int triangle, NdfmipRay ray, vec3 fallback) {
    NdfmipPlaneCrossing x = ndfmipRayPlaneBarycentrics(triangle, ray);
    if (!x.valid || isinf(x.u) || isnan(x.u) || isinf(x.v) || isnan(x.v)) return fallback;
    return ndfmipInterpolate(triangle, x.u, x.v);
}
