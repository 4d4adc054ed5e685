#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "ndfmip/evaluate.h"
#include "ndfmip/toksvig.h"
#include "test_support.h"

namespace ndfmip {
namespace {

ShadeContext context(float s) {
    ShadeContext c;
    c.light = glm::normalize(glm::vec3(0.4f, 0.2f, 1.f));
    c.view = glm::vec3(0, 0, 1);
    c.exponent = s;
    return c;
}

TEST(AlignedTruth, FlatMapEveryMethodEqualsTheTruth) {
    Image map(12, 6, 3);
    glm::vec3 n = glm::normalize(glm::vec3(0.1f, 0.2f, 1.f));
    for (int y = 0; y < 6; ++y)
        for (int x = 0; x < 12; ++x) test::setNormal(map, x, y, n.x, n.y, n.z);
    Pyramid p = buildPyramid(map);
    for (Method m : allMethods()) {
        if (bakeFitsMaterialRoughness(m)) continue; // a GGX fit: these lobes are Blinn-Phong's
        // sh reproduces a lobe only up to its order: at l* = 30 a lobe of s = 4 keeps all but
        // ~exp(-30^2/4) of itself.
        BakeOptions options;
        options.parameters["order"] = 30;
        const float s = m == Method::Sh ? 4.f : 64.f;
        Bake bake = bakeMethod(m, p, options);
        for (int k = 0; k < int(p.levels.size()); ++k) {
            ErrorStats e =
                compareToTruth(shadeLevel(bake, k, context(s)), groundTruthLevel(p, k, context(s)));
            // vmf: identical normals give kappa = 1e5 (the cap), which H eq. 29 turns into
            // s' = s / (1 + s / kappa): 0.06% narrower at s = 64. lean: its lobe is Beckmann's
            // of alpha^2 = 2/(s + 2), which stands for Blinn-Phong s to 6% (tilted 13 degrees,
            // where the slope-space lobe narrows along the tilt).
            const double tolerance = m == Method::Vmf ? 2e-3 : m == Method::Lean ? 0.07 : 1e-5;
            EXPECT_LT(e.relativeRmse, tolerance) << methodName(m) << " level " << k;
        }
    }
}

TEST(AlignedTruth, TruthIsTheMeanOfTheLobeOverTheBlock) {
    Image map(2, 2, 3);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-0.5f, 0.5f);
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 2; ++x) test::setNormal(map, x, y, u(rng), u(rng), 1.f);
    Pyramid p = buildPyramid(map);
    ShadeContext c = context(20.f);
    glm::vec3 h = halfVector(c);
    double expected = 0;
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 2; ++x) {
            const float* n = map.at(x, y);
            expected += blinnPhong(glm::dot(glm::vec3(n[0], n[1], n[2]), h), 20.f) / 4;
        }
    EXPECT_NEAR(groundTruthLevel(p, 1, c).at(0, 0)[0], expected, 1e-5);
    // At level 0 every method shades the texel's own normal: equal to the truth.
    Bake toksvig = bakeToksvig(p, {});
    ErrorStats e = compareToTruth(shadeLevel(toksvig, 0, c), groundTruthLevel(p, 0, c));
    EXPECT_LT(e.relativeRmse, 1e-5);
}

TEST(AlignedTruth, ToksvigBeatsTheNaiveMipmapOnAVGroove) {
    // Normals at +-theta (the V-groove of Han et al. Fig. 1): the naive mipmap sees a flat
    // surface and a sharp highlight; Toksvig widens it.
    Image map(8, 8, 3);
    const float theta = 0.35f;
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x)
            test::setNormal(map, x, y, (x % 2 ? -1.f : 1.f) * std::sin(theta), 0, std::cos(theta));
    Pyramid p = buildPyramid(map);
    ShadeContext c = context(64.f);
    Image truth = groundTruthLevel(p, 2, c);
    ErrorStats naive = compareToTruth(shadeLevel(bakeNaive(p, {}), 2, c), truth);
    ErrorStats toksvig = compareToTruth(shadeLevel(bakeToksvig(p, {}), 2, c), truth);
    EXPECT_LT(toksvig.relativeRmse, 0.5 * naive.relativeRmse)
        << "toksvig " << toksvig.relativeRmse << " naive " << naive.relativeRmse;
    EXPECT_NEAR(compareToTruth(truth, truth).energyRatio, 1.0, 1e-12);
}

} // namespace
} // namespace ndfmip
