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

void bilinearTaps(int level, int w, int h, glm::vec2 uv, float weight, TapList& out) {
    // Texel centres sit at (i + 0.5) / size.
    const float x = uv.x * float(w) - 0.5f;
    const float y = uv.y * float(h) - 0.5f;
    const float fx0 = std::floor(x), fy0 = std::floor(y);
    const float fx = x - fx0, fy = y - fy0;
    const int x0 = wrap(int(fx0), w), x1 = wrap(int(fx0) + 1, w);
    const int y0 = wrap(int(fy0), h), y1 = wrap(int(fy0) + 1, h);
    const float wt[4] = {(1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy};
    const int xs[4] = {x0, x1, x0, x1}, ys[4] = {y0, y0, y1, y1};
    for (int k = 0; k < 4; ++k) {
        if (wt[k] == 0.f || out.count == TapList::kMaxTaps) continue;
        out.tap[out.count++] = {level, xs[k], ys[k], weight * wt[k]};
    }
}

void trilinearTaps(const std::vector<glm::ivec2>& sizes, glm::vec2 uv, float lod, float weight,
                   TapList& out) {
    const int last = int(sizes.size()) - 1;
    lod = std::clamp(lod, 0.f, float(last));
    const int k0 = int(std::floor(lod));
    const int k1 = std::min(k0 + 1, last);
    const float f = lod - float(k0);
    bilinearTaps(k0, sizes[k0].x, sizes[k0].y, uv, weight * (1.f - f), out);
    if (f > 0.f) bilinearTaps(k1, sizes[k1].x, sizes[k1].y, uv, weight * f, out);
}

void filteredTaps(const std::vector<glm::ivec2>& sizes, glm::vec2 uv, const UvFootprint& footprint,
                  int maxProbes, float lodBias, TapList& out) {
    out.count = 0;
    const glm::vec2 size(sizes.front());
    const float lx = glm::length(footprint.dx * size), ly = glm::length(footprint.dy * size);
    const float major = std::max(lx, ly), minor = std::min(lx, ly);
    // A footprint within 1% of square reads as square: the float axes of a square pixel's
    // footprint differ by rounding, and ceil would double its probes.
    int probes = 1;
    if (maxProbes > 1 && minor > 0.f)
        probes = std::clamp(int(std::ceil(major / minor - 0.01f)), 1, maxProbes);
    if (probes == 1) {
        trilinearTaps(sizes, uv, (major > 0.f ? std::log2(major) : 0.f) + lodBias, 1.f, out);
        return;
    }
    const glm::vec2 axis = lx >= ly ? footprint.dx : footprint.dy;
    const float lod = std::log2(major / float(probes)) + lodBias;
    for (int i = 0; i < probes; ++i) {
        float t = (float(i) + 0.5f) / float(probes) - 0.5f;
        trilinearTaps(sizes, uv + t * axis, lod, 1.f / float(probes), out);
    }
}

std::vector<glm::ivec2> levelSizes(const MipChain& chain) {
    std::vector<glm::ivec2> sizes;
    for (const Image* level : chain.levels) sizes.emplace_back(level->width, level->height);
    return sizes;
}

namespace {

// The sums kept in locals, which the compiler holds in registers: summed into out, every tap's
// stores and loads would go through memory (out may alias the texels). Same order, same sums.
template <int Channels> void gatherFixed(const MipChain& chain, const TapList& taps, float* out) {
    float sum[Channels] = {};
    for (int t = 0; t < taps.count; ++t) {
        const TexelTap& tap = taps.tap[t];
        const float* texel = chain.levels[tap.level]->at(tap.x, tap.y);
        for (int c = 0; c < Channels; ++c) sum[c] += tap.weight * texel[c];
    }
    for (int c = 0; c < Channels; ++c) out[c] = sum[c];
}

} // namespace

void gatherTaps(const MipChain& chain, const TapList& taps, float* out) {
    switch (chain.channels) {
    case 1:
        return gatherFixed<1>(chain, taps, out);
    case 2:
        return gatherFixed<2>(chain, taps, out);
    case 3:
        return gatherFixed<3>(chain, taps, out);
    case 4:
        return gatherFixed<4>(chain, taps, out);
    default:
        break;
    }
    for (int c = 0; c < chain.channels; ++c) out[c] = 0.f;
    for (int t = 0; t < taps.count; ++t) {
        const TexelTap& tap = taps.tap[t];
        const float* texel = chain.levels[tap.level]->at(tap.x, tap.y);
        for (int c = 0; c < chain.channels; ++c) out[c] += tap.weight * texel[c];
    }
}

void accumulateBilinear(const Image& level, glm::vec2 uv, float weight, float* out) {
    TapList taps;
    bilinearTaps(0, level.width, level.height, uv, weight, taps);
    for (int t = 0; t < taps.count; ++t) {
        const float* texel = level.at(taps.tap[t].x, taps.tap[t].y);
        for (int c = 0; c < level.channels; ++c) out[c] += taps.tap[t].weight * texel[c];
    }
}

void sampleTrilinear(const MipChain& chain, glm::vec2 uv, float lod, float* out) {
    TapList taps;
    trilinearTaps(levelSizes(chain), uv, lod, 1.f, taps);
    gatherTaps(chain, taps, out);
}

void sampleFiltered(const MipChain& chain, glm::vec2 uv, const UvFootprint& footprint,
                    int maxProbes, float* out, float lodBias) {
    TapList taps;
    filteredTaps(levelSizes(chain), uv, footprint, maxProbes, lodBias, taps);
    gatherTaps(chain, taps, out);
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
