#include <cmath>

#include <gtest/gtest.h>

#include "ndfmip/bake.h"
#include "ndfmip/roughness.h"
#include "ndfmip/toksvig.h"
#include "test_support.h"

namespace ndfmip {
namespace {

// Integral over the upper hemisphere of f(direction), midpoint rule in (cos theta, phi).
template <class F> double hemisphereIntegral(F f, int n = 1024) {
    double sum = 0;
    for (int i = 0; i < n; ++i) {
        double z = (i + 0.5) / n;
        double r = std::sqrt(1 - z * z);
        for (int j = 0; j < 64; ++j) {
            double phi = 2 * M_PI * (j + 0.5) / 64;
            sum += f(glm::vec3(float(r * std::cos(phi)), float(r * std::sin(phi)), float(z)));
        }
    }
    return sum * (1.0 / n) * (2 * M_PI / 64);
}

TEST(Toksvig, Sigma2FromLengthIsEquationOne) {
    EXPECT_FLOAT_EQ(toksvigSigma2(1.f), 0.f);
    EXPECT_FLOAT_EQ(toksvigSigma2(0.5f), 1.f);
    EXPECT_NEAR(toksvigSigma2(0.8f), 0.25f, 1e-6f);
}

TEST(Toksvig, FactorLimits) {
    for (float s : {1.f, 16.f, 512.f}) {
        EXPECT_FLOAT_EQ(toksvigFactor(1.f, s), 1.f);
        EXPECT_GT(toksvigFactor(1.f - 1e-6f, s), 0.99f);
        EXPECT_FLOAT_EQ(toksvigFactor(0.f, s), 0.f);
        EXPECT_LT(toksvigFactor(1e-4f, s), 1e-3f);
    }
}

TEST(Toksvig, FactorIsOneOverOnePlusSSigma2) {
    // Eq. (5)-(6): ft = 1/(1 + s sigma^2) with sigma^2 from eq. (1).
    for (float length : {0.3f, 0.7f, 0.95f})
        for (float s : {4.f, 64.f})
            EXPECT_NEAR(toksvigFactor(length, s), 1.f / (1.f + s * toksvigSigma2(length)), 1e-6f);
}

TEST(Toksvig, UnitMeanNormalGivesPlainBlinnPhong) {
    glm::vec3 n = glm::normalize(glm::vec3(0.2f, -0.1f, 1.f));
    glm::vec3 h = glm::normalize(glm::vec3(0.3f, 0.f, 1.f));
    EXPECT_NEAR(toksvigSpecular(n, h, 64.f), blinnPhong(glm::dot(n, h), 64.f), 1e-5f);
    EXPECT_NEAR(naiveSpecular(0.5f * n, h, 64.f), blinnPhong(glm::dot(n, h), 64.f), 1e-5f);
}

TEST(Toksvig, WidenedLobeKeepsUnitEnergy) {
    // Eq. (7)-(8): the normalised lobe integrates to 1 whatever ft.
    for (float length : {1.f, 0.9f, 0.6f}) {
        glm::vec3 na(0.f, 0.f, length);
        double e = hemisphereIntegral([&](glm::vec3 h) { return toksvigSpecular(na, h, 100.f); });
        EXPECT_NEAR(e, 1.0, 2e-3) << "length " << length;
    }
}

TEST(Toksvig, BakeStoresUnnormalisedMeanAndRoughness) {
    const float theta = 0.4f;
    Image map(2, 2, 3);
    test::setNormal(map, 0, 0, std::sin(theta), 0, std::cos(theta));
    test::setNormal(map, 1, 0, -std::sin(theta), 0, std::cos(theta));
    test::setNormal(map, 0, 1, std::sin(theta), 0, std::cos(theta));
    test::setNormal(map, 1, 1, -std::sin(theta), 0, std::cos(theta));
    Pyramid p = buildPyramid(map);
    BakeOptions options;
    options.baseRoughness = 0.1f;
    Bake bake = bakeToksvig(p, options);
    ASSERT_EQ(bake.levels.size(), 2u);
    const float* na = bake.levels[1][0]->at(0, 0);
    EXPECT_NEAR(na[2], std::cos(theta), 1e-6f);
    EXPECT_NEAR(na[0], 0.f, 1e-6f);
    float sigma2 = (1 - std::cos(theta)) / std::cos(theta);
    EXPECT_NEAR(bake.levels[1][1]->at(0, 0)[0], std::sqrt(0.01f + kVarianceScale * sigma2), 1e-5f);
    EXPECT_NEAR(bake.levels[0][1]->at(0, 0)[0], 0.1f, 1e-6f); // unit normals: base roughness
    Bake naive = bakeNaive(p, {});
    EXPECT_NEAR(naive.levels[1][0]->at(0, 0)[2], 1.f, 1e-6f);
}

TEST(Roughness, VarianceRoughnessClosedForm) {
    EXPECT_FLOAT_EQ(varianceRoughness(1.f, 0.3f), 0.3f);
    EXPECT_NEAR(varianceRoughness(0.9f, 0.f, 1.f), std::sqrt(0.1f / 0.9f), 1e-6f);
    EXPECT_NEAR(varianceRoughness(0.9f, 0.f), std::sqrt(2.f * (0.1f / 0.9f)), 1e-6f); // c = 2
    // Unreal's form keeps alpha' <= 1 and is alpha0 where the normals agree.
    EXPECT_NEAR(mappedRoughness(RoughnessMapping::Unreal, 1.f, 0.3f), 0.3f, 1e-6f);
    const float v = 0.1f / 0.9f, b = 2.f * v * (1.f - 0.09f);
    EXPECT_NEAR(mappedRoughness(RoughnessMapping::Unreal, 0.9f, 0.3f),
                std::sqrt((0.09f + b) / (1.f + b)), 1e-6f);
    EXPECT_LT(mappedRoughness(RoughnessMapping::Unreal, 0.01f, 0.9f), 1.f);
    EXPECT_FLOAT_EQ(varianceRoughness(0.1f, 0.5f), 1.f); // capped
    EXPECT_FLOAT_EQ(perceptualRoughness(0.25f), 0.5f);
}

TEST(ToksvigLut, RowNaNaOneIsThePlainTable) {
    for (float s : {8.f, 32.f, 200.f})
        for (float x : {0.f, 0.3f, 0.9f, 0.999f, 1.f})
            EXPECT_NEAR(toksvigLutValue(x, 1.f, s), std::pow(x, s), 1e-6f) << s << " " << x;
}

TEST(ToksvigLut, RowZeroIsOneOverOnePlusS) {
    for (float s : {8.f, 32.f, 200.f})
        for (float x : {0.f, 0.5f, 1.f})
            EXPECT_NEAR(toksvigLutValue(x, 0.f, s), 1.f / (1.f + s), 1e-7f);
}

TEST(ToksvigLut, TableSamplesEquationNineAtTexelCentres) {
    ToksvigLutOptions o;
    o.exponent = 32.f;
    o.size = 16;
    Image lut = toksvigLut(o);
    ASSERT_EQ(lut.width, 16);
    for (int j : {0, 7, 15})
        for (int i : {0, 5, 15}) {
            float x = (i + 0.5f) / 16, y = (j + 0.5f) / 16, len = std::sqrt(y);
            float ft = len / (len + 32.f * (1 - len));
            float expected = (1 + ft * 32.f) / 33.f * std::pow(std::min(x / len, 1.f), ft * 32.f);
            EXPECT_NEAR(lut.at(i, j)[0], expected, 1e-5f) << i << "," << j;
        }
}

TEST(ToksvigLut, SensitivityIsTheDerivativeOfRelativeIntensity) {
    const float s = 40.f;
    auto intensity = [&](double l) { return (1 + toksvigFactor(float(l), s) * s) / (1 + s); };
    for (float l : {0.5f, 0.9f, 0.99f}) {
        double h = 1e-3, numeric = (intensity(l + h) - intensity(l - h)) / (2 * h);
        EXPECT_NEAR(toksvigIntensitySensitivity(l, s), numeric, 1e-3 * numeric);
    }
    EXPECT_NEAR(toksvigIntensitySensitivity(1.f, s), s * s / (1 + s),
                1e-4f);                                      // eq. (10) at |Na| = 1
    EXPECT_NEAR(lengthQuantisationError(8), 0.0068f, 5e-5f); // the paper's figure
}

TEST(ToksvigLut, PhaseOutBlendsTowardsTheAliasedValue) {
    ToksvigLutOptions o;
    o.exponent = 128.f;
    o.bitDepth = 8;
    o.threshold = 0.05f;
    const float x = 0.93f, y = 0.98f, len = std::sqrt(y);
    float error = lengthQuantisationError(8) * toksvigIntensitySensitivity(len, 128.f);
    ASSERT_GT(error, o.threshold);
    float w = o.threshold / error;
    float expected = w * toksvigLutValue(x, y, 128.f) + (1 - w) * std::pow(x / len, 128.f);
    EXPECT_NEAR(toksvigLutEntry(x, y, o), expected, 1e-6f);
    // Where normals vary a lot the error is small and the table is eq. (9) itself.
    EXPECT_FLOAT_EQ(toksvigLutEntry(0.2f, 0.09f, o), toksvigLutValue(0.2f, 0.09f, 128.f));
    // 16-bit normals are precise enough at this exponent for the full filtering.
    o.bitDepth = 16;
    EXPECT_FLOAT_EQ(toksvigLutEntry(x, y, o), toksvigLutValue(x, y, 128.f));
}

TEST(GlossMap, ShortenedNormalsGiveBackTheRequestedExponent) {
    const float s0 = 256.f;
    for (float s : {1.f, 10.f, 100.f, 256.f}) {
        float length = glossLength(s, s0);
        EXPECT_NEAR(toksvigFactor(length, s0) * s0, s, 1e-3f * s) << s;
    }
    Image normals(2, 1, 3), gloss(2, 1, 1);
    test::setNormal(normals, 0, 0, 0, 0, 1);
    test::setNormal(normals, 1, 0, 0.6f, 0, 0.8f);
    gloss.pixels = {0.25f, 1.f};
    applyGlossMap(normals, gloss, s0);
    EXPECT_NEAR(normals.at(0, 0)[2], glossLength(64.f, s0), 1e-6f);
    EXPECT_NEAR(normals.at(1, 0)[0], 0.6f, 1e-6f); // gloss 1: unchanged
}

} // namespace
} // namespace ndfmip
