// The reference renderer: ground truth (many samples per pixel) and a filtered method on a
// plane seen at a grazing angle, which spans every mip level of the map in one image. Methods
// under the default filtering rule (2 x 2 sub-samples, LOD bias -0.5, each texel shaded) and
// under a GPU's plain trilinear lookup (one lookup, parameters blended).
#include <benchmark/benchmark.h>

#include "bench_support.h"
#include "ndfmip/bake.h"
#include "ndfmip/render.h"

namespace {

ndfmip::Scene grazingPlane(int pixels) {
    ndfmip::Scene s;
    s.camera.eye = {0.f, -4.f, 0.8f};
    s.camera.target = {0.f, 0.f, 0.f};
    s.camera.width = s.camera.height = pixels;
    s.geometry.size = {16.f, 16.f};
    s.geometry.tiling = {8.f, 8.f};
    ndfmip::Light light;
    light.direction = glm::normalize(glm::vec3(0.f, 0.6f, 0.8f));
    s.lights = {light};
    s.material.brdf = ndfmip::Brdf::BlinnPhong;
    s.material.exponent = 64.f;
    return s;
}

// The bake of `method` for the scene's material: the fitted single lobes are fitted to its
// roughness.
ndfmip::RenderTextures texturesFor(ndfmip::Method method, const ndfmip::Material& material) {
    ndfmip::RenderTextures t;
    t.normals = ndfmip::bench::syntheticMap(1024);
    ndfmip::BakeOptions options;
    if (ndfmip::bakeFitsMaterialRoughness(method)) options.baseRoughness = material.roughness;
    t.bake = ndfmip::bakeMethod(method, ndfmip::buildPyramid(t.normals), options);
    return t;
}

void BM_RenderGroundTruth(benchmark::State& state) {
    const ndfmip::Scene scene = grazingPlane(int(state.range(0)));
    ndfmip::RenderTextures t;
    t.normals = ndfmip::bench::syntheticMap(1024);
    ndfmip::RenderOptions o;
    o.spp = int(state.range(1));
    for (auto _ : state) {
        auto image = ndfmip::render(scene, t, ndfmip::kGroundTruth, o);
        benchmark::DoNotOptimize(image.value().pixels.data());
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * state.range(0) * state.range(0) *
                            state.range(1));
}

// The scene rendered with `method` under the default rule or (`plain`) a GPU's one trilinear
// lookup with the parameters blended.
void renderMethod(benchmark::State& state, const ndfmip::Scene& scene, ndfmip::Method method,
                  bool plain, float specularAa = 0.f) {
    const ndfmip::RenderTextures t = texturesFor(method, scene.material);
    ndfmip::RenderOptions o;
    o.specularAntiAliasing.variance = specularAa;
    if (plain) {
        o.taps = 1;
        o.lodBias = 0.f;
        o.shadeFilter = ndfmip::ShadeFilter::Parameter;
    }
    for (auto _ : state) {
        auto image = ndfmip::render(scene, t, ndfmip::methodName(method), o);
        benchmark::DoNotOptimize(image.value().pixels.data());
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * state.range(0) * state.range(0));
}

// Args: image side, rule (0 the default, 1 the plain lookup).
void BM_RenderMethod(benchmark::State& state, ndfmip::Method method) {
    renderMethod(state, grazingPlane(int(state.range(0))), method, state.range(1) == 1);
}

// The plain lookup (an engine's one tap, parameters blended) under GGX alpha = 0.1: vmf's lobes
// convolved with GGX (a 12-node mixture per lobe) and the fitted single lobes (ggx-fit's
// roughness, ggx-aniso's tensor from its moments) against Toksvig's one widened lobe.
void BM_RenderMethodGgx(benchmark::State& state, ndfmip::Method method) {
    ndfmip::Scene scene = grazingPlane(int(state.range(0)));
    scene.material.brdf = ndfmip::Brdf::Ggx;
    scene.material.roughness = 0.1f;
    renderMethod(state, scene, method, true);
}

// The plain lookup under GGX alpha = 0.1, naive, without (0) and with (1) an engine's specular
// anti-aliasing (Filament's variance 0.15): the normal plane read at the next pixels too.
void BM_RenderSpecularAa(benchmark::State& state) {
    ndfmip::Scene scene = grazingPlane(int(state.range(0)));
    scene.material.brdf = ndfmip::Brdf::Ggx;
    scene.material.roughness = 0.1f;
    renderMethod(state, scene, ndfmip::Method::Naive, true, state.range(1) == 1 ? 0.15f : 0.f);
}

} // namespace

BENCHMARK(BM_RenderSpecularAa)
    ->Args({1024, 0})
    ->Args({1024, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_RenderGroundTruth)->Args({512, 256})->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_RenderMethod, naive, ndfmip::Method::Naive)
    ->Args({1024, 0})
    ->Args({1024, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_RenderMethod, toksvig, ndfmip::Method::Toksvig)
    ->Args({1024, 0})
    ->Args({1024, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_RenderMethod, sh7, ndfmip::Method::Sh)
    ->Args({1024, 0})
    ->Args({1024, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_RenderMethod, vmf4, ndfmip::Method::Vmf)
    ->Args({1024, 0})
    ->Args({1024, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_RenderMethodGgx, toksvig, ndfmip::Method::Toksvig)
    ->Arg(1024)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_RenderMethodGgx, vmf4, ndfmip::Method::Vmf)
    ->Arg(1024)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_RenderMethodGgx, ggx_fit, ndfmip::Method::GgxFit)
    ->Arg(1024)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_RenderMethodGgx, ggx_aniso, ndfmip::Method::GgxAniso)
    ->Arg(1024)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
