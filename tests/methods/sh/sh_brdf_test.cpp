// Legendre coefficients of BRDF lobes: quadrature against closed forms and its own refinement,
// the convolution identity of H eq. 17 through the SH basis, truncation, and the table format.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>

#include <gtest/gtest.h>

#include "ndfmip/brdf.h"
#include "ndfmip/sh_brdf.h"
#include "ndfmip/spherical_harmonics.h"
#include "test_support.h"

namespace ndfmip {
namespace {

constexpr double kPiD = 3.14159265358979323846;

double maxAbs(const std::vector<double>& a) {
    double m = 0;
    for (double x : a) m = std::max(m, std::fabs(x));
    return m;
}

double maxDifference(const std::vector<double>& a, const std::vector<double>& b) {
    EXPECT_EQ(a.size(), b.size());
    double m = 0;
    for (size_t i = 0; i < std::min(a.size(), b.size()); ++i)
        m = std::max(m, std::fabs(a[i] - b[i]));
    return m;
}

// Legendre polynomials P_0 ... P_order at t, by the recurrence (an independent copy).
std::vector<double> legendre(double t, int order) {
    std::vector<double> p(order + 1);
    p[0] = 1;
    if (order >= 1) p[1] = t;
    for (int l = 1; l < order; ++l) p[l + 1] = ((2 * l + 1) * t * p[l] - l * p[l - 1]) / (l + 1);
    return p;
}

// r truncated to order: Sum_{l <= order} A_l (2l + 1)/(4 pi) P_l(t).
double truncatedLobe(const std::vector<double>& a, int order, double t) {
    std::vector<double> p = legendre(t, order);
    double sum = 0;
    for (int l = 0; l <= order; ++l) sum += a[l] * (2 * l + 1) / (4 * kPiD) * p[l];
    return sum;
}

struct NamedLobe {
    std::string name;
    std::function<double(double)> r;
};

std::vector<NamedLobe> sharpAndBroadLobes() {
    std::vector<NamedLobe> lobes;
    for (double s : {1.0, 8.0, 100.0, 1e4})
        lobes.push_back({"blinnphong " + std::to_string(s),
                         [s](double t) { return blinnPhongTransfer(t, s); }});
    for (double a : {0.01, 0.1, 0.5, 1.0}) {
        lobes.push_back(
            {"beckmann " + std::to_string(a), [a](double t) { return beckmannTransfer(t, a); }});
        lobes.push_back({"ggx " + std::to_string(a), [a](double t) { return ggxTransfer(t, a); }});
    }
    return lobes;
}

// ---- numeric projection ----------------------------------------------------------------------

TEST(ShBrdf, ProjectionConvergesWhenTheNodesDouble) {
    TransferProjectionOptions doubled;
    doubled.nodesPerPanel = 64;
    for (const NamedLobe& lobe : sharpAndBroadLobes()) {
        for (int order : {30, 300}) {
            std::vector<double> a = projectTransfer(lobe.r, order);
            std::vector<double> b = projectTransfer(lobe.r, order, doubled);
            EXPECT_LE(maxDifference(a, b), 1e-10 * maxAbs(a)) << lobe.name << " order " << order;
        }
    }
}

TEST(ShBrdf, ProjectionOfBlinnPhongMatchesTheClosedForm) {
    // Fractional exponents put a singular derivative at the clamp t = 0; s = 1e4 is a lobe
    // about 0.01 rad wide.
    for (double s : {0.5, 1.0, 2.5, 8.0, 12.0, 100.0, 1e3, 1e4}) {
        for (int order : {kMaxShOrder, 400}) {
            std::vector<double> projected =
                projectTransfer([s](double t) { return blinnPhongTransfer(t, s); }, order);
            std::vector<double> exact = blinnPhongCoefficients(s, order);
            EXPECT_LE(maxDifference(projected, exact), 1e-10) << "s = " << s << " order " << order;
        }
    }
}

TEST(ShBrdf, BlinnPhongClosedFormMatchesTheGammaFunctionIntegral) {
    // Integral_0^1 t^s P_l(t) dt = sqrt(pi) 2^(-s-1) Gamma(s+1) / (Gamma(1+(s-l)/2)
    // Gamma((s+l+3)/2)), evaluated here through lgamma and the sign of the Gamma functions, away
    // from their poles.
    for (double s : {2.5, 8.0, 33.3}) {
        std::vector<double> a = blinnPhongCoefficients(s, 20);
        for (int l = 0; l <= 20; ++l) {
            double x = 1 + (s - l) / 2, y = (s + l + 3) / 2;
            double logMagnitude = 0.5 * std::log(kPiD) - (s + 1) * std::log(2.0) +
                                  std::lgamma(s + 1) - std::lgamma(x) - std::lgamma(y);
            double sign = std::tgamma(x) < 0 ? -1.0 : 1.0;
            double expected = (s + 1) * sign * std::exp(logMagnitude);
            EXPECT_NEAR(a[l], expected, 1e-12 * std::max(1.0, std::fabs(expected)))
                << s << " " << l;
        }
    }
}

TEST(ShBrdf, LambertClosedFormIsExact) {
    std::vector<double> closed = lambertCoefficients(kMaxShOrder);
    // Ramamoorthi and Hanrahan's pi, 2 pi / 3, pi / 4, 0, -pi / 24, divided by pi.
    EXPECT_NEAR(closed[0], 1.0, 1e-15);
    EXPECT_NEAR(closed[1], 2.0 / 3.0, 1e-15);
    EXPECT_NEAR(closed[2], 1.0 / 4.0, 1e-15);
    EXPECT_EQ(closed[3], 0.0);
    EXPECT_NEAR(closed[4], -1.0 / 24.0, 1e-15);
    EXPECT_NEAR(closed[6], 1.0 / 64.0, 1e-15);
    for (int l = 3; l <= kMaxShOrder; l += 2) EXPECT_EQ(closed[l], 0.0) << l;

    std::vector<double> projected = projectTransfer(lambertTransfer, kMaxShOrder);
    EXPECT_LE(maxDifference(closed, projected), 1e-12);
    // The clamped cosine is Blinn-Phong with s = 1.
    EXPECT_LE(maxDifference(closed, blinnPhongCoefficients(1.0, kMaxShOrder)), 1e-15);
}

TEST(ShBrdf, MicrofacetLobesMatchTheirClosedForms) {
    for (double alpha : {0.01, 0.1, 0.3, 0.5, 1.0}) {
        std::vector<double> beckmann =
            projectTransfer([alpha](double t) { return beckmannTransfer(t, alpha); }, 4);
        std::vector<double> ggx =
            projectTransfer([alpha](double t) { return ggxTransfer(t, alpha); }, 4);
        // Both are normalised so that their projected area is 1: A_1 = 2 pi Integral D t dt = 1.
        EXPECT_NEAR(beckmann[1], 1.0, 1e-10) << alpha;
        EXPECT_NEAR(ggx[1], 1.0, 1e-10) << alpha;
        // GGX: A_0 = 1 + a^2 / (2k) ln((1 + k)/(1 - k)), k = sqrt(1 - a^2) (2 for a = 1).
        double k = std::sqrt(1 - alpha * alpha);
        double ggxA0 = k > 0 ? 1 + alpha * alpha / (2 * k) * std::log((1 + k) / (1 - k)) : 2.0;
        EXPECT_NEAR(ggx[0], ggxA0, 1e-10) << alpha;
        // Beckmann: A_0 = Integral_0^inf e^-x sqrt(1 + a^2 x) dx
        //               = 1 + sqrt(pi) a / 2 e^(1/a^2) erfc(1/a) (e^(1/a^2) overflows below 0.1).
        if (alpha >= 0.1) {
            double beckmannA0 = 1 + std::sqrt(kPiD) * alpha / 2 * std::exp(1 / (alpha * alpha)) *
                                        std::erfc(1 / alpha);
            EXPECT_NEAR(beckmann[0], beckmannA0, 1e-10) << alpha;
        }
    }
}

TEST(ShBrdf, DoubleLobesAgreeWithTheRenderersFloatLobes) {
    for (double t : {0.1, 0.3, 0.5, 0.7, 0.9, 0.95}) {
        for (double s : {1.0, 8.0, 64.0})
            EXPECT_NEAR(blinnPhongTransfer(t, s), blinnPhong(float(t), float(s)),
                        1e-5 * blinnPhongTransfer(t, s) + 1e-30)
                << t << " " << s;
        for (double alpha : {0.3, 0.6, 1.0}) {
            EXPECT_NEAR(beckmannTransfer(t, alpha), beckmannD(float(t), float(alpha)),
                        1e-4 * beckmannTransfer(t, alpha) + 1e-30)
                << t << " " << alpha;
            EXPECT_NEAR(ggxTransfer(t, alpha), ggxD(float(t), float(alpha)),
                        1e-5 * ggxTransfer(t, alpha))
                << t << " " << alpha;
        }
        EXPECT_NEAR(lambertTransfer(t), t / kPiD, 1e-16);
    }
    for (double t : {-1.0, -0.5, 0.0}) {
        EXPECT_EQ(blinnPhongTransfer(t, 8), 0.0);
        EXPECT_EQ(beckmannTransfer(t, 0.3), 0.0);
        EXPECT_EQ(ggxTransfer(t, 0.3), 0.0);
        EXPECT_EQ(lambertTransfer(t), 0.0);
    }
    EXPECT_EQ(beckmannTransfer(1e-200, 0.3), 0.0); // no 0/0 where t^2 underflows
}

// ---- the paper's Gaussian approximation ------------------------------------------------------

TEST(ShBrdf, BlinnPhongApproximationErrorIsAsDocumented) {
    // exp(-l^2 / (2s)) against the exact A_l, for s >= 2: at l <= sqrt(s) the relative error stays
    // under 8.5% (largest where sqrt(s) reaches a new integer: 8.4% at s = 9) and under
    // 0.5 / sqrt(s) from s = 100 on; the exact values decay as exp(-l (l + 1) / (2s)) for large
    // s, hence the ratio exp(l / (2s)) ~ 1 + 1 / (2 sqrt(s)) at l = sqrt(s). At every l the
    // absolute error stays under 0.052 A_0.
    double worst = 0;
    for (double s = 2; s <= 1e4; s += s < 100 ? 0.01 : 0.01 * std::sqrt(s)) {
        const int last = int(std::floor(std::sqrt(s)));
        std::vector<double> exact = blinnPhongCoefficients(s, 3 * last + 3);
        std::vector<double> approx = blinnPhongApproxCoefficients(s, 3 * last + 3);
        ASSERT_EQ(approx[0], 1.0);
        double relative = 0;
        for (int l = 0; l <= last; ++l)
            relative = std::max(relative, std::fabs(approx[l] - exact[l]) / exact[l]);
        ASSERT_LT(relative, 0.085) << "s = " << s;
        if (s >= 100) {
            ASSERT_LT(relative, 0.5 / std::sqrt(s)) << "s = " << s;
        }
        ASSERT_LT(maxDifference(approx, exact), 0.052) << "s = " << s;
        worst = std::max(worst, relative);
    }
    EXPECT_GT(worst, 0.08); // the bound above is not loose
}

// ---- H eq. 17 through the SH basis -----------------------------------------------------------

// For random texels of 20 normals and random w: Sum_l A_l Sum_m Y_lm(w) mean_i Y_lm(n_i) equals
// mean_i r_{l*}(w.n_i) (the addition theorem, to rounding), and differs from mean_i r(w.n_i) by
// at most the truncation error sup_t |r(t) - r_{l*}(t)|, itself at most
// Sum_{l > l*} |A_l| (2l + 1)/(4 pi) since |P_l| <= 1.
struct FunkHeckeCase {
    std::string name;
    std::function<double(double)> r;
    std::vector<double> a; // far past `order`
    int order;
    double spread; // normals are normalize(z + spread * gaussian)
};

TEST(ShBrdf, EffectiveBrdfOfAnAveragedNdfIsTheAveragedLobe) {
    auto table =
        loadTabulatedTransfer(std::string(NDFMIP_SOURCE_DIR) + "/data/brdf/example_f_theta_h.txt");
    ASSERT_TRUE(table.ok()) << table.error().message;
    const TabulatedTransfer f = table.value();
    std::vector<FunkHeckeCase> cases = {
        {"lambert order 2", lambertTransfer, lambertCoefficients(4000), 2, 3.0},
        {"blinnphong 8 order 16", [](double t) { return blinnPhongTransfer(t, 8); },
         blinnPhongCoefficients(8, 4000), 16, 0.5},
        {"beckmann 0.3 order 20", [](double t) { return beckmannTransfer(t, 0.3); },
         projectTransfer([](double t) { return beckmannTransfer(t, 0.3); }, 400), 20, 0.4},
        {"example table order 30", [&f](double t) { return evaluate(f, t); },
         tabulatedCoefficients(f, 400).value(), kMaxShOrder, 0.2},
    };
    std::mt19937 rng(17);
    std::normal_distribution<double> gaussian;
    for (const FunkHeckeCase& c : cases) {
        const int order = c.order;
        double tailBound = 0;
        for (size_t l = order + 1; l < c.a.size(); ++l)
            tailBound += std::fabs(c.a[l]) * (2 * l + 1) / (4 * kPiD);
        double supError = 0; // sup over t of the truncation error, on a fine grid in theta
        for (int k = 0; k <= 200000; ++k) {
            double t = std::cos(kPiD * k / 200000);
            supError = std::max(supError, std::fabs(c.r(t) - truncatedLobe(c.a, order, t)));
        }
        // The sum |A_l| (2l + 1)/(4 pi) bounds the error only once it reaches the tail's end: true
        // for the analytic lobes (A reaches far past their decay), not for the table, whose
        // interpolation kinks decay as l^-2.5.
        if (c.name != "example table order 30") {
            EXPECT_LE(supError, tailBound * 1.0001 + 1e-12) << c.name;
        }
        double worst = 0;
        for (int trial = 0; trial < 50; ++trial) {
            std::vector<double> g(shCount(order), 0.0), y(shCount(order));
            std::vector<glm::dvec3> normals;
            for (int i = 0; i < 20; ++i) {
                glm::dvec3 n = glm::normalize(
                    glm::dvec3(0, 0, 1) +
                    c.spread * glm::dvec3(gaussian(rng), gaussian(rng), gaussian(rng)));
                normals.push_back(n);
                evaluateSh(n, order, y.data());
                for (int k = 0; k < shCount(order); ++k) g[k] += y[k] / 20;
            }
            glm::dvec3 w =
                glm::normalize(glm::dvec3(0, 0, 1) +
                               c.spread * glm::dvec3(gaussian(rng), gaussian(rng), gaussian(rng)));
            evaluateSh(w, order, y.data());
            double viaSh = 0, truncated = 0, full = 0, scale = 0;
            for (int l = 0; l <= order; ++l) {
                scale += std::fabs(c.a[l]) * (2 * l + 1) / (4 * kPiD);
                for (int m = -l; m <= l; ++m) viaSh += c.a[l] * y[shIndex(l, m)] * g[shIndex(l, m)];
            }
            for (const glm::dvec3& n : normals) {
                truncated += truncatedLobe(c.a, order, glm::dot(w, n)) / 20;
                full += c.r(glm::dot(w, n)) / 20;
            }
            EXPECT_NEAR(viaSh, truncated, 1e-12 * scale) << c.name;
            EXPECT_LE(std::fabs(viaSh - full), supError * 1.001 + 1e-12) << c.name;
            worst = std::max(worst, std::fabs(viaSh - full));
        }
        EXPECT_GT(worst, 0.0) << c.name;
        if (c.name == "lambert order 2") {
            // r_2(t) = (3/8 + 2t + 15t^2/8) / (4 pi) is worst at the clamp: r_2(0) = 3 / (32 pi),
            // 9% of r(1).
            EXPECT_NEAR(supError, truncatedLobe(c.a, 2, 0.0), 1e-12);
            EXPECT_NEAR(supError, 3 / (32 * kPiD), 1e-12);
        }
        if (c.name == "blinnphong 8 order 16") {
            EXPECT_LT(tailBound, 1e-3);
        }
    }
}

// ---- truncation ------------------------------------------------------------------------------

TEST(ShBrdf, TotalEnergyIsParseval) {
    // Sum_l (2l + 1)/(4 pi) A_l^2 = Integral_{S^2} r^2 = (s + 1)^2 / (2 pi (2s + 1)) for
    // Blinn-Phong.
    for (double s : {1.0, 8.0, 100.0}) {
        std::vector<double> a = blinnPhongCoefficients(s, kMaxTransferOrder);
        double energy = 0;
        for (size_t l = 0; l < a.size(); ++l) energy += (2 * l + 1) / (4 * kPiD) * a[l] * a[l];
        EXPECT_NEAR(energy, (s + 1) * (s + 1) / (2 * kPiD * (2 * s + 1)), 1e-9) << s;
    }
}

TEST(ShBrdf, TruncationLossOfLambertAtOrderTwoIsOneIn128) {
    // Bands 0..2 hold (1 + 3 (2/3)^2 + 5 (1/4)^2)/(4 pi) = 127/(48 * 4 pi) of the energy 2/(3 pi).
    std::vector<double> a = lambertCoefficients(kMaxTransferOrder);
    EXPECT_NEAR(truncationEnergyLoss(a, 2), 1.0 / 128.0, 1e-9);
    EXPECT_EQ(truncationEnergyLoss(a, 2), truncationEnergyLoss(a, 3)); // odd bands are empty
    double previous = 1;
    for (int order = 0; order < 100; ++order) {
        double loss = truncationEnergyLoss(a, order);
        EXPECT_LE(loss, previous);
        previous = loss;
    }
    EXPECT_EQ(truncationEnergyLoss(a, kMaxTransferOrder), 0.0);
    EXPECT_EQ(truncationEnergyLoss(std::vector<double>(5, 0.0), 1), 0.0);
    EXPECT_EQ(orderNeeded(a, 1.0 / 128.0), 2);
    EXPECT_EQ(orderNeeded(a, 1.0 / 129.0), 4);
    EXPECT_EQ(orderNeeded(std::vector<double>(5, 0.0), 0.1), 0);
}

TEST(ShBrdf, OrderNeededIsTheSmallestOrderWithinTolerance) {
    std::vector<double> a = blinnPhongCoefficients(50, 2000);
    for (double tolerance : {1e-1, 1e-2, 1e-3, 1e-6}) {
        int order = orderNeeded(a, tolerance);
        EXPECT_LE(truncationEnergyLoss(a, order), tolerance);
        ASSERT_GT(order, 0);
        EXPECT_GT(truncationEnergyLoss(a, order - 1), tolerance);
    }
}

TEST(ShBrdf, OrderNeededGrowsLikeTheSquareRootOfTheExponent) {
    // A_l ~ exp(-l^2/(2s)) puts a fraction ~exp(-l*^2/s) of the energy past l*, so
    // l* ~ sqrt(s ln(1/tolerance)): 2.15 sqrt(s) at 1%.
    const double tolerance = 0.01;
    int previous = 0;
    for (double s = 16; s <= 16384; s *= 4) {
        int order = orderNeeded(blinnPhongCoefficients(s, kMaxTransferOrder), tolerance);
        EXPECT_NEAR(order / std::sqrt(s), std::sqrt(std::log(1 / tolerance)), 0.15) << s;
        if (previous > 0) {
            EXPECT_NEAR(double(order) / previous, 2.0, 0.15) << s;
        }
        previous = order;
    }
    // The paper's operating points at this tolerance: l* = 7 for s = 12 (64 coefficients), and
    // s = 50 needing "about 300" coefficients.
    EXPECT_EQ(orderNeeded(blinnPhongCoefficients(12, 1000), tolerance), 7);
    EXPECT_EQ(shCount(orderNeeded(blinnPhongCoefficients(50, 1000), tolerance)), 256);
}

TEST(ShBrdf, BrdfOrderNeededDoesNotDependOnWhereTheProjectionStops) {
    for (double s : {4.0, 64.0, 2000.0}) {
        Result<int> order = brdfOrderNeeded(Brdf::BlinnPhong, float(s), 0.2f, 1e-3);
        ASSERT_TRUE(order.ok()) << order.error().message;
        EXPECT_EQ(order.value(),
                  orderNeeded(blinnPhongCoefficients(float(s), kMaxTransferOrder), 1e-3))
            << s;
    }
    Result<int> lambert = brdfOrderNeeded(Brdf::Lambert, 1, 1, 1.0 / 129.0);
    ASSERT_TRUE(lambert.ok());
    EXPECT_EQ(lambert.value(), 4);
    for (Brdf brdf : {Brdf::Beckmann, Brdf::Ggx}) {
        Result<int> order = brdfOrderNeeded(brdf, 1, 0.2f, 1e-2);
        ASSERT_TRUE(order.ok()) << order.error().message;
        Result<std::vector<double>> a = brdfCoefficients(brdf, 1, 0.2f, 1000);
        ASSERT_TRUE(a.ok());
        EXPECT_EQ(order.value(), orderNeeded(a.value(), 1e-2));
        // Sharper lobes need more orders.
        EXPECT_GT(brdfOrderNeeded(brdf, 1, 0.05f, 1e-2).value(), order.value());
    }
    for (double tolerance : {0.0, 1.0, -1.0, std::nan("")}) {
        Result<int> bad = brdfOrderNeeded(Brdf::BlinnPhong, 8, 0.2f, tolerance);
        ASSERT_FALSE(bad.ok()) << tolerance;
        EXPECT_NE(bad.error().message.find("tolerance"), std::string::npos) << bad.error().message;
    }
}

// ---- the renderer's materials ----------------------------------------------------------------

TEST(ShBrdf, BrdfCoefficientsUseTheRenderersLobes) {
    Result<std::vector<double>> lambert = brdfCoefficients(Brdf::Lambert, 32, 0.2f, 8);
    ASSERT_TRUE(lambert.ok());
    EXPECT_EQ(lambert.value(), lambertCoefficients(8));
    Result<std::vector<double>> phong = brdfCoefficients(Brdf::BlinnPhong, 32, 0.2f, 8);
    ASSERT_TRUE(phong.ok());
    EXPECT_EQ(phong.value(), blinnPhongCoefficients(32, 8));
    // Beckmann and GGX: against a projection of the float lobes of brdf.h (to their precision).
    for (Brdf brdf : {Brdf::Beckmann, Brdf::Ggx}) {
        Result<std::vector<double>> a = brdfCoefficients(brdf, 32, 0.3f, 8);
        ASSERT_TRUE(a.ok());
        std::vector<double> fromFloat = projectTransfer(
            [brdf](double t) { return double(specularLobe(brdf, float(t), 32.f, 0.3f)); }, 8);
        EXPECT_LE(maxDifference(a.value(), fromFloat), 1e-4 * maxAbs(fromFloat)) << brdfName(brdf);
    }
}

struct BadMaterial {
    Brdf brdf;
    float exponent, alpha;
    int order;
    const char* expected;
};

TEST(ShBrdf, BrdfCoefficientsRejectBadParameters) {
    const float nan = std::nanf("");
    for (const BadMaterial& bad : std::vector<BadMaterial>{
             {Brdf::Lambert, 1, 1, -1, "SH order -1 outside [0, 4096]"},
             {Brdf::BlinnPhong, 8, 1, kMaxTransferOrder + 1, "SH order 4097 outside [0, 4096]"},
             {Brdf::BlinnPhong, nan, 1, 8, "Blinn-Phong exponent nan outside (0, 1e6]"},
             {Brdf::BlinnPhong, 0, 1, 8, "Blinn-Phong exponent 0 outside (0, 1e6]"},
             {Brdf::BlinnPhong, 2e6, 1, 8, "Blinn-Phong exponent 2e+06 outside (0, 1e6]"},
             {Brdf::Beckmann, 8, 0, 8, "beckmann roughness 0 outside (0, 1]"},
             {Brdf::Ggx, 8, 1.5f, 8, "ggx roughness 1.5 outside (0, 1]"},
             {Brdf::Ggx, 8, nan, 8, "ggx roughness nan outside (0, 1]"},
         }) {
        Result<std::vector<double>> a =
            brdfCoefficients(bad.brdf, bad.exponent, bad.alpha, bad.order);
        ASSERT_FALSE(a.ok()) << bad.expected;
        EXPECT_EQ(a.error().message, bad.expected);
    }
}

// ---- tabulated lobes -------------------------------------------------------------------------

std::string dataFile(const std::string& name) {
    return std::string(NDFMIP_SOURCE_DIR) + "/data/brdf/" + name;
}

TEST(ShBrdf, ExampleLobeTableMatchesItsFormula) {
    Result<TabulatedTransfer> table = loadTabulatedTransfer(dataFile("example_f_theta_h.txt"));
    ASSERT_TRUE(table.ok()) << table.error().message;
    const TabulatedTransfer& f = table.value();
    EXPECT_EQ(f.angle, "theta_h");
    EXPECT_EQ(f.valueName, "f");
    ASSERT_EQ(f.anglesDegrees.size(), 181u);
    // The header's formula: 0.75 of Blinn-Phong s = 60 plus 0.25 of s = 2.
    auto formula = [](double t) {
        return 0.75 * blinnPhongTransfer(t, 60) + 0.25 * blinnPhongTransfer(t, 2);
    };
    for (double t : {1.0, 0.999, 0.99, 0.95, 0.8, 0.5, 0.1})
        EXPECT_NEAR(evaluate(f, t), formula(t), 5e-3 * formula(1.0)) << t; // linear interpolation
    EXPECT_EQ(evaluate(f, -0.5), 0.0);
    Result<std::vector<double>> a = tabulatedCoefficients(f, kMaxShOrder);
    ASSERT_TRUE(a.ok()) << a.error().message;
    std::vector<double> expected = blinnPhongCoefficients(60, kMaxShOrder),
                        broad = blinnPhongCoefficients(2, kMaxShOrder);
    for (int l = 0; l <= kMaxShOrder; ++l) expected[l] = 0.75 * expected[l] + 0.25 * broad[l];
    EXPECT_NEAR(a.value()[0], 1.0, 1e-3);
    EXPECT_LE(maxDifference(a.value(), expected), 1e-3);
}

TEST(ShBrdf, ExampleFactorTableMatchesItsFormula) {
    Result<TabulatedTransfer> table = loadTabulatedTransfer(dataFile("example_g_theta_d.txt"));
    ASSERT_TRUE(table.ok()) << table.error().message;
    const TabulatedTransfer& g = table.value();
    EXPECT_EQ(g.angle, "theta_d");
    for (double degrees = 0; degrees <= 90; degrees += 2.5) {
        double theta = degrees * kPiD / 180;
        double schlick = 0.04 + 0.96 * std::pow(1 - std::cos(theta), 5);
        EXPECT_NEAR(tabulatedFactor(g, theta), schlick, 2e-3) << degrees;
    }
    EXPECT_NEAR(tabulatedFactor(g, kPiD / 2), 1.0, 1e-9);
    Result<std::vector<double>> a = tabulatedCoefficients(g, 4);
    ASSERT_FALSE(a.ok());
    EXPECT_NE(a.error().message.find("example_g_theta_d.txt: a theta_d table"), std::string::npos)
        << a.error().message;
}

void writeText(const std::string& path, const std::string& text) {
    std::ofstream(path, std::ios::binary) << text;
}

TEST(ShBrdf, TablesInterpolateLinearlyInTheAngle) {
    test::TempDir dir("sh_brdf");
    writeText(dir.file("ramp.txt"), "# a ramp\n\ntheta_h_degrees f\n0 1\n90 0\n");
    Result<TabulatedTransfer> ramp = loadTabulatedTransfer(dir.file("ramp.txt"));
    ASSERT_TRUE(ramp.ok()) << ramp.error().message;
    for (double degrees : {0.0, 10.0, 45.0, 80.0})
        EXPECT_NEAR(evaluate(ramp.value(), std::cos(degrees * kPiD / 180)), 1 - degrees / 90,
                    1e-12);
    // r = 1 - 2 theta / pi on [0, pi/2]: A_0 = 2 pi - 4, A_1 = pi / 2.
    Result<std::vector<double>> a = tabulatedCoefficients(ramp.value(), 2);
    ASSERT_TRUE(a.ok());
    EXPECT_NEAR(a.value()[0], 2 * kPiD - 4, 1e-12);
    EXPECT_NEAR(a.value()[1], kPiD / 2, 1e-12);

    // A step with a jump at its last row: r = 1 for theta <= 30 degrees, 0 beyond, so
    // A_l = 2 pi (P_{l-1}(c) - P_{l+1}(c)) / (2l + 1) with c = cos 30 degrees (A_0 = 2 pi (1 - c)).
    writeText(dir.file("step.txt"), "theta_h_degrees f\r\n0 1\r\n+30 1.0e0\r\n");
    Result<TabulatedTransfer> step = loadTabulatedTransfer(dir.file("step.txt"));
    ASSERT_TRUE(step.ok()) << step.error().message;
    const double c = std::cos(kPiD / 6);
    std::vector<double> p = legendre(c, 41);
    Result<std::vector<double>> b = tabulatedCoefficients(step.value(), 40);
    ASSERT_TRUE(b.ok());
    EXPECT_NEAR(b.value()[0], 2 * kPiD * (1 - c), 1e-12);
    for (int l = 1; l <= 40; ++l)
        EXPECT_NEAR(b.value()[l], 2 * kPiD * (p[l - 1] - p[l + 1]) / (2 * l + 1), 1e-12) << l;
    EXPECT_EQ(evaluate(step.value(), std::cos(kPiD / 6 + 1e-9)), 0.0);
    EXPECT_EQ(evaluate(step.value(), std::nan("")), 0.0);
}

struct BadTable {
    const char* name;
    const char* text;
    const char* expected; // after "<path>"
};

class ShBrdfBadTable : public ::testing::TestWithParam<BadTable> {};

TEST_P(ShBrdfBadTable, IsRejectedWithFileAndLine) {
    test::TempDir dir("sh_brdf_bad");
    const std::string path = dir.file(std::string(GetParam().name) + ".txt");
    writeText(path, GetParam().text);
    Result<TabulatedTransfer> table = loadTabulatedTransfer(path);
    ASSERT_FALSE(table.ok());
    EXPECT_EQ(table.error().message, path + GetParam().expected);
    EXPECT_EQ(table.error().message.find('\n'), std::string::npos);
}

INSTANTIATE_TEST_SUITE_P(
    Tables, ShBrdfBadTable,
    ::testing::Values(
        BadTable{"empty", "# only a comment\n\n", ": no header line (empty file?)"},
        BadTable{"no_header", "0 1\n90 0\n",
                 ":1: expected the header 'theta_h_degrees NAME' or 'theta_d_degrees NAME'"},
        BadTable{"bad_header", "# c\ntheta_h f extra\n0 1\n",
                 ":2: expected the header 'theta_h_degrees NAME' or 'theta_d_degrees NAME'"},
        BadTable{"one_row", "theta_h_degrees f\n0 1\n", ": 1 data row, at least 2 are needed"},
        BadTable{"three_fields", "theta_h_degrees f\n0 1\n10 1 2\n",
                 ":3: expected 'angle value', found 3 fields"},
        BadTable{"word", "theta_h_degrees f\n0 1\n10 bright\n",
                 ":3: value 'bright' is not a number"},
        BadTable{"long_word", "theta_h_degrees f\n0 1\n10 0123456789abcdefghijklmnopqrstuvwxyz\n",
                 ":3: value '0123456789abcdefghijklmnopqrstuv\xE2\x80\xA6' is not a number"},
        BadTable{"trailing", "theta_h_degrees f\n0 1x\n", ":2: value '1x' is not a number"},
        BadTable{"nan_value", "theta_h_degrees f\n0 1\n10 nan\n", ":3: value is NaN"},
        BadTable{"nan_angle", "theta_h_degrees f\n0 1\nNaN 1\n", ":3: angle is NaN"},
        BadTable{"infinite", "theta_h_degrees f\n0 inf\n", ":2: value is infinite"},
        BadTable{"negative", "theta_d_degrees g\n0 1\n10 -0.5\n", ":3: negative value -0.5"},
        BadTable{"above_90", "theta_h_degrees f\n0 1\n95 0\n",
                 ":3: angle 95 outside [0, 90] degrees"},
        BadTable{"below_0", "theta_h_degrees f\n-5 1\n", ":2: angle -5 outside [0, 90] degrees"},
        BadTable{"first_not_0", "theta_h_degrees f\n5 1\n10 0\n",
                 ":2: the first angle must be 0, found 5"},
        BadTable{"duplicate", "theta_h_degrees f\n0 1\n10 1\n10 0\n",
                 ":4: angle 10 does not increase (previous 10)"},
        BadTable{"decreasing", "theta_h_degrees f\n0 1\n20 1\n\n10 0\n",
                 ":5: angle 10 does not increase (previous 20)"}),
    [](const ::testing::TestParamInfo<BadTable>& param) { return std::string(param.param.name); });

TEST(ShBrdf, UnreadableTablesAreErrors) {
    test::TempDir dir("sh_brdf_unreadable");
    const std::string missing = dir.file("missing.txt");
    Result<TabulatedTransfer> a = loadTabulatedTransfer(missing);
    ASSERT_FALSE(a.ok());
    EXPECT_EQ(a.error().message, missing + ": cannot read: No such file or directory");
    Result<TabulatedTransfer> b = loadTabulatedTransfer(dir.path.string());
    ASSERT_FALSE(b.ok());
    EXPECT_EQ(b.error().message, dir.path.string() + ": cannot read: is a directory");
    // tabulatedCoefficients checks its order like brdfCoefficients.
    writeText(dir.file("ok.txt"), "theta_h_degrees f\n0 1\n90 0\n");
    Result<TabulatedTransfer> ok = loadTabulatedTransfer(dir.file("ok.txt"));
    ASSERT_TRUE(ok.ok());
    EXPECT_FALSE(tabulatedCoefficients(ok.value(), -1).ok());
    EXPECT_FALSE(tabulatedCoefficients(ok.value(), kMaxTransferOrder + 1).ok());
}

} // namespace
} // namespace ndfmip
