// The cube-face box chain (environment_cube_chain.h) and the cube-face helpers it rests on:
// closed forms for the solid angles, a constant map kept exactly, a smooth map's integral kept at
// every level and its mean kept at the poles, where the equirectangular box chain loses it.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "env/env_test_support.h"
#include "ndfmip/environment_cube_chain.h"

namespace ndfmip {
namespace {

using namespace envtest;

TEST(CubeFaces, CoordinatesInvertTheDirection) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(0.001, 0.999);
    for (int i = 0; i < 600; ++i) {
        const int face = i % kCubeFaces;
        const double s = u(rng), t = u(rng);
        int f;
        double s2, t2;
        cubeFaceCoordinates(cubeFaceDirection(face, s, t), f, s2, t2);
        EXPECT_EQ(f, face);
        EXPECT_NEAR(s2, s, 1e-12);
        EXPECT_NEAR(t2, t, 1e-12);
    }
}

TEST(CubeFaces, TexelSolidAnglesCoverTheSphere) {
    for (int size : {1, 2, 3, 8, 64}) {
        double sum = 0.;
        for (int y = 0; y < size; ++y)
            for (int x = 0; x < size; ++x) sum += cubeTexelSolidAngle(size, x, y);
        EXPECT_NEAR(kCubeFaces * sum, 4. * M_PI, 1e-12) << size;
    }
    // The centre texel of a fine face is about its plane area over the distance^3 = 1; a corner
    // texel 3^(3/2) times smaller.
    EXPECT_NEAR(cubeTexelSolidAngle(1001, 500, 500), 4. / (1001. * 1001.), 1e-10);
    EXPECT_NEAR(cubeTexelSolidAngle(1000, 0, 0) * std::pow(3., 1.5), 4. / 1e6, 1e-8);
}

TEST(CubeMipChain, ConstantEnvironmentIsTheSameAtEveryLevelAndDirection) {
    const glm::dvec3 c(0.5, 1., 2.);
    Environment env = mapOf(128, [&](glm::dvec3) { return c; });
    env.rotation = 0.7;
    const CubeMipChain chain = buildCubeMipChain(env, 16);
    ASSERT_EQ(chain.levels.size(), 5u); // 16, 8, 4, 2, 1
    for (double lod = 0.; lod <= 4.5; lod += 0.25)
        for (int i = 0; i < 200; ++i) {
            const glm::vec3 got = sampleCubeMipChain(chain, lod, spiralDirection(i, 200));
            for (int k = 0; k < 3; ++k)
                ASSERT_NEAR(got[k], c[k], 1e-5 * c[k]) << "lod " << lod << " direction " << i;
        }
}

// L = a + b d.y: brighter towards +Y, the pole of the equirectangular map.
constexpr double kA = 1., kB = 0.8;
Environment verticalGradient() {
    return mapOf(512, [](glm::dvec3 d) { return glm::dvec3(kA + kB * d.y); });
}

TEST(CubeMipChain, EveryLevelKeepsTheIntegral) {
    const CubeMipChain chain = buildCubeMipChain(verticalGradient(), 32);
    for (size_t k = 0; k < chain.levels.size(); ++k) {
        const int n = chain.levels[k][0].width;
        double sum = 0.;
        for (int face = 0; face < kCubeFaces; ++face)
            for (int y = 0; y < n; ++y)
                for (int x = 0; x < n; ++x)
                    sum += cubeTexelSolidAngle(n, x, y) * chain.levels[k][size_t(face)].at(x, y)[0];
        EXPECT_NEAR(sum, 4. * M_PI * kA, 2e-3) << "level " << k; // the integral of b d.y is 0
    }
}

// The mean of d.y over the directions through [-h, h]^2 of the +Y face's plane:
// integral (1 + a^2 + b^2)^-2 over integral (1 + a^2 + b^2)^-3/2 (dw = da db / r^3, d.y = 1 / r).
double meanHeightOverSquare(double h) {
    const int steps = 400;
    double num = 0., den = 0.;
    for (int j = 0; j < steps; ++j)
        for (int i = 0; i < steps; ++i) {
            const double a = h * (2. * (i + 0.5) / steps - 1.),
                         b = h * (2. * (j + 0.5) / steps - 1.);
            const double r2 = 1. + a * a + b * b;
            num += 1. / (r2 * r2);
            den += 1. / (r2 * std::sqrt(r2));
        }
    return num / den;
}

TEST(CubeMipChain, SmoothEnvironmentKeepsItsMeanAtThePoles) {
    const Environment env = verticalGradient();
    const CubeMipChain chain = buildCubeMipChain(env, 32);
    ASSERT_EQ(chain.levels.size(), 6u);
    for (size_t k = 0; k < chain.levels.size(); ++k) {
        // At the pole (a face's centre) the lookup averages the four central texels, which span
        // [-2/n, 2/n]^2 of the face plane (the whole face for n <= 2).
        const int n = chain.levels[k][0].width;
        const double h = std::min(1., 2. / n),
                     meanY = n == 1 ? meanHeightOverSquare(1.) : meanHeightOverSquare(h);
        const double up = sampleCubeMipChain(chain, double(k), glm::dvec3(0., 1., 0.))[0];
        const double down = sampleCubeMipChain(chain, double(k), glm::dvec3(0., -1., 0.))[0];
        EXPECT_NEAR(up, kA + kB * meanY, 2e-3) << "level " << k;
        EXPECT_NEAR(down, kA - kB * meanY, 2e-3) << "level " << k;
    }
    // The whole +Y face's mean height is 0.78 or so: the coarsest level still reads the sky as
    // brighter above. The equirectangular box chain's 2 x 1 level spans every latitude and reads
    // a at the pole, as bright as the horizon.
    EXPECT_GT(meanHeightOverSquare(1.), 0.7);
    Image equirect = resampleEquirect(env.radiance, 256);
    while (equirect.width > 2) equirect = resampleEquirect(equirect, equirect.width / 2);
    float pole[3];
    sampleEquirect(equirect, glm::dvec3(0., 1., 0.), pole);
    EXPECT_NEAR(pole[0], kA, 1e-3);
}

TEST(CubeMipChain, LookupsAreContinuousAcrossFaceEdges) {
    const CubeMipChain chain = buildCubeMipChain(
        mapOf(256, [](glm::dvec3 d) { return glm::dvec3(1. + 0.5 * d.x + 0.3 * d.y - 0.4 * d.z); }),
        16);
    for (size_t k = 0; k < chain.levels.size(); ++k)
        for (double height : {0., 0.3, -0.6}) {
            // Around the horizon (four edges) at a fixed height: steps of 0.05 degrees.
            glm::vec3 previous = sampleCubeLevel(chain.levels[k], glm::dvec3(1., height, 0.));
            const int steps = 7200;
            double largest = 0.;
            for (int i = 1; i <= steps; ++i) {
                const double phi = 2. * M_PI * i / steps;
                const glm::vec3 v = sampleCubeLevel(
                    chain.levels[k], glm::dvec3(std::cos(phi), height, std::sin(phi)));
                largest = std::max(largest, double(glm::length(v - previous)));
                previous = v;
            }
            // The map changes by at most ~1.2 per radian; a step of 1/1146 radian over the
            // coarsest (1 x 1) faces' bilinear ramp moves a few thousandths.
            EXPECT_LT(largest, 0.01) << "level " << k << " height " << height;
        }
}

} // namespace
} // namespace ndfmip
