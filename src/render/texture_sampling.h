// GPU-style texture filtering of a method's planes: bilinear within a level with wrapped
// addressing, linear between levels (trilinear), and optional anisotropic probes. Filtering is
// split in two: which texels a lookup reads and with what weights (the taps), then what is done
// with them, so that a method can blend its parameters before shading (what a GPU's sampler
// does) or shade each texel and blend the results (shading is linear in the NDF).
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include "ndfmip/image.h"
#include "ndfmip/render.h"

namespace ndfmip {

// Most channels a method may filter at once (all its linear planes together).
constexpr int kMaxFilteredChannels = 1024;

// One plane at every level (levels[k]), all with `channels` channels.
struct MipChain {
    std::vector<const Image*> levels;
    int channels = 0;
};

// One texel a lookup reads, and its weight.
struct TexelTap {
    int level, x, y; // no initialisers: a TapList is made per lookup and filled as needed
    float weight;
};

// The taps of one filtered lookup: at most 64 probes of 8 texels each.
struct TapList {
    static constexpr int kMaxTaps = 64 * 8;
    TexelTap tap[kMaxTaps];
    int count = 0;
};

// Appends the (up to) four taps of a bilinear lookup of `level` (w x h texels) at uv, each
// weight scaled by `weight`; taps of weight 0 are left out.
void bilinearTaps(int level, int w, int h, glm::vec2 uv, float weight, TapList& out);

// The taps of a trilinear lookup at (uv, lod), lod clamped to [0, last level]; `sizes` holds
// each level's (width, height).
void trilinearTaps(const std::vector<glm::ivec2>& sizes, glm::vec2 uv, float lod, float weight,
                   TapList& out);

// As a GPU with anisotropic filtering: up to maxProbes trilinear probes spread along the major
// axis of the footprint, each at the LOD of the footprint's length divided by the probe count,
// plus lodBias. Replaces `out`'s taps.
void filteredTaps(const std::vector<glm::ivec2>& sizes, glm::vec2 uv, const UvFootprint& footprint,
                  int maxProbes, float lodBias, TapList& out);

// Each level's size of a chain.
std::vector<glm::ivec2> levelSizes(const MipChain& chain);

// out[0..channels) = Sum of weight * texel over the taps.
void gatherTaps(const MipChain& chain, const TapList& taps, float* out);

// Adds weight * bilinear(level k at uv) into out[0..channels).
void accumulateBilinear(const Image& level, glm::vec2 uv, float weight, float* out);

// Trilinear sample at (uv, lod): lod clamped to [0, last level].
void sampleTrilinear(const MipChain& chain, glm::vec2 uv, float lod, float* out);

// filteredTaps then gatherTaps.
void sampleFiltered(const MipChain& chain, glm::vec2 uv, const UvFootprint& footprint,
                    int maxProbes, float* out, float lodBias = 0.f);

// The texel of `image` that contains uv (wrapped addressing).
const float* nearestTexel(const Image& image, glm::vec2 uv);

// Level-0 unit normal at uv: bilinear then renormalised, or the nearest texel.
glm::vec3 sampleNormal(const Image& normals, glm::vec2 uv, bool nearest);

} // namespace ndfmip
