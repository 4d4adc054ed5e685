#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <omp.h>

#include "ndfmip/pyramid.h"
#include "ndfmip/vmf.h"
#include "test_support.h"

namespace ndfmip {
namespace {

constexpr double kPi = 3.14159265358979323846;

const glm::vec3 kRed(1, 0, 0), kBlue(0, 0, 1);

glm::vec3 tilted(double degreesInX) {
    double t = degreesInX * kPi / 180;
    return glm::vec3(float(std::sin(t)), 0.f, float(std::cos(t)));
}

void setColor(Image& albedo, int x, int y, glm::vec3 c) {
    float* p = albedo.at(x, y);
    p[0] = c.r;
    p[1] = c.g;
    p[2] = c.b;
}

glm::vec3 colorAt(const Image& albedo, int x, int y) {
    const float* p = albedo.at(x, y);
    return {p[0], p[1], p[2]};
}

// 8 x 8 checker of normals tilted +40 deg (red) and -40 deg (blue) in x; the albedo has an
// alpha channel that must not matter.
struct Checker {
    Image normals{8, 8, 3}, albedo{8, 8, 4};
    Checker() {
        for (int y = 0; y < 8; ++y)
            for (int x = 0; x < 8; ++x) {
                bool plus = (x + y) % 2 == 0;
                glm::vec3 n = tilted(plus ? 40 : -40);
                test::setNormal(normals, x, y, n.x, n.y, n.z);
                setColor(albedo, x, y, plus ? kRed : kBlue);
                albedo.at(x, y)[3] = float(x * 8 + y);
            }
    }
};

// Normals around `clusters` random directions (spread 1/sqrt(kappa)), colours uniform in [0, 1).
struct RandomMap {
    Image normals, albedo;
    RandomMap(int width, int height, int clusters, double kappa, uint64_t seed)
        : normals(width, height, 3), albedo(width, height, 3) {
        std::mt19937_64 rng(seed);
        std::normal_distribution<double> gauss(0, 1);
        std::uniform_real_distribution<double> uniform(0, 1);
        std::vector<glm::dvec3> centres;
        for (int c = 0; c < clusters; ++c)
            centres.push_back(glm::normalize(glm::dvec3(gauss(rng), gauss(rng), 2 + uniform(rng))));
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x) {
                glm::dvec3 m = centres[size_t(rng() % uint64_t(clusters))];
                double s = 1 / std::sqrt(kappa);
                glm::dvec3 n = m + s * glm::dvec3(gauss(rng), gauss(rng), gauss(rng));
                test::setNormal(normals, x, y, float(n.x), float(n.y), float(n.z));
                setColor(albedo, x, y,
                         glm::vec3(float(uniform(rng)), float(uniform(rng)), float(uniform(rng))));
            }
    }
};

glm::dvec3 footprintMean(const Pyramid& pyramid, const Image& albedo, int level, int x, int y) {
    Footprint f = footprint(pyramid, level, x, y);
    glm::dvec3 sum(0);
    for (int v = f.y0; v < f.y1; ++v)
        for (int u = f.x0; u < f.x1; ++u) sum += glm::dvec3(colorAt(albedo, u, v));
    return sum / double(f.count());
}

// Eq. 31 written out: z_ij from vmfLogDensity, normalised over j in long double.
std::vector<glm::dvec3> directColors(const Pyramid& pyramid, const Image& albedo, int level, int x,
                                     int y, std::span<const VmfLobe> lobes) {
    Footprint f = footprint(pyramid, level, x, y);
    std::vector<long double> zSum(lobes.size(), 0);
    std::vector<glm::dvec3> zy(lobes.size(), glm::dvec3(0));
    for (int v = f.y0; v < f.y1; ++v)
        for (int u = f.x0; u < f.x1; ++u) {
            const float* p = pyramid.base->at(u, v);
            glm::vec3 n = glm::normalize(glm::vec3(p[0], p[1], p[2]));
            std::vector<double> logTerm(lobes.size());
            double largest = -std::numeric_limits<double>::infinity();
            for (size_t j = 0; j < lobes.size(); ++j) {
                logTerm[j] = std::log(double(lobes[j].alpha)) +
                             vmfLogDensity(n, lobes[j].mu, lobes[j].kappa);
                largest = std::max(largest, logTerm[j]);
            }
            long double total = 0;
            for (double t : logTerm) total += std::exp((long double)(t - largest));
            for (size_t j = 0; j < lobes.size(); ++j) {
                double z = double(std::exp((long double)(logTerm[j] - largest)) / total);
                zSum[j] += z;
                zy[j] += z * glm::dvec3(colorAt(albedo, u, v));
            }
        }
    std::vector<glm::dvec3> colors;
    for (size_t j = 0; j < lobes.size(); ++j) colors.push_back(zy[j] / double(zSum[j]));
    return colors;
}

void expectNear(glm::vec3 a, glm::dvec3 b, double tolerance, const std::string& where) {
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], tolerance) << where << " channel " << c;
}

std::string texelName(size_t k, int x, int y) {
    return "level " + std::to_string(k) + " texel " + std::to_string(x) + "," + std::to_string(y);
}

TEST(VmfColor, TwoColouredGroupsGiveARedAndABlueLobe) {
    Checker map;
    Pyramid pyramid = buildPyramid(map.normals);
    std::vector<VmfLevel> levels = fitVmfPyramid(pyramid, 2, {}, nullptr);
    fitLobeColors(pyramid, map.albedo, levels);
    ASSERT_EQ(levels.size(), 4u);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x)
            EXPECT_EQ(levels[0].texel(x, y)[0].color, colorAt(map.albedo, x, y));
    for (size_t k = 1; k < levels.size(); ++k)
        for (int y = 0; y < levels[k].height; ++y)
            for (int x = 0; x < levels[k].width; ++x) {
                std::span<const VmfLobe> lobes = levels[k].texel(x, y);
                ASSERT_EQ(lobes.size(), 2u) << texelName(k, x, y);
                for (const VmfLobe& l : lobes) {
                    bool plus = l.mu.x > 0;
                    EXPECT_NEAR(std::abs(l.mu.x), std::sin(40 * kPi / 180), 1e-4);
                    expectNear(l.color, glm::dvec3(plus ? kRed : kBlue), 1e-3, texelName(k, x, y));
                }
                EXPECT_LT(lobes[0].mu.x * lobes[1].mu.x, 0.f); // one on each side
            }
}

TEST(VmfColor, OneLobeTakesTheMeanColour) {
    Checker checker;
    Pyramid pyramid = buildPyramid(checker.normals);
    std::vector<VmfLevel> levels = fitVmfPyramid(pyramid, 1, {}, nullptr);
    fitLobeColors(pyramid, checker.albedo, levels);
    for (size_t k = 1; k < levels.size(); ++k)
        for (const VmfLobe& l : levels[k].lobes)
            expectNear(l.color, glm::dvec3(0.5, 0, 0.5), 1e-6, "level " + std::to_string(k));

    RandomMap random(16, 12, 3, 50, 1);
    Pyramid other = buildPyramid(random.normals);
    levels = fitVmfPyramid(other, 1, {}, nullptr);
    fitLobeColors(other, random.albedo, levels);
    for (size_t k = 0; k < levels.size(); ++k)
        for (int y = 0; y < levels[k].height; ++y)
            for (int x = 0; x < levels[k].width; ++x)
                expectNear(levels[k].texel(x, y)[0].color,
                           footprintMean(other, random.albedo, int(k), x, y), 1e-6,
                           texelName(k, x, y));
}

TEST(VmfColor, LobesThatExplainNothingTakeTheMeanColour) {
    // The top texel's second lobe turned to face away from every normal (its z underflow to 0
    // even in log space: log-terms ~1e5 below the first lobe's), then emptied (alpha 0).
    Checker map;
    Pyramid pyramid = buildPyramid(map.normals);
    std::vector<VmfLevel> levels = fitVmfPyramid(pyramid, 2, {}, nullptr);
    ASSERT_EQ(levels[3].lobes.size(), 2u);
    levels[3].lobes[1].mu = glm::vec3(0, 0, -1);
    levels[3].lobes[1].kappa = kDefaultKappaMax;
    fitLobeColors(pyramid, map.albedo, levels);
    for (const VmfLobe& l : levels[3].lobes)
        expectNear(l.color, glm::dvec3(0.5, 0, 0.5), 1e-6, "top");
    levels[3].lobes[1].alpha = 0;
    levels[3].lobes[1].color = glm::vec3(0.f);
    fitLobeColors(pyramid, map.albedo, levels);
    expectNear(levels[3].lobes[1].color, glm::dvec3(0.5, 0, 0.5), 1e-6, "empty");
}

TEST(VmfColor, UniformColourColoursEveryLobe) {
    RandomMap random(16, 16, 4, 200, 2);
    const glm::vec3 color(0.2f, 0.55f, 0.9f);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) setColor(random.albedo, x, y, color);
    Pyramid pyramid = buildPyramid(random.normals);
    std::vector<VmfLevel> levels = fitVmfPyramid(pyramid, 4, {}, nullptr);
    fitLobeColors(pyramid, random.albedo, levels);
    for (size_t k = 0; k < levels.size(); ++k) {
        if (k > 0) { // texels with several lobes
            EXPECT_GT(levels[k].lobes.size(), levels[k].offsets.size() - 1) << k;
        }
        for (const VmfLobe& l : levels[k].lobes)
            expectNear(l.color, glm::dvec3(color), 1e-6, "level " + std::to_string(k));
    }
}

TEST(VmfColor, MatchesEquation31WrittenOut) {
    // Overlapping clusters (z far from 0 and 1), odd size, and lobes as sharp as kappaMax at
    // level 1 (pairs of nearly equal normals): the log-space E-step against a direct one.
    RandomMap random(19, 13, 3, 30, 3);
    Pyramid pyramid = buildPyramid(random.normals);
    std::vector<VmfLevel> levels = fitVmfPyramid(pyramid, 3, {}, nullptr);
    fitLobeColors(pyramid, random.albedo, levels);
    int mixed = 0;
    for (size_t k = 1; k < levels.size(); ++k)
        for (int y = 0; y < levels[k].height; ++y)
            for (int x = 0; x < levels[k].width; ++x) {
                std::span<const VmfLobe> lobes = levels[k].texel(x, y);
                std::vector<glm::dvec3> direct =
                    directColors(pyramid, random.albedo, int(k), x, y, lobes);
                for (size_t j = 0; j < lobes.size(); ++j)
                    expectNear(lobes[j].color, direct[j], 1e-5, texelName(k, x, y));
                if (lobes.size() > 1) ++mixed;
            }
    EXPECT_GT(mixed, 10);
}

TEST(VmfColor, AlphaWeightedColoursAddUpToTheMeanColour) {
    // At an EM fixed point alpha_j = Sum_i z_ij / N, so Sum_j alpha_j y_j = Sum_i y_i / N.
    RandomMap random(16, 16, 3, 2000, 4);
    Pyramid pyramid = buildPyramid(random.normals);
    VmfFitOptions options;
    options.tolerance = 1e-12;
    options.maxIterations = 500;
    options.exactKappa = true;
    std::vector<VmfLevel> levels = fitVmfPyramid(pyramid, 3, options, nullptr);
    fitLobeColors(pyramid, random.albedo, levels);
    for (size_t k = 0; k < levels.size(); ++k)
        for (int y = 0; y < levels[k].height; ++y)
            for (int x = 0; x < levels[k].width; ++x) {
                glm::dvec3 sum(0);
                for (const VmfLobe& l : levels[k].texel(x, y))
                    sum += double(l.alpha) * glm::dvec3(l.color);
                glm::dvec3 mean = footprintMean(pyramid, random.albedo, int(k), x, y);
                for (int c = 0; c < 3; ++c)
                    EXPECT_NEAR(sum[c], mean[c], 1e-5) << texelName(k, x, y);
            }
}

TEST(VmfColor, SameBitsOnAnyThreadCount) {
    RandomMap random(64, 48, 4, 100, 5);
    Pyramid pyramid = buildPyramid(random.normals);
    std::vector<VmfLevel> one = fitVmfPyramid(pyramid, 3, {}, nullptr);
    std::vector<VmfLevel> many = one;
    int threads = omp_get_max_threads();
    omp_set_num_threads(1);
    fitLobeColors(pyramid, random.albedo, one);
    omp_set_num_threads(std::max(3, threads));
    fitLobeColors(pyramid, random.albedo, many);
    omp_set_num_threads(threads);
    for (size_t k = 0; k < one.size(); ++k)
        for (size_t i = 0; i < one[k].lobes.size(); ++i)
            ASSERT_EQ(one[k].lobes[i].color, many[k].lobes[i].color) << k << " " << i;
}

TEST(VmfColor, MismatchedInputsLeaveTheLobesAlone) {
    Checker map;
    Pyramid pyramid = buildPyramid(map.normals);
    std::vector<VmfLevel> levels = fitVmfPyramid(pyramid, 2, {}, nullptr);
    fitLobeColors(pyramid, Image(8, 4, 3), levels);
    fitLobeColors(pyramid, Image(8, 8, 1), levels);
    std::vector<VmfLevel> fewer(levels.begin(), levels.end() - 1);
    fitLobeColors(pyramid, map.albedo, fewer);
    for (const std::vector<VmfLevel>* set : {&levels, &fewer})
        for (const VmfLevel& level : *set)
            for (const VmfLobe& l : level.lobes) EXPECT_EQ(l.color, glm::vec3(0.f));
}

TEST(VmfColor, PackedColourFiltersLinearly) {
    VmfLobe a{0.3f, {0, 0, 1}, 50.f, {0.9f, 0.2f, 0.1f}};
    VmfLobe b{0.6f, {1, 0, 0}, 5.f, {0.1f, 0.4f, 0.8f}};
    EXPECT_EQ(packLobeColor(a), 0.3f * a.color);
    for (const VmfLobe& l : {a, b}) {
        glm::vec3 back = unpackLobeColor(packLobeColor(l), packLobe(l).x);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(back[c], l.color[c], 1e-7);
    }
    // Filtering both planes with the same weights gives the alpha-weighted colour.
    for (float w : {0.5f, 0.25f}) {
        glm::vec3 color = (1 - w) * packLobeColor(a) + w * packLobeColor(b);
        float alpha = (1 - w) * packLobe(a).x + w * packLobe(b).x;
        glm::vec3 expected = ((1 - w) * a.alpha * a.color + w * b.alpha * b.color) /
                             ((1 - w) * a.alpha + w * b.alpha);
        glm::vec3 got = unpackLobeColor(color, alpha);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], expected[c], 1e-6) << w;
    }
    // Empty lobes store and give back nothing.
    VmfLobe empty{0.f, {0, 0, 1}, 0.f, {1, 1, 1}};
    EXPECT_EQ(packLobeColor(empty), glm::vec3(0.f));
    EXPECT_EQ(unpackLobeColor(glm::vec3(0.5f), 0.f), glm::vec3(0.f));
}

TEST(VmfColor, AlbedoSizeCheckNamesTheMismatch) {
    EXPECT_TRUE(checkAlbedoSize(Image(8, 4, 3), 8, 4, "a.png").ok());
    EXPECT_TRUE(checkAlbedoSize(Image(8, 4, 4), 8, 4, "a.png").ok());
    EXPECT_EQ(checkAlbedoSize(Image(8, 4, 3), 16, 4, "a.png").error,
              "a.png: albedo map is 8x4 but the normal map is 16x4");
    EXPECT_EQ(checkAlbedoSize(Image(), 16, 4, "a.png").error,
              "a.png: albedo map is 0x0 but the normal map is 16x4");
    EXPECT_EQ(checkAlbedoSize(Image(8, 4, 2), 8, 4, "b.exr").error,
              "b.exr: albedo map has 2 channels, expected 3 (RGB) or 4 (RGBA)");
}

} // namespace
} // namespace ndfmip
