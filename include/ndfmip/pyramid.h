// The NDF mip pyramid: for every texel of every level, the exact set of level-0 normals it
// covers (as index ranges) and their unnormalised mean Na (first moment of the NDF).
//
// Sizes follow the GPU convention: level k+1 is max(1, floor(w_k / 2)) x max(1, floor(h_k / 2)).
// Texel i of level k+1 covers children 2i and 2i+1 of level k; where w_k is odd the last
// texel of level k+1 also takes child 2i+2 (likewise for rows). The footprints of one level
// therefore partition level 0, and each coarser partition is a union of finer ones; for
// power-of-two sizes a level-k texel covers exactly a 2^k x 2^k block.
#pragma once

#include <cstddef>
#include <vector>

#include "ndfmip/image.h"

namespace ndfmip {

// Half-open range [x0, x1) x [y0, y1) of level-0 texels.
struct Footprint {
    int x0 = 0, x1 = 0, y0 = 0, y1 = 0;
    int width() const { return x1 - x0; }
    int height() const { return y1 - y0; }
    size_t count() const { return size_t(width()) * size_t(height()); }
    bool operator==(const Footprint&) const = default;
};

struct PyramidLevel {
    int width = 0, height = 0;
    std::vector<int>
        columnEdges;           // width + 1 level-0 column boundaries: texel i covers [e[i], e[i+1])
    std::vector<int> rowEdges; // height + 1 level-0 row boundaries
    SharedImage mean; // 3 channels: Na, the mean of the covered level-0 normals (level 0: the map)
};

struct Pyramid {
    SharedImage base;                 // level-0 normals
    std::vector<PyramidLevel> levels; // levels[0] is the map itself, the last one is 1x1
};

// Number of levels down to 1x1 for a width x height map.
int levelCount(int width, int height);

// Builds every level. Means are accumulated in double from the children, weighted by the
// number of level-0 texels each child covers (exact up to float rounding of each level's
// stored mean; no quantisation between levels). `normals` has 3 channels.
Pyramid buildPyramid(SharedImage normals);
Pyramid buildPyramid(const Image& normals); // copies the map

// Na of every texel of `level`; level 0 is the base map itself.
inline const Image& levelMean(const Pyramid& pyramid, int level) {
    return *pyramid.levels[level].mean;
}

// Any linear per-texel quantity (`finer`: one image of level - 1, any channel count) averaged
// down to `level` with the pyramid's footprints: each texel gets the exact mean over the
// level-0 texels it covers, as Na does.
Image averageToLevel(const Pyramid& pyramid, const Image& finer, int level);

// Level-0 texels covered by texel (x, y) of `level`.
Footprint footprint(const Pyramid& pyramid, int level, int x, int y);

// The same for a width x height map without building its pyramid.
Footprint footprintOf(int width, int height, int level, int x, int y);

} // namespace ndfmip
