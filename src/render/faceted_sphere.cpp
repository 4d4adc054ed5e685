// A faceted UV sphere with interpolated (Phong) vertex normals: the mesh, ray-triangle
// intersection (Moller-Trumbore) and the interpolated normal on a triangle's plane.
#include <cmath>
#include <limits>

#include "ndfmip/interpolated.h"

namespace ndfmip {

FacetedSphereMesh facetedSphereMesh(const Geometry& g) {
    FacetedSphereMesh mesh;
    mesh.center = g.center;
    mesh.radius = g.radius;
    const int segments = g.segments, rings = g.rings;
    // Vertex (i, j) for rings + 1 polar angles and `segments` azimuths; the poles repeat per
    // azimuth (same point, same normal), which keeps the indexing a plain grid.
    auto index = [&](int i, int j) { return i * segments + (j % segments); };
    for (int i = 0; i <= rings; ++i) {
        const double theta = M_PI * double(i) / double(rings);
        for (int j = 0; j < segments; ++j) {
            const double phi = 2.0 * M_PI * double(j) / double(segments);
            const glm::vec3 n(glm::dvec3(std::sin(theta) * std::cos(phi),
                                         std::sin(theta) * std::sin(phi), std::cos(theta)));
            mesh.normals.push_back(n);
            mesh.positions.push_back(g.center + g.radius * n);
        }
    }
    for (int i = 0; i < rings; ++i)
        for (int j = 0; j < segments; ++j) {
            const int a = index(i, j), b = index(i, j + 1), c = index(i + 1, j),
                      d = index(i + 1, j + 1);
            if (i > 0)
                mesh.triangles.emplace_back(a, c, b); // skips the degenerate one at the north pole
            if (i < rings - 1) mesh.triangles.emplace_back(b, c, d); // and at the south pole
        }
    for (const glm::ivec3& t : mesh.triangles) {
        const glm::vec3 p0 = mesh.positions[t.x], p1 = mesh.positions[t.y],
                        p2 = mesh.positions[t.z];
        glm::vec3 n = glm::normalize(glm::cross(p1 - p0, p2 - p0));
        if (glm::dot(n, (p0 + p1 + p2) / 3.f - g.center) < 0.f) n = -n;
        mesh.faceNormals.push_back(n);
    }
    return mesh;
}

namespace {

// Moller-Trumbore: t and the barycentrics (u, v) of p1 and p2; no bounds on u, v.
bool rayPlaneBarycentrics(const FacetedSphereMesh& mesh, int triangle, const Ray& ray, float& t,
                          float& u, float& v) {
    const glm::ivec3 tri = mesh.triangles[size_t(triangle)];
    const glm::vec3 p0 = mesh.positions[tri.x];
    const glm::vec3 e1 = mesh.positions[tri.y] - p0, e2 = mesh.positions[tri.z] - p0;
    const glm::vec3 p = glm::cross(ray.direction, e2);
    const float det = glm::dot(e1, p);
    if (std::abs(det) < 1e-20f) return false;
    const float inv = 1.f / det;
    const glm::vec3 s = ray.origin - p0;
    u = glm::dot(s, p) * inv;
    const glm::vec3 q = glm::cross(s, e1);
    v = glm::dot(ray.direction, q) * inv;
    t = glm::dot(e2, q) * inv;
    return true;
}

glm::vec3 interpolate(const FacetedSphereMesh& mesh, int triangle, float u, float v) {
    const glm::ivec3 tri = mesh.triangles[size_t(triangle)];
    return (1.f - u - v) * mesh.normals[tri.x] + u * mesh.normals[tri.y] + v * mesh.normals[tri.z];
}

} // namespace

FacetedHit intersectFacetedSphere(const FacetedSphereMesh& mesh, const Ray& ray) {
    FacetedHit hit;
    // Every facet lies inside the circumscribed sphere: rays that miss it miss them all.
    const glm::vec3 oc = ray.origin - mesh.center;
    const float b = glm::dot(oc, ray.direction);
    const float c = glm::dot(oc, oc) - mesh.radius * mesh.radius;
    if (c > 0.f && (b > 0.f || b * b - c * glm::dot(ray.direction, ray.direction) < 0.f))
        return hit;
    float best = std::numeric_limits<float>::infinity();
    float bestU = 0.f, bestV = 0.f;
    for (int k = 0; k < int(mesh.triangles.size()); ++k) {
        float t, u, v;
        if (!rayPlaneBarycentrics(mesh, k, ray, t, u, v)) continue;
        // A small tolerance on the edges keeps rays through a shared edge from slipping between.
        constexpr float kEdge = -1e-6f;
        if (u < kEdge || v < kEdge || u + v > 1.f - kEdge || !(t > 0.f) || t >= best) continue;
        best = t;
        hit.triangle = k;
        bestU = u;
        bestV = v;
    }
    if (hit.triangle < 0) return hit;
    hit.hit = true;
    hit.t = best;
    hit.position = ray.origin + best * ray.direction;
    hit.faceNormal = mesh.faceNormals[size_t(hit.triangle)];
    hit.interpolated = interpolate(mesh, hit.triangle, bestU, bestV);
    return hit;
}

glm::vec3 interpolatedNormalOnPlane(const FacetedSphereMesh& mesh, int triangle, const Ray& ray,
                                    glm::vec3 fallback) {
    float t, u, v;
    if (!rayPlaneBarycentrics(mesh, triangle, ray, t, u, v) || !std::isfinite(u) ||
        !std::isfinite(v))
        return fallback;
    return interpolate(mesh, triangle, u, v);
}

} // namespace ndfmip
