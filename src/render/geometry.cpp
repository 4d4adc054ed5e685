// Camera rays, ray-object intersection with a tangent frame, and ray-differential footprints.
#include <cmath>

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

Ray cameraRay(const CameraFrame& f, float px, float py) {
    // Image-plane coordinates in [-1, 1], y up.
    const float sx = 2.f * px / f.width - 1.f;
    const float sy = 1.f - 2.f * py / f.height;
    const glm::vec3 across = f.right * (sx * f.halfWidth) + f.up * (sy * f.halfHeight);
    if (f.type == CameraType::Orthographic) return {f.eye + across, f.forward};
    return {f.eye, glm::normalize(f.forward + across)};
}

SurfaceHit intersect(const Geometry& g, const Ray& ray) {
    SurfaceHit h;
    if (g.type == GeometryType::Plane) {
        float denom = glm::dot(ray.direction, g.normal);
        if (std::abs(denom) < 1e-12f) return h;
        float t = glm::dot(g.center - ray.origin, g.normal) / denom;
        if (!(t > 0.f)) return h;
        glm::vec3 p = ray.origin + t * ray.direction;
        glm::vec3 bitangent = glm::cross(g.normal, g.tangent);
        glm::vec3 d = p - g.center;
        float s = glm::dot(d, g.tangent) / g.size.x + 0.5f; // 0 .. 1 along the tangent
        float r = 0.5f - glm::dot(d, bitangent) / g.size.y; // 0 at the bitangent's edge
        if (s < 0.f || s > 1.f || r < 0.f || r > 1.f) return h;
        h.hit = true;
        h.t = t;
        h.position = p;
        h.uv = {s * g.tiling.x, r * g.tiling.y};
        h.tangent = g.tangent;
        h.bitangent = bitangent;
        h.normal = g.normal;
        h.dpdu = g.tangent * (g.size.x / g.tiling.x);
        h.dpdv = -bitangent * (g.size.y / g.tiling.y);
        return h;
    }
    // Sphere: nearest positive root of |o + t d - c|^2 = R^2.
    glm::vec3 oc = ray.origin - g.center;
    float b = glm::dot(oc, ray.direction);
    float c = glm::dot(oc, oc) - g.radius * g.radius;
    float disc = b * b - c;
    if (disc < 0.f) return h;
    float root = std::sqrt(disc);
    float t = -b - root;
    if (!(t > 0.f)) t = -b + root;
    if (!(t > 0.f)) return h;
    glm::vec3 p = ray.origin + t * ray.direction;
    glm::vec3 n = glm::normalize(p - g.center);
    float theta = std::acos(glm::clamp(n.z, -1.f, 1.f));
    float phi = std::atan2(n.y, n.x);
    if (phi < 0.f) phi += 2.f * kPi;
    float sinTheta = std::sin(theta), cosTheta = std::cos(theta);
    float sinPhi = std::sin(phi), cosPhi = std::cos(phi);
    h.hit = true;
    h.t = t;
    h.position = p;
    h.uv = {phi / (2.f * kPi) * g.tiling.x, theta / kPi * g.tiling.y};
    h.normal = n;
    h.tangent = {-sinPhi, cosPhi, 0.f};
    h.bitangent = glm::cross(h.normal, h.tangent); // towards the north pole: decreasing v
    h.dpdu = glm::vec3(-sinPhi, cosPhi, 0.f) * (g.radius * sinTheta * 2.f * kPi / g.tiling.x);
    h.dpdv =
        glm::vec3(cosTheta * cosPhi, cosTheta * sinPhi, -sinTheta) * (g.radius * kPi / g.tiling.y);
    return h;
}

UvFootprint uvFootprint(const CameraFrame& camera, const SurfaceHit& hit, float px, float py) {
    // Where the neighbouring pixels' rays meet the tangent plane at the hit, as uv offsets:
    // solve dp = du dpdu + dv dpdv in the least-squares sense (2x2 normal equations).
    auto offset = [&](float qx, float qy) {
        Ray r = cameraRay(camera, qx, qy);
        float denom = glm::dot(r.direction, hit.normal);
        if (std::abs(denom) < 1e-12f) return glm::vec2(0.f);
        float t = glm::dot(hit.position - r.origin, hit.normal) / denom;
        glm::vec3 dp = r.origin + t * r.direction - hit.position;
        float a = glm::dot(hit.dpdu, hit.dpdu), b = glm::dot(hit.dpdu, hit.dpdv);
        float c = glm::dot(hit.dpdv, hit.dpdv);
        float ru = glm::dot(dp, hit.dpdu), rv = glm::dot(dp, hit.dpdv);
        float det = a * c - b * b;
        if (std::abs(det) < 1e-20f) return glm::vec2(0.f);
        return glm::vec2((c * ru - b * rv) / det, (a * rv - b * ru) / det);
    };
    return {offset(px + 1.f, py), offset(px, py + 1.f)};
}

float mipLod(const UvFootprint& f, int width, int height) {
    const glm::vec2 scale{float(width), float(height)};
    float rho = glm::max(glm::length(f.dx * scale), glm::length(f.dy * scale));
    return rho > 0.f ? std::log2(rho) : 0.f;
}

} // namespace ndfmip
