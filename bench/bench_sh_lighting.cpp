// The paper's environment shading (environment_sh_shading.h): rotating order-8 SH coefficients,
// preparing the lighting of a 1024-wide map, and one shade call per method.
#include <cmath>
#include <random>
#include <vector>

#include <benchmark/benchmark.h>

#include "ndfmip/environment_sh_shading.h"
#include "ndfmip/environment_sh_views.h"
#include "ndfmip/sh_rotation.h"
#include "ndfmip/spherical_harmonics.h"

namespace {

glm::dmat3 someRotation() {
    const glm::dvec3 n = glm::normalize(glm::dvec3(0.3, -0.5, 0.8)),
                     t = glm::normalize(glm::cross(glm::dvec3(0., 1., 0.), n));
    return glm::dmat3(t, glm::cross(n, t), n);
}

void BM_RotateSh(benchmark::State& state) {
    const int order = int(state.range(0)), channels = int(state.range(1));
    std::vector<double> in(size_t(ndfmip::shCount(order) * channels)), out(in.size());
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> u(-1., 1.);
    for (double& x : in) x = u(rng);
    const glm::dmat3 r = someRotation();
    ndfmip::rotateSh(r, order, in.data(), out.data(), channels); // the per-order table, built once
    for (auto _ : state) {
        ndfmip::rotateSh(r, order, in.data(), out.data(), channels);
        benchmark::DoNotOptimize(out.data());
    }
}
BENCHMARK(BM_RotateSh)->Args({8, 1})->Args({8, 6})->Unit(benchmark::kMicrosecond);

const ndfmip::Environment& sky() {
    static ndfmip::Environment env = [] {
        ndfmip::Environment e;
        const int width = 1024;
        e.radiance = ndfmip::Image(width, width / 2, 3);
        for (int y = 0; y < width / 2; ++y)
            for (int x = 0; x < width; ++x) {
                const glm::dvec3 d =
                    ndfmip::equirectDirection((x + 0.5) / width, (y + 0.5) / (width / 2));
                float* p = e.radiance.at(x, y);
                p[0] = p[1] = p[2] = float(0.5 + 0.4 * d.y);
            }
        return e;
    }();
    return env;
}

void BM_PrepareShLighting(benchmark::State& state) {
    for (auto _ : state) {
        ndfmip::ShLighting lighting = ndfmip::prepareShLighting(sky(), 8, glm::dvec3(0., 0., 1.));
        benchmark::DoNotOptimize(lighting.reparameterised.data());
    }
}
BENCHMARK(BM_PrepareShLighting)->Unit(benchmark::kMillisecond)->UseRealTime();

// The sparse set of views (environment_sh_views.h) of the grid of frequency f (4 f^2 + 2 views):
// L once, then L' per view.
void BM_PrepareShViewSet(benchmark::State& state) {
    const int f = int(state.range(0));
    for (auto _ : state) {
        ndfmip::ShViewSet set = ndfmip::prepareShViewSet(sky(), 8, f);
        benchmark::DoNotOptimize(set.views.data());
    }
    state.counters["views"] = ndfmip::shViewCount(f);
}
BENCHMARK(BM_PrepareShViewSet)
    ->Arg(1)
    ->Arg(2)
    ->Arg(4)
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// What a pixel pays for its own view: the weights and the blend of L' (order 8, mean-normal axes).
void BM_InterpolateShLighting(benchmark::State& state) {
    static const ndfmip::ShViewSet set = [] {
        ndfmip::Environment small;
        small.radiance = ndfmip::resampleEquirect(sky().radiance, 64);
        return ndfmip::prepareShViewSet(small, 8, 4);
    }();
    ndfmip::ShLighting lighting;
    glm::dvec3 view = glm::normalize(glm::dvec3(0.3, 0.8, 0.5));
    for (auto _ : state) {
        ndfmip::interpolateShLighting(set, view, lighting);
        benchmark::DoNotOptimize(lighting.reparameterisedAxes[0].data());
        view.x = -view.x; // alternate between two cells
    }
}
BENCHMARK(BM_InterpolateShLighting)->Unit(benchmark::kMicrosecond);

// One texel's parameters under a smooth sky, order 8: the SH method's coefficients of a single
// normal, four vMF lobes.
struct ShadingSetup {
    ndfmip::Material material;
    ndfmip::ShShading a;
    ndfmip::ShLighting lighting;
    std::vector<float> g;
    float lobes[16] = {0.4f, 0.f, 0.f,  0.39f, 0.3f, 0.1f,   0.f, 0.28f,
                       0.2f, 0.f, 0.1f, 0.18f, 0.1f, -0.05f, 0.f, 0.09f};
    glm::mat3 frame{someRotation()};

    explicit ShadingSetup(ndfmip::Brdf brdf) {
        material.brdf = brdf;
        material.albedo = glm::vec3(0.5f);
        a = ndfmip::shShadingFor(material, 8).value();
        lighting = ndfmip::prepareShLighting(
            [](glm::dvec3 d) { return glm::dvec3(0.5 + 0.4 * d.y); }, 8, glm::dvec3(0., 0., 1.),
            ndfmip::SpecularCosine::MeanNormal, 16);
        const std::vector<double> y = ndfmip::evaluateSh(glm::dvec3(0., 0., 1.), 8);
        g.assign(y.begin(), y.end());
    }
};

void BM_ShadeShEnvironment(benchmark::State& state) {
    const ShadingSetup s(ndfmip::Brdf::BlinnPhong);
    for (auto _ : state)
        benchmark::DoNotOptimize(ndfmip::shadeShEnvironment(
            s.material, s.material.albedo, s.g.data(), s.a, {0.f, 0.f, 1.f}, s.frame, s.lighting));
}
BENCHMARK(BM_ShadeShEnvironment)->Unit(benchmark::kMicrosecond);

// Four lobes; Blinn-Phong's widened lobe is in closed form, GGX's is projected per lobe.
void BM_ShadeVmfEnvironmentSh(benchmark::State& state) {
    const auto brdf = state.range(0) == 0 ? ndfmip::Brdf::BlinnPhong : ndfmip::Brdf::Ggx;
    const auto transfer = state.range(1) == 0 ? ndfmip::VmfSpecularTransfer::Widened
                                              : ndfmip::VmfSpecularTransfer::Convolved;
    const ShadingSetup s(brdf);
    for (auto _ : state)
        benchmark::DoNotOptimize(ndfmip::shadeVmfEnvironmentSh(s.material, s.material.albedo,
                                                               s.lobes, 4, nullptr, {0.f, 0.f, 1.f},
                                                               s.frame, s.lighting, s.a, transfer));
}
BENCHMARK(BM_ShadeVmfEnvironmentSh)
    ->Args({0, 0})
    ->Args({1, 0})
    ->Args({1, 1})
    ->Unit(benchmark::kMicrosecond);

} // namespace
