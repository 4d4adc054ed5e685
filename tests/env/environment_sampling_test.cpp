// The environment sampler: its density integrates to 1, agrees with what it samples, follows the
// luminance, and the world <-> environment mapping is a proper rotation.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "env/env_test_support.h"
#include "ndfmip/environment_lighting.h"

namespace ndfmip {
namespace {

// A map with a bright blob, a coloured band and a dark floor, so rows and columns differ.
Environment unevenMap(int width, double rotationDegrees = 0.) {
    Environment env = envtest::mapOf(width, [](glm::dvec3 d) {
        const double blob =
            std::exp(20. * (glm::dot(d, glm::normalize(glm::dvec3(0.6, 0.5, -0.3))) - 1.));
        const double band = std::abs(d.y) < 0.2 ? 0.5 : 0.;
        return glm::dvec3(0.05 + 30. * blob + band, 0.02 + 20. * blob, d.y > 0. ? 0.1 : 0.);
    });
    env.rotation = rotationDegrees * M_PI / 180.;
    return env;
}

TEST(EnvironmentFrames, WorldToEnvironmentIsAProperRotationAndItsInverse) {
    const glm::vec3 x = worldToEnvironment(glm::vec3(1, 0, 0)),
                    y = worldToEnvironment(glm::vec3(0, 1, 0)),
                    z = worldToEnvironment(glm::vec3(0, 0, 1));
    EXPECT_FLOAT_EQ(glm::dot(glm::cross(x, y), z), 1.f); // right-handed stays right-handed
    EXPECT_EQ(z, glm::vec3(0, 1, 0));                    // world up is the map's top
    EXPECT_EQ(y, glm::vec3(0, 0, 1));                    // the default view is the map's centre
    const glm::vec3 w(0.3f, -0.7f, 0.2f);
    EXPECT_EQ(environmentToWorld(worldToEnvironment(w)), w);
    const glm::mat3 m = tangentToEnvironment({1, 0, 0}, {0, 1, 0}, {0, 0, 1});
    EXPECT_EQ(m * w, worldToEnvironment(w));
}

TEST(EnvironmentSampler, PdfIntegratesToOneOverTheSphere) {
    for (double rotation : {0., 73.}) {
        const EnvironmentSampler s = makeEnvironmentSampler(unevenMap(64, rotation));
        // Midpoint rule on a grid 4x finer than the texels.
        const int w = 256, h = 128;
        double sum = 0.;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                sum += environmentPdf(s, equirectDirection((x + 0.5) / w, (y + 0.5) / h)) *
                       equirectTexelSolidAngle(w, h, y);
        EXPECT_NEAR(sum, 1., 1e-9) << "rotation " << rotation;
    }
}

TEST(EnvironmentSampler, SampledPdfEqualsPdfOfTheSampledDirection) {
    const EnvironmentSampler s = makeEnvironmentSampler(unevenMap(64, 41.));
    std::mt19937_64 random(7);
    std::uniform_real_distribution<double> uniform(0., 1.);
    for (int i = 0; i < 20000; ++i) {
        const EnvironmentSample e = sampleEnvironment(s, uniform(random), uniform(random));
        ASSERT_NEAR(glm::length(e.direction), 1., 1e-12);
        ASSERT_GT(e.pdf, 0.);
        ASSERT_EQ(e.pdf, environmentPdf(s, e.direction)) << i;
    }
}

TEST(EnvironmentSampler, HistogramOfSamplesMatchesThePdf) {
    // Counts over a coarse equirect grid against the pdf integrated over each cell; the grid is
    // turned against the map's so the rotation is exercised.
    const EnvironmentSampler s = makeEnvironmentSampler(unevenMap(32, 100.));
    const int w = 16, h = 8, n = 400000;
    std::vector<double> counts(size_t(w * h), 0.);
    std::mt19937_64 random(3);
    std::uniform_real_distribution<double> uniform(0., 1.);
    for (int i = 0; i < n; ++i) {
        const glm::dvec2 uv =
            equirectCoordinates(sampleEnvironment(s, uniform(random), uniform(random)).direction);
        counts[size_t(std::min(int(uv.y * h), h - 1) * w + std::min(int(uv.x * w), w - 1))] += 1.;
    }
    const int k = 16; // sub-cells per cell side for the expected mass
    double chi2 = 0.;
    int cells = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            double mass = 0.;
            for (int j = 0; j < k; ++j)
                for (int i = 0; i < k; ++i)
                    mass += environmentPdf(s, equirectDirection((x + (i + 0.5) / k) / w,
                                                                (y + (j + 0.5) / k) / h)) *
                            equirectTexelSolidAngle(w * k, h * k, y * k + j);
            const double expected = mass * n;
            if (expected < 20.) continue;
            const double d = counts[size_t(y * w + x)] - expected;
            chi2 += d * d / expected;
            ++cells;
        }
    // Mean chi^2 per cell is 1 for a matching density; the sub-cell quadrature adds a little.
    EXPECT_LT(chi2 / cells, 2.) << cells << " cells";
}

TEST(EnvironmentSampler, DensityFollowsLuminanceAndBlackMapsAreUniform) {
    Environment env =
        envtest::mapOf(16, [](glm::dvec3 d) { return glm::dvec3(d.y > 0. ? 3. : 1.); });
    const EnvironmentSampler s = makeEnvironmentSampler(env);
    // Radiance 3 over the upper half, 1 below: pdf = L / (2 pi (3 + 1)).
    EXPECT_NEAR(environmentPdf(s, {0., 0.9, 0.1}), 3. / (8. * M_PI), 1e-12);
    EXPECT_NEAR(environmentPdf(s, {0.2, -0.9, 0.}), 1. / (8. * M_PI), 1e-12);
    Environment black = envtest::mapOf(16, [](glm::dvec3) { return glm::dvec3(0.); });
    const EnvironmentSampler u = makeEnvironmentSampler(black);
    EXPECT_NEAR(environmentPdf(u, {0.3, 0.4, glm::sqrt(0.75)}), 1. / (4. * M_PI), 1e-12);
    EXPECT_NEAR(sampleEnvironment(u, 0.3, 0.9).pdf, 1. / (4. * M_PI), 1e-12);
}

TEST(EnvironmentSampler, RadianceLookupSeesTheRotatedMap) {
    Environment env = unevenMap(32, 0.);
    const glm::dvec3 d = glm::normalize(glm::dvec3(0.6, 0.5, -0.3));
    const glm::vec3 before = environmentRadiance(env, d);
    env.rotation = 90. * M_PI / 180.;
    // What the file shows along d is now seen along R_y(90) d.
    EXPECT_EQ(environmentRadiance(env, rotateAboutY(d, env.rotation)), before);
}

} // namespace
} // namespace ndfmip
