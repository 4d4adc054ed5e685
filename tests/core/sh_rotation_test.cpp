#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "core/quadrature.h"
#include "ndfmip/sh_rotation.h"
#include "ndfmip/spherical_harmonics.h"

namespace ndfmip {
namespace {

// Rodrigues: rotation by `angle` about the unit `axis`.
glm::dmat3 rotation(glm::dvec3 axis, double angle) {
    axis = glm::normalize(axis);
    const double c = std::cos(angle), s = std::sin(angle);
    glm::dmat3 r(c);
    for (int col = 0; col < 3; ++col)
        for (int row = 0; row < 3; ++row) r[col][row] += (1. - c) * axis[row] * axis[col];
    const glm::dmat3 cross(glm::dvec3(0., axis.z, -axis.y), glm::dvec3(-axis.z, 0., axis.x),
                           glm::dvec3(axis.y, -axis.x, 0.)); // columns: cross(axis, e_i)
    return r + s * cross;
}

glm::dmat3 randomRotation(std::mt19937& rng) {
    std::normal_distribution<double> n;
    std::uniform_real_distribution<double> angle(0., M_PI);
    return rotation(glm::dvec3(n(rng), n(rng), n(rng)), angle(rng));
}

std::vector<double> randomCoefficients(std::mt19937& rng, int order) {
    std::uniform_real_distribution<double> u(-1., 1.);
    std::vector<double> c(size_t(shCount(order)));
    for (double& x : c) x = u(rng);
    return c;
}

double evaluate(const std::vector<double>& c, int order, glm::dvec3 d) {
    std::vector<double> y = evaluateSh(d, order);
    double sum = 0.;
    for (size_t i = 0; i < y.size(); ++i) sum += c[i] * y[i];
    return sum;
}

TEST(ShRotation, IdentityLeavesCoefficients) {
    std::mt19937 rng(1);
    const int order = 8;
    const std::vector<double> c = randomCoefficients(rng, order);
    std::vector<double> out(c.size());
    rotateSh(glm::dmat3(1.), order, c.data(), out.data());
    for (size_t i = 0; i < c.size(); ++i) EXPECT_NEAR(out[i], c[i], 1e-13) << i;
}

// f(R^T d) projected by a product rule exact for degree 2 order (Gauss-Legendre in z, equally
// spaced phi): an independent route to the rotated coefficients.
TEST(ShRotation, EqualsProjectionOfRotatedFunction) {
    std::mt19937 rng(2);
    for (int order : {1, 2, 4, 8}) {
        for (int trial = 0; trial < 5; ++trial) {
            const glm::dmat3 r = randomRotation(rng);
            const std::vector<double> c = randomCoefficients(rng, order);
            std::vector<double> rotated(c.size()), projected(c.size(), 0.);
            rotateSh(r, order, c.data(), rotated.data());
            std::vector<double> z, w;
            gaussLegendre(order + 1, z, w);
            const int phis = 2 * order + 2;
            for (size_t i = 0; i < z.size(); ++i)
                for (int k = 0; k < phis; ++k) {
                    const double s = std::sqrt(1. - z[i] * z[i]), phi = 2. * M_PI * k / phis;
                    const glm::dvec3 d(s * std::cos(phi), s * std::sin(phi), z[i]);
                    const double f = evaluate(c, order, glm::transpose(r) * d);
                    const std::vector<double> y = evaluateSh(d, order);
                    for (size_t j = 0; j < y.size(); ++j)
                        projected[j] += w[i] * 2. * M_PI / phis * f * y[j];
                }
            for (size_t j = 0; j < c.size(); ++j)
                EXPECT_NEAR(rotated[j], projected[j], 1e-12) << order << " " << j;
        }
    }
}

// Pointwise: the rotated expansion at d equals the original at R^T d, up to the highest order
// the basis supports.
TEST(ShRotation, PointwiseAtEveryOrder) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1., 1.);
    for (int order : {0, 3, 8, 12, 20, kMaxShOrder}) {
        const glm::dmat3 r = randomRotation(rng);
        const std::vector<double> c = randomCoefficients(rng, order);
        std::vector<double> rotated(c.size());
        rotateSh(r, order, c.data(), rotated.data());
        double scale = 0.;
        for (double x : c) scale += x * x;
        scale = std::sqrt(scale);
        for (int trial = 0; trial < 20; ++trial) {
            const glm::dvec3 d = glm::normalize(glm::dvec3(u(rng), u(rng), u(rng)));
            EXPECT_NEAR(evaluate(rotated, order, d), evaluate(c, order, glm::transpose(r) * d),
                        1e-10 * scale)
                << "order " << order;
        }
    }
}

TEST(ShRotation, ComposesAndPreservesBandEnergy) {
    std::mt19937 rng(4);
    const int order = 8;
    for (int trial = 0; trial < 10; ++trial) {
        const glm::dmat3 r1 = randomRotation(rng), r2 = randomRotation(rng);
        const std::vector<double> c = randomCoefficients(rng, order);
        std::vector<double> twice(c.size()), once(c.size());
        rotateSh(r2, order, c.data(), twice.data());
        rotateSh(r1, order, twice.data(), twice.data()); // in place
        rotateSh(r1 * r2, order, c.data(), once.data());
        for (size_t i = 0; i < c.size(); ++i) EXPECT_NEAR(twice[i], once[i], 1e-9) << i;
        for (int l = 0; l <= order; ++l) {
            double before = 0., after = 0.;
            for (int i = shIndex(l, -l); i <= shIndex(l, l); ++i)
                before += c[size_t(i)] * c[size_t(i)], after += once[size_t(i)] * once[size_t(i)];
            EXPECT_NEAR(after, before, 1e-9 * before) << "band " << l;
        }
    }
}

// A rotation and its inverse give the coefficients back to rounding, at every order.
TEST(ShRotation, InverseRoundTrip) {
    std::mt19937 rng(6);
    for (int order : {8, kMaxShOrder}) {
        double worst = 0.;
        for (int trial = 0; trial < 20; ++trial) {
            const glm::dmat3 r = randomRotation(rng);
            std::vector<double> c = randomCoefficients(rng, order), back(c.size());
            double norm = 0.;
            for (double x : c) norm += x * x;
            for (double& x : c) x /= std::sqrt(norm);
            rotateSh(r, order, c.data(), back.data());
            rotateSh(glm::transpose(r), order, back.data(), back.data());
            for (size_t i = 0; i < c.size(); ++i)
                worst = std::max(worst, std::fabs(back[i] - c[i]));
        }
        EXPECT_LT(worst, 1e-14) << "order " << order;
    }
}

// Interleaved channels give each channel's single rotation.
TEST(ShRotation, ChannelsRotateIndependently) {
    std::mt19937 rng(5);
    const int order = 8, n = shCount(order);
    const glm::dmat3 r = randomRotation(rng);
    const std::vector<double> a = randomCoefficients(rng, order),
                              b = randomCoefficients(rng, order);
    std::vector<double> both(2 * static_cast<size_t>(n)), ra(static_cast<size_t>(n)),
        rb(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i)
        both[2 * size_t(i)] = a[size_t(i)], both[2 * size_t(i) + 1] = b[size_t(i)];
    rotateSh(r, order, both.data(), both.data(), 2);
    rotateSh(r, order, a.data(), ra.data());
    rotateSh(r, order, b.data(), rb.data());
    for (int i = 0; i < n; ++i) {
        EXPECT_NEAR(both[2 * size_t(i)], ra[size_t(i)], 1e-14);
        EXPECT_NEAR(both[2 * size_t(i) + 1], rb[size_t(i)], 1e-14);
    }
}

} // namespace
} // namespace ndfmip
