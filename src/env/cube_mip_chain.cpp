// The cube-face box chain of environment_cube_chain.h.
#include "ndfmip/environment_cube_chain.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace ndfmip {
namespace {

// Texel (x, y) of `face`; one past an edge, the adjacent face's texel under the extended plane's
// texel centre. (Past a corner, where three faces meet, there is no fourth texel:
// sampleCubeLevel stands the other three's mean in for it.)
const float* texelAt(const std::array<Image, kCubeFaces>& level, int face, int x, int y) {
    const int n = level[0].width;
    if (x >= 0 && x < n && y >= 0 && y < n) return level[size_t(face)].at(x, y);
    int f;
    double s, t;
    cubeFaceCoordinates(cubeFaceDirection(face, (x + 0.5) / n, (y + 0.5) / n), f, s, t);
    return level[size_t(f)].at(std::clamp(int(s * n), 0, n - 1), std::clamp(int(t * n), 0, n - 1));
}

// Each coarse texel the solid-angle-weighted mean of its 2x2 children.
std::array<Image, kCubeFaces> halve(const std::array<Image, kCubeFaces>& fine) {
    const int n = fine[0].width, half = n / 2;
    std::vector<double> omega(size_t(n) * size_t(n)); // the same on every face
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
            omega[size_t(y) * size_t(n) + size_t(x)] = cubeTexelSolidAngle(n, x, y);
    std::array<Image, kCubeFaces> coarse;
    for (int face = 0; face < kCubeFaces; ++face) {
        Image& out = coarse[size_t(face)];
        out = Image(half, half, 3);
        for (int y = 0; y < half; ++y)
            for (int x = 0; x < half; ++x) {
                double sum[3] = {0., 0., 0.}, weight = 0.;
                for (int j = 0; j < 2; ++j)
                    for (int i = 0; i < 2; ++i) {
                        const int cx = 2 * x + i, cy = 2 * y + j;
                        const double w = omega[size_t(cy) * size_t(n) + size_t(cx)];
                        const float* p = fine[size_t(face)].at(cx, cy);
                        for (int c = 0; c < 3; ++c) sum[c] += w * p[c];
                        weight += w;
                    }
                float* p = out.at(x, y);
                for (int c = 0; c < 3; ++c) p[c] = float(sum[c] / weight);
            }
    }
    return coarse;
}

} // namespace

std::array<Image, kCubeFaces> cubeMipChainBase(const Environment& env, int size) {
    assert(size >= 1 && (size & (size - 1)) == 0 && env.radiance.channels == 3);
    // The map as seen, at most 8 size wide (two texels per face texel at the horizon,
    // area-weighted); then 4 x 4 bilinear lookups per face texel read every texel under it.
    const int width = std::min(env.radiance.width, 8 * size);
    Image resampled;
    if (env.rotation != 0. || width != env.radiance.width)
        resampled = resampleEquirect(env.radiance, width, env.rotation);
    const Image& seen = resampled.pixels.empty() ? env.radiance : resampled;
    std::array<Image, kCubeFaces> faces;
    for (int face = 0; face < kCubeFaces; ++face)
        faces[size_t(face)] = cubeFaceFromEquirect(seen, face, size, 4);
    return faces;
}

CubeMipChain buildCubeMipChain(const Environment& env, int size) {
    CubeMipChain chain;
    chain.levels.push_back(cubeMipChainBase(env, size));
    while (chain.levels.back()[0].width > 1) chain.levels.push_back(halve(chain.levels.back()));
    return chain;
}

glm::vec3 sampleCubeLevel(const std::array<Image, kCubeFaces>& level, glm::dvec3 d) {
    const int n = level[0].width;
    int face;
    double s, t;
    cubeFaceCoordinates(d, face, s, t);
    const double px = s * n - 0.5, py = t * n - 0.5;
    const int x0 = int(std::floor(px)), y0 = int(std::floor(py));
    const float fx = float(px - x0), fy = float(py - y0);
    glm::vec3 p[2][2]; // [j][i]: texel (x0 + i, y0 + j)
    int corner = -1;   // the one past a cube corner, if any (2 j + i)
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 2; ++i) {
            const int x = x0 + i, y = y0 + j;
            if ((x < 0 || x >= n) && (y < 0 || y >= n)) corner = 2 * j + i;
            const float* texel = texelAt(level, face, x, y);
            p[j][i] = glm::vec3(texel[0], texel[1], texel[2]);
        }
    if (corner >= 0) {
        const int j = corner / 2, i = corner % 2;
        p[j][i] = (p[j][1 - i] + p[1 - j][i] + p[1 - j][1 - i]) / 3.f;
    }
    return (1.f - fy) * ((1.f - fx) * p[0][0] + fx * p[0][1]) +
           fy * ((1.f - fx) * p[1][0] + fx * p[1][1]);
}

glm::vec3 sampleCubeMipChain(const CubeMipChain& chain, double lod, glm::dvec3 d) {
    assert(!chain.levels.empty());
    lod = std::clamp(lod, 0., double(chain.levels.size() - 1));
    const int k0 = int(lod), k1 = std::min(k0 + 1, int(chain.levels.size()) - 1);
    const float f = float(lod - k0);
    const glm::vec3 a = sampleCubeLevel(chain.levels[size_t(k0)], d);
    if (!(f > 0.f) || k1 == k0) return a;
    return (1.f - f) * a + f * sampleCubeLevel(chain.levels[size_t(k1)], d);
}

} // namespace ndfmip
