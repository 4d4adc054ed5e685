// A faceted UV sphere with interpolated (Phong) vertex normals: the mesh, and its ray-triangle
// intersection and interpolated normal, which are the GPU renderer's faceted_trace.glsl.
#include <cmath>

#include <glm/glm.hpp>

#include "ndfmip/glsl.h"
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

namespace glsl_detail {

using glm::abs;
using glm::cross;
using glm::isinf;
using glm::isnan;
using glm::ivec3;
using glm::uintBitsToFloat;

// faceted_trace.glsl over a FacetedSphereMesh: the data members stand in for the GPU's uniforms
// of the same names, the accessors for its texture.
struct FacetedTrace : ShaderLibrary {
    explicit FacetedTrace(const FacetedSphereMesh& m)
        : mesh(m), ndfmipTriangleCount(int(m.triangles.size())), ndfmipCenter(m.center),
          ndfmipRadius(m.radius) {}

    struct NdfmipRay {
        vec3 origin;
        vec3 direction;
    };

    const FacetedSphereMesh& mesh;
    int ndfmipTriangleCount;
    vec3 ndfmipCenter;
    float ndfmipRadius;

    ivec3 ndfmipTriangle(int k) const { return mesh.triangles[size_t(k)]; }
    vec3 ndfmipVertex(int i) const { return mesh.positions[size_t(i)]; }
    vec3 ndfmipVertexNormal(int i) const { return mesh.normals[size_t(i)]; }
    vec3 ndfmipFaceNormal(int k) const { return mesh.faceNormals[size_t(k)]; }

// clang-format off
#include "render/faceted_trace.glsl"
    // clang-format on
};

} // namespace glsl_detail

namespace {

using glsl_detail::FacetedTrace;

FacetedTrace::NdfmipRay glslRay(const Ray& ray) {
    return {ray.origin, ray.direction};
}

} // namespace

// The GLSL hit has FacetedHit's fields in its order, and on a miss FacetedHit's defaults.
FacetedHit intersectFacetedSphere(const FacetedSphereMesh& mesh, const Ray& ray) {
    const FacetedTrace::NdfmipFacetedHit h =
        FacetedTrace(mesh).ndfmipIntersectFaceted(glslRay(ray));
    return {h.hit, h.t, h.position, h.triangle, h.faceNormal, h.interpolated};
}

glm::vec3 interpolatedNormalOnPlane(const FacetedSphereMesh& mesh, int triangle, const Ray& ray,
                                    glm::vec3 fallback) {
    return FacetedTrace(mesh).ndfmipInterpolatedOnPlane(triangle, glslRay(ray), fallback);
}

} // namespace ndfmip
