// GPU-style texture filtering of a method's planes: bilinear within a level with wrapped
// addressing, linear between levels (trilinear), and optional anisotropic probes.
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

// Adds weight * bilinear(level k at uv) into out[0..channels).
void accumulateBilinear(const Image& level, glm::vec2 uv, float weight, float* out);

// Trilinear sample at (uv, lod): lod clamped to [0, last level].
void sampleTrilinear(const MipChain& chain, glm::vec2 uv, float lod, float* out);

// As a GPU with anisotropic filtering: up to maxProbes trilinear probes spread along the major
// axis of the footprint, each at the LOD of the footprint's length divided by the probe count.
void sampleFiltered(const MipChain& chain, glm::vec2 uv, const UvFootprint& footprint, int maxProbes,
                    float* out);

// The texel of `image` that contains uv (wrapped addressing).
const float* nearestTexel(const Image& image, glm::vec2 uv);

// Level-0 unit normal at uv: bilinear then renormalised, or the nearest texel.
glm::vec3 sampleNormal(const Image& normals, glm::vec2 uv, bool nearest);

} // namespace ndfmip
