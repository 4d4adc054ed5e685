// LEAN mapping (Olano and Baker, "LEAN Mapping", I3D 2010): per texel the first and second
// moments of the normals' slopes b = (n.x/n.z, n.y/n.z), which mip-map linearly; a shader
// turns them into the covariance of a 2D Gaussian of slopes, an anisotropic Beckmann lobe.
// The anisotropic single-lobe peer of Toksvig (one isotropic lobe) and vMF (several); sggx reads
// the same moments as one anisotropic GGX lobe (shaders/sggx.glsl).
#include <algorithm>
#include <cmath>

#include "ndfmip/bake.h"
#include "ndfmip/method_shading.h"

namespace ndfmip {

Bake bakeLean(const Pyramid& pyramid, const BakeOptions& options) {
    Bake bake;
    bake.method = Method::Lean;
    bake.parameters["min_z"] = kLeanMinZ;
    bake.planes = {
        {"lean_moments",
         {"E[bx]", "E[by]", "E[bx^2]", "E[by^2]"},
         "slope moments, b = (n.x, n.y) / max(n.z, min_z): first and second",
         true},
        {"lean_cross", {"E[bx by]"}, "slope cross moment", true},
    };
    const int count = int(pyramid.levels.size());
    const Image& normals = *pyramid.base;
    Image level0(normals.width, normals.height, 5, Image::Uninitialized{});
#pragma omp parallel for schedule(static)
    for (size_t i = 0; i < normals.texelCount(); ++i) {
        float n[3];
        normalizeOrFlat(&normals.pixels[3 * i], n);
        const float z = std::max(n[2], kLeanMinZ);
        const float bx = n[0] / z, by = n[1] / z;
        float* out = &level0.pixels[5 * i];
        out[0] = bx, out[1] = by, out[2] = bx * bx, out[3] = by * by, out[4] = bx * by;
    }
    // Each level: the exact footprint means (the pyramid's rule), split into the two planes.
    Image moments = std::move(level0);
    bake.levels.resize(count);
    for (int k = 0; k < count; ++k) {
        if (k > 0) moments = averageToLevel(pyramid, moments, k);
        Image first(moments.width, moments.height, 4, Image::Uninitialized{});
        Image cross(moments.width, moments.height, 1, Image::Uninitialized{});
        for (size_t i = 0; i < moments.texelCount(); ++i) {
            std::copy_n(&moments.pixels[5 * i], 4, &first.pixels[4 * i]);
            cross.pixels[i] = moments.pixels[5 * i + 4];
        }
        bake.levels[k] = {std::make_shared<const Image>(std::move(first)),
                          std::make_shared<const Image>(std::move(cross))};
        if (options.progress) options.progress(k + 1, count);
    }
    return bake;
}

namespace {

// A lobe of the slope moments p at h: `glslLobe` (lean's Beckmann or sggx's GGX); tabulated lobes
// have no widening rule, as for toksvig: the table about the mean slope's normal.
template <class GlslLobe>
float slopeMomentLobe(const Material& m, const float* p, glm::vec3 h, GlslLobe glslLobe) {
    if (m.brdf == Brdf::Tabulated)
        return materialLobe(m, glm::dot(glm::normalize(glm::vec3(p[0], p[1], 1.f)), h), 0.f, 0.f);
    return glslLobe(glslMaterial(m), glm::vec4(p[0], p[1], p[2], p[3]), p[4], h);
}

// The cosines about the mean slope's normal (ndfmipShadeLeanLobe) with `lobe` at h.
template <class Lobe>
glm::vec3 shadeSlopeMoments(const Material& m, glm::vec3 albedo, const float* p, glm::vec3 l,
                            glm::vec3 v, Lobe lobe) {
    const glm::vec3 h = glm::normalize(l + v);
    return glsl().ndfmipShadeLeanLobe(glslMaterial(m, specularFactor(m, l, h)), albedo,
                                      glm::vec4(p[0], p[1], p[2], p[3]), p[4], l, v, lobe(m, p, h));
}

} // namespace

float leanLobe(const Material& m, const float* p, glm::vec3 h) {
    return slopeMomentLobe(m, p, h,
                           [](GlslMaterial g, glm::vec4 moments, float cross, glm::vec3 w) {
                               return glsl().ndfmipLeanLobe(g, moments, cross, w);
                           });
}

float sggxLobe(const Material& m, const float* p, glm::vec3 h) {
    return slopeMomentLobe(m, p, h,
                           [](GlslMaterial g, glm::vec4 moments, float cross, glm::vec3 w) {
                               return glsl().ndfmipSggxLobe(g, moments, cross, w);
                           });
}

glm::vec3 shadeLean(const Material& m, glm::vec3 albedo, const float* p, glm::vec3 l, glm::vec3 v) {
    return shadeSlopeMoments(m, albedo, p, l, v, leanLobe);
}

glm::vec3 shadeSggx(const Material& m, glm::vec3 albedo, const float* p, glm::vec3 l, glm::vec3 v) {
    return shadeSlopeMoments(m, albedo, p, l, v, sggxLobe);
}

} // namespace ndfmip
