// Rotation of SH coefficients (sh_rotation.h) by sampling: band l of f(R^T d) is band l of f read
// at R^T d_k for fixed points d_k, and its coefficients are the least-squares fit of band l's
// 2l + 1 basis functions to those samples. The fit is exact (the samples come from a function of
// that band), so its only error is rounding, scaled by the conditioning of the points: the
// pseudo-inverse of each band's point matrix is computed once per order, and a rotation then
// costs one basis evaluation per point and two small matrix-vector products per band.
//
// The points are a Fibonacci spiral of 4 order + 4 directions, twice the 2 order + 1 that the
// highest band needs at least; spread that evenly, each band's columns are nearly orthogonal and
// the normal equations below stay well conditioned (tests check random rotations at order 8 to
// 1e-12 and the measured error is in docs/SPHERICAL_HARMONICS.md).
#include "ndfmip/sh_rotation.h"

#include <array>
#include <cassert>
#include <cmath>
#include <mutex>
#include <vector>

#include "ndfmip/spherical_harmonics.h"

namespace ndfmip {
namespace {

// pseudoInverse[l]: (A^T A)^-1 A^T with A_km = Y_lm(d_k).
using RotationPoints = ShRotationSampling;

int pointCount(int order) {
    return 4 * order + 4;
}

glm::dvec3 spiral(int i, int count) {
    const double z = 1. - 2. * (i + 0.5) / count, phi = i * 2.399963229728653, // golden angle
        s = std::sqrt(std::max(0., 1. - z * z));
    return {s * std::cos(phi), s * std::sin(phi), z};
}

// Solves the symmetric positive definite system G X = B in place (Cholesky), G n x n, B n x k.
void solveSpd(std::vector<double>& g, int n, std::vector<double>& b, int k) {
    for (int j = 0; j < n; ++j) {
        double d = g[size_t(j * n + j)];
        for (int p = 0; p < j; ++p) d -= g[size_t(j * n + p)] * g[size_t(j * n + p)];
        assert(d > 0.);
        d = std::sqrt(d);
        g[size_t(j * n + j)] = d;
        for (int i = j + 1; i < n; ++i) {
            double s = g[size_t(i * n + j)];
            for (int p = 0; p < j; ++p) s -= g[size_t(i * n + p)] * g[size_t(j * n + p)];
            g[size_t(i * n + j)] = s / d;
        }
    }
    for (int c = 0; c < k; ++c) {
        for (int i = 0; i < n; ++i) { // L y = b
            double s = b[size_t(i * k + c)];
            for (int p = 0; p < i; ++p) s -= g[size_t(i * n + p)] * b[size_t(p * k + c)];
            b[size_t(i * k + c)] = s / g[size_t(i * n + i)];
        }
        for (int i = n - 1; i >= 0; --i) { // L^T x = y
            double s = b[size_t(i * k + c)];
            for (int p = i + 1; p < n; ++p) s -= g[size_t(p * n + i)] * b[size_t(p * k + c)];
            b[size_t(i * k + c)] = s / g[size_t(i * n + i)];
        }
    }
}

RotationPoints makePoints(int order) {
    RotationPoints r;
    const int count = pointCount(order), coefficients = shCount(order);
    std::vector<double> y(size_t(count) * size_t(coefficients));
    for (int k = 0; k < count; ++k) {
        r.points.push_back(spiral(k, count));
        evaluateSh(r.points.back(), order, &y[size_t(k) * size_t(coefficients)]);
    }
    for (int l = 0; l <= order; ++l) {
        const int n = 2 * l + 1, first = shIndex(l, -l);
        auto a = [&](int k, int m) {
            return y[size_t(k) * size_t(coefficients) + size_t(first + m)];
        };
        std::vector<double> gram(size_t(n) * size_t(n), 0.), rhs(size_t(n) * size_t(count));
        for (int i = 0; i < n; ++i) {
            for (int j = 0; j < n; ++j)
                for (int k = 0; k < count; ++k) gram[size_t(i * n + j)] += a(k, i) * a(k, j);
            for (int k = 0; k < count; ++k) rhs[size_t(i * count + k)] = a(k, i);
        }
        solveSpd(gram, n, rhs, count);
        r.pseudoInverse.push_back(std::move(rhs));
    }
    return r;
}

constexpr int kMaxChannels = 16;

} // namespace

const ShRotationSampling& shRotationSampling(int order) {
    assert(order >= 0 && order <= kMaxShOrder);
    static std::array<std::once_flag, kMaxShOrder + 1> once;
    static std::array<RotationPoints, kMaxShOrder + 1> table;
    std::call_once(once[size_t(order)], [order] { table[size_t(order)] = makePoints(order); });
    return table[size_t(order)];
}

void rotateSh(const glm::dmat3& R, int order, const double* in, double* out, int channels) {
    assert(order >= 0 && order <= kMaxShOrder && channels >= 1 && channels <= kMaxChannels);
    const RotationPoints& p = shRotationSampling(order);
    const int count = int(p.points.size()), bands = order + 1;
    const glm::dmat3 inverse = glm::transpose(R);
    // samples[(k * bands + l) * channels + c]: band l of channel c read at R^T d_k.
    std::vector<double> samples(size_t(count) * size_t(bands) * size_t(channels), 0.);
    double y[shCount(kMaxShOrder)];
    for (int k = 0; k < count; ++k) {
        evaluateSh(glm::normalize(inverse * p.points[size_t(k)]), order, y);
        for (int l = 0; l <= order; ++l) {
            double* s = &samples[(size_t(k) * size_t(bands) + size_t(l)) * size_t(channels)];
            for (int i = shIndex(l, -l); i <= shIndex(l, l); ++i)
                for (int c = 0; c < channels; ++c)
                    s[c] += in[size_t(i) * size_t(channels) + size_t(c)] * y[i];
        }
    }
    for (int l = 0; l <= order; ++l) {
        const std::vector<double>& pinv = p.pseudoInverse[size_t(l)];
        for (int m = 0; m < 2 * l + 1; ++m) {
            double sum[kMaxChannels] = {};
            for (int k = 0; k < count; ++k) {
                const double w = pinv[size_t(m * count + k)];
                const double* s =
                    &samples[(size_t(k) * size_t(bands) + size_t(l)) * size_t(channels)];
                for (int c = 0; c < channels; ++c) sum[c] += w * s[c];
            }
            for (int c = 0; c < channels; ++c)
                out[size_t(shIndex(l, -l) + m) * size_t(channels) + size_t(c)] = sum[c];
        }
    }
}

void rotateSh(const glm::dmat3& R, int order, const double* in, double* out) {
    rotateSh(R, order, in, out, 1);
}

} // namespace ndfmip
