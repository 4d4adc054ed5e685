// Texture filtering as GPUs do it (see texture_sampling.h).
#include "texture_sampling.h"

#include <algorithm>
#include <cmath>

namespace ndfmip {

namespace {

int wrap(int i, int n) {
    if (i >= 0 && i < n) return i;
    int r = i % n;
    return r < 0 ? r + n : r;
}

} // namespace

void accumulateBilinear(const Image& level, glm::vec2 uv, float weight, float* out) {
    // Texel centres sit at (i + 0.5) / size.
    const float x = uv.x * float(level.width) - 0.5f;
    const float y = uv.y * float(level.height) - 0.5f;
    const float fx0 = std::floor(x), fy0 = std::floor(y);
    const float fx = x - fx0, fy = y - fy0;
    const int x0 = wrap(int(fx0), level.width), x1 = wrap(int(fx0) + 1, level.width);
    const int y0 = wrap(int(fy0), level.height), y1 = wrap(int(fy0) + 1, level.height);
    const float w[4] = {(1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy};
    const float* t[4] = {level.at(x0, y0), level.at(x1, y0), level.at(x0, y1), level.at(x1, y1)};
    for (int k = 0; k < 4; ++k) {
        if (w[k] == 0.f) continue;
        for (int c = 0; c < level.channels; ++c) out[c] += weight * w[k] * t[k][c];
    }
}

void sampleTrilinear(const MipChain& chain, glm::vec2 uv, float lod, float* out) {
    for (int c = 0; c < chain.channels; ++c) out[c] = 0.f;
    const int last = int(chain.levels.size()) - 1;
    lod = std::clamp(lod, 0.f, float(last));
    const int k0 = int(std::floor(lod));
    const int k1 = std::min(k0 + 1, last);
    const float f = lod - float(k0);
    accumulateBilinear(*chain.levels[k0], uv, 1.f - f, out);
    if (f > 0.f) accumulateBilinear(*chain.levels[k1], uv, f, out);
}

void sampleFiltered(const MipChain& chain, glm::vec2 uv, const UvFootprint& footprint, int maxProbes,
                    float* out) {
    const Image& base = *chain.levels.front();
    const glm::vec2 size(float(base.width), float(base.height));
    const float lx = glm::length(footprint.dx * size), ly = glm::length(footprint.dy * size);
    const float major = std::max(lx, ly), minor = std::min(lx, ly);
    int probes = 1;
    if (maxProbes > 1 && minor > 0.f) probes = std::clamp(int(std::ceil(major / minor)), 1, maxProbes);
    if (probes == 1) {
        sampleTrilinear(chain, uv, major > 0.f ? std::log2(major) : 0.f, out);
        return;
    }
    const glm::vec2 axis = lx >= ly ? footprint.dx : footprint.dy;
    const float lod = std::log2(major / float(probes));
    float probe[kMaxFilteredChannels];
    for (int c = 0; c < chain.channels; ++c) out[c] = 0.f;
    for (int i = 0; i < probes; ++i) {
        float t = (float(i) + 0.5f) / float(probes) - 0.5f;
        sampleTrilinear(chain, uv + t * axis, lod, probe);
        for (int c = 0; c < chain.channels; ++c) out[c] += probe[c] / float(probes);
    }
}

const float* nearestTexel(const Image& image, glm::vec2 uv) {
    int x = wrap(int(std::floor(uv.x * float(image.width))), image.width);
    int y = wrap(int(std::floor(uv.y * float(image.height))), image.height);
    return image.at(x, y);
}

glm::vec3 sampleNormal(const Image& normals, glm::vec2 uv, bool nearest) {
    if (nearest) {
        const float* n = nearestTexel(normals, uv);
        return {n[0], n[1], n[2]};
    }
    float sum[3] = {0.f, 0.f, 0.f};
    accumulateBilinear(normals, uv, 1.f, sum);
    float n[3];
    normalizeOrFlat(sum, n);
    return {n[0], n[1], n[2]};
}

} // namespace ndfmip

namespace ndfmip {

std::vector<SharedImage> albedoMips(const Pyramid& pyramid, SharedImage albedo) {
    std::vector<SharedImage> levels{albedo};
    for (int k = 1; k < int(pyramid.levels.size()); ++k)
        levels.push_back(std::make_shared<const Image>(averageToLevel(pyramid, *levels.back(), k)));
    return levels;
}

} // namespace ndfmip
