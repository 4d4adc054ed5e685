// vMF lobes for a whole pyramid (Han et al. 2007, Sec. 7): merged or farthest-point seeds and
// spherical EM over every level-0 normal of every texel, plain or coherent (Sec. 7.3). Each level
// costs about the same, (normals) x J x (iterations + 1) exps, so the counters report the EM
// iterations.
#include <benchmark/benchmark.h>

#include "bench_support.h"
#include "ndfmip/pyramid.h"
#include "ndfmip/vmf.h"

namespace {

using ndfmip::bench::syntheticMap;

void setCounters(benchmark::State& state, const ndfmip::VmfFitStats& stats, size_t texels) {
    state.counters["mean_iterations"] = stats.meanIterations;
    state.counters["max_iterations"] = double(stats.maxIterations);
    state.counters["not_converged"] = double(stats.notConverged);
    state.counters["lobes_per_texel"] = double(stats.lobes) / double(stats.texels);
    state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(texels));
}

// Args: map size, J, seeding (0 merge, the default; 1 farthest point). The pyramid itself (a
// few ms) is built outside the timing.
void BM_VmfPyramid(benchmark::State& state) {
    const ndfmip::SharedImage& map = syntheticMap(int(state.range(0)));
    ndfmip::Pyramid pyramid = ndfmip::buildPyramid(map);
    ndfmip::VmfFitOptions options;
    options.seeding =
        state.range(2) == 0 ? ndfmip::VmfSeeding::Merge : ndfmip::VmfSeeding::FarthestPoint;
    ndfmip::VmfFitStats stats;
    for (auto _ : state) {
        std::vector<ndfmip::VmfLevel> levels =
            ndfmip::fitVmfPyramid(pyramid, int(state.range(1)), options, &stats);
        benchmark::DoNotOptimize(levels.back().lobes.data());
    }
    setCounters(state, stats, map->texelCount());
}

// Coherent lobes (Sec. 7.3), C = 1: top-down, each level's texels in anti-diagonal wavefronts.
// Args: map size, J, alignedKappa. lobe_mismatch: lobeMismatch of the result, degrees.
void BM_VmfPyramidCoherent(benchmark::State& state) {
    const ndfmip::SharedImage& map = syntheticMap(int(state.range(0)));
    ndfmip::Pyramid pyramid = ndfmip::buildPyramid(map);
    ndfmip::VmfFitOptions options;
    options.coherence = 1;
    options.alignedKappa = state.range(2) != 0;
    ndfmip::VmfFitStats stats;
    std::vector<ndfmip::VmfLevel> levels;
    for (auto _ : state) {
        levels = ndfmip::fitVmfPyramidCoherent(pyramid, int(state.range(1)), options, &stats);
        benchmark::DoNotOptimize(levels.back().lobes.data());
    }
    setCounters(state, stats, map->texelCount());
    state.counters["lobe_mismatch"] = ndfmip::lobeMismatch(levels);
}

// One large texel: the E-step's throughput, in normal-lobe evaluations per second.
void BM_VmfFitOneTexel(benchmark::State& state) {
    const ndfmip::SharedImage& map = syntheticMap(int(state.range(0)));
    const int J = int(state.range(1));
    std::vector<glm::vec3> normals(map->texelCount());
    for (size_t i = 0; i < normals.size(); ++i)
        normals[i] = glm::vec3(map->pixels[3 * i], map->pixels[3 * i + 1], map->pixels[3 * i + 2]);
    std::vector<ndfmip::VmfLobe> candidates;
    for (size_t i = 0; i < 64; ++i)
        candidates.push_back({1.f, normals[i * 7919 % normals.size()], 20.f});
    std::vector<ndfmip::VmfLobe> start = ndfmip::farthestPointLobes(candidates, J);
    ndfmip::VmfFitOptions options;
    options.tolerance = 0; // a fixed number of passes
    options.maxIterations = 10;
    options.minAlpha = 0;
    int64_t evaluations = 0;
    for (auto _ : state) {
        ndfmip::VmfFitResult fit =
            ndfmip::fitVmfMixture(normals.data(), nullptr, normals.size(), start, options);
        evaluations += int64_t(normals.size()) * int64_t(fit.logLikelihoodTrace.size()) * J;
        benchmark::DoNotOptimize(fit.lobes.data());
    }
    state.SetItemsProcessed(evaluations);
}

BENCHMARK(BM_VmfPyramid)
    ->Args({512, 4, 0})
    ->Args({512, 4, 1})
    ->Args({512, 6, 0})
    ->Args({512, 6, 1})
    ->Args({512, 8, 0})
    ->Args({512, 8, 1})
    ->Args({2048, 4, 0})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_VmfPyramidCoherent)
    ->Args({512, 4, 0})
    ->Args({512, 4, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_VmfFitOneTexel)
    ->Args({512, 4})
    ->Args({512, 6})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

} // namespace
