// vMF lobes for a whole pyramid (Han et al. 2007, Sec. 7.1): level 0 one sharp lobe per normal,
// each coarser texel initialised by farthest-point clustering of its children's lobes and fitted
// by EM to every level-0 normal of its footprint.
//
// The level-0 normals are reordered once so that every texel's footprint, at every level, is one
// contiguous run of three float arrays (x[], y[], z[]): a texel's children come one after the
// other, recursively, as in a Morton order but following the pyramid's own footprints (odd sizes
// included). The EM then reads its normals without gathering them. Coherent lobes (Sec. 7.3) are
// fitted top-down instead, in vmf_coherent.cpp.
#include <algorithm>
#include <cassert>

#include <omp.h>

#include "methods/vmf/vmf_internal.h"

namespace ndfmip {
namespace vmf {
namespace {

// For each coarse texel along an axis, the first fine texel it covers: coarse edges are a subset
// of the fine edges (pyramid.h). coarse.size() + 1 entries, the last one the fine count.
std::vector<int> firstChildren(const std::vector<int>& coarseEdges,
                               const std::vector<int>& fineEdges) {
    std::vector<int> first(coarseEdges.size());
    size_t f = 0;
    for (size_t c = 0; c < coarseEdges.size(); ++c) {
        while (fineEdges[f] != coarseEdges[c]) ++f;
        first[c] = int(f);
    }
    return first;
}

ChildRanges childRanges(const PyramidLevel& coarse, const PyramidLevel& fine) {
    return {firstChildren(coarse.columnEdges, fine.columnEdges),
            firstChildren(coarse.rowEdges, fine.rowEdges)};
}

// Where each texel's footprint starts in the reordered normals, for every level.
std::vector<std::vector<size_t>> footprintStarts(const Pyramid& pyramid,
                                                 const std::vector<ChildRanges>& children) {
    const int levels = int(pyramid.levels.size());
    std::vector<std::vector<size_t>> start(levels);
    start[levels - 1] = {0};
    for (int k = levels - 1; k >= 1; --k) {
        const PyramidLevel& coarse = pyramid.levels[k];
        const PyramidLevel& fine = pyramid.levels[k - 1];
        const ChildRanges& range = children[k];
        start[k - 1].resize(size_t(fine.width) * fine.height);
#pragma omp parallel for schedule(static)
        for (int y = 0; y < coarse.height; ++y) {
            for (int x = 0; x < coarse.width; ++x) {
                size_t s = start[k][size_t(y) * coarse.width + x];
                for (int fy = range.rows[y]; fy < range.rows[y + 1]; ++fy)
                    for (int fx = range.columns[x]; fx < range.columns[x + 1]; ++fx) {
                        start[k - 1][size_t(fy) * fine.width + fx] = s;
                        s += texelArea(fine, fx, fy);
                    }
            }
        }
    }
    return start;
}

} // namespace

size_t texelArea(const PyramidLevel& level, int x, int y) {
    return size_t(level.columnEdges[x + 1] - level.columnEdges[x]) *
           size_t(level.rowEdges[y + 1] - level.rowEdges[y]);
}

FootprintOrder footprintOrder(const Pyramid& pyramid) {
    const int levelCount = int(pyramid.levels.size());
    const Image& base = *pyramid.base;
    const size_t normalCount = base.texelCount();
    FootprintOrder order;
    order.children.resize(levelCount);
    for (int k = 1; k < levelCount; ++k)
        order.children[k] = childRanges(pyramid.levels[k], pyramid.levels[k - 1]);
    order.start = footprintStarts(pyramid, order.children);
    order.soa.resize(3 * normalCount);
    float* px = order.soa.data();
    float* py = px + normalCount;
    float* pz = py + normalCount;
    const std::vector<size_t>& start0 = order.start[0];
#pragma omp parallel for schedule(static)
    for (size_t t = 0; t < normalCount; ++t) {
        float n[3];
        normalizeOrFlat(&base.pixels[3 * t], n);
        size_t s = start0[t];
        px[s] = n[0];
        py[s] = n[1];
        pz[s] = n[2];
    }
    std::vector<size_t>().swap(order.start[0]);
    return order;
}

} // namespace vmf

namespace {

using vmf::ChildRanges;
using vmf::texelArea;

struct TexelFit {
    int lobes = 0;
    int iterations = 0;
    bool converged = true;
};

// Lobes of texel (x, y) of level k: farthest-point start from the children, EM over the footprint.
TexelFit fitTexel(const Pyramid& pyramid, int k, int x, int y, const ChildRanges& range,
                  const VmfLevel& finer, const vmf::Samples& all, size_t start, int J,
                  const VmfFitOptions& options, bool parallel, VmfLobe* out) {
    const PyramidLevel& fine = pyramid.levels[k - 1];
    const double area = double(texelArea(pyramid.levels[k], x, y));
    thread_local std::vector<VmfLobe> candidates;
    candidates.clear();
    for (int fy = range.rows[y]; fy < range.rows[y + 1]; ++fy)
        for (int fx = range.columns[x]; fx < range.columns[x + 1]; ++fx) {
            float share = float(double(texelArea(fine, fx, fy)) / area);
            for (VmfLobe lobe : finer.texel(fx, fy)) {
                lobe.alpha *= share;
                candidates.push_back(lobe);
            }
        }
    vmf::LobeSet lobes;
    if (options.seeding == VmfSeeding::Merge)
        vmf::mergeCandidates(candidates.data(), candidates.size(), J, options, lobes);
    else
        vmf::farthestPoint(candidates.data(), candidates.size(), J, lobes);

    vmf::Samples samples{all.x + start, all.y + start, all.z + start, nullptr, size_t(area)};
    vmf::EmOutcome outcome = vmf::runEm(samples, lobes, options, parallel, nullptr);
    if (options.lobeBudget > 0.f) {
        vmf::LobeSet fitted = lobes;
        vmf::mergeCandidates(fitted.lobe, size_t(fitted.count), fitted.count, options, lobes,
                             options.lobeBudget);
    }
    std::copy(lobes.lobe, lobes.lobe + lobes.count, out);
    return {lobes.count, outcome.iterations, outcome.converged};
}

VmfLevel packLevel(int width, int height, int J, const std::vector<VmfLobe>& slots,
                   const std::vector<TexelFit>& fits) {
    VmfLevel level;
    level.width = width;
    level.height = height;
    const size_t texels = fits.size();
    level.offsets.resize(texels + 1);
    size_t total = 0;
    for (size_t t = 0; t < texels; ++t) {
        level.offsets[t] = uint32_t(total);
        total += size_t(fits[t].lobes);
    }
    assert(total < (size_t(1) << 32));
    level.offsets[texels] = uint32_t(total);
    level.lobes.resize(total);
#pragma omp parallel for schedule(static)
    for (size_t t = 0; t < texels; ++t)
        std::copy_n(slots.begin() + t * J, fits[t].lobes, level.lobes.begin() + level.offsets[t]);
    return level;
}

} // namespace

std::vector<VmfLevel> fitVmfPyramid(const Pyramid& pyramid, int J, const VmfFitOptions& options,
                                    VmfFitStats* stats) {
    if (options.coherence > 0) return fitVmfPyramidCoherent(pyramid, J, options, stats);
    assert(J >= 1 && J <= kMaxVmfLobes && !pyramid.levels.empty());
    J = std::clamp(J, 1, kMaxVmfLobes);
    const int levelCount = int(pyramid.levels.size());
    const Image& base = *pyramid.base;
    const size_t normalCount = base.texelCount();

    const vmf::FootprintOrder order = vmf::footprintOrder(pyramid);
    const std::vector<ChildRanges>& children = order.children;
    const std::vector<std::vector<size_t>>& start = order.start;
    const vmf::Samples all = order.all();

    // Level 0: one lobe per normal.
    std::vector<VmfLevel> result(levelCount);
    VmfLevel& level0 = result[0];
    level0.width = base.width;
    level0.height = base.height;
    level0.offsets.resize(normalCount + 1);
    level0.lobes.resize(normalCount);
    const float kappa0 = std::clamp(options.levelZeroKappa, 0.f, std::max(options.kappaMax, 0.f));
#pragma omp parallel for schedule(static)
    for (size_t t = 0; t < normalCount; ++t) {
        float n[3];
        normalizeOrFlat(&base.pixels[3 * t], n);
        level0.offsets[t] = uint32_t(t);
        level0.lobes[t] = VmfLobe{1.f, {n[0], n[1], n[2]}, kappa0, glm::vec3(0.f)};
    }
    level0.offsets[normalCount] = uint32_t(normalCount);

    VmfFitStats total;
    const int threads = omp_get_max_threads();
    for (int k = 1; k < levelCount; ++k) {
        const PyramidLevel& coarse = pyramid.levels[k];
        const int width = coarse.width;
        const size_t texels = size_t(width) * coarse.height;
        std::vector<VmfLobe> slots(texels * J);
        std::vector<TexelFit> fits(texels);
        auto fit = [&](size_t t, bool parallel) {
            int x = int(t % width), y = int(t / width);
            fits[t] = fitTexel(pyramid, k, x, y, children[k], result[k - 1], all, start[k][t], J,
                               options, parallel, &slots[t * J]);
        };
        // Many texels: one per thread at a time. The few large texels of the top levels: each
        // fit splits its passes over the normals across the threads instead. Both give the same
        // bits (vmf_internal.h, kChunk).
        if (texels >= size_t(2 * threads)) {
            // Chunks small enough to balance texels of unequal iteration counts.
            const size_t chunk = std::max<size_t>(1, texels / (size_t(threads) * 64));
#pragma omp parallel for schedule(dynamic, chunk)
            for (size_t t = 0; t < texels; ++t) fit(t, false);
        } else {
            for (size_t t = 0; t < texels; ++t) fit(t, true);
        }
        result[k] = packLevel(width, coarse.height, J, slots, fits);
        for (const TexelFit& f : fits) {
            total.iterations += uint64_t(f.iterations);
            total.maxIterations = std::max(total.maxIterations, f.iterations);
            total.notConverged += f.converged ? 0 : 1;
            total.lobes += uint64_t(f.lobes);
        }
        total.texels += texels;
    }
    total.meanIterations = total.texels ? double(total.iterations) / double(total.texels) : 0.0;
    if (stats) *stats = total;
    return result;
}

} // namespace ndfmip
