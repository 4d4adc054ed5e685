#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <omp.h>

#include "methods/vmf/vmf_internal.h"
#include "ndfmip/pyramid.h"
#include "ndfmip/vmf.h"
#include "test_support.h"
#include "vmf_test_support.h"

namespace ndfmip {
namespace {

using namespace vmftest;

double alphaSum(std::span<const VmfLobe> lobes) {
    double sum = 0;
    for (const VmfLobe& l : lobes) sum += l.alpha;
    return sum;
}

void expectFinite(std::span<const VmfLobe> lobes) {
    for (const VmfLobe& l : lobes) {
        EXPECT_TRUE(std::isfinite(l.alpha) && l.alpha > 0) << l.alpha;
        EXPECT_TRUE(std::isfinite(l.kappa) && l.kappa >= 0) << l.kappa;
        EXPECT_NEAR(glm::length(l.mu), 1.f, 1e-5f);
    }
}

// Starting lobes drawn from the data: farthest-point clustering of its first 200 normals.
std::vector<VmfLobe> seedFrom(const std::vector<glm::vec3>& normals, int J) {
    std::vector<VmfLobe> candidates;
    for (size_t i = 0; i < 200; ++i) candidates.push_back(lobe(1.f, normals[i], 10.f));
    return farthestPointLobes(candidates, J);
}

// ---- one lobe ------------------------------------------------------------------------------

TEST(Vmf, LogNormalizerMatchesDirectFormula) {
    for (double kappa : {1e-6, 1e-3, 0.1, 0.5, 1.0, 5.0, 50.0, 300.0, 700.0}) {
        double direct = std::log(kappa / (4 * kPi * std::sinh(kappa)));
        EXPECT_NEAR(vmfLogNormalizer(kappa), direct, 1e-13 * std::max(1.0, std::abs(direct)))
            << kappa;
    }
    EXPECT_DOUBLE_EQ(vmfLogNormalizer(0), -std::log(4 * kPi));
}

TEST(Vmf, LogNormalizerIsFiniteAtTheExtremes) {
    // kappa -> 0: kappa / (4 pi sinh kappa) -> 1/(4 pi).
    EXPECT_NEAR(vmfLogNormalizer(1e-8), -std::log(4 * kPi), 1e-14);
    // sinh(1e6) overflows a double; the log form does not.
    double big = vmfLogNormalizer(1e6);
    EXPECT_TRUE(std::isfinite(big));
    EXPECT_NEAR(big, std::log(1e6) - 1e6 - std::log(2 * kPi), 1e-9);
    EXPECT_TRUE(std::isfinite(vmfLogDensity({0, 0, 1}, {0, 0, 1}, 1e6)));
    EXPECT_TRUE(std::isfinite(vmfLogDensity({0, 0, -1}, {0, 0, 1}, 1e6)));
}

TEST(Vmf, DensityIntegratesToOne) {
    // Integral over the sphere = 2 pi Integral_{-1}^{1} gamma(t) dt, t = mu.n; with u = kappa (1 -
    // t) the lobe is e^(-u) in u, resolved the same way at every kappa (midpoint rule).
    for (double kappa : {0.0, 0.5, 10.0, 1000.0}) {
        double span = kappa > 0 ? std::min(2 * kappa, 60.0) : 2.0;
        const int steps = 200000;
        double sum = 0;
        for (int i = 0; i < steps; ++i) {
            double u = (i + 0.5) * span / steps;
            double t = kappa > 0 ? 1 - u / kappa : 1 - u;
            double dt = kappa > 0 ? span / steps / kappa : span / steps;
            sum += std::exp(vmfLogNormalizer(kappa) + kappa * t) * dt;
        }
        EXPECT_NEAR(2 * kPi * sum, 1.0, 1e-6) << kappa;
    }
    // The same through vmfLogDensity at a few points against the closed form.
    glm::vec3 mu = glm::normalize(glm::vec3(0.3f, -0.2f, 1.f));
    glm::vec3 n = glm::normalize(glm::vec3(0.1f, 0.1f, 1.f));
    double expected = vmfLogNormalizer(20) + 20 * glm::dot(glm::dvec3(mu), glm::dvec3(n));
    EXPECT_NEAR(vmfLogDensity(n, mu, 20), expected, 1e-12);
}

TEST(Vmf, MixtureLogDensityIsLogSumExp) {
    std::vector<VmfLobe> lobes = {lobe(0.25f, {0, 0, 1}, 30.f), lobe(0.75f, direction(60, 0), 5.f)};
    glm::vec3 n = direction(20, 10);
    double direct = std::log(0.25 * std::exp(vmfLogDensity(n, lobes[0].mu, 30)) +
                             0.75 * std::exp(vmfLogDensity(n, lobes[1].mu, 5)));
    EXPECT_NEAR(vmfMixtureLogDensity(n, lobes), direct, 1e-12);
    // Far from two very sharp lobes every density underflows; the log does not.
    std::vector<VmfLobe> sharp = {lobe(0.5f, {0, 0, 1}, 1e5f), lobe(0.5f, {1, 0, 0}, 1e5f)};
    double far = vmfMixtureLogDensity(glm::vec3(0, 0, -1), sharp);
    EXPECT_TRUE(std::isfinite(far));
    EXPECT_NEAR(far, std::log(0.5) + vmfLogDensity({0, 0, -1}, {1, 0, 0}, 1e5), 1e-6);
}

TEST(Vmf, LangevinMatchesCothMinusInverse) {
    for (double kappa : {0.099, 0.101, 0.5, 2.0, 10.0, 19.9, 20.1, 100.0}) {
        long double k = kappa;
        long double direct = std::cosh(k) / std::sinh(k) - 1 / k;
        EXPECT_NEAR(langevin(kappa), double(direct), 1e-14) << kappa;
    }
    EXPECT_EQ(langevin(0), 0);
    EXPECT_NEAR(langevin(1e-6) / 1e-6, 1.0 / 3, 1e-12); // A(k) ~ k/3
    EXPECT_NEAR(langevin(1e6), 1 - 1e-6, 1e-15);
}

TEST(Vmf, InverseLangevinInvertsLangevin) {
    for (double kappa : {1e-4, 0.05, 0.5, 3.0, 19.9, 25.0, 1e3, 1e5})
        EXPECT_NEAR(inverseLangevin(langevin(kappa)), kappa, 1e-9 * kappa) << kappa;
    EXPECT_EQ(inverseLangevin(0), 0);
}

TEST(Vmf, BanerjeeKappaAndItsInverse) {
    // Algorithm 1, line 12.
    for (double r : {0.1, 0.5, 0.9, 0.999})
        EXPECT_NEAR(kappaFromMeanLength(r, 1e30), (3 * r - r * r * r) / (1 - r * r),
                    1e-12 / (1 - r));
    EXPECT_EQ(kappaFromMeanLength(0), 0);
    EXPECT_EQ(kappaFromMeanLength(-0.5), 0);
    EXPECT_EQ(kappaFromMeanLength(1.0, 123.0), 123.0);
    EXPECT_EQ(kappaFromMeanLength(0.9999999, 1e4), 1e4);
    for (double kappa : {1e-6, 0.01, 1.0, 10.0, 1e3, 1e5, 1e8}) {
        double r = meanLengthFromKappa(kappa);
        EXPECT_GE(r, 0);
        EXPECT_LT(r, 1);
        EXPECT_NEAR(kappaFromMeanLength(r, 1e30), kappa, 1e-9 * kappa) << kappa;
    }
    EXPECT_EQ(meanLengthFromKappa(0), 0);
}

TEST(Vmf, BanerjeeKappaIsWithinHalfOfTheExactInverse) {
    // The claim of vmf.h: 0 <= kappa_B(r) - A^-1(r) <= 0.5, -> 0 as r -> 0 and -> 0.5 as r -> 1.
    double worst = 0;
    for (double r = 0.001; r < 0.9999; r += 0.001) {
        double difference = kappaFromMeanLength(r, 1e30) - inverseLangevin(r);
        EXPECT_GE(difference, -1e-9) << r;
        worst = std::max(worst, difference);
    }
    EXPECT_LE(worst, 0.5 + 1e-9);
    EXPECT_NEAR(kappaFromMeanLength(0.01, 1e30) - inverseLangevin(0.01), 0, 1e-5);
    EXPECT_NEAR(kappaFromMeanLength(0.99999, 1e30) - inverseLangevin(0.99999), 0.5, 1e-3);
}

TEST(Vmf, QuantisationKappaMatchesTheAngularErrorOfQuantisedNormals) {
    EXPECT_FLOAT_EQ(quantisationKappa(8), 3.f * 255.f * 255.f);
    EXPECT_FLOAT_EQ(quantisationKappa(16), float(3.0 * 65535.0 * 65535.0));
    // Simulated: b-bit unorm storage of random unit normals; a sharp vMF has E[theta^2] = 2/kappa.
    for (int bits : {6, 8, 10}) {
        std::mt19937_64 rng(bits);
        double steps = std::ldexp(1.0, bits) - 1, sumTheta2 = 0;
        const int count = 200000;
        for (int i = 0; i < count; ++i) {
            glm::vec3 n = sampleVmf({0, 0, 1}, 1.0, rng);
            glm::dvec3 q;
            for (int c = 0; c < 3; ++c) q[c] = std::round((n[c] + 1) / 2 * steps) / steps * 2 - 1;
            double theta = angleBetween(n, glm::vec3(q));
            sumTheta2 += theta * theta;
        }
        double kappa = quantisationKappa(bits);
        EXPECT_NEAR(sumTheta2 / count, 2 / kappa, 0.05 * 2 / kappa) << bits;
    }
}

// ---- storage (H eq. 33) --------------------------------------------------------------------

TEST(Vmf, PackUnpackRoundTrip) {
    std::mt19937_64 rng(3);
    for (float kappa : {0.f, 0.01f, 1.f, 10.f, 100.f, 1e4f, 1e5f})
        for (float alpha : {0.1f, 1.f}) {
            VmfLobe in = lobe(alpha, sampleVmf({0, 0, 1}, 0.0, rng), kappa);
            glm::vec4 packed = packLobe(in);
            EXPECT_FLOAT_EQ(packed.x, alpha);
            EXPECT_NEAR(glm::length(glm::vec3(packed.y, packed.z, packed.w)) / alpha,
                        meanLengthFromKappa(kappa), 1e-7);
            VmfLobe out = unpackLobe(packed);
            EXPECT_EQ(out.alpha, alpha);
            // 1 - r keeps about 6e-8 / (1 - r) ~ 6e-8 kappa of relative precision in float.
            EXPECT_NEAR(out.kappa, kappa, 1e-6 + (1e-6 + 1.5e-7 * kappa) * kappa) << kappa;
            if (kappa > 0) {
                EXPECT_LT(angleBetween(out.mu, in.mu), 1e-6) << kappa;
            }
        }
    VmfLobe empty = unpackLobe(glm::vec4(0, 0.1f, 0, 0));
    EXPECT_EQ(empty.alpha, 0.f);
    EXPECT_EQ(empty.kappa, 0.f);
    EXPECT_EQ(packLobe(lobe(0.f, {0, 0, 1}, 10.f)), glm::vec4(0.f));
}

TEST(Vmf, PackedLobesInterpolateTheirMeans) {
    // Averaging two packed lobes (what a bilinear tap does) gives alpha~ = mean alpha and
    // r~ = (alpha1 r1 mu1 + alpha2 r2 mu2) / (alpha1 + alpha2).
    VmfLobe a = lobe(0.6f, direction(10, 0), 200.f), b = lobe(0.2f, direction(10, 90), 50.f);
    VmfLobe mixed = unpackLobe(0.5f * (packLobe(a) + packLobe(b)));
    glm::dvec3 mean = (0.6 * meanLengthFromKappa(200) * glm::dvec3(a.mu) +
                       0.2 * meanLengthFromKappa(50) * glm::dvec3(b.mu)) /
                      0.8;
    EXPECT_FLOAT_EQ(mixed.alpha, 0.4f);
    EXPECT_NEAR(mixed.kappa, kappaFromMeanLength(glm::length(mean)), 1e-3 * mixed.kappa);
    EXPECT_LT(angleBetween(mixed.mu, glm::vec3(mean)), 1e-6);
}

TEST(Vmf, PackedLobesOfAFitSumToTheMeanNormal) {
    // alpha_j r_j mu_j = Sum_i z_ij n_i / N and Sum_j z_ij = 1: the lobes' stored vectors add up
    // to the Toksvig mean Na, whatever the fit converged to (no lobe capped, merged or dropped).
    std::vector<VmfLobe> truth = {lobe(0.5f, direction(30, 0), 40.f),
                                  lobe(0.5f, direction(30, 120), 15.f),
                                  lobe(0.2f, direction(50, 240), 80.f)};
    std::vector<glm::vec3> normals = sampleMixture(truth, 5000, 11);
    glm::dvec3 mean(0);
    for (glm::vec3 n : normals) mean += glm::dvec3(n);
    mean /= double(normals.size());
    VmfFitOptions options;
    options.minAlpha = 0;
    VmfFitResult fit =
        fitVmfMixture(normals.data(), nullptr, normals.size(), seedFrom(normals, 3), options);
    glm::dvec3 stored(0);
    for (const VmfLobe& l : fit.lobes) {
        glm::vec4 p = packLobe(l);
        stored += glm::dvec3(p.y, p.z, p.w);
    }
    EXPECT_NEAR(glm::length(stored - mean), 0, 2e-6) << fit.lobes.size();
}

// ---- EM ------------------------------------------------------------------------------------

struct Recovery {
    std::vector<VmfLobe> truth;
    bool exactKappa;
};

void expectRecovered(const Recovery& c, uint64_t seed) {
    const size_t count = 20000;
    std::vector<glm::vec3> normals = sampleMixture(c.truth, count, seed);
    VmfFitOptions options;
    options.exactKappa = c.exactKappa;
    options.tolerance = 1e-7;
    VmfFitResult fit = fitVmfMixture(normals.data(), nullptr, count,
                                     seedFrom(normals, int(c.truth.size())), options);
    ASSERT_EQ(fit.lobes.size(), c.truth.size());
    EXPECT_TRUE(fit.converged);
    EXPECT_NEAR(alphaSum(fit.lobes), 1.0, 1e-6);
    for (const VmfLobe& t : c.truth) {
        const VmfLobe* best = &fit.lobes[0];
        for (const VmfLobe& l : fit.lobes)
            if (angleBetween(l.mu, t.mu) < angleBetween(best->mu, t.mu)) best = &l;
        // Tolerances for 20k samples: alpha within 0.03 (sampling std ~0.004), mu within 2 deg,
        // kappa within 15% (sampling std ~2-3%; Banerjee's estimate adds <= 0.5).
        EXPECT_NEAR(best->alpha, t.alpha, 0.03);
        EXPECT_LT(degrees(angleBetween(best->mu, t.mu)), 2.0);
        EXPECT_NEAR(best->kappa, t.kappa, 0.15 * t.kappa);
    }
}

TEST(Vmf, EmRecoversTwoLobes) {
    Recovery c{{lobe(0.6f, direction(40, 0), 50.f), lobe(0.4f, direction(40, 180), 200.f)}, false};
    expectRecovered(c, 1);
    c.exactKappa = true;
    expectRecovered(c, 2);
}

TEST(Vmf, EmRecoversThreeLobes) {
    Recovery c{{lobe(0.5f, direction(20, 0), 20.f), lobe(0.3f, direction(60, 90), 100.f),
                lobe(0.2f, direction(60, 220), 400.f)},
               false};
    expectRecovered(c, 3);
    c.exactKappa = true;
    expectRecovered(c, 4);
}

TEST(Vmf, LogLikelihoodNeverDecreases) {
    // Overlapping lobes: EM crawls, so the trace has many small steps. With the exact M-step every
    // iteration is an EM step and cannot lower the log-likelihood; float responsibilities
    // leave noise far below 1e-9 relative.
    std::vector<VmfLobe> truth = {lobe(0.5f, direction(15, 0), 30.f),
                                  lobe(0.3f, direction(15, 150), 20.f),
                                  lobe(0.2f, direction(25, 260), 60.f)};
    std::vector<glm::vec3> normals = sampleMixture(truth, 20000, 5);
    VmfFitOptions options;
    options.exactKappa = true;
    options.tolerance = 0;
    options.maxIterations = 100;
    options.minAlpha = 0;
    VmfFitResult fit =
        fitVmfMixture(normals.data(), nullptr, normals.size(), seedFrom(normals, 4), options);
    ASSERT_EQ(fit.logLikelihoodTrace.size(), size_t(fit.iterations) + 1);
    EXPECT_GT(fit.iterations, 20);
    EXPECT_EQ(fit.logLikelihoodTrace.back(), fit.logLikelihood);
    for (size_t t = 1; t < fit.logLikelihoodTrace.size(); ++t) {
        double now = fit.logLikelihoodTrace[t], before = fit.logLikelihoodTrace[t - 1];
        double scale = std::max(std::abs(now), double(normals.size()));
        EXPECT_GE(now - before, -1e-9 * scale) << "iteration " << t;
    }
    EXPECT_GT(fit.logLikelihood, fit.logLikelihoodTrace.front());

    // Banerjee's kappa (the default) is not the exact maximiser: the trace may dip near
    // convergence, which then ends the fit (tolerance 0), but only by rounding-sized amounts.
    options.exactKappa = false;
    VmfFitResult banerjee =
        fitVmfMixture(normals.data(), nullptr, normals.size(), seedFrom(normals, 4), options);
    EXPECT_GT(banerjee.iterations, 20);
    for (size_t t = 1; t < banerjee.logLikelihoodTrace.size(); ++t) {
        double now = banerjee.logLikelihoodTrace[t], before = banerjee.logLikelihoodTrace[t - 1];
        double scale = std::max(std::abs(now), double(normals.size()));
        EXPECT_GE(now - before, -1e-6 * scale) << "iteration " << t;
    }
    // ... and it lands where the exact fit does, a little lower (kappa biased by up to +0.5).
    EXPECT_LT(banerjee.logLikelihood, fit.logLikelihood);
    EXPECT_GT(banerjee.logLikelihood, fit.logLikelihood - 1e-2 * double(normals.size()));
}

TEST(Vmf, LogLikelihoodIsTheMixtureLogDensitySum) {
    std::vector<VmfLobe> truth = {lobe(0.7f, direction(20, 0), 60.f),
                                  lobe(0.3f, direction(40, 200), 10.f)};
    std::vector<glm::vec3> normals = sampleMixture(truth, 3001, 6);
    VmfFitResult fit = fitVmfMixture(normals.data(), nullptr, normals.size(), seedFrom(normals, 2));
    // The returned lobes as a mixture, in double: alphas scaled to sum 1 and directions to unit
    // length (float rounding leaves both off by ~1e-7, which kappa |mu| would magnify).
    double sum = alphaSum(fit.lobes), direct = 0;
    for (glm::vec3 n : normals) {
        double density = 0;
        for (const VmfLobe& l : fit.lobes) {
            double cosine = glm::dot(glm::dvec3(n), glm::normalize(glm::dvec3(l.mu)));
            density += l.alpha / sum * std::exp(vmfLogNormalizer(l.kappa) + l.kappa * cosine);
        }
        direct += std::log(density);
    }
    EXPECT_NEAR(fit.logLikelihood, direct, 1e-9 * double(normals.size()));
}

TEST(Vmf, OneLobeIsTheClosedFormAfterOneIteration) {
    std::vector<glm::vec3> normals = sampleMixture({lobe(1.f, direction(25, 40), 12.f)}, 4003, 7);
    glm::dvec3 sum(0);
    for (glm::vec3 n : normals) sum += glm::dvec3(n);
    glm::dvec3 mean = sum / double(normals.size());
    VmfFitOptions options;
    options.maxIterations = 1;
    VmfFitResult once = fitVmfMixture(normals.data(), nullptr, normals.size(),
                                      {lobe(1.f, {1, 0, 0}, 3.f)}, options);
    ASSERT_EQ(once.lobes.size(), 1u);
    EXPECT_EQ(once.iterations, 1);
    EXPECT_EQ(once.lobes[0].alpha, 1.f);
    EXPECT_LT(angleBetween(once.lobes[0].mu, glm::vec3(mean)), 1e-6);
    EXPECT_NEAR(once.lobes[0].kappa, kappaFromMeanLength(glm::length(mean)),
                1e-5 * once.lobes[0].kappa);
    // Further iterations change nothing but rounding.
    VmfFitResult full =
        fitVmfMixture(normals.data(), nullptr, normals.size(), {lobe(1.f, {1, 0, 0}, 3.f)});
    EXPECT_TRUE(full.converged);
    EXPECT_LE(full.iterations, 2);
    EXPECT_LT(angleBetween(full.lobes[0].mu, once.lobes[0].mu), 1e-6);
    EXPECT_NEAR(full.lobes[0].kappa, once.lobes[0].kappa, 1e-5 * once.lobes[0].kappa);
}

TEST(Vmf, WeightsCountLikeRepeatedNormals) {
    std::vector<VmfLobe> truth = {lobe(0.5f, direction(30, 0), 30.f),
                                  lobe(0.5f, direction(30, 180), 30.f)};
    std::vector<glm::vec3> normals = sampleMixture(truth, 1001, 8);
    std::vector<float> weights(normals.size());
    std::vector<glm::vec3> repeated;
    for (size_t i = 0; i < normals.size(); ++i) {
        weights[i] = float(1 + i % 3);
        for (int k = 0; k < 1 + int(i % 3); ++k) repeated.push_back(normals[i]);
    }
    std::vector<VmfLobe> start = seedFrom(normals, 2);
    VmfFitResult weighted = fitVmfMixture(normals.data(), weights.data(), normals.size(), start);
    VmfFitResult plain = fitVmfMixture(repeated.data(), nullptr, repeated.size(), start);
    ASSERT_EQ(weighted.lobes.size(), plain.lobes.size());
    EXPECT_NEAR(weighted.logLikelihood, plain.logLikelihood, 1e-6 * std::abs(plain.logLikelihood));
    for (size_t j = 0; j < plain.lobes.size(); ++j) {
        EXPECT_NEAR(weighted.lobes[j].alpha, plain.lobes[j].alpha, 1e-5);
        EXPECT_NEAR(weighted.lobes[j].kappa, plain.lobes[j].kappa, 1e-4 * plain.lobes[j].kappa);
        EXPECT_LT(angleBetween(weighted.lobes[j].mu, plain.lobes[j].mu), 1e-5);
    }
}

// ---- degenerate inputs ---------------------------------------------------------------------

TEST(Vmf, IdenticalNormalsGiveOneCappedLobe) {
    glm::vec3 n = glm::normalize(glm::vec3(0.3f, -0.4f, 0.8f));
    std::vector<glm::vec3> normals(100, n);
    std::vector<VmfLobe> start = {lobe(0.4f, {0, 0, 1}, 10.f), lobe(0.3f, {1, 0, 0}, 1e5f),
                                  lobe(0.2f, n, 50.f), lobe(0.1f, {0, -1, 0}, 0.f)};
    VmfFitResult fit = fitVmfMixture(normals.data(), nullptr, normals.size(), start);
    ASSERT_EQ(fit.lobes.size(), 1u);
    expectFinite(fit.lobes);
    EXPECT_EQ(fit.lobes[0].alpha, 1.f);
    EXPECT_LT(angleBetween(fit.lobes[0].mu, n), 1e-6);
    EXPECT_EQ(fit.lobes[0].kappa, kDefaultKappaMax);
    EXPECT_TRUE(std::isfinite(fit.logLikelihood));
}

TEST(Vmf, TwoDistinctNormalsWithFourLobes) {
    glm::vec3 a = direction(30, 0), b = direction(30, 180);
    std::vector<glm::vec3> normals(60, a);
    normals.insert(normals.end(), 40, b);
    std::vector<VmfLobe> start = {
        lobe(0.25f, direction(20, 10), 100.f), lobe(0.25f, direction(20, 170), 100.f),
        lobe(0.25f, direction(50, 90), 100.f), lobe(0.25f, direction(5, 270), 100.f)};
    VmfFitResult fit = fitVmfMixture(normals.data(), nullptr, normals.size(), start);
    expectFinite(fit.lobes);
    EXPECT_NEAR(alphaSum(fit.lobes), 1.0, 1e-6);
    ASSERT_EQ(fit.lobes.size(), 2u);
    EXPECT_NEAR(fit.lobes[0].alpha, 0.6f, 1e-5);
    EXPECT_NEAR(fit.lobes[1].alpha, 0.4f, 1e-5);
    EXPECT_LT(angleBetween(fit.lobes[0].mu, a), 1e-5);
    EXPECT_LT(angleBetween(fit.lobes[1].mu, b), 1e-5);
    EXPECT_EQ(fit.lobes[0].kappa, kDefaultKappaMax);
}

TEST(Vmf, SingleNormal) {
    glm::vec3 n = direction(70, 300);
    VmfFitResult fit =
        fitVmfMixture(&n, nullptr, 1, {lobe(1.f, {0, 0, 1}, 5.f), lobe(1.f, {1, 0, 0}, 5.f)});
    ASSERT_EQ(fit.lobes.size(), 1u);
    expectFinite(fit.lobes);
    EXPECT_EQ(fit.lobes[0].alpha, 1.f);
    EXPECT_LT(angleBetween(fit.lobes[0].mu, n), 1e-6);
    EXPECT_EQ(fit.lobes[0].kappa, kDefaultKappaMax);
}

TEST(Vmf, CancellingNormals) {
    glm::vec3 n = direction(40, 30);
    std::vector<glm::vec3> normals = {n, -n, n, -n};
    // One lobe: r = 0, so the lobe is uniform.
    VmfFitResult one =
        fitVmfMixture(normals.data(), nullptr, normals.size(), {lobe(1.f, {0, 0, 1}, 10.f)});
    ASSERT_EQ(one.lobes.size(), 1u);
    expectFinite(one.lobes);
    EXPECT_LT(one.lobes[0].kappa, 1e-6f); // |r| is float rounding

    EXPECT_NEAR(one.logLikelihood, 4 * vmfLogNormalizer(0), 1e-6);
    // Two lobes find both directions.
    VmfFitResult two =
        fitVmfMixture(normals.data(), nullptr, normals.size(),
                      {lobe(1.f, direction(10, 30), 10.f), lobe(1.f, direction(170, 30), 10.f)});
    ASSERT_EQ(two.lobes.size(), 2u);
    expectFinite(two.lobes);
    EXPECT_NEAR(two.lobes[0].alpha, 0.5f, 1e-6);
    EXPECT_EQ(two.lobes[0].kappa, kDefaultKappaMax);
}

TEST(Vmf, NoDataAndNoStart) {
    std::vector<VmfLobe> start = {lobe(2.f, {0, 0, 2}, 5.f), lobe(0.f, {1, 0, 0}, 5.f),
                                  lobe(2.f, {1, 0, 0}, 1e9f)};
    VmfFitResult empty = fitVmfMixture(nullptr, nullptr, 0, start);
    ASSERT_EQ(empty.lobes.size(), 2u); // the alpha-0 lobe is ignored
    expectFinite(empty.lobes);
    EXPECT_NEAR(alphaSum(empty.lobes), 1.0, 1e-7);
    EXPECT_EQ(empty.lobes[1].kappa, kDefaultKappaMax);
    EXPECT_EQ(empty.logLikelihood, 0);

    std::vector<glm::vec3> normals = sampleMixture({lobe(1.f, direction(10, 0), 50.f)}, 500, 9);
    std::vector<float> zero(normals.size(), 0.f);
    VmfFitResult weightless = fitVmfMixture(normals.data(), zero.data(), normals.size(), start);
    EXPECT_NEAR(alphaSum(weightless.lobes), 1.0, 1e-7);

    // No starting lobe: one lobe at the mean.
    VmfFitResult unseeded = fitVmfMixture(normals.data(), nullptr, normals.size(), {});
    ASSERT_EQ(unseeded.lobes.size(), 1u);
    EXPECT_LT(degrees(angleBetween(unseeded.lobes[0].mu, direction(10, 0))), 1.0);
}

TEST(Vmf, LightLobesAreDropped) {
    // A third starting lobe far from all data ends with alpha ~ 0 and is dropped.
    std::vector<VmfLobe> truth = {lobe(0.5f, direction(30, 0), 100.f),
                                  lobe(0.5f, direction(30, 180), 100.f)};
    std::vector<glm::vec3> normals = sampleMixture(truth, 2000, 10);
    std::vector<VmfLobe> start = {lobe(0.3f, direction(30, 0), 50.f),
                                  lobe(0.3f, direction(30, 180), 50.f),
                                  lobe(0.4f, direction(150, 90), 50.f)};
    VmfFitResult fit = fitVmfMixture(normals.data(), nullptr, normals.size(), start);
    EXPECT_EQ(fit.lobes.size(), 2u);
    EXPECT_NEAR(alphaSum(fit.lobes), 1.0, 1e-6);
}

// ---- farthest-point initialisation ---------------------------------------------------------

TEST(Vmf, FarthestPointPicksTheSpreadDirections) {
    glm::vec3 A(0, 0, 1), B(1, 0, 0), C = glm::normalize(glm::vec3(0.99f, 0, 0.1f)), D(-1, 0, 0),
                                      E = glm::normalize(glm::vec3(0, 1, 0.2f));
    std::vector<VmfLobe> candidates = {lobe(0.2f, B, 1.f), lobe(0.3f, A, 2.f), lobe(0.2f, C, 3.f),
                                       lobe(0.1f, D, 4.f), lobe(0.2f, E, 5.f)};
    // A is the heaviest; B and D are both 90 deg from it (B has the lower index); then D
    // (90 deg from A, 180 from B) beats E (79 deg from A) and C (6 deg from B).
    std::vector<VmfLobe> chosen = farthestPointLobes(candidates, 3);
    ASSERT_EQ(chosen.size(), 3u);
    EXPECT_EQ(chosen[0].kappa, 2.f);
    EXPECT_EQ(chosen[1].kappa, 1.f);
    EXPECT_EQ(chosen[2].kappa, 4.f);
    // Clusters: A takes E, B takes C.
    EXPECT_NEAR(chosen[0].alpha, 0.5f, 1e-6);
    EXPECT_NEAR(chosen[1].alpha, 0.4f, 1e-6);
    EXPECT_NEAR(chosen[2].alpha, 0.1f, 1e-6);
    // J = 4 adds E (79 deg from A) before C (6 deg from B).
    std::vector<VmfLobe> four = farthestPointLobes(candidates, 4);
    ASSERT_EQ(four.size(), 4u);
    EXPECT_EQ(four[3].kappa, 5.f);
    // Every candidate when J allows.
    EXPECT_EQ(farthestPointLobes(candidates, 8).size(), 5u);
}

TEST(Vmf, FarthestPointSkipsDuplicatesAndEmptyLobes) {
    glm::vec3 n = direction(20, 20);
    std::vector<VmfLobe> same = {lobe(0.25f, n, 10.f), lobe(0.25f, n, 20.f), lobe(0.5f, n, 30.f),
                                 lobe(0.f, {1, 0, 0}, 1.f)};
    std::vector<VmfLobe> chosen = farthestPointLobes(same, 4);
    ASSERT_EQ(chosen.size(), 1u);
    EXPECT_EQ(chosen[0].kappa, 30.f);
    EXPECT_FLOAT_EQ(chosen[0].alpha, 1.f);
    EXPECT_TRUE(farthestPointLobes({lobe(0.f, n, 1.f)}, 2).empty());
}

// ---- the E-step kernel ---------------------------------------------------------------------

// The moments of one E-step, in double, lobe by lobe, from the formulas.
vmf::Moments referenceMoments(const std::vector<glm::vec3>& normals,
                              const std::vector<float>& weights,
                              const std::vector<VmfLobe>& lobes) {
    vmf::Moments m;
    m.clear(int(lobes.size()));
    for (size_t i = 0; i < normals.size(); ++i) {
        double w = weights.empty() ? 1.0 : weights[i];
        double logDensity = vmfMixtureLogDensity(normals[i], lobes);
        m.logLikelihood += w * logDensity;
        for (size_t j = 0; j < lobes.size(); ++j) {
            double z =
                std::exp(std::log(double(lobes[j].alpha)) +
                         vmfLogDensity(normals[i], lobes[j].mu, lobes[j].kappa) - logDensity);
            m.n[j] += w * z;
            m.rx[j] += w * z * (normals[i].x - lobes[j].mu.x);
            m.ry[j] += w * z * (normals[i].y - lobes[j].mu.y);
            m.rz[j] += w * z * (normals[i].z - lobes[j].mu.z);
        }
    }
    return m;
}

TEST(Vmf, EStepKernelsMatchTheFormulas) {
    std::vector<VmfLobe> lobes = {
        lobe(0.4f, direction(20, 0), 40.f), lobe(0.3f, direction(40, 120), 1e4f),
        lobe(0.2f, direction(30, 240), 0.5f), lobe(0.1f, direction(90, 60), 1e5f)};
    std::vector<glm::vec3> normals = sampleMixture(lobes, 5003, 12); // not a multiple of 8
    std::mt19937_64 rng(13);
    std::vector<float> weights(normals.size());
    for (float& w : weights) w = std::uniform_real_distribution<float>(0.f, 2.f)(rng);
    std::vector<float> x, y, z;
    for (glm::vec3 n : normals) x.push_back(n.x), y.push_back(n.y), z.push_back(n.z);

    vmf::LobeTerms terms;
    terms.count = int(lobes.size());
    for (size_t j = 0; j < lobes.size(); ++j) {
        terms.c[j] = std::log(double(lobes[j].alpha)) + vmfLogNormalizer(lobes[j].kappa);
        terms.kx[j] = double(lobes[j].kappa) * lobes[j].mu.x;
        terms.ky[j] = double(lobes[j].kappa) * lobes[j].mu.y;
        terms.kz[j] = double(lobes[j].kappa) * lobes[j].mu.z;
        terms.mx[j] = lobes[j].mu.x;
        terms.my[j] = lobes[j].mu.y;
        terms.mz[j] = lobes[j].mu.z;
    }
    for (bool weighted : {false, true}) {
        vmf::Moments expected =
            referenceMoments(normals, weighted ? weights : std::vector<float>{}, lobes);
        vmf::Samples samples{x.data(), y.data(), z.data(), weighted ? weights.data() : nullptr,
                             normals.size()};
        for (vmf::Kernel kernel : {vmf::Kernel::Portable, vmf::Kernel::Avx2}) {
            vmf::Kernel used = vmf::selectKernel(kernel);
            vmf::Moments got;
            got.clear(terms.count);
            vmf::eStep(samples, 0, normals.size(), terms, got);
            double total = double(normals.size());
            // Float exp and log: ~1e-9 per normal against ~1.4 per normal.
            EXPECT_NEAR(got.logLikelihood, expected.logLikelihood,
                        1e-8 * std::abs(expected.logLikelihood))
                << int(used) << weighted;
            for (int j = 0; j < terms.count; ++j) {
                EXPECT_NEAR(got.n[j], expected.n[j], 1e-6 * total) << j;
                EXPECT_NEAR(got.rx[j], expected.rx[j], 1e-6 * total) << j;
                EXPECT_NEAR(got.ry[j], expected.ry[j], 1e-6 * total) << j;
                EXPECT_NEAR(got.rz[j], expected.rz[j], 1e-6 * total) << j;
            }
        }
    }
    vmf::selectKernel(vmf::Kernel::Auto);
}

TEST(Vmf, FitIsTheSameOnAnyThreadCount) {
    std::vector<VmfLobe> truth = {lobe(0.5f, direction(20, 0), 20.f),
                                  lobe(0.5f, direction(20, 180), 20.f)};
    std::vector<glm::vec3> normals = sampleMixture(truth, 50000, 14);
    std::vector<VmfLobe> start = seedFrom(normals, 3);
    int threads = omp_get_max_threads();
    omp_set_num_threads(1);
    VmfFitResult one = fitVmfMixture(normals.data(), nullptr, normals.size(), start);
    omp_set_num_threads(std::max(2, threads));
    VmfFitResult many = fitVmfMixture(normals.data(), nullptr, normals.size(), start);
    omp_set_num_threads(threads);
    EXPECT_EQ(one.logLikelihoodTrace, many.logLikelihoodTrace);
    ASSERT_EQ(one.lobes.size(), many.lobes.size());
    for (size_t j = 0; j < one.lobes.size(); ++j) {
        EXPECT_EQ(one.lobes[j].alpha, many.lobes[j].alpha);
        EXPECT_EQ(one.lobes[j].mu, many.lobes[j].mu);
        EXPECT_EQ(one.lobes[j].kappa, many.lobes[j].kappa);
    }
}

// ---- the pyramid ---------------------------------------------------------------------------

// Grooves: columns alternate between normals tilted +-30 deg about y, jittered by ~1 deg.
Image grooveMap(int width, int height, uint64_t seed) {
    Image map(width, height, 3);
    std::mt19937_64 rng(seed);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            glm::vec3 n = sampleVmf(direction(30, x % 2 ? 180 : 0), 3000, rng);
            test::setNormal(map, x, y, n.x, n.y, n.z);
        }
    return map;
}

TEST(Vmf, PyramidOfGroovesEndsWithTheirTwoDirections) {
    Pyramid pyramid = buildPyramid(grooveMap(8, 8, 15));
    VmfFitStats stats;
    std::vector<VmfLevel> levels = fitVmfPyramid(pyramid, 4, {}, &stats);
    ASSERT_EQ(levels.size(), 4u);
    // Level 0: one lobe per normal.
    ASSERT_EQ(levels[0].lobes.size(), 64u);
    EXPECT_EQ(
        levels[0].texel(3, 5)[0].mu,
        glm::vec3(pyramid.base->at(3, 5)[0], pyramid.base->at(3, 5)[1], pyramid.base->at(3, 5)[2]));
    EXPECT_EQ(levels[0].texel(3, 5)[0].kappa, kDefaultKappaMax);
    for (size_t k = 0; k < levels.size(); ++k)
        for (int y = 0; y < levels[k].height; ++y)
            for (int x = 0; x < levels[k].width; ++x) {
                std::span<const VmfLobe> lobes = levels[k].texel(x, y);
                ASSERT_GE(lobes.size(), 1u);
                ASSERT_LE(lobes.size(), 4u);
                expectFinite(lobes);
                EXPECT_NEAR(alphaSum(lobes), 1.0, 1e-6);
            }
    // The top texel: lobes of alpha 1/2 in all around each groove direction, as wide as the
    // jitter (kappa 3000; a lobe may also sit on one outlier, ~3 deg out).
    std::span<const VmfLobe> top = levels[3].texel(0, 0);
    ASSERT_GE(top.size(), 2u);
    for (int side = 0; side < 2; ++side) {
        glm::vec3 groove = direction(30, side ? 180 : 0);
        double weight = 0;
        for (const VmfLobe& l : top)
            if (degrees(angleBetween(l.mu, groove)) < 6) weight += l.alpha;
        EXPECT_NEAR(weight, 0.5, 1e-6) << side;
    }
    double heaviest = std::min(angleBetween(top[0].mu, direction(30, 0)),
                               angleBetween(top[0].mu, direction(30, 180)));
    EXPECT_LT(degrees(heaviest), 0.5);
    EXPECT_GT(top[0].kappa, 1500);
    EXPECT_LT(top[0].kappa, 6000);
    EXPECT_EQ(stats.texels, 16u + 4u + 1u);
    EXPECT_GT(stats.meanIterations, 0);
}

TEST(Vmf, PyramidTexelIsTheFitOfItsFootprint) {
    // The pyramid's top texel equals fitVmfMixture over all normals, started from the level
    // below's lobes (alphas weighted by the children's areas) merged by mergedLobes, or with
    // VmfSeeding::FarthestPoint from their farthest points.
    Pyramid pyramid = buildPyramid(grooveMap(8, 8, 16));
    std::vector<glm::vec3> normals;
    for (size_t i = 0; i < pyramid.base->texelCount(); ++i) {
        const float* p = &pyramid.base->pixels[3 * i];
        normals.emplace_back(p[0], p[1], p[2]);
    }
    for (VmfSeeding seeding : {VmfSeeding::Merge, VmfSeeding::FarthestPoint}) {
        VmfFitOptions options;
        options.tolerance = 1e-12; // converged, so that summation order alone tells them apart
        options.maxIterations = 1000;
        options.exactKappa = true; // monotone EM: Banerjee's kappa can end a fit on a rounding dip
        options.seeding = seeding;
        std::vector<VmfLevel> levels = fitVmfPyramid(pyramid, 3, options, nullptr);
        std::vector<VmfLobe> candidates;
        for (int y = 0; y < 2; ++y)
            for (int x = 0; x < 2; ++x)
                for (VmfLobe l : levels[2].texel(x, y)) {
                    l.alpha *= 0.25f;
                    candidates.push_back(l);
                }
        const std::vector<VmfLobe> seeds = seeding == VmfSeeding::Merge
                                               ? mergedLobes(candidates, 3, options)
                                               : farthestPointLobes(candidates, 3);
        VmfFitResult fit = fitVmfMixture(normals.data(), nullptr, normals.size(), seeds, options);
        std::span<const VmfLobe> top = levels[3].texel(0, 0);
        ASSERT_EQ(top.size(), fit.lobes.size());
        for (size_t j = 0; j < top.size(); ++j) {
            // Two lobes of this map trade alpha along a flat ridge of the likelihood, where EM
            // creeps: the two summation orders stop ~2e-5 apart in alpha, not in mu or kappa.
            EXPECT_NEAR(top[j].alpha, fit.lobes[j].alpha, 5e-5);
            EXPECT_LT(angleBetween(top[j].mu, fit.lobes[j].mu), 1e-5);
            EXPECT_NEAR(top[j].kappa, fit.lobes[j].kappa, 1e-4 * fit.lobes[j].kappa);
        }
    }
}

TEST(Vmf, PyramidOfAnOddMapKeepsTheMeanNormal) {
    // Odd sizes (footprints of 2 and 3 texels), every level: the packed lobes of each texel add up
    // to its Na, as packLobe promises (no lobe dropped with minAlpha = 0; capped lobes of
    // single normals are off by 1 - meanLengthFromKappa(1e5) ~ 1e-5).
    Pyramid pyramid = buildPyramid(oddClusteredMap(17));
    VmfFitOptions options;
    options.minAlpha = 0;
    std::vector<VmfLevel> levels = fitVmfPyramid(pyramid, 4, options, nullptr);
    ASSERT_EQ(levels.size(), pyramid.levels.size());
    for (size_t k = 1; k < levels.size(); ++k) {
        const Image& mean = levelMean(pyramid, int(k));
        ASSERT_EQ(levels[k].width, mean.width);
        ASSERT_EQ(levels[k].height, mean.height);
        for (int y = 0; y < mean.height; ++y)
            for (int x = 0; x < mean.width; ++x) {
                glm::dvec3 stored(0);
                for (const VmfLobe& l : levels[k].texel(x, y)) {
                    glm::vec4 p = packLobe(l);
                    stored += glm::dvec3(p.y, p.z, p.w);
                }
                const float* na = mean.at(x, y);
                EXPECT_NEAR(glm::length(stored - glm::dvec3(na[0], na[1], na[2])), 0, 3e-5)
                    << "level " << k << " texel " << x << "," << y;
            }
    }
}

TEST(Vmf, PyramidIsTheSameOnAnyThreadCount) {
    // 64 x 64 with J = 4: the top levels split their passes across threads (4096 normals: two
    // chunks), the lower ones split texels.
    Pyramid pyramid = buildPyramid(grooveMap(64, 64, 18));
    int threads = omp_get_max_threads();
    omp_set_num_threads(1);
    std::vector<VmfLevel> one = fitVmfPyramid(pyramid, 4, {}, nullptr);
    omp_set_num_threads(std::max(2, threads));
    std::vector<VmfLevel> many = fitVmfPyramid(pyramid, 4, {}, nullptr);
    omp_set_num_threads(threads);
    ASSERT_EQ(one.size(), many.size());
    for (size_t k = 0; k < one.size(); ++k) {
        ASSERT_EQ(one[k].offsets, many[k].offsets);
        for (size_t i = 0; i < one[k].lobes.size(); ++i) {
            EXPECT_EQ(one[k].lobes[i].alpha, many[k].lobes[i].alpha);
            EXPECT_EQ(one[k].lobes[i].mu, many[k].lobes[i].mu);
            EXPECT_EQ(one[k].lobes[i].kappa, many[k].lobes[i].kappa);
        }
    }
}

TEST(Vmf, PyramidAgreesAcrossKernels) {
    // The portable E-step and the AVX2 one (where the CPU has it) fit the same lobes: both are
    // within ~1e-7 of the formulas, far inside what EM's stopping rule resolves.
    Pyramid pyramid = buildPyramid(grooveMap(16, 16, 19));
    VmfFitOptions options;
    options.tolerance = 1e-9;
    vmf::selectKernel(vmf::Kernel::Portable);
    std::vector<VmfLevel> portable = fitVmfPyramid(pyramid, 3, options, nullptr);
    vmf::selectKernel(vmf::Kernel::Auto);
    std::vector<VmfLevel> fast = fitVmfPyramid(pyramid, 3, options, nullptr);
    ASSERT_EQ(portable.size(), fast.size());
    for (size_t k = 1; k < fast.size(); ++k) {
        ASSERT_EQ(portable[k].offsets, fast[k].offsets) << k;
        for (size_t i = 0; i < fast[k].lobes.size(); ++i) {
            const VmfLobe &a = portable[k].lobes[i], &b = fast[k].lobes[i];
            EXPECT_NEAR(a.alpha, b.alpha, 1e-4) << k << " " << i;
            EXPECT_LT(angleBetween(a.mu, b.mu), 1e-4) << k << " " << i;
            EXPECT_NEAR(a.kappa, b.kappa, 1e-3 * b.kappa) << k << " " << i;
        }
    }
}

} // namespace
} // namespace ndfmip
