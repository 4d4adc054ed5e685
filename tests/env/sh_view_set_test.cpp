// The sparse set of prepared views (environment_sh_views.h): the grid and its weights against the
// octahedral map they interpolate in, and the interpolated lighting against prepareShLighting for
// the same view.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "env/env_test_support.h"
#include "ndfmip/environment_sh_views.h"
#include "ndfmip/sh_brdf.h"
#include "ndfmip/spherical_harmonics.h"
#include "test_support.h"

namespace ndfmip {
namespace {

using envtest::mapOf;

// The view's point on the octahedron |x| + |y| + |z| = 1, where the weights are barycentric.
glm::dvec3 octahedral(glm::dvec3 v) {
    return v / (std::fabs(v.x) + std::fabs(v.y) + std::fabs(v.z));
}

// Views of every kind: random, on the axes, on the faces' edges (one coordinate 0, either sign).
std::vector<glm::dvec3> testViews() {
    std::vector<glm::dvec3> views = {{1., 0., 0.},       {0., -1., 0.},      {0., 0., -1.},
                                     {0.3, 0., -0.7},    {-0., 0.5, 0.2},    {0.4, -0.4, 0.},
                                     {1e-17, 0.6, -0.3}, {-1e-17, 0.6, -0.3}};
    std::mt19937 rng(7);
    std::normal_distribution<double> gauss;
    for (int i = 0; i < 200; ++i) views.push_back(glm::dvec3(gauss(rng), gauss(rng), gauss(rng)));
    return views;
}

// A sky with a small bright sun: the case the fixed view finds hardest.
glm::dvec3 sunSky(glm::dvec3 d) {
    const glm::dvec3 sun = glm::normalize(glm::dvec3(0.6, 0.5, 0.4));
    return glm::dvec3(0.5 + 0.4 * d.y) + glm::dvec3(40. * std::exp(200. * (glm::dot(d, sun) - 1.)));
}

glm::dvec3 gradientSky(glm::dvec3 d) {
    return {1. + 0.5 * d.x - 0.3 * d.y, 0.8 + 0.2 * d.z + 0.3 * d.x * d.y, 0.6 + 0.4 * d.y * d.y};
}

// A proper rotation whose columns are a tangent frame in the environment frame.
glm::mat3 tangentFrame(glm::dvec3 normal, glm::dvec3 towards) {
    const glm::dvec3 n = glm::normalize(normal),
                     t = glm::normalize(towards - glm::dot(towards, n) * n);
    return glm::mat3(glm::dmat3(t, glm::cross(n, t), n));
}

Material blinnPhong16() {
    Material m;
    m.brdf = Brdf::BlinnPhong;
    m.exponent = 16.f;
    m.albedo = glm::vec3(0.f);
    m.specular = glm::vec3(1.f);
    return m;
}

// A sharp NDF at the tangent frame's normal: g_lm = Y_lm(z).
std::vector<float> sharpNdf(int order) {
    const std::vector<double> y = evaluateSh(glm::dvec3(0., 0., 1.), order);
    return std::vector<float>(y.begin(), y.end());
}

// ---- the grid and its weights
// ----------------------------------------------------------------------

TEST(ShViewSet, GridHasItsCountOfDistinctUnitViews) {
    for (int f = 1; f <= 6; ++f) {
        const std::vector<glm::dvec3> views = shViewDirections(f);
        ASSERT_EQ(int(views.size()), 4 * f * f + 2) << "f = " << f;
        EXPECT_EQ(shViewCount(f), 4 * f * f + 2);
        EXPECT_EQ(shViewFrequency(shViewCount(f)), f);
        EXPECT_EQ(shViewFrequency(shViewCount(f) + 1), f + 1);
        for (size_t i = 0; i < views.size(); ++i) {
            EXPECT_NEAR(glm::length(views[i]), 1., 1e-15);
            for (size_t j = 0; j < i; ++j)
                EXPECT_GT(glm::length(views[i] - views[j]), 0.1 / f) << i << " " << j;
        }
    }
    EXPECT_EQ(shViewFrequency(1), 1);
    EXPECT_EQ(kMaxShViews, shViewCount(kMaxShViewFrequency));
}

TEST(ShViewSet, AGridViewIsItsOwnOnlyNeighbour) {
    for (int f : {1, 2, 3, 5, kMaxShViewFrequency}) {
        const std::vector<glm::dvec3> views = shViewDirections(f);
        for (size_t i = 0; i < views.size(); ++i) {
            const ShViewWeights w = shViewWeights(f, views[i]);
            ASSERT_EQ(w.count, 1) << "f = " << f << ", view " << i;
            EXPECT_EQ(w.index[0], int(i));
            EXPECT_EQ(w.weight[0], 1.);
        }
    }
}

// Non-negative, summing to 1, and reproducing the view's point on the octahedron from its
// neighbours' points (barycentric weights reproduce every linear function of the face), with
// neighbours no farther than a cell.
TEST(ShViewSet, WeightsAreBarycentricInTheOctahedralMap) {
    for (int f : {1, 2, 4, 7}) {
        const std::vector<glm::dvec3> grid = shViewDirections(f);
        for (glm::dvec3 v : testViews()) {
            const ShViewWeights w = shViewWeights(f, v);
            ASSERT_GE(w.count, 1);
            ASSERT_LE(w.count, 3);
            double sum = 0.;
            glm::dvec3 point(0.);
            for (int k = 0; k < w.count; ++k) {
                EXPECT_GT(w.weight[k], 0.);
                ASSERT_GE(w.index[k], 0);
                ASSERT_LT(w.index[k], int(grid.size()));
                sum += w.weight[k];
                point += w.weight[k] * octahedral(grid[size_t(w.index[k])]);
                // A cell's corners are within one step (1/f in the map) on each axis.
                const glm::dvec3 gap = octahedral(grid[size_t(w.index[k])]) - octahedral(v);
                EXPECT_LE(std::fabs(gap.x) + std::fabs(gap.y) + std::fabs(gap.z), 2. / f + 1e-12);
            }
            EXPECT_NEAR(sum, 1., 1e-14);
            const glm::dvec3 expected = octahedral(v);
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(point[c], expected[c], 1e-14) << "f = " << f;
        }
    }
}

// Continuous over the faces' edges: views a hair apart on either side of x = 0 or z = 0 blend
// the grid's views (any smooth function of them) to nearly the same value.
TEST(ShViewSet, WeightsAreContinuousAcrossFaces) {
    const int f = 3;
    const std::vector<glm::dvec3> grid = shViewDirections(f);
    auto blend = [&](glm::dvec3 v) {
        const ShViewWeights w = shViewWeights(f, v);
        glm::dvec3 sum(0.);
        for (int k = 0; k < w.count; ++k)
            sum += w.weight[k] * gradientSky(grid[size_t(w.index[k])]);
        return sum;
    };
    for (glm::dvec3 edge :
         {glm::dvec3(0., 0.3, 0.7), glm::dvec3(0.4, -0.5, 0.), glm::dvec3(0., -0.2, -0.9)}) {
        const glm::dvec3 across =
            edge.x == 0. ? glm::dvec3(1e-9, 0., 0.) : glm::dvec3(0., 0., 1e-9);
        const glm::dvec3 a = blend(edge + across), b = blend(edge - across);
        EXPECT_LT(glm::length(a - b), 1e-7);
    }
}

// ---- the interpolated lighting
// ---------------------------------------------------------------------

void expectSameCoefficients(const std::vector<glm::dvec3>& a, const std::vector<glm::dvec3>& b) {
    ASSERT_EQ(a.size(), b.size());
    for (size_t i = 0; i < a.size(); ++i)
        for (int c = 0; c < 3; ++c) EXPECT_EQ(a[i][c], b[i][c]) << "coefficient " << i;
}

TEST(ShViewSet, AtAPreparedViewEqualsPrepareShLighting) {
    const Environment env = mapOf(48, sunSky);
    const int order = 4, f = 2;
    const std::vector<glm::dvec3> grid = shViewDirections(f);
    for (SpecularCosine cosine : {SpecularCosine::MeanNormal, SpecularCosine::HalfVector,
                                  SpecularCosine::None, SpecularCosine::Reflecting}) {
        const ShViewSet set = prepareShViewSet(env, order, f, cosine);
        ASSERT_EQ(set.views.size(), grid.size());
        for (size_t i : {size_t(0), size_t(5), size_t(11), grid.size() - 1}) {
            const ShLighting exact = prepareShLighting(env, order, grid[i], cosine);
            const ShLighting interpolated = interpolateShLighting(set, grid[i]);
            EXPECT_EQ(interpolated.order, order);
            EXPECT_EQ(interpolated.cosine, cosine);
            expectSameCoefficients(interpolated.radiance, exact.radiance);
            expectSameCoefficients(interpolated.reparameterised, exact.reparameterised);
            for (int k = 0; k < 3; ++k)
                expectSameCoefficients(interpolated.reparameterisedAxes[k],
                                       exact.reparameterisedAxes[k]);
            EXPECT_TRUE(set.views[i].radiance.empty()); // L is kept once, in the set
        }
    }
}

// With no cosine, L'_00 = Integral L(w_i) Y_00 dw_i = L_00 for every view (Y_00 is constant and
// the Jacobian cancels), so its interpolation must give L_00 for any view; the higher bands do
// depend on the view.
TEST(ShViewSet, ViewIndependentCoefficientInterpolatesExactly) {
    const Environment env = mapOf(48, sunSky);
    const ShViewSet set = prepareShViewSet(env, 2, 2, SpecularCosine::None);
    double spread = 0.;
    for (glm::dvec3 v : testViews()) {
        const ShLighting lighting = interpolateShLighting(set, v);
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(lighting.reparameterised[0][c], set.radiance[0][c],
                        1e-11 * set.radiance[0][c]);
        spread = std::max(
            spread, std::fabs(lighting.reparameterised[2].x - set.views[0].reparameterised[2].x));
    }
    EXPECT_GT(spread, 1e-3 * set.radiance[0].x);
}

// The relative RMS error of the specular term of a sharp NDF (Blinn-Phong s = 16, order 8) with
// the interpolated lighting against the lighting prepared for each true view, over `count` true
// views spread over the sphere (none on the grid) and 80 normals facing each.
double interpolationError(const Environment& env, const ShViewSet& set, int count) {
    const Material m = blinnPhong16();
    const ShShading a = shShadingFor(m, set.order).value();
    const std::vector<float> g = sharpNdf(set.order);
    double error = 0., norm = 0.;
    for (int j = 0; j < count; ++j) {
        const glm::dvec3 view = envtest::spiralDirection(j, count);
        const ShLighting exact = prepareShLighting(env, set.order, view, set.cosine);
        const ShLighting interpolated = interpolateShLighting(set, view);
        for (int i = 0; i < 200; ++i) {
            const glm::dvec3 n = envtest::spiralDirection(i, 200);
            if (glm::dot(n, view) < 0.2) continue;
            const glm::mat3 frame = tangentFrame(n, glm::cross(view, glm::dvec3(0.3, 0.9, 0.1)));
            const glm::vec3 v(glm::transpose(glm::dmat3(frame)) * view);
            const glm::dvec3 reference(
                shadeShEnvironment(m, glm::vec3(0.f), g.data(), a, v, frame, exact));
            const glm::dvec3 approximate(
                shadeShEnvironment(m, glm::vec3(0.f), g.data(), a, v, frame, interpolated));
            error += glm::dot(approximate - reference, approximate - reference);
            norm += glm::dot(reference, reference);
        }
    }
    return std::sqrt(error / norm);
}

// Errors per set size for docs/ENVIRONMENT.md; each larger set must do better.
std::vector<double> errorsBySetSize(const Environment& env, const std::vector<int>& frequencies,
                                    const char* name) {
    std::vector<double> errors;
    for (int f : frequencies) {
        const ShViewSet set = prepareShViewSet(env, 8, f);
        errors.push_back(interpolationError(env, set, 7));
        std::printf(
            "%s: %4d views (f = %d): relative RMS specular error against the true view %.4f\n",
            name, shViewCount(f), f, errors.back());
    }
    return errors;
}

TEST(ShViewSet, ErrorBetweenViewsFallsAsTheSetGrows) {
    const std::vector<double> errors = errorsBySetSize(mapOf(64, sunSky), {1, 2, 4}, "sun sky");
    for (size_t i = 1; i < errors.size(); ++i) EXPECT_LT(errors[i], errors[i - 1]);
    EXPECT_GT(errors.front(), 0.);
}

TEST(ShViewSet, ErrorBetweenViewsOnSharedMaps) {
    const auto maps = envtest::sharedMapsAt(128);
    if (maps.empty()) GTEST_SKIP() << "no shared environment maps";
    for (const auto& [file, env] : maps) {
        const std::vector<double> errors = errorsBySetSize(env, {1, 2, 4}, file.c_str());
        for (size_t i = 1; i < errors.size(); ++i) EXPECT_LT(errors[i], errors[i - 1]);
    }
}

// The sh shading keeps the lighting rotated into the last frame, per thread, keyed by the
// lighting's id: a second view's lighting in the same frame must not be served the first's.
TEST(ShViewSet, ShadingInOneFrameFollowsTheInterpolatedView) {
    const Environment env = mapOf(48, sunSky);
    const ShViewSet set = prepareShViewSet(env, 4, 2);
    const Material m = blinnPhong16();
    const ShShading a = shShadingFor(m, 4).value();
    const std::vector<float> g = sharpNdf(4);
    const glm::mat3 frame = tangentFrame(glm::dvec3(0.1, 0.9, 0.3), glm::dvec3(1., 0., 0.));
    const glm::dvec3 first = glm::normalize(glm::dvec3(0.2, 0.8, 0.5)),
                     second = glm::normalize(glm::dvec3(-0.4, 0.7, 0.1));
    auto shade = [&](glm::dvec3 view, ShLighting& lighting) {
        interpolateShLighting(set, view, lighting);
        const glm::vec3 v(glm::transpose(glm::dmat3(frame)) * view);
        return shadeShEnvironment(m, glm::vec3(0.f), g.data(), a, v, frame, lighting);
    };
    glm::vec3 fresh(0.f); // the second view shaded on a thread whose cache is empty
    std::thread([&] {
        ShLighting lighting;
        fresh = shade(second, lighting);
    }).join();
    ShLighting reused; // one buffer for both views, as the renderer keeps one per thread
    const glm::vec3 before = shade(first, reused);
    const glm::vec3 after = shade(second, reused);
    EXPECT_EQ(after, fresh);
    EXPECT_NE(after, before);
}

} // namespace
} // namespace ndfmip
