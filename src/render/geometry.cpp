// Camera rays, ray-object intersection with a tangent frame, and ray-differential footprints:
// the camera's frame here, the rest the GPU renderer's render/ray_geometry.glsl compiled as C++.
#include <cmath>

#include <glm/glm.hpp>

#include "ndfmip/glsl.h"
#include "ndfmip/render.h"

namespace ndfmip {

CameraFrame cameraFrame(const Camera& c) {
    CameraFrame f;
    f.type = c.type;
    f.eye = c.eye;
    f.forward = glm::normalize(c.target - c.eye);
    f.right = glm::normalize(glm::cross(f.forward, c.up));
    f.up = glm::cross(f.right, f.forward);
    const float aspect = float(c.width) / float(c.height);
    f.halfHeight = c.type == CameraType::Orthographic ? 0.5f * c.orthoHeight
                                                      : std::tan(glm::radians(c.fovY) * 0.5f);
    f.halfWidth = f.halfHeight * aspect;
    f.width = float(c.width);
    f.height = float(c.height);
    return f;
}

namespace glsl_detail {

using glm::abs;
using glm::cross;
using glm::ivec3;

// ray_geometry.glsl over a CameraFrame and a Geometry: the data members stand in for the GPU's
// uniforms of the same names.
struct RayGeometry : ShaderLibrary {
    explicit RayGeometry(const CameraFrame& f)
        : ndfmipCameraType(f.type == CameraType::Orthographic ? 1 : 0), ndfmipEye(f.eye),
          ndfmipForward(f.forward), ndfmipRight(f.right), ndfmipUp(f.up),
          ndfmipHalfSize(f.halfWidth, f.halfHeight), ndfmipImageSize(f.width, f.height) {}
    explicit RayGeometry(const Geometry& g)
        : ndfmipGeometryType(g.type == GeometryType::Plane ? 0 : 1), ndfmipCenter(g.center),
          ndfmipNormal(g.normal), ndfmipTangent(g.tangent), ndfmipPlaneSize(g.size),
          ndfmipTiling(g.tiling), ndfmipRadius(g.radius) {}

    int ndfmipCameraType = 0;
    vec3 ndfmipEye{0.f}, ndfmipForward{0.f}, ndfmipRight{0.f}, ndfmipUp{0.f};
    vec2 ndfmipHalfSize{0.f}, ndfmipImageSize{0.f};
    int ndfmipGeometryType = 0;
    vec3 ndfmipCenter{0.f}, ndfmipNormal{0.f}, ndfmipTangent{0.f};
    vec2 ndfmipPlaneSize{0.f}, ndfmipTiling{0.f};
    float ndfmipRadius = 0.f;

// clang-format off
#include "render/ray_geometry.glsl"
    // clang-format on
};

} // namespace glsl_detail

using glsl_detail::RayGeometry;

Ray cameraRay(const CameraFrame& f, float px, float py) {
    const RayGeometry::NdfmipRay ray = RayGeometry(f).ndfmipCameraRay(px, py);
    return {ray.origin, ray.direction};
}

// The GLSL hit has SurfaceHit's fields in its order, and on a miss SurfaceHit's defaults.
SurfaceHit intersect(const Geometry& g, const Ray& ray) {
    const RayGeometry::NdfmipHit h = RayGeometry(g).ndfmipIntersect({ray.origin, ray.direction});
    return {h.hit, h.t, h.position, h.uv, h.tangent, h.bitangent, h.normal, h.dpdu, h.dpdv};
}

UvFootprint uvFootprint(const CameraFrame& camera, const SurfaceHit& hit, float px, float py) {
    // Where the neighbouring pixels' rays meet the tangent plane at the hit, as uv offsets.
    const RayGeometry::NdfmipHit h{hit.hit,       hit.t,      hit.position, hit.uv,  hit.tangent,
                                   hit.bitangent, hit.normal, hit.dpdu,     hit.dpdv};
    RayGeometry rays(camera);
    return {rays.ndfmipUvOffset(h, px + 1.f, py), rays.ndfmipUvOffset(h, px, py + 1.f)};
}

float mipLod(const UvFootprint& f, int width, int height) {
    const glm::vec2 scale{float(width), float(height)};
    float rho = glm::max(glm::length(f.dx * scale), glm::length(f.dy * scale));
    return rho > 0.f ? std::log2(rho) : 0.f;
}

} // namespace ndfmip
