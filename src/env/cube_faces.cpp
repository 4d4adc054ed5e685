// Cube faces of an equirectangular map (environment.h): the GL/Vulkan/KTX2 face order and
// orientation, each texel averaged from bilinear lookups spread over it.
#include <algorithm>

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
    case 0: d = {1., b, -a}; break;
    case 1: d = {-1., b, a}; break;
    case 2: d = {a, 1., -b}; break;
    case 3: d = {a, -1., b}; break;
    case 4: d = {a, b, 1.}; break;
    default: d = {-a, b, -1.}; break;
    }
    return glm::normalize(d);
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
