// Coherent vMF lobes for a whole pyramid (Han et al. 2007, Sec. 7.3): fitted top-down, each
// texel's EM started from its parent's lobes in their slots, and its directions pulled toward the
// same slot of the texels fitted before it (H eq. 32), so that hardware filtering of the packed
// slots (H eq. 33) blends lobes that belong together.
//
// Started from the parent, slot j of every texel under one parent begins as the same lobe and EM
// moves it only as far as the texel's own normals ask: siblings' and cousins' slots stay alike
// without a pull that turns the fine levels' sharp lobes off their normals. (Started instead from
// each texel's own best fit, its lobes permuted into the parent's slots, needed a pull of C = 1
// for the coarse levels' slots to match, and that pull cost the fine levels: in eval's engine
// view 1.15x the floor at footprint 4 against 1.04x started from the parent, docs/RESULTS.md.)
//
// A texel depends on its parent and on its left, upper-left, upper and upper-right neighbours:
// every texel of the anti-diagonal x + 2y = d depends only on earlier anti-diagonals, so each
// one is fitted in parallel and the result is that of the paper's scanline order.
#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <vector>

#include <omp.h>

#include "core/splitmix.h"
#include "methods/vmf/vmf_internal.h"

namespace ndfmip {
namespace {

using vmf::texelArea;

// For each fine texel along an axis, the coarse texel that covers it (firstChild: the
// ChildRanges entries of the coarse level, the last one the fine count).
std::vector<int> parentsOf(const std::vector<int>& firstChild) {
    std::vector<int> parent(size_t(firstChild.back()));
    for (size_t c = 0; c + 1 < firstChild.size(); ++c)
        for (int f = firstChild[c]; f < firstChild[c + 1]; ++f) parent[size_t(f)] = int(c);
    return parent;
}

struct TexelFit {
    int lobes = 0;
    int iterations = 0;
    bool converged = true;
};

TexelFit fitSlots(const vmf::Samples& samples, vmf::LobeSet& lobes, const vmf::Alignment& alignment,
                  const VmfFitOptions& options, bool parallel) {
    vmf::EmOutcome outcome = vmf::runSlotEm(samples, lobes, alignment, options, parallel, nullptr);
    int live = 0;
    for (int j = 0; j < lobes.count; ++j) live += lobes.lobe[j].alpha > 0 ? 1 : 0;
    return {live, outcome.iterations, outcome.converged};
}

VmfLevel slotLevel(int width, int height, int J) {
    VmfLevel level;
    level.width = width;
    level.height = height;
    const size_t texels = size_t(width) * size_t(height);
    assert(texels * size_t(J) < (size_t(1) << 32));
    level.offsets.resize(texels + 1);
    for (size_t t = 0; t <= texels; ++t) level.offsets[t] = uint32_t(t * size_t(J));
    level.lobes.resize(texels * size_t(J));
    return level;
}

// The subsample's stride: a power of two that leaves at least 128 normals across both ways.
int subsampleStride(const Image& base) {
    int stride = 1;
    while (std::min(base.width, base.height) / (2 * stride) >= 128) stride *= 2;
    return stride;
}

// One normal per stride x stride block at a jittered place (the block's own random draw, so
// that a map's period cannot line up with the stride).
Image jitteredSubsample(const Image& base, int stride) {
    const int width = base.width / stride, height = base.height / stride;
    Image sub(width, height, 3, Image::Uninitialized{});
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            SplitMix64 block{uint64_t(y) * uint64_t(width) + uint64_t(x)};
            const uint64_t h = block.next();
            const int jx = int(h % uint64_t(stride)), jy = int((h >> 32) % uint64_t(stride));
            std::copy_n(base.at(x * stride + jx, y * stride + jy), 3, sub.at(x, y));
        }
    return sub;
}

// The plain (bottom-up, merge-seeded) top lobes of a map whose plain pyramid costs little (at
// most 255 normals across: stride 1), or of a jittered subsample of about 128 x 128 normals:
// where the top texel's EM over every normal starts. The whole map's plain pyramid gives the same
// start at about the cost of the coherent fit itself.
struct TopSeed {
    vmf::LobeSet lobes;
    bool fitted = false; // the plain fit of every normal already (stride 1): no EM left to run
};

TopSeed topSeed(const Pyramid& pyramid, int J, const VmfFitOptions& plainOptions) {
    const int stride = subsampleStride(*pyramid.base);
    const std::vector<VmfLevel> plain =
        stride == 1 ? fitVmfPyramid(pyramid, J, plainOptions, nullptr)
                    : fitVmfPyramid(buildPyramid(jitteredSubsample(*pyramid.base, stride)), J,
                                    plainOptions, nullptr);
    const auto top = plain.back().texel(0, 0);
    TopSeed seed;
    seed.lobes.count = int(top.size());
    std::copy(top.begin(), top.end(), seed.lobes.lobe);
    seed.fitted = stride == 1;
    return seed;
}

} // namespace

std::vector<VmfLevel> fitVmfPyramidCoherent(const Pyramid& pyramid, int J,
                                            const VmfFitOptions& options, VmfFitStats* stats) {
    assert(J >= 1 && J <= kMaxVmfLobes && !pyramid.levels.empty());
    J = std::clamp(J, 1, kMaxVmfLobes);
    const int levelCount = int(pyramid.levels.size());
    const int top = levelCount - 1;
    const Image& base = *pyramid.base;
    const float kappa0 = std::clamp(options.levelZeroKappa, 0.f, std::max(options.kappaMax, 0.f));
    const double coherence = options.coherence > 0 ? double(options.coherence) : 0.0;

    std::vector<VmfLevel> result(levelCount);
    for (int k = 0; k < levelCount; ++k)
        result[k] = slotLevel(pyramid.levels[k].width, pyramid.levels[k].height, J);
    VmfFitStats total;
    auto tally = [&total](const TexelFit& f) {
        ++total.texels;
        total.iterations += uint64_t(f.iterations);
        total.maxIterations = std::max(total.maxIterations, f.iterations);
        total.notConverged += f.converged ? 0 : 1;
        total.lobes += uint64_t(f.lobes);
    };

    if (top == 0) { // a 1x1 map: its one normal, in slot 0
        float n[3];
        normalizeOrFlat(base.pixels.data(), n);
        result[0].lobes[0] = VmfLobe{1.f, {n[0], n[1], n[2]}, kappa0, glm::vec3(0.f)};
        if (stats) *stats = total;
        return result;
    }

    const vmf::FootprintOrder order = vmf::footprintOrder(pyramid);
    const vmf::Samples all = order.all();
    const bool nested = omp_in_parallel();

    // The top texel: no parent, no neighbour, no pull; the plain fit of every normal, started
    // from the plain pyramid of a jittered subsample (topSeed); a small map's plain pyramid is
    // that fit already.
    {
        VmfFitOptions plainOptions = options;
        plainOptions.coherence = 0.f;
        plainOptions.alignedKappa = false;
        TopSeed seed = topSeed(pyramid, J, plainOptions);
        vmf::EmOutcome outcome{0, true};
        if (!seed.fitted) outcome = vmf::runEm(all, seed.lobes, plainOptions, !nested, nullptr);
        std::copy(seed.lobes.lobe, seed.lobes.lobe + seed.lobes.count, result[top].lobes.begin());
        tally({seed.lobes.count, outcome.iterations, outcome.converged});
    }

    for (int k = top - 1; k >= 1; --k) {
        const PyramidLevel& level = pyramid.levels[k];
        const int width = level.width, height = level.height;
        const vmf::ChildRanges& up = order.children[k + 1];
        const std::vector<int> parentColumn = parentsOf(up.columns);
        const std::vector<int> parentRow = parentsOf(up.rows);
        const VmfLevel& coarser = result[k + 1];
        VmfLevel& out = result[k];
        std::vector<TexelFit> fits(size_t(width) * height);

        auto fit = [&](int x, int y, bool parallel) {
            const size_t t = size_t(y) * width + x;
            const VmfLobe* parent =
                coarser.texel(parentColumn[size_t(x)], parentRow[size_t(y)]).data();
            vmf::LobeSet lobes;
            lobes.count = J;
            std::copy(parent, parent + J, lobes.lobe);
            // align_j = Sum_k alpha_jk mu_jk over the texels fitted before this one.
            vmf::Alignment alignment;
            auto add = [&](const VmfLobe* neighbour) {
                for (int j = 0; j < J; ++j)
                    if (neighbour[j].alpha > 0)
                        alignment.pull[j] +=
                            double(neighbour[j].alpha) * glm::dvec3(neighbour[j].mu);
            };
            add(parent);
            if (x > 0) add(&out.lobes[out.offsets[t - 1]]);
            if (y > 0) {
                const size_t above = t - size_t(width);
                if (x > 0) add(&out.lobes[out.offsets[above - 1]]);
                add(&out.lobes[out.offsets[above]]);
                if (x + 1 < width) add(&out.lobes[out.offsets[above + 1]]);
            }
            for (int j = 0; j < J; ++j) alignment.pull[j] *= coherence;
            const vmf::Samples samples{all.x + order.start[k][t], all.y + order.start[k][t],
                                       all.z + order.start[k][t], nullptr, texelArea(level, x, y)};
            fits[t] = fitSlots(samples, lobes, alignment, options, parallel);
            std::copy(lobes.lobe, lobes.lobe + J, out.lobes.begin() + out.offsets[t]);
        };

        // Texels this large split their passes across the threads (see fitVmfPyramid).
        const bool large = texelArea(level, 0, 0) >= 8 * vmf::kChunk;
        const int threads = omp_get_max_threads();
        for (int d = 0; d <= (width - 1) + 2 * (height - 1); ++d) {
            const int yLow = std::max(0, (d - (width - 1) + 1) / 2);
            const int yHigh = std::min(height - 1, d / 2);
            const int texels = yHigh - yLow + 1;
            if (large || texels < 2 || nested) {
                for (int y = yLow; y <= yHigh; ++y) fit(d - 2 * y, y, large && !nested);
                continue;
            }
            const int chunk = std::max(1, texels / (threads * 4));
#pragma omp parallel for schedule(dynamic, chunk)
            for (int y = yLow; y <= yHigh; ++y) fit(d - 2 * y, y, false);
        }
        for (const TexelFit& f : fits) tally(f);
    }

    // Level 0: each normal in the slot of the parent lobe most responsible for it.
    {
        const vmf::ChildRanges& up = order.children[1];
        const std::vector<int> parentColumn = parentsOf(up.columns);
        const std::vector<int> parentRow = parentsOf(up.rows);
        VmfLevel& out = result[0];
        const int width = base.width;
#pragma omp parallel for schedule(static)
        for (int y = 0; y < base.height; ++y)
            for (int x = 0; x < width; ++x) {
                const size_t t = size_t(y) * width + x;
                float n[3];
                normalizeOrFlat(&base.pixels[3 * t], n);
                const glm::vec3 normal(n[0], n[1], n[2]);
                const VmfLobe* parent =
                    result[1].texel(parentColumn[size_t(x)], parentRow[size_t(y)]).data();
                int best = -1;
                double bestLog = 0;
                for (int j = 0; j < J; ++j) {
                    if (!(parent[j].alpha > 0)) continue;
                    double logTerm = std::log(double(parent[j].alpha)) +
                                     vmfLogDensity(normal, parent[j].mu, parent[j].kappa);
                    if (best < 0 || logTerm > bestLog) best = j, bestLog = logTerm;
                }
                out.lobes[out.offsets[t] + size_t(std::max(best, 0))] =
                    VmfLobe{1.f, normal, kappa0, glm::vec3(0.f)};
            }
    }

    total.meanIterations = total.texels ? double(total.iterations) / double(total.texels) : 0.0;
    if (stats) *stats = total;
    return result;
}

} // namespace ndfmip
