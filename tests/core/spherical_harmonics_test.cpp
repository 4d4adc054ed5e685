#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "ndfmip/spherical_harmonics.h"

namespace ndfmip {
namespace {

// Gauss-Legendre nodes and weights on [-1, 1] (Newton on P_n), exact for degree 2n - 1.
void gaussLegendre(int n, std::vector<double>& x, std::vector<double>& w) {
    x.resize(n);
    w.resize(n);
    for (int i = 0; i < n; ++i) {
        double z = std::cos(M_PI * (i + 0.75) / (n + 0.5)), dp = 0;
        for (int iteration = 0; iteration < 100; ++iteration) {
            double p0 = 1, p1 = z;
            for (int k = 2; k <= n; ++k) {
                double p2 = ((2 * k - 1) * z * p1 - (k - 1) * p0) / k;
                p0 = p1;
                p1 = p2;
            }
            dp = n * (z * p1 - p0) / (z * z - 1);
            double step = p1 / dp;
            z -= step;
            if (std::fabs(step) < 1e-15) break;
        }
        x[i] = z;
        w[i] = 2 / ((1 - z * z) * dp * dp);
    }
}

// Integral over the sphere of products of Y_lm: exact quadrature for band-limited integrands.
TEST(SphericalHarmonics, OrthonormalByExactQuadrature) {
    const int order = 16, n = shCount(order);
    std::vector<double> zs, ws;
    gaussLegendre(order + 2, zs, ws);
    const int phis = 2 * order + 3;
    std::vector<double> gram(size_t(n) * n, 0.0);
    for (size_t i = 0; i < zs.size(); ++i) {
        double r = std::sqrt(1 - zs[i] * zs[i]);
        for (int j = 0; j < phis; ++j) {
            double phi = 2 * M_PI * j / phis;
            std::vector<double> y =
                evaluateSh({r * std::cos(phi), r * std::sin(phi), zs[i]}, order);
            double weight = ws[i] * 2 * M_PI / phis;
            for (int a = 0; a < n; ++a)
                for (int b = a; b < n; ++b) gram[size_t(a) * n + b] += weight * y[a] * y[b];
        }
    }
    for (int a = 0; a < n; ++a)
        for (int b = a; b < n; ++b)
            ASSERT_NEAR(gram[size_t(a) * n + b], a == b ? 1.0 : 0.0, 1e-10) << a << "," << b;
}

TEST(SphericalHarmonics, ClosedFormsUpToBandTwo) {
    std::mt19937 rng(5);
    std::normal_distribution<double> g;
    for (int trial = 0; trial < 20; ++trial) {
        glm::dvec3 d = glm::normalize(glm::dvec3(g(rng), g(rng), g(rng)));
        std::vector<double> y = evaluateSh(d, 2);
        const double x = d.x, yy = d.y, z = d.z;
        const double expected[9] = {0.5 * std::sqrt(1 / M_PI),
                                    std::sqrt(3 / (4 * M_PI)) * yy,
                                    std::sqrt(3 / (4 * M_PI)) * z,
                                    std::sqrt(3 / (4 * M_PI)) * x,
                                    0.5 * std::sqrt(15 / M_PI) * x * yy,
                                    0.5 * std::sqrt(15 / M_PI) * yy * z,
                                    0.25 * std::sqrt(5 / M_PI) * (3 * z * z - 1),
                                    0.5 * std::sqrt(15 / M_PI) * x * z,
                                    0.25 * std::sqrt(15 / M_PI) * (x * x - yy * yy)};
        for (int i = 0; i < 9; ++i) EXPECT_NEAR(y[i], expected[i], 1e-12) << i;
    }
}

TEST(SphericalHarmonics, AdditionTheoremHoldsEverywhere) {
    // Sum over m of Y_lm(d)^2 = (2l + 1)/(4 pi) for every direction (addition theorem), poles
    // included.
    const int order = 20;
    for (glm::dvec3 d : {glm::dvec3(0, 0, 1), glm::dvec3(0, 0, -1), glm::dvec3(1, 0, 0),
                         glm::normalize(glm::dvec3(0.3, -0.7, 0.2))}) {
        std::vector<double> y = evaluateSh(d, order);
        for (int l = 0; l <= order; ++l) {
            double sum = 0;
            for (int m = -l; m <= l; ++m) sum += y[shIndex(l, m)] * y[shIndex(l, m)];
            EXPECT_NEAR(sum, (2 * l + 1) / (4 * M_PI), 1e-10 * (2 * l + 1)) << "l = " << l;
        }
    }
}

TEST(SphericalHarmonics, ProjectionOfOneIsTwoRootPi) {
    // Integral of f = 1 against Y_00 is 2 sqrt(pi); every other coefficient vanishes (checked
    // by the orthonormality test). Y_00 is the constant 1 / (2 sqrt(pi)).
    std::vector<double> y = evaluateSh({0.6, 0.0, 0.8}, 0);
    EXPECT_NEAR(4 * M_PI * y[0], 2 * std::sqrt(M_PI), 1e-12);
}

} // namespace
} // namespace ndfmip
