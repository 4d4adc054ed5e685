// Cube faces of an equirectangular map (environment.h): the GL/Vulkan/KTX2 face order and
// orientation, its inverse and the texels' solid angles, each texel averaged from bilinear
// lookups spread over it.
#include <algorithm>
#include <cmath>

#include "ndfmip/environment.h"

namespace ndfmip {

const char* cubeFaceName(int face) {
    static constexpr const char* kNames[kCubeFaces] = {"px", "nx", "py", "ny", "pz", "nz"};
    return kNames[std::clamp(face, 0, kCubeFaces - 1)];
}

glm::dvec3 cubeFaceDirection(int face, double s, double t) {
    const double a = 2. * s - 1., b = 1. - 2. * t;
    glm::dvec3 d;
    switch (face) {
    case 0:
        d = {1., b, -a};
        break;
    case 1:
        d = {-1., b, a};
        break;
    case 2:
        d = {a, 1., -b};
        break;
    case 3:
        d = {a, -1., b};
        break;
    case 4:
        d = {a, b, 1.};
        break;
    default:
        d = {-a, b, -1.};
        break;
    }
    return glm::normalize(d);
}

void cubeFaceCoordinates(glm::dvec3 d, int& face, double& s, double& t) {
    const glm::dvec3 m = glm::abs(d);
    double a, b; // the face-plane coordinates of cubeFaceDirection
    if (m.x >= m.y && m.x >= m.z) {
        face = d.x > 0. ? 0 : 1;
        a = (d.x > 0. ? -d.z : d.z) / m.x, b = d.y / m.x;
    } else if (m.y >= m.z) {
        face = d.y > 0. ? 2 : 3;
        a = d.x / m.y, b = (d.y > 0. ? -d.z : d.z) / m.y;
    } else {
        face = d.z > 0. ? 4 : 5;
        a = (d.z > 0. ? d.x : -d.x) / m.z, b = d.y / m.z;
    }
    s = std::clamp(0.5 * (a + 1.), 0., 1.);
    t = std::clamp(0.5 * (1. - b), 0., 1.);
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
