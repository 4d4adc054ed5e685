// Pyramid + Toksvig bake against a plain memcpy of the same input: the bake is memory-bound,
// so the ratio to memcpy says how close it runs to the machine's limit.
#include <cmath>
#include <cstring>
#include <map>
#include <random>

#include <benchmark/benchmark.h>

#include "bench_support.h"
#include "ndfmip/bake.h"
#include "ndfmip/pyramid.h"

namespace {

using ndfmip::bench::syntheticMap;

void setBytes(benchmark::State& state, const ndfmip::Image& map) {
    state.SetBytesProcessed(int64_t(state.iterations()) *
                            int64_t(map.pixels.size() * sizeof(float)));
}

void BM_Memcpy(benchmark::State& state) {
    const ndfmip::SharedImage& shared = syntheticMap(int(state.range(0)));
    const ndfmip::Image& map = *shared;
    std::vector<float> copy(map.pixels.size());
    for (auto _ : state) {
        std::memcpy(copy.data(), map.pixels.data(), map.pixels.size() * sizeof(float));
        benchmark::DoNotOptimize(copy.data());
        benchmark::ClobberMemory();
    }
    setBytes(state, map);
}

void BM_Pyramid(benchmark::State& state) {
    const ndfmip::SharedImage& shared = syntheticMap(int(state.range(0)));
    const ndfmip::Image& map = *shared;
    for (auto _ : state) {
        ndfmip::Pyramid p = ndfmip::buildPyramid(shared);
        benchmark::DoNotOptimize(p.levels.back().mean->pixels.data());
    }
    setBytes(state, map);
}

void BM_ToksvigBake(benchmark::State& state) {
    const ndfmip::SharedImage& shared = syntheticMap(int(state.range(0)));
    const ndfmip::Image& map = *shared;
    for (auto _ : state) {
        ndfmip::Pyramid p = ndfmip::buildPyramid(shared);
        ndfmip::Bake bake = ndfmip::bakeToksvig(p, {});
        benchmark::DoNotOptimize(bake.levels.back().front()->pixels.data());
    }
    setBytes(state, map);
}

// ggx-fit: the pyramid and a GGX roughness fitted to every texel's filtered NDF (alpha 0.1).
void BM_GgxFitBake(benchmark::State& state) {
    const ndfmip::SharedImage& shared = syntheticMap(int(state.range(0)));
    ndfmip::BakeOptions options;
    options.baseRoughness = 0.1f;
    for (auto _ : state) {
        ndfmip::Pyramid p = ndfmip::buildPyramid(shared);
        ndfmip::Bake bake = ndfmip::bakeGgxFit(p, options);
        benchmark::DoNotOptimize(bake.levels.back().back()->pixels.data());
    }
    setBytes(state, *shared);
}

// ggx-aniso: the pyramid and an anisotropic GGX lobe fitted to every texel's filtered NDF
// (alpha 0.1).
void BM_GgxAnisoBake(benchmark::State& state) {
    const ndfmip::SharedImage& shared = syntheticMap(int(state.range(0)));
    ndfmip::BakeOptions options;
    options.baseRoughness = 0.1f;
    for (auto _ : state) {
        ndfmip::Pyramid p = ndfmip::buildPyramid(shared);
        ndfmip::Bake bake = ndfmip::bakeGgxAniso(p, options);
        benchmark::DoNotOptimize(bake.levels.back().back()->pixels.data());
    }
    setBytes(state, *shared);
}

// Spherical-harmonic bake (Han et al. Sec. 5): (l*+1)^2 coefficients per texel at every level.
void BM_ShBake(benchmark::State& state) {
    const ndfmip::SharedImage& shared = syntheticMap(int(state.range(0)));
    ndfmip::BakeOptions options;
    options.parameters["order"] = int(state.range(1));
    for (auto _ : state) {
        ndfmip::Pyramid p = ndfmip::buildPyramid(shared);
        ndfmip::Bake bake = ndfmip::bakeSh(p, options);
        benchmark::DoNotOptimize(bake.levels.back().front()->pixels.data());
    }
    state.counters["bytes_per_texel_level0"] =
        double(ndfmip::shPlaneCount(int(options.parameters["order"])) * 4 * sizeof(float));
}

BENCHMARK(BM_Memcpy)->Arg(1024)->Arg(4096)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Pyramid)->Arg(1024)->Arg(4096)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_ToksvigBake)->Arg(1024)->Arg(4096)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_GgxFitBake)->Arg(1024)->Arg(4096)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_GgxAnisoBake)->Arg(1024)->Arg(4096)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_ShBake)
    ->Args({2048, 7})
    ->Args({1024, 10})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

} // namespace

BENCHMARK_MAIN();
