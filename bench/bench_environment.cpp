// Environment maps (environment.h) at the size of the shared 1k maps: the SH projection, one
// GGX level of the default chain, and the DFG table.
#include <cmath>

#include <benchmark/benchmark.h>

#include "ndfmip/environment.h"

namespace {

// A sky with a small bright sun, width x width/2.
const ndfmip::Environment& syntheticSky(int width) {
    static ndfmip::Environment env;
    if (env.radiance.width == width) return env;
    env.radiance = ndfmip::Image(width, width / 2, 3);
    const glm::dvec3 sun = glm::normalize(glm::dvec3(0.6, 0.25, -0.4));
    for (int y = 0; y < width / 2; ++y)
        for (int x = 0; x < width; ++x) {
            const glm::dvec3 d =
                ndfmip::equirectDirection((x + 0.5) / width, (y + 0.5) / (width / 2));
            const double sky = 0.5 + 0.4 * d.y,
                         bright = glm::dot(d, sun) > std::cos(0.02) ? 2000. : 0.;
            float* p = env.radiance.at(x, y);
            p[0] = float(0.6 * sky + bright), p[1] = float(0.8 * sky + bright),
            p[2] = float(sky + bright);
        }
    return env;
}

void BM_EnvironmentSh(benchmark::State& state) {
    const ndfmip::Environment& env = syntheticSky(int(state.range(0)));
    for (auto _ : state) {
        ndfmip::EnvironmentSh sh = ndfmip::projectEnvironmentSh(env, int(state.range(1)));
        benchmark::DoNotOptimize(sh.radiance.data());
    }
}
BENCHMARK(BM_EnvironmentSh)->Args({1024, 8})->Unit(benchmark::kMillisecond)->UseRealTime();

// Level k of the default chain of a 1024-wide map: 1024 >> k wide, r = 1 - sqrt(1 - k/4),
// 1024 samples doubled from level 2.
void BM_PrefilterGgxLevel(benchmark::State& state) {
    const ndfmip::Environment& env = syntheticSky(1024);
    const int k = int(state.range(0));
    const double r = ndfmip::lodToPerceptualRoughness(ndfmip::LodMapping::Filament, k / 4.);
    for (auto _ : state) {
        ndfmip::Image level =
            ndfmip::prefilterGgxLevel(env, r, 1024 >> k, 1024 << std::max(0, k - 1));
        benchmark::DoNotOptimize(level.pixels.data());
    }
}
BENCHMARK(BM_PrefilterGgxLevel)
    ->Arg(1)
    ->Arg(2)
    ->Arg(4)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

void BM_DfgTable(benchmark::State& state) {
    for (auto _ : state) {
        ndfmip::Image table = ndfmip::dfgTable(int(state.range(0)), int(state.range(1)));
        benchmark::DoNotOptimize(table.pixels.data());
    }
}
BENCHMARK(BM_DfgTable)->Args({128, 4096})->Unit(benchmark::kMillisecond)->UseRealTime();

} // namespace
