// NDF mip pyramid: exact footprints and first moments (see pyramid.h for the size rule).
#include "ndfmip/pyramid.h"

#include <algorithm>
#include <cassert>

namespace ndfmip {
namespace {

// Children of coarse texel i along one axis of a level whose finer size is `fine`:
// [2i, 2i+2), and the last coarse texel also takes child 2i+2 when `fine` is odd.
struct ChildRange {
    int begin, end;
};

ChildRange children(int i, int coarse, int fine) {
    if (fine == 1) return {0, 1};
    int end = (i == coarse - 1) ? fine : 2 * i + 2;
    return {2 * i, end};
}

std::vector<int> coarserEdges(const std::vector<int>& fineEdges, int coarse) {
    int fine = int(fineEdges.size()) - 1;
    std::vector<int> edges(coarse + 1);
    for (int i = 0; i < coarse; ++i) edges[i] = fineEdges[children(i, coarse, fine).begin];
    edges[coarse] = fineEdges[fine];
    return edges;
}

// Mean of the children of each coarse texel, each child weighted by its level-0 area: the
// exact mean over the coarse texel's level-0 footprint of whatever linear quantity `fineImage`
// holds (any channel count).
Image averageChildren(const Image& fineImage, const PyramidLevel& fine,
                      const PyramidLevel& coarse) {
    const int cw = coarse.width, ch = coarse.height, channels = fineImage.channels;
    Image mean(cw, ch, channels, Image::Uninitialized{});
#pragma omp parallel for schedule(static)
    for (int y = 0; y < ch; ++y) {
        std::vector<double> sum(channels);
        ChildRange rows = children(y, ch, fine.height);
        for (int x = 0; x < cw; ++x) {
            ChildRange cols = children(x, cw, fine.width);
            std::fill(sum.begin(), sum.end(), 0.0);
            double area = 0;
            for (int fy = rows.begin; fy < rows.end; ++fy) {
                double rowArea = fine.rowEdges[fy + 1] - fine.rowEdges[fy];
                for (int fx = cols.begin; fx < cols.end; ++fx) {
                    double a = rowArea * (fine.columnEdges[fx + 1] - fine.columnEdges[fx]);
                    const float* m = fineImage.at(fx, fy);
                    for (int c = 0; c < channels; ++c) sum[c] += a * m[c];
                    area += a;
                }
            }
            float* out = mean.at(x, y);
            for (int c = 0; c < channels; ++c) out[c] = float(sum[c] / area);
        }
    }
    return mean;
}

// Level 1 straight from level 0 for the common even-size case: the hot, memory-bound pass.
Image averageEvenBlocks(const Image& base, const PyramidLevel& coarse) {
    const int cw = coarse.width, ch = coarse.height;
    Image mean(cw, ch, 3, Image::Uninitialized{});
#pragma omp parallel for schedule(static)
    for (int y = 0; y < ch; ++y) {
        const float* r0 = base.at(0, 2 * y);
        const float* r1 = base.at(0, 2 * y + 1);
        float* out = mean.at(0, y);
        for (int x = 0; x < cw; ++x) {
            const float* a = r0 + 6 * x;
            const float* b = r1 + 6 * x;
            for (int c = 0; c < 3; ++c)
                out[3 * x + c] =
                    float((double(a[c]) + a[c + 3] + (double(b[c]) + b[c + 3])) * 0.25);
        }
    }
    return mean;
}

// Level-0 boundaries of every texel of `level` along an axis of `size` texels.
std::vector<int> axisEdges(int size, int level) {
    std::vector<int> edges(size + 1);
    for (int i = 0; i <= size; ++i) edges[i] = i;
    for (int k = 0; k < level; ++k) {
        size = std::max(1, size / 2);
        edges = coarserEdges(edges, size);
    }
    return edges;
}

} // namespace

int levelCount(int width, int height) {
    int levels = 1;
    while (width > 1 || height > 1) {
        width = std::max(1, width / 2);
        height = std::max(1, height / 2);
        ++levels;
    }
    return levels;
}

Pyramid buildPyramid(const Image& normals) {
    return buildPyramid(std::make_shared<Image>(normals));
}

Pyramid buildPyramid(SharedImage base) {
    const Image& normals = *base;
    assert(normals.channels == 3 && !normals.empty());
    Pyramid pyramid;
    pyramid.base = base;
    const int count = levelCount(normals.width, normals.height);
    pyramid.levels.resize(count);

    PyramidLevel& level0 = pyramid.levels[0];
    level0.width = normals.width;
    level0.height = normals.height;
    level0.columnEdges = axisEdges(normals.width, 0);
    level0.rowEdges = axisEdges(normals.height, 0);
    level0.mean = base;

    for (int k = 1; k < count; ++k) {
        const PyramidLevel& fine = pyramid.levels[k - 1];
        PyramidLevel& coarse = pyramid.levels[k];
        coarse.width = std::max(1, fine.width / 2);
        coarse.height = std::max(1, fine.height / 2);
        coarse.columnEdges = coarserEdges(fine.columnEdges, coarse.width);
        coarse.rowEdges = coarserEdges(fine.rowEdges, coarse.height);
        bool evenBlocks = k == 1 && fine.width % 2 == 0 && fine.height % 2 == 0;
        coarse.mean =
            std::make_shared<Image>(evenBlocks ? averageEvenBlocks(normals, coarse)
                                               : averageChildren(*fine.mean, fine, coarse));
    }
    return pyramid;
}

Image averageToLevel(const Pyramid& pyramid, const Image& finer, int level) {
    assert(level >= 1 && level < int(pyramid.levels.size()));
    const PyramidLevel& fine = pyramid.levels[level - 1];
    assert(finer.width == fine.width && finer.height == fine.height);
    return averageChildren(finer, fine, pyramid.levels[level]);
}

Footprint footprint(const Pyramid& pyramid, int level, int x, int y) {
    const PyramidLevel& l = pyramid.levels[level];
    assert(x >= 0 && x < l.width && y >= 0 && y < l.height);
    return {l.columnEdges[x], l.columnEdges[x + 1], l.rowEdges[y], l.rowEdges[y + 1]};
}

} // namespace ndfmip

namespace ndfmip {

Footprint footprintOf(int width, int height, int level, int x, int y) {
    std::vector<int> columns = axisEdges(width, level), rows = axisEdges(height, level);
    assert(x >= 0 && x + 1 < int(columns.size()) && y >= 0 && y + 1 < int(rows.size()));
    return {columns[x], columns[x + 1], rows[y], rows[y + 1]};
}

} // namespace ndfmip
