// The split-sum (engine) shading of each method (environment_splitsum.h): preparing the lighting
// from a 1024x512 map, and shading throughput per method over a fixed set of inputs.
#include <cmath>
#include <random>
#include <vector>

#include <benchmark/benchmark.h>

#include "ndfmip/environment_splitsum.h"

namespace {

// A sky with a small bright sun, 1024 x 512 (as bench_environment.cpp).
const ndfmip::Environment& sky() {
    static ndfmip::Environment env;
    if (!env.radiance.empty()) return env;
    const int width = 1024;
    env.radiance = ndfmip::Image(width, width / 2, 3);
    const glm::dvec3 sun = glm::normalize(glm::dvec3(0.6, 0.25, -0.4));
    for (int y = 0; y < width / 2; ++y)
        for (int x = 0; x < width; ++x) {
            const glm::dvec3 d =
                ndfmip::equirectDirection((x + 0.5) / width, (y + 0.5) / (width / 2));
            const double s = 0.5 + 0.4 * d.y,
                         bright = glm::dot(d, sun) > std::cos(0.02) ? 2000. : 0.;
            float* p = env.radiance.at(x, y);
            p[0] = float(0.6 * s + bright), p[1] = float(0.8 * s + bright),
            p[2] = float(s + bright);
        }
    return env;
}

// Preparation at level-0 width range(0) with the default options (all four chains, the lobe
// albedo tables, order-2 SH).
void BM_PrepareSplitSum(benchmark::State& state) {
    ndfmip::SplitSumOptions options;
    options.size = int(state.range(0));
    for (auto _ : state) {
        ndfmip::SplitSumLighting lighting = ndfmip::prepareSplitSum(sky(), options);
        benchmark::DoNotOptimize(lighting.chains.data());
    }
}
BENCHMARK(BM_PrepareSplitSum)->Arg(256)->Arg(512)->Unit(benchmark::kMillisecond)->UseRealTime();

// One rule's chain alone (range(1): 0 log2sigma, 1 filament, 2 unity, 3 unreal) at width
// range(0), with the SH and a 2 x 2 albedo table of 1 sample (negligible).
void BM_PrepareSplitSumChain(benchmark::State& state) {
    ndfmip::SplitSumOptions options;
    options.size = int(state.range(0));
    options.rules = {ndfmip::EnvironmentLod(state.range(1))};
    options.albedoTableSize = 2;
    options.albedoSamples = 1;
    for (auto _ : state) {
        ndfmip::SplitSumLighting lighting = ndfmip::prepareSplitSum(sky(), options);
        benchmark::DoNotOptimize(lighting.chains.data());
    }
}
BENCHMARK(BM_PrepareSplitSumChain)
    ->ArgsProduct({{256}, {0, 1, 2, 3}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

const ndfmip::SplitSumLighting& lighting() {
    static const ndfmip::SplitSumLighting prepared = ndfmip::prepareSplitSum(sky(), {});
    return prepared;
}

struct Inputs {
    std::vector<glm::vec3> normals, views;
};

const Inputs& inputs() {
    static Inputs in;
    if (!in.normals.empty()) return in;
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(-0.6f, 0.6f), length(0.7f, 1.f);
    for (int i = 0; i < 4096; ++i) {
        in.normals.push_back(glm::normalize(glm::vec3(u(rng), u(rng), 1.f)) * length(rng));
        in.views.push_back(glm::normalize(glm::vec3(u(rng), u(rng), 1.f)));
    }
    return in;
}

ndfmip::Material ggx() {
    ndfmip::Material m;
    m.brdf = ndfmip::Brdf::Ggx;
    m.roughness = 0.2f;
    m.albedo = glm::vec3(0.3f);
    return m;
}

// Shades per second for one method (range(0)) under one LOD rule (range(1)): 0 naive, 1 toksvig,
// 2 roughness mips, 3 vmf with 4 lobes.
void BM_ShadeSplitSum(benchmark::State& state) {
    const Inputs& in = inputs();
    const ndfmip::SplitSumLighting& light = lighting();
    const ndfmip::Material m = ggx();
    const auto rule = ndfmip::EnvironmentLod(state.range(1));
    const glm::mat3 frame(1.f);
    std::vector<float> lobes(16);
    size_t i = 0;
    for (auto _ : state) {
        const size_t k = i++ % in.normals.size();
        const glm::vec3 na = in.normals[k], v = in.views[k];
        glm::vec3 c;
        switch (state.range(0)) {
        case 0:
            c = ndfmip::shadeNaiveSplitSum(m, m.albedo, na, v, frame, light, rule);
            break;
        case 1:
            c = ndfmip::shadeToksvigSplitSum(m, m.albedo, na, v, frame, light, rule,
                                             ndfmip::RoughnessMapping::Ours);
            break;
        case 2:
            c = ndfmip::shadeRoughnessMipsSplitSum(m, m.albedo, na, 0.5f, false, v, frame, light,
                                                   rule);
            break;
        default:
            for (int j = 0; j < 4; ++j) {
                const glm::vec3 mu = in.normals[(k + size_t(j)) % in.normals.size()];
                lobes[size_t(4 * j)] = 0.25f;
                for (int a = 0; a < 3; ++a) lobes[size_t(4 * j + 1 + a)] = 0.25f * mu[a];
            }
            c = ndfmip::shadeVmfSplitSum(m, m.albedo, lobes.data(), 4, nullptr, v, frame, light,
                                         rule);
        }
        benchmark::DoNotOptimize(c);
    }
    state.SetItemsProcessed(int64_t(state.iterations()));
}
BENCHMARK(BM_ShadeSplitSum)->ArgsProduct({{0, 1, 2, 3}, {0, 1}})->Unit(benchmark::kNanosecond);

} // namespace
