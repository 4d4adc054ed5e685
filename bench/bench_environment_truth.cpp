// The ground truth under an environment: a 128 x 128 view of a plane in perspective under a
// synthetic 512 x 256 map (a sky gradient and a small sun), GGX alpha 0.2 over a diffuse base.
// Time per image at a given spp; items are pixel samples (each one environment sample, one BRDF
// sample, MIS).
#include <cmath>

#include <benchmark/benchmark.h>

#include "bench_support.h"
#include "ndfmip/environment_lighting.h"
#include "ndfmip/render.h"

namespace {

std::shared_ptr<const ndfmip::EnvironmentLighting> syntheticSky() {
    ndfmip::Environment env;
    env.radiance = ndfmip::Image(512, 256, 3);
    const glm::dvec3 sun = glm::normalize(glm::dvec3(0.4, 0.6, 0.7));
    for (int y = 0; y < 256; ++y)
        for (int x = 0; x < 512; ++x) {
            const glm::dvec3 d = ndfmip::equirectDirection((x + 0.5) / 512, (y + 0.5) / 256);
            const double sky = d.y > 0. ? 0.5 + 0.5 * d.y : 0.1;
            const double glow = glm::dot(d, sun) > 0.999 ? 2000. : 0.;
            float* p = env.radiance.at(x, y);
            p[0] = float(0.6 * sky + glow), p[1] = float(0.7 * sky + glow),
            p[2] = float(sky + 0.9 * glow);
        }
    return std::make_shared<const ndfmip::EnvironmentLighting>(
        ndfmip::makeEnvironmentLighting(std::move(env)));
}

void BM_RenderGroundTruthEnvironment(benchmark::State& state) {
    ndfmip::Scene s;
    s.camera.width = s.camera.height = int(state.range(0));
    s.geometry.size = {4.f, 4.f};
    s.geometry.tiling = {4.f, 4.f};
    s.material.brdf = ndfmip::Brdf::Ggx;
    s.material.roughness = 0.2f;
    s.material.albedo = glm::vec3(0.3f);
    s.environment.path = "(synthetic)";
    ndfmip::RenderTextures t;
    t.normals = ndfmip::bench::syntheticMap(512);
    t.environment = syntheticSky();
    ndfmip::RenderOptions o;
    o.spp = int(state.range(1));
    for (auto _ : state) {
        auto image = ndfmip::render(s, t, ndfmip::kGroundTruth, o);
        benchmark::DoNotOptimize(image.value().pixels.data());
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * state.range(0) * state.range(0) *
                            state.range(1));
}

} // namespace

BENCHMARK(BM_RenderGroundTruthEnvironment)
    ->Args({128, 16})
    ->Args({128, 64})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
