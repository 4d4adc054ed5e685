// The scene's camera rays, the ray's hit on the object with its tangent frame, and the
// ray-differential footprint: one source for the CPU renderer (src/render/geometry.cpp, through
// glsl.h) and the GPU renderer (after raycast.glsl). Needs the camera and the object as each side
// holds them (the CPU's CameraFrame and Geometry, the GPU's uniforms of the same names):
//   int ndfmipCameraType (0 perspective, 1 orthographic); vec3 ndfmipEye, ndfmipForward,
//   ndfmipRight, ndfmipUp; vec2 ndfmipHalfSize (half the image plane: at distance 1, perspective,
//   or in world units); vec2 ndfmipImageSize (pixels);
//   int ndfmipGeometryType (0 plane, 1 sphere); vec3 ndfmipCenter, ndfmipNormal, ndfmipTangent;
//   vec2 ndfmipPlaneSize, ndfmipTiling; float ndfmipRadius.

struct NdfmipRay {
    vec3 origin;
    vec3 direction;
};

struct NdfmipHit {
    bool hit;
    float t;
    vec3 position;
    vec2 uv;
    vec3 tangent;
    vec3 bitangent;
    vec3 normal;
    vec3 dpdu;
    vec3 dpdv;
};

// The ray through image position (px, py), in pixels from the top-left corner.
NdfmipRay ndfmipCameraRay(float px, float py) {
    float sx = 2.0f * px / ndfmipImageSize.x - 1.0f;
    float sy = 1.0f - 2.0f * py / ndfmipImageSize.y;
    vec3 across = ndfmipRight * (sx * ndfmipHalfSize.x) + ndfmipUp * (sy * ndfmipHalfSize.y);
    NdfmipRay ray;
    if (ndfmipCameraType == 1) {
        ray.origin = ndfmipEye + across;
        ray.direction = ndfmipForward;
    } else {
        ray.origin = ndfmipEye;
        ray.direction = normalize(ndfmipForward + across);
    }
    return ray;
}

// The nearest hit t > 0 on the plane (its rectangle) or the sphere, with the uv (tiling applied),
// the unit frame (tangent: +x of the normal map, towards +u; bitangent: +y, towards the top row,
// -v) and the position's derivatives along uv.
NdfmipHit ndfmipIntersect(NdfmipRay ray) {
    NdfmipHit h;
    h.hit = false;
    h.t = 0.0f;
    h.position = vec3(0.0f);
    h.uv = vec2(0.0f);
    h.tangent = vec3(1.0f, 0.0f, 0.0f);
    h.bitangent = vec3(0.0f, 1.0f, 0.0f);
    h.normal = vec3(0.0f, 0.0f, 1.0f);
    h.dpdu = vec3(0.0f);
    h.dpdv = vec3(0.0f);
    if (ndfmipGeometryType == 0) {
        float denom = dot(ray.direction, ndfmipNormal);
        if (abs(denom) < 1e-12f) return h;
        float t = dot(ndfmipCenter - ray.origin, ndfmipNormal) / denom;
        if (!(t > 0.0f)) return h;
        vec3 p = ray.origin + t * ray.direction;
        vec3 bitangent = cross(ndfmipNormal, ndfmipTangent);
        vec3 d = p - ndfmipCenter;
        float s = dot(d, ndfmipTangent) / ndfmipPlaneSize.x + 0.5f;
        float r = 0.5f - dot(d, bitangent) / ndfmipPlaneSize.y;
        if (s < 0.0f || s > 1.0f || r < 0.0f || r > 1.0f) return h;
        h.hit = true;
        h.t = t;
        h.position = p;
        h.uv = vec2(s * ndfmipTiling.x, r * ndfmipTiling.y);
        h.tangent = ndfmipTangent;
        h.bitangent = bitangent;
        h.normal = ndfmipNormal;
        h.dpdu = ndfmipTangent * (ndfmipPlaneSize.x / ndfmipTiling.x);
        h.dpdv = -bitangent * (ndfmipPlaneSize.y / ndfmipTiling.y);
        return h;
    }
    // Sphere: the nearest positive root of |o + t d - c|^2 = R^2.
    vec3 oc = ray.origin - ndfmipCenter;
    float b = dot(oc, ray.direction);
    float c = dot(oc, oc) - ndfmipRadius * ndfmipRadius;
    float disc = b * b - c;
    if (disc < 0.0f) return h;
    float root = sqrt(disc);
    float t = -b - root;
    if (!(t > 0.0f)) t = -b + root;
    if (!(t > 0.0f)) return h;
    vec3 p = ray.origin + t * ray.direction;
    vec3 n = normalize(p - ndfmipCenter);
    // The frame from n itself, not from sin and cos of the angles (GPUs' trig functions are
    // approximations; these agree with the CPU's to rounding).
    float sinTheta = sqrt(n.x * n.x + n.y * n.y);
    float cosTheta = clamp(n.z, -1.0f, 1.0f);
    float theta = atan(sinTheta, cosTheta);
    float phi = atan(n.y, n.x);
    if (phi < 0.0f) phi += 2.0f * NDFMIP_PI;
    float cosPhi = sinTheta > 0.0f ? n.x / sinTheta : 1.0f;
    float sinPhi = sinTheta > 0.0f ? n.y / sinTheta : 0.0f;
    h.hit = true;
    h.t = t;
    h.position = p;
    h.uv = vec2(phi / (2.0f * NDFMIP_PI) * ndfmipTiling.x, theta / NDFMIP_PI * ndfmipTiling.y);
    h.normal = n;
    h.tangent = vec3(-sinPhi, cosPhi, 0.0f);
    h.bitangent = cross(h.normal, h.tangent);
    h.dpdu = vec3(-sinPhi, cosPhi, 0.0f) * (ndfmipRadius * sinTheta * 2.0f * NDFMIP_PI / ndfmipTiling.x);
    h.dpdv = vec3(cosTheta * cosPhi, cosTheta * sinPhi, -sinTheta) * (ndfmipRadius * NDFMIP_PI / ndfmipTiling.y);
    return h;
}

// uv offset to where the ray through (qx, qy) meets the hit's tangent plane (ray differentials):
// dp = du dpdu + dv dpdv solved in the least-squares sense (2x2 normal equations).
vec2 ndfmipUvOffset(NdfmipHit hit, float qx, float qy) {
    NdfmipRay r = ndfmipCameraRay(qx, qy);
    float denom = dot(r.direction, hit.normal);
    if (abs(denom) < 1e-12f) return vec2(0.0f);
    float t = dot(hit.position - r.origin, hit.normal) / denom;
    vec3 dp = r.origin + t * r.direction - hit.position;
    float a = dot(hit.dpdu, hit.dpdu);
    float b = dot(hit.dpdu, hit.dpdv);
    float c = dot(hit.dpdv, hit.dpdv);
    float ru = dot(dp, hit.dpdu);
    float rv = dot(dp, hit.dpdv);
    float det = a * c - b * b;
    if (abs(det) < 1e-20f) return vec2(0.0f);
    return vec2((c * ru - b * rv) / det, (a * rv - b * ru) / det);
}

// A world direction in the hit's tangent frame.
vec3 ndfmipToTangent(NdfmipHit hit, vec3 w) { return vec3(dot(w, hit.tangent), dot(w, hit.bitangent), dot(w, hit.normal)); }
