// Cube faces of an equirectangular map (environment.h): the GL/Vulkan/KTX2 face order and
// orientation, its inverse and the texels' solid angles, each texel averaged from bilinear
// lookups spread over it.
#include <algorithm>
#include <cmath>

#include <glm/glm.hpp>

#include "ndfmip/environment.h"

namespace ndfmip {
namespace glsl_detail {

using glm::abs;
using glm::max;

// cube_faces.glsl in double: its vec2 and vec3 stand for glm's double vectors here, so the
// offline faces are laid out to double precision with the GPU's table and rule.
struct CubeFacesDouble {
    using vec2 = glm::dvec2;
    using vec3 = glm::dvec3;
// clang-format off
#include "render/cube_faces.glsl"
    // clang-format on
};

} // namespace glsl_detail

const char* cubeFaceName(int face) {
    static constexpr const char* kNames[kCubeFaces] = {"px", "nx", "py", "ny", "pz", "nz"};
    return kNames[std::clamp(face, 0, kCubeFaces - 1)];
}

glm::dvec3 cubeFaceDirection(int face, double s, double t) {
    return glm::normalize(
        glsl_detail::CubeFacesDouble().ndfmipCubeFaceDirection(face, {2. * s - 1., 2. * t - 1.}));
}

void cubeFaceCoordinates(glm::dvec3 d, int& face, double& s, double& t) {
    const auto p = glsl_detail::CubeFacesDouble().ndfmipCubeFacePoint(d);
    face = p.face;
    s = std::clamp(0.5 * (p.ab.x + 1.), 0., 1.);
    t = std::clamp(0.5 * (p.ab.y + 1.), 0., 1.);
}

namespace {

// The solid angle of the face-plane rectangle [0, a] x [0, b] seen from the cube's centre
// (the plane at distance 1): atan(a b / sqrt(a^2 + b^2 + 1)).
double cornerSolidAngle(double a, double b) {
    return std::atan2(a * b, std::sqrt(a * a + b * b + 1.));
}

} // namespace

double cubeTexelSolidAngle(int size, int x, int y) {
    const double a0 = 2. * x / size - 1., a1 = 2. * (x + 1) / size - 1.;
    const double b0 = 2. * y / size - 1., b1 = 2. * (y + 1) / size - 1.;
    return cornerSolidAngle(a1, b1) - cornerSolidAngle(a0, b1) - cornerSolidAngle(a1, b0) +
           cornerSolidAngle(a0, b0);
}

Image cubeFaceFromEquirect(const Image& map, int face, int size, int samples) {
    Image out(size, size, map.channels, Image::Uninitialized{});
    const int n = std::max(samples, 1);
    const float weight = 1.f / float(n * n);
#pragma omp parallel for schedule(static) if (size >= 64)
    for (int y = 0; y < size; ++y) {
        std::vector<float> texel(size_t(map.channels)), sum(size_t(map.channels));
        for (int x = 0; x < size; ++x) {
            std::fill(sum.begin(), sum.end(), 0.f);
            for (int j = 0; j < n; ++j)
                for (int i = 0; i < n; ++i) {
                    const double s = (x + (i + 0.5) / n) / size, t = (y + (j + 0.5) / n) / size;
                    sampleEquirect(map, cubeFaceDirection(face, s, t), texel.data());
                    for (int c = 0; c < map.channels; ++c) sum[size_t(c)] += texel[size_t(c)];
                }
            float* p = out.at(x, y);
            for (int c = 0; c < map.channels; ++c) p[c] = sum[size_t(c)] * weight;
        }
    }
    return out;
}

} // namespace ndfmip
