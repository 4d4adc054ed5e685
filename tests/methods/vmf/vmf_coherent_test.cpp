// Coherent vMF lobes (Han et al. 2007, Sec. 7.3): the aligned M-step (H eq. 32), fits that keep
// their slots, the top-down pyramid and the lobe-mismatch metric.
#include <algorithm>
#include <cmath>
#include <random>
#include <span>
#include <vector>

#include <gtest/gtest.h>
#include <omp.h>

#include "ndfmip/evaluate.h"
#include "ndfmip/pyramid.h"
#include "ndfmip/vmf.h"
#include "test_support.h"
#include "vmf_test_support.h"

namespace ndfmip {
namespace {

using namespace vmftest;

glm::dvec3 meanOf(const std::vector<glm::vec3>& normals) {
    glm::dvec3 mean(0);
    for (glm::vec3 n : normals) mean += glm::dvec3(n);
    return mean / double(normals.size());
}

glm::dvec3 packedSum(std::span<const VmfLobe> lobes) {
    glm::dvec3 sum(0);
    for (const VmfLobe& l : lobes) {
        glm::vec4 p = packLobe(l);
        sum += glm::dvec3(p.y, p.z, p.w);
    }
    return sum;
}

bool sameBits(const VmfLobe& a, const VmfLobe& b) {
    return a.alpha == b.alpha && a.mu == b.mu && a.kappa == b.kappa && a.color == b.color;
}

// ---- H eq. 32 in one fit -------------------------------------------------------------------

TEST(VmfCoherent, OneLobeMovesToTheMeanPlusThePull) {
    // One lobe owns every normal (z_i1 = 1), so r_1 is the normals' mean r whatever the lobe:
    // one M-step gives mu = normalize(r + C align), kappa from |r|, and the next is the same.
    std::vector<glm::vec3> normals = sampleMixture({lobe(1.f, direction(20, 0), 50.f)}, 4000, 1);
    const glm::dvec3 r = meanOf(normals);
    const glm::vec3 align = 0.7f * direction(60, 90);
    const std::vector<VmfLobe> start = {lobe(1.f, direction(10, 30), 10.f)};
    for (float C : {0.25f, 1.f, 4.f}) {
        VmfFitOptions options;
        options.coherence = C;
        VmfFitResult fit =
            fitVmfMixture(normals.data(), nullptr, normals.size(), start, options, &align);
        ASSERT_EQ(fit.lobes.size(), 1u);
        EXPECT_TRUE(fit.converged);
        glm::dvec3 expected = glm::normalize(r + double(C) * glm::dvec3(align));
        EXPECT_LT(angleBetween(fit.lobes[0].mu, glm::vec3(expected)), 1e-6) << C;
        EXPECT_NEAR(fit.lobes[0].kappa, kappaFromMeanLength(glm::length(r)),
                    1e-5 * fit.lobes[0].kappa)
            << C;
        EXPECT_EQ(fit.lobes[0].alpha, 1.f);
        // alignedKappa: kappa from the mean's length along the pulled direction.
        options.alignedKappa = true;
        VmfFitResult aligned =
            fitVmfMixture(normals.data(), nullptr, normals.size(), start, options, &align);
        ASSERT_EQ(aligned.lobes.size(), 1u);
        EXPECT_EQ(aligned.lobes[0].mu, fit.lobes[0].mu) << C;
        EXPECT_NEAR(aligned.lobes[0].kappa, kappaFromMeanLength(glm::dot(r, expected)),
                    1e-5 * aligned.lobes[0].kappa)
            << C;
        EXPECT_LT(aligned.lobes[0].kappa, 0.9 * fit.lobes[0].kappa) << C;
    }
}

TEST(VmfCoherent, PullMovesEachLobeTowardItsAlignment) {
    std::vector<VmfLobe> truth = {lobe(0.6f, direction(30, 0), 60.f),
                                  lobe(0.4f, direction(30, 180), 60.f)};
    std::vector<glm::vec3> normals = sampleMixture(truth, 6000, 2);
    // Each slot pulled toward a direction 40 degrees around the z axis from its own.
    const glm::vec3 align[2] = {direction(30, 40), direction(30, 220)};
    double previous[2] = {0, 0};
    for (float C : {0.f, 0.05f, 0.2f, 1.f, 1e6f}) {
        VmfFitOptions options;
        options.coherence = C;
        VmfFitResult fit =
            fitVmfMixture(normals.data(), nullptr, normals.size(), truth, options, align);
        ASSERT_EQ(fit.lobes.size(), 2u);
        for (int j = 0; j < 2; ++j) {
            double angle = angleBetween(fit.lobes[j].mu, align[j]);
            if (C > 0) {
                EXPECT_LT(angle, previous[j]) << C << " " << j;
            } else {
                // Unpulled: the lobe sits on its own normals, ~20 degrees from its alignment.
                EXPECT_LT(degrees(angleBetween(fit.lobes[j].mu, truth[j].mu)), 2);
            }
            if (C == 1e6f) {
                EXPECT_LT(angle, 1e-5) << j;
            }
            previous[j] = angle;
        }
    }
}

TEST(VmfCoherent, WithoutPullTheSlotFitIsThePlainFit) {
    // C = 0 (or no alignment to speak of): the slot fit runs the plain fit's arithmetic, lobe for
    // lobe, when the start is sorted by alpha and nothing is dropped or merged.
    std::vector<VmfLobe> truth = {lobe(0.5f, direction(30, 0), 40.f),
                                  lobe(0.3f, direction(30, 120), 15.f),
                                  lobe(0.2f, direction(50, 240), 80.f)};
    std::vector<glm::vec3> normals = sampleMixture(truth, 5000, 3);
    std::vector<VmfLobe> start = {lobe(0.45f, direction(25, 10), 20.f),
                                  lobe(0.35f, direction(35, 100), 20.f),
                                  lobe(0.2f, direction(45, 250), 20.f)};
    const glm::vec3 align[3] = {direction(90, 0), direction(90, 90), glm::vec3(0.f)};
    VmfFitOptions options;
    options.minAlpha = 0;
    VmfFitResult plain = fitVmfMixture(normals.data(), nullptr, normals.size(), start, options);
    VmfFitResult slots =
        fitVmfMixture(normals.data(), nullptr, normals.size(), start, options, align);
    EXPECT_EQ(plain.logLikelihoodTrace, slots.logLikelihoodTrace);
    EXPECT_EQ(plain.iterations, slots.iterations);
    EXPECT_EQ(plain.converged, slots.converged);
    ASSERT_EQ(slots.lobes.size(), 3u);
    std::vector<VmfLobe> sorted = slots.lobes;
    std::stable_sort(sorted.begin(), sorted.end(),
                     [](const VmfLobe& a, const VmfLobe& b) { return a.alpha > b.alpha; });
    ASSERT_EQ(plain.lobes.size(), 3u);
    for (size_t j = 0; j < 3; ++j) EXPECT_TRUE(sameBits(sorted[j], plain.lobes[j])) << j;
}

TEST(VmfCoherent, PulledStepIsEquation32OnTheSameEStep) {
    // From the same lobes, one M-step with C = 0 gives alpha_j and r_j = r(kappa_j) mu_j of the
    // E-step; one with C > 0 the same alpha_j and kappa_j and mu_j = normalize(r_j + C align_j).
    // Their packed lobes add up to the mean normal without the pull, and are off by
    // Sum_j alpha_j (|r_j| mu_j - r_j) with it.
    std::vector<VmfLobe> truth = {lobe(0.5f, direction(25, 0), 30.f),
                                  lobe(0.3f, direction(35, 130), 20.f),
                                  lobe(0.2f, direction(40, 250), 60.f)};
    std::vector<glm::vec3> normals = sampleMixture(truth, 8000, 4);
    const glm::dvec3 mean = meanOf(normals);
    const glm::vec3 align[3] = {0.5f * direction(90, 45), 1.2f * direction(60, 200),
                                0.3f * direction(10, 300)};
    VmfFitOptions options;
    options.minAlpha = 0;
    options.maxIterations = 1;
    VmfFitResult unpulled =
        fitVmfMixture(normals.data(), nullptr, normals.size(), truth, options, align);
    options.coherence = 0.8f;
    VmfFitResult pulled =
        fitVmfMixture(normals.data(), nullptr, normals.size(), truth, options, align);
    ASSERT_EQ(unpulled.lobes.size(), 3u);
    ASSERT_EQ(pulled.lobes.size(), 3u);
    EXPECT_NEAR(glm::length(packedSum(unpulled.lobes) - mean), 0, 2e-6);
    glm::dvec3 offset(0);
    for (int j = 0; j < 3; ++j) {
        const VmfLobe &f = unpulled.lobes[size_t(j)], &p = pulled.lobes[size_t(j)];
        EXPECT_EQ(p.alpha, f.alpha) << j;
        EXPECT_EQ(p.kappa, f.kappa) << j;
        glm::dvec3 r = meanLengthFromKappa(f.kappa) * glm::dvec3(f.mu);
        glm::dvec3 expected = glm::normalize(r + 0.8 * glm::dvec3(align[j]));
        EXPECT_LT(angleBetween(p.mu, glm::vec3(expected)), 1e-6) << j;
        EXPECT_GT(degrees(angleBetween(p.mu, f.mu)), 1) << j; // the pull does move it
        offset += double(f.alpha) * (glm::length(r) * glm::dvec3(p.mu) - r);
    }
    EXPECT_NEAR(glm::length(packedSum(pulled.lobes) - (mean + offset)), 0, 2e-6);
    EXPECT_GT(glm::length(offset), 1e-2);

    // alignedKappa: kappa_j from r_j . mu_j, so lobe j stores the point of its axis nearest
    // alpha_j r_j, and the packed sum leaves the mean by minus the parts of r_j across the axes.
    options.alignedKappa = true;
    VmfFitResult aligned =
        fitVmfMixture(normals.data(), nullptr, normals.size(), truth, options, align);
    ASSERT_EQ(aligned.lobes.size(), 3u);
    glm::dvec3 across(0);
    for (int j = 0; j < 3; ++j) {
        const VmfLobe &f = unpulled.lobes[size_t(j)], &a = aligned.lobes[size_t(j)];
        const VmfLobe& p = pulled.lobes[size_t(j)];
        EXPECT_EQ(a.alpha, f.alpha) << j;
        EXPECT_EQ(a.mu, p.mu) << j;
        glm::dvec3 r = meanLengthFromKappa(f.kappa) * glm::dvec3(f.mu);
        glm::dvec3 axis = glm::normalize(glm::dvec3(a.mu));
        EXPECT_NEAR(a.kappa, kappaFromMeanLength(glm::dot(r, axis)), 1e-5 * a.kappa) << j;
        across += double(f.alpha) * (r - glm::dot(r, axis) * axis);
    }
    EXPECT_NEAR(glm::length(packedSum(aligned.lobes) - (mean - across)), 0, 2e-6);
}

TEST(VmfCoherent, SlotsKeepTheirPlaces) {
    // Out of alpha order, an empty slot, a lobe pointing where no normal is (dropped) and two
    // identical lobes (merged into the lower slot): every slot stays where it was.
    std::vector<VmfLobe> truth = {lobe(0.2f, direction(30, 0), 50.f),
                                  lobe(0.8f, direction(30, 180), 50.f)};
    std::vector<glm::vec3> normals = sampleMixture(truth, 5000, 5);
    std::vector<VmfLobe> start = {
        lobe(0.1f, direction(28, 5), 20.f), lobe(0.f, direction(0, 0), 20.f),
        lobe(0.3f, direction(32, 175), 20.f), lobe(0.3f, direction(32, 175), 20.f),
        lobe(0.2f, direction(170, 0), 20.f)};
    const glm::vec3 align[5] = {direction(30, 0), direction(0, 0), direction(30, 180),
                                direction(30, 180), direction(170, 0)};
    VmfFitOptions options;
    options.coherence = 0.1f;
    VmfFitResult fit =
        fitVmfMixture(normals.data(), nullptr, normals.size(), start, options, align);
    ASSERT_EQ(fit.lobes.size(), 5u);
    EXPECT_TRUE(sameBits(fit.lobes[1], VmfLobe{})); // empty from the start
    EXPECT_TRUE(sameBits(fit.lobes[3], VmfLobe{})); // merged into slot 2
    EXPECT_TRUE(sameBits(fit.lobes[4], VmfLobe{})); // no normal near it: dropped
    EXPECT_NEAR(fit.lobes[0].alpha, 0.2, 0.02);
    EXPECT_NEAR(fit.lobes[2].alpha, 0.8, 0.02);
    EXPECT_NEAR(double(fit.lobes[0].alpha) + double(fit.lobes[2].alpha), 1.0, 1e-6);
    EXPECT_LT(degrees(angleBetween(fit.lobes[0].mu, truth[0].mu)), 2);
    EXPECT_LT(degrees(angleBetween(fit.lobes[2].mu, truth[1].mu)), 2);
}

// ---- the lobe-mismatch metric --------------------------------------------------------------

VmfLevel levelOf(int width, int height, const std::vector<std::vector<VmfLobe>>& texels) {
    VmfLevel level;
    level.width = width;
    level.height = height;
    level.offsets.push_back(0);
    for (const std::vector<VmfLobe>& t : texels) {
        level.lobes.insert(level.lobes.end(), t.begin(), t.end());
        level.offsets.push_back(uint32_t(level.lobes.size()));
    }
    return level;
}

TEST(VmfCoherent, LobeMismatchIsTheWeightedMeanAngle) {
    // Level 1, 2 x 2 texels. Pairs: (0,0)-(1,0), (0,1)-(1,1) across; (0,0)-(0,1), (1,0)-(1,1)
    // down. Slot j against slot j, weight min(alpha, alpha'), empty or missing slots skipped.
    const glm::vec3 z = direction(0, 0);
    VmfLevel level1 =
        levelOf(2, 2,
                {{lobe(0.5f, z, 10), lobe(0.5f, direction(90, 0), 10)},
                 {lobe(0.25f, direction(10, 0), 10), lobe(0.75f, direction(90, 20), 10)},
                 {lobe(1.f, direction(30, 90), 10), lobe(0.f, z, 0)},
                 {lobe(0.6f, direction(30, 90), 10)}});
    // Across: top (0.25 x 10 deg + 0.5 x 20 deg), bottom (0.6 x 0). Down: left (0.5 x 30),
    // right (0.25 x angle between (10, 0) and (30, 90)).
    double rightDown = degrees(angleBetween(direction(10, 0), direction(30, 90)));
    double expected = (0.25 * 10 + 0.5 * 20 + 0.6 * 0 + 0.5 * 30 + 0.25 * rightDown) /
                      (0.25 + 0.5 + 0.6 + 0.5 + 0.25);
    // Level 0 differs wildly; it only counts from firstLevel 0.
    VmfLevel level0 = levelOf(4, 4, std::vector<std::vector<VmfLobe>>(16, {lobe(1.f, z, 10)}));
    level0.lobes[0].mu = direction(90, 0);
    std::vector<VmfLevel> levels = {level0, level1};
    EXPECT_NEAR(lobeMismatch(levels), expected, 1e-4);
    EXPECT_NEAR(lobeMismatch(levels, 1), expected, 1e-4);
    // Level 0 adds the pairs of texel (0,0) with (1,0) and (0,1): weight 1 and 90 deg each, and
    // 22 more pairs at 0 deg.
    EXPECT_NEAR(lobeMismatch(levels, 0), (expected * 2.1 + 180) / (2.1 + 24), 1e-4);
    EXPECT_EQ(lobeMismatch(levels, 2), 0.0);
}

// ---- the pyramid ---------------------------------------------------------------------------

// Two groove directions in a pattern that drifts over the map: every texel belongs to grooves
// running along y (normals tilted +-theta about y, alternating by column) or along x (tilted
// about x, alternating by row), the share of each changing smoothly across the map, and theta
// itself drifting between 15 and 35 degrees. Coarse texels see up to four lobes whose weights
// and directions vary from texel to texel, so sorting lobes by alpha shuffles them.
Image twoGrooveMap(int size, uint64_t seed) {
    Image map(size, size, 3);
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> uniform(0, 1);
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            double u = double(x) / size, v = double(y) / size;
            double alongY =
                0.5 + 0.45 * std::sin(2 * vmftest::kPi * u) * std::cos(2 * vmftest::kPi * v);
            double theta = 25 + 10 * std::sin(2 * vmftest::kPi * (u + 0.5 * v));
            bool grooveAlongY = uniform(rng) < alongY;
            double phi = grooveAlongY ? (x % 2 ? 180 : 0) : (y % 2 ? 270 : 90);
            glm::vec3 n = sampleVmf(direction(theta, phi), 300, rng); // ~3 degrees of jitter
            test::setNormal(map, x, y, n.x, n.y, n.z);
        }
    return map;
}

// The normals of texel (x, y) of level k.
std::vector<glm::vec3> footprintNormals(const Pyramid& pyramid, int k, int x, int y) {
    std::vector<glm::vec3> out;
    Footprint f = footprint(pyramid, k, x, y);
    for (int j = f.y0; j < f.y1; ++j)
        for (int i = f.x0; i < f.x1; ++i) {
            const float* p = pyramid.base->at(i, j);
            out.push_back(glm::normalize(glm::vec3(p[0], p[1], p[2])));
        }
    return out;
}

// Sum over the level's texels of the log-likelihood of their lobes for every normal they cover.
double levelLogLikelihood(const Pyramid& pyramid, const VmfLevel& level, int k) {
    double sum = 0;
    for (int y = 0; y < level.height; ++y)
        for (int x = 0; x < level.width; ++x)
            for (glm::vec3 n : footprintNormals(pyramid, k, x, y))
                sum += vmfMixtureLogDensity(n, level.texel(x, y));
    return sum;
}

void expectSlots(const std::vector<VmfLevel>& levels, const Pyramid& pyramid, int J) {
    ASSERT_EQ(levels.size(), pyramid.levels.size());
    for (size_t k = 0; k < levels.size(); ++k) {
        const VmfLevel& level = levels[k];
        ASSERT_EQ(level.width, pyramid.levels[k].width);
        ASSERT_EQ(level.height, pyramid.levels[k].height);
        const size_t texels = size_t(level.width) * size_t(level.height);
        ASSERT_EQ(level.offsets.size(), texels + 1);
        ASSERT_EQ(level.lobes.size(), texels * size_t(J));
        for (size_t t = 0; t <= texels; ++t) ASSERT_EQ(level.offsets[t], t * size_t(J));
        for (int y = 0; y < level.height; ++y)
            for (int x = 0; x < level.width; ++x) {
                double alphas = 0;
                int live = 0;
                for (const VmfLobe& l : level.texel(x, y)) {
                    if (l.alpha == 0) {
                        EXPECT_TRUE(sameBits(l, VmfLobe{}));
                        continue;
                    }
                    ++live;
                    alphas += l.alpha;
                    EXPECT_TRUE(std::isfinite(l.alpha) && l.alpha > 0);
                    EXPECT_TRUE(std::isfinite(l.kappa) && l.kappa >= 0);
                    EXPECT_NEAR(glm::length(l.mu), 1.f, 1e-5f);
                }
                EXPECT_NEAR(alphas, 1.0, 1e-6) << "level " << k << " texel " << x << "," << y;
                if (k == 0) {
                    EXPECT_EQ(live, 1);
                }
            }
    }
}

TEST(VmfCoherent, PyramidHasJSlotsEverywhere) {
    Pyramid pyramid = buildPyramid(twoGrooveMap(32, 6));
    VmfFitOptions options;
    options.coherence = 1;
    VmfFitStats stats;
    std::vector<VmfLevel> levels = fitVmfPyramidCoherent(pyramid, 4, options, &stats);
    expectSlots(levels, pyramid, 4);
    EXPECT_EQ(stats.texels, 256u + 64u + 16u + 4u + 1u);
    // Level 0: the normal itself, alpha 1, in the slot of the parent lobe most responsible for it.
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) {
            float unit[3];
            normalizeOrFlat(pyramid.base->at(x, y), unit);
            glm::vec3 n(unit[0], unit[1], unit[2]);
            std::span<const VmfLobe> parent = levels[1].texel(x / 2, y / 2);
            int best = 0;
            for (int j = 1; j < 4; ++j)
                if (parent[j].alpha > 0 &&
                    std::log(parent[j].alpha) + vmfLogDensity(n, parent[j].mu, parent[j].kappa) >
                        std::log(parent[best].alpha) +
                            vmfLogDensity(n, parent[best].mu, parent[best].kappa))
                    best = j;
            const VmfLobe& l = levels[0].texel(x, y)[best];
            EXPECT_EQ(l.alpha, 1.f) << x << "," << y;
            EXPECT_EQ(l.mu, n);
            EXPECT_EQ(l.kappa, kDefaultKappaMax);
        }
    // fitVmfPyramid hands coherent fits over.
    std::vector<VmfLevel> same = fitVmfPyramid(pyramid, 4, options, nullptr);
    for (size_t k = 0; k < levels.size(); ++k)
        for (size_t i = 0; i < levels[k].lobes.size(); ++i)
            ASSERT_TRUE(sameBits(levels[k].lobes[i], same[k].lobes[i])) << k << " " << i;
}

TEST(VmfCoherent, OneTexelMap) {
    Image map(1, 1, 3);
    test::setNormal(map, 0, 0, 0.f, 0.6f, 0.8f);
    Pyramid pyramid = buildPyramid(map);
    VmfFitOptions options;
    options.coherence = 1;
    std::vector<VmfLevel> levels = fitVmfPyramidCoherent(pyramid, 3, options, nullptr);
    expectSlots(levels, pyramid, 3);
    EXPECT_EQ(levels[0].lobes[0].mu, glm::vec3(0.f, 0.6f, 0.8f));
}

TEST(VmfCoherent, WithoutPullAnOddPyramidKeepsTheMeanNormal) {
    // Odd sizes, C = 0: slot-coherent starts alone, so every texel's packed lobes add up to its Na
    // as in fitVmfPyramid (minAlpha = 0: nothing dropped).
    Pyramid pyramid = buildPyramid(oddClusteredMap(7));
    VmfFitOptions options;
    options.minAlpha = 0;
    std::vector<VmfLevel> levels = fitVmfPyramidCoherent(pyramid, 4, options, nullptr);
    expectSlots(levels, pyramid, 4);
    for (size_t k = 1; k < levels.size(); ++k) {
        const Image& mean = levelMean(pyramid, int(k));
        for (int y = 0; y < mean.height; ++y)
            for (int x = 0; x < mean.width; ++x) {
                const float* na = mean.at(x, y);
                EXPECT_NEAR(
                    glm::length(packedSum(levels[k].texel(x, y)) - glm::dvec3(na[0], na[1], na[2])),
                    0, 3e-5)
                    << "level " << k << " texel " << x << "," << y;
            }
    }
}

// align_j of texel (x, y) of level k as the pyramid forms it: the parent and the left,
// upper-left, upper and upper-right texels.
std::vector<glm::dvec3> alignmentOf(const std::vector<VmfLevel>& levels, int k, int x, int y,
                                    int J) {
    std::vector<glm::dvec3> align(size_t(J), glm::dvec3(0));
    auto add = [&](std::span<const VmfLobe> lobes) {
        for (int j = 0; j < J; ++j)
            align[size_t(j)] += double(lobes[size_t(j)].alpha) * glm::dvec3(lobes[size_t(j)].mu);
    };
    const VmfLevel& level = levels[size_t(k)];
    add(levels[size_t(k) + 1].texel(x / 2, y / 2)); // power-of-two sizes
    if (x > 0) add(level.texel(x - 1, y));
    if (y > 0) {
        if (x > 0) add(level.texel(x - 1, y - 1));
        add(level.texel(x, y - 1));
        if (x + 1 < level.width) add(level.texel(x + 1, y - 1));
    }
    return align;
}

TEST(VmfCoherent, PulledPyramidStaysNearTheMeanNormal) {
    // With C > 0 the packed lobes leave Na: lobe j stores alpha_j |r_j| mu_j instead of
    // alpha_j r_j, at most 2 C alpha_j |align_j| away; with alignedKappa alpha_j (r_j . mu_j) mu_j,
    // at most C alpha_j |align_j| away. alpha_j and the E-step's r_j still add up to Na, so with
    // kappa from |r_j| the stored lengths alpha_j |r_j| add up to at least |Na|.
    Pyramid pyramid = buildPyramid(twoGrooveMap(32, 8));
    const int J = 4;
    for (bool alignedKappa : {false, true}) {
        VmfFitOptions options;
        options.coherence = 1;
        options.minAlpha = 0;
        options.alignedKappa = alignedKappa;
        std::vector<VmfLevel> levels = fitVmfPyramidCoherent(pyramid, J, options, nullptr);
        double largest = 0;
        for (int k = 1; k + 1 < int(levels.size()); ++k) {
            const Image& mean = levelMean(pyramid, k);
            for (int y = 0; y < mean.height; ++y)
                for (int x = 0; x < mean.width; ++x) {
                    const float* p = mean.at(x, y);
                    const glm::dvec3 na(p[0], p[1], p[2]);
                    std::span<const VmfLobe> lobes = levels[size_t(k)].texel(x, y);
                    std::vector<glm::dvec3> align = alignmentOf(levels, k, x, y, J);
                    double bound = 3e-5, lengths = 0;
                    for (int j = 0; j < J; ++j) {
                        bound += (alignedKappa ? 1 : 2) * options.coherence *
                                 lobes[size_t(j)].alpha * glm::length(align[size_t(j)]);
                        glm::vec4 packed = packLobe(lobes[size_t(j)]);
                        lengths += glm::length(glm::dvec3(packed.y, packed.z, packed.w));
                    }
                    double error = glm::length(packedSum(lobes) - na);
                    EXPECT_LE(error, bound) << alignedKappa << " " << k << " " << x << "," << y;
                    if (!alignedKappa) {
                        EXPECT_GE(lengths, glm::length(na) - 3e-5) << k << " " << x << "," << y;
                    }
                    largest = std::max(largest, error);
                }
        }
        EXPECT_GT(largest, 1e-2); // the pull does cost the mean normal something
    }
}

TEST(VmfCoherent, PyramidIsTheSameOnAnyThreadCount) {
    // 256 x 256: the two texels below the top (16384 normals each) split their passes across
    // threads, the levels below them split each anti-diagonal's texels.
    Pyramid pyramid = buildPyramid(twoGrooveMap(256, 9));
    VmfFitOptions options;
    options.coherence = 1;
    int threads = omp_get_max_threads();
    omp_set_num_threads(1);
    std::vector<VmfLevel> one = fitVmfPyramidCoherent(pyramid, 4, options, nullptr);
    omp_set_num_threads(std::max(2, threads));
    std::vector<VmfLevel> many = fitVmfPyramidCoherent(pyramid, 4, options, nullptr);
    omp_set_num_threads(threads);
    ASSERT_EQ(one.size(), many.size());
    for (size_t k = 0; k < one.size(); ++k) {
        ASSERT_EQ(one[k].lobes.size(), many[k].lobes.size());
        for (size_t i = 0; i < one[k].lobes.size(); ++i)
            ASSERT_TRUE(sameBits(one[k].lobes[i], many[k].lobes[i])) << k << " " << i;
    }
    EXPECT_EQ(lobeMismatch(one), lobeMismatch(many));
}

// A size x size map whose columns alternate every two texels between vMF samples (kappa) about
// two directions `polar` degrees from z, at azimuths a and b.
Image alternatingColumns(int size, float polar, float a, float b, float kappa, uint64_t seed) {
    Image map(size, size, 3);
    std::mt19937_64 rng(seed);
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            glm::vec3 n = sampleVmf(direction(polar, x % 4 < 2 ? a : b), kappa, rng);
            test::setNormal(map, x, y, n.x, n.y, n.z);
        }
    return map;
}

TEST(VmfCoherent, TopTexelIsThePlainFitOfEveryNormal) {
    // 512 x 512: the top texel's EM over every normal starts from the plain pyramid of a
    // 128 x 128 subsample (stride 4) instead of the whole map's. Columns alternate every two
    // texels between normals 30 degrees either side of z: period 4, the stride. Measured: 2.45859
    // nats per normal against the whole map's plain fit's 2.45874 (2.45861 with the subsample
    // taken at the same place in every block: the EM finds both sides from there too).
    const int size = 512;
    Pyramid pyramid = buildPyramid(alternatingColumns(size, 30, 0, 180, 400, 11));
    const int top = int(pyramid.levels.size()) - 1;
    std::vector<VmfLevel> plain = fitVmfPyramid(pyramid, 4, {}, nullptr);
    VmfFitOptions options;
    options.coherence = kHardwareFilteringCoherence;
    options.alignedKappa = true;
    std::vector<VmfLevel> coherent = fitVmfPyramidCoherent(pyramid, 4, options, nullptr);

    const double normals = double(size) * size;
    EXPECT_NEAR(levelLogLikelihood(pyramid, coherent[size_t(top)], top) / normals,
                levelLogLikelihood(pyramid, plain[size_t(top)], top) / normals, 1e-3);
    // Each side holds half the weight, its lobes' weighted mean direction on it.
    double side[2] = {0, 0};
    glm::dvec3 mean[2] = {glm::dvec3(0), glm::dvec3(0)};
    for (const VmfLobe& l : coherent[size_t(top)].texel(0, 0)) {
        const int s = l.mu.x > 0 ? 0 : 1;
        side[s] += l.alpha;
        mean[s] += double(l.alpha) * glm::dvec3(l.mu);
    }
    for (int s = 0; s < 2; ++s) {
        EXPECT_NEAR(side[s], 0.5, 0.02) << s;
        EXPECT_LT(degrees(angleBetween(glm::vec3(mean[s]), direction(30, s == 0 ? 0 : 180))), 0.5)
            << s;
    }
}

TEST(VmfCoherent, SmallMapsTopTexelIsThePlainPyramidsOwn) {
    // 64 x 64 (under 256 normals across): the plain pyramid of the whole map is cheap, and its
    // top texel is already the plain fit of every normal, so the coherent pyramid takes it as it
    // is; EM run again from there would move it by its tolerance.
    Pyramid pyramid = buildPyramid(alternatingColumns(64, 25, 30, 200, 60, 5));
    VmfFitOptions options;
    options.coherence = kHardwareFilteringCoherence;
    options.alignedKappa = true;
    VmfFitOptions plainOptions = options;
    plainOptions.coherence = 0.f;
    plainOptions.alignedKappa = false;
    const std::vector<VmfLevel> plain = fitVmfPyramid(pyramid, 4, plainOptions, nullptr);
    const std::vector<VmfLevel> coherent = fitVmfPyramidCoherent(pyramid, 4, options, nullptr);
    const std::span<const VmfLobe> a = plain.back().texel(0, 0), b = coherent.back().texel(0, 0);
    ASSERT_GE(a.size(), 2u);
    ASSERT_GE(b.size(), a.size());
    for (size_t j = 0; j < b.size(); ++j) {
        const VmfLobe want = j < a.size() ? a[j] : VmfLobe{};
        EXPECT_EQ(b[j].alpha, want.alpha) << j;
        EXPECT_EQ(b[j].kappa, want.kappa) << j;
        EXPECT_EQ(b[j].mu, want.mu) << j;
    }
}

// What hardware filtering makes of two neighbours: every pair of horizontally adjacent texels of
// level k, their slots' packed values averaged (H eq. 33) and unpacked, judged against the two
// footprints' normals together by smoothedNdfError (s = 64); the mean over the pairs.
double blendedPairError(const Pyramid& pyramid, const VmfLevel& level, int k) {
    double sum = 0;
    int pairs = 0;
    for (int y = 0; y < level.height; ++y)
        for (int x = 0; x + 1 < level.width; ++x) {
            std::span<const VmfLobe> a = level.texel(x, y), b = level.texel(x + 1, y);
            std::vector<VmfLobe> blended;
            for (size_t j = 0; j < std::max(a.size(), b.size()); ++j) {
                glm::vec4 p(0.f);
                if (j < a.size()) p += 0.5f * packLobe(a[j]);
                if (j < b.size()) p += 0.5f * packLobe(b[j]);
                if (p.x > 0) blended.push_back(unpackLobe(p));
            }
            std::vector<glm::vec3> normals = footprintNormals(pyramid, k, x, y);
            const std::vector<glm::vec3> right = footprintNormals(pyramid, k, x + 1, y);
            normals.insert(normals.end(), right.begin(), right.end());
            sum += smoothedNdfError(normals.data(), normals.size(), blended, 64);
            ++pairs;
        }
    return sum / pairs;
}

TEST(VmfCoherent, AlignedLobesMatchAcrossTexelsAtLittleCost) {
    // 64 x 64 two-groove map, J = 4: slots by decreasing alpha (the plain fit), and the top-down
    // fit (alignedKappa, as the bake runs it) with no pull, eval's engine-view pull C = 0.03 and
    // C = 1. Measured: mismatch (degrees) 20.2, 4.7, 4.5, 2.2. Log-likelihood per normal, levels
    // 1..6: plain 8.29 2.24 1.58 1.17 0.57 0.28; C = 0 5.40 2.18 1.58 1.17 0.57 0.28; C = 1 3.00
    // 1.80 1.34 0.94 0.51 0.28. Blended pairs' NDF error, levels 1..5: plain 0.31 0.52 0.47 0.52
    // 0.51; C = 0 0.058 0.047 0.053 0.122 0.194; C = 1 0.182 0.168 0.191 0.222 0.211. Each texel
    // started from its parent's lobes keeps its slots close to its neighbours' at no cost in
    // likelihood from 16 normals a texel up, and the pull buys a lower mismatch with both
    // likelihood and the blend: turned sharp lobes widen (alignedKappa) and blend worse.
    Pyramid pyramid = buildPyramid(twoGrooveMap(64, 10));
    const int J = 4;
    std::vector<VmfLevel> plain = fitVmfPyramid(pyramid, J, {}, nullptr);
    VmfFitOptions options;
    options.alignedKappa = true;
    std::vector<VmfLevel> started = fitVmfPyramidCoherent(pyramid, J, options, nullptr);
    options.coherence = kEngineViewCoherence;
    std::vector<VmfLevel> light = fitVmfPyramidCoherent(pyramid, J, options, nullptr);
    options.coherence = 1;
    std::vector<VmfLevel> pulled = fitVmfPyramidCoherent(pyramid, J, options, nullptr);

    const double mismatchPlain = lobeMismatch(plain);
    EXPECT_GT(mismatchPlain, 15);
    EXPECT_LT(lobeMismatch(started), 0.3 * mismatchPlain);
    EXPECT_LT(lobeMismatch(light), lobeMismatch(started));
    EXPECT_LT(lobeMismatch(pulled), 0.6 * lobeMismatch(started));

    const double normals = 64.0 * 64.0;
    const int top = int(plain.size()) - 1;
    for (int k = 1; k < top; ++k) {
        const double perNormalPlain = levelLogLikelihood(pyramid, plain[size_t(k)], k) / normals;
        const double perNormalStarted =
            levelLogLikelihood(pyramid, started[size_t(k)], k) / normals;
        const double perNormalPulled = levelLogLikelihood(pyramid, pulled[size_t(k)], k) / normals;
        if (k >= 2) {
            EXPECT_GT(perNormalStarted, perNormalPlain - 0.1) << k;
        } else { // 4 normals, 4 lobes: the plain fit puts a spike on each
            EXPECT_GT(perNormalStarted, perNormalPlain - 4) << k;
        }
        EXPECT_LT(perNormalPulled, perNormalStarted) << k;

        const double blendPlain = blendedPairError(pyramid, plain[size_t(k)], k);
        const double blendStarted = blendedPairError(pyramid, started[size_t(k)], k);
        EXPECT_LT(blendStarted, 0.45 * blendPlain) << k;
        EXPECT_LT(blendStarted, blendedPairError(pyramid, pulled[size_t(k)], k)) << k;
        EXPECT_NEAR(blendedPairError(pyramid, light[size_t(k)], k), blendStarted,
                    0.05 * blendStarted)
            << k;
    }
}

} // namespace
} // namespace ndfmip
