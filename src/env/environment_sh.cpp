// Spherical harmonics of an equirectangular map's radiance (environment.h).
//
// The map is constant over each texel, so its exact coefficients are sums of each texel's
// radiance times the integral of Y_lm over the texel. Over a texel, the basis separates in the
// map's own spherical coordinates (theta from +Y, phi along the row), but our basis has its pole
// on +Z. So the projection runs on the basis turned to the map's pole, Z_lm(d) = Y_lm(P d) with
// P d = (d.z, -d.x, d.y) (theta and phi of d are the polar angle and azimuth of P d), where
//     integral over a texel of Z_lm = Theta_l|m|(row) Phi_m(column),
// Phi in closed form and Theta by Gauss-Legendre; then band by band back to Y_lm:
//     Y_lm(d) = sum_m' D_mm' Z_lm'(d),  D_mm' = integral Y_lm(d) Y_lm'(P d) dd,
// D by a product rule that is exact for the band's degree.
#include "ndfmip/environment.h"

#include <cassert>
#include <cmath>

#include "core/quadrature.h"
#include "ndfmip/sh_brdf.h"
#include "ndfmip/spherical_harmonics.h"

namespace ndfmip {
namespace {

glm::dvec3 toMapPole(glm::dvec3 d) {
    return {d.z, -d.x, d.y};
}

// D of every band, as one (order+1)^2 x (order+1)^2 block-diagonal matrix stored densely per band:
// d[shIndex(l, m)][m' + l].
std::vector<std::vector<double>> bandRotations(int order) {
    const int count = shCount(order);
    std::vector<std::vector<double>> d(static_cast<size_t>(count));
    for (int l = 0; l <= order; ++l)
        for (int m = -l; m <= l; ++m) d[size_t(shIndex(l, m))].assign(size_t(2 * l + 1), 0.);
    // Gauss-Legendre in z with order + 1 nodes times order * 2 + 2 equally spaced phi: exact for
    // polynomials of degree 2 order on the sphere, and each product is of degree 2 l.
    std::vector<double> z, w;
    gaussLegendre(order + 1, z, w);
    const int phis = 2 * order + 2;
    std::vector<double> y(static_cast<size_t>(count)), yp(static_cast<size_t>(count));
    for (size_t i = 0; i < z.size(); ++i) {
        const double s = std::sqrt(std::max(0., 1. - z[i] * z[i]));
        for (int k = 0; k < phis; ++k) {
            const double phi = 2. * M_PI * (k + 0.5) / phis;
            const glm::dvec3 dir(s * std::cos(phi), s * std::sin(phi), z[i]);
            evaluateSh(dir, order, y.data());
            evaluateSh(toMapPole(dir), order, yp.data());
            const double weight = w[i] * 2. * M_PI / phis;
            for (int l = 0; l <= order; ++l)
                for (int m = -l; m <= l; ++m)
                    for (int mp = -l; mp <= l; ++mp)
                        d[size_t(shIndex(l, m))][size_t(mp + l)] +=
                            weight * y[size_t(shIndex(l, m))] * yp[size_t(shIndex(l, mp))];
        }
    }
    return d;
}

} // namespace

EnvironmentSh projectEnvironmentSh(const Environment& env, int order) {
    assert(order >= 0 && order <= kMaxShOrder);
    const Image& map = env.radiance;
    const int width = map.width, height = map.height, ms = 2 * order + 1; // m = -order ... order
    const int count = shCount(order);

    // Phi_m(x): the integral of cos(m phi) (m > 0), sin(|m| phi) (m < 0) or 1 over column x, phi
    // the azimuth seen after the rotation (phi_file - rotation; environment.h). Written with
    // half-angle products, which keep their precision on narrow columns.
    std::vector<double> phiIntegral(size_t(width) * size_t(ms));
    for (int x = 0; x < width; ++x) {
        const double dphi = 2. * M_PI / width;
        const double mid = 2. * M_PI * ((x + 0.5) / width - 0.5) - env.rotation;
        double* p = &phiIntegral[size_t(x) * size_t(ms)];
        p[order] = dphi;
        for (int k = 1; k <= order; ++k) {
            const double half = 2. * std::sin(k * dphi / 2.) / k;
            p[order + k] = std::cos(k * mid) * half;
            p[order - k] = std::sin(k * mid) * half;
        }
    }

    // Theta_l|m|(y): the polar part of Z_lm times sin(theta) over row y, by 12-point
    // Gauss-Legendre in theta (a row of the smallest map spans 45 degrees; the integrand is a
    // trigonometric polynomial of degree order + 1).
    std::vector<double> nodes, weights;
    gaussLegendre(12, nodes, weights);
    std::vector<double> thetaIntegral(size_t(height) * size_t(count), 0.);
    std::vector<double> basis(static_cast<size_t>(count));
    for (int y = 0; y < height; ++y) {
        const double t0 = M_PI * y / height, t1 = M_PI * (y + 1) / height;
        double* t = &thetaIntegral[size_t(y) * size_t(count)];
        for (size_t i = 0; i < nodes.size(); ++i) {
            const double theta = 0.5 * (t0 + t1) + 0.5 * (t1 - t0) * nodes[i];
            // At phi = 0 the basis holds the polar part of m >= 0 (and 0 for m < 0).
            evaluateSh({std::sin(theta), 0., std::cos(theta)}, order, basis.data());
            const double weight = 0.5 * (t1 - t0) * weights[i] * std::sin(theta);
            for (int l = 0; l <= order; ++l)
                for (int m = 0; m <= l; ++m)
                    t[shIndex(l, m)] += weight * basis[size_t(shIndex(l, m))];
        }
    }

    // Per row, F_m = sum over columns of radiance times Phi_m; then the row's share of every
    // coefficient. Rows are summed in order afterwards, so the result does not depend on threads.
    std::vector<glm::dvec3> rowSums(size_t(height) * size_t(count));
#pragma omp parallel for schedule(static)
    for (int y = 0; y < height; ++y) {
        std::vector<glm::dvec3> f(size_t(ms), glm::dvec3(0.));
        const float* row = map.at(0, y);
        for (int x = 0; x < width; ++x) {
            const glm::dvec3 radiance(row[3 * x], row[3 * x + 1], row[3 * x + 2]);
            const double* p = &phiIntegral[size_t(x) * size_t(ms)];
            for (int j = 0; j < ms; ++j) f[size_t(j)] += radiance * p[j];
        }
        const double* t = &thetaIntegral[size_t(y) * size_t(count)];
        glm::dvec3* out = &rowSums[size_t(y) * size_t(count)];
        for (int l = 0; l <= order; ++l)
            for (int m = -l; m <= l; ++m)
                out[shIndex(l, m)] = t[shIndex(l, std::abs(m))] * f[size_t(order + m)];
    }
    std::vector<glm::dvec3> z(size_t(count), glm::dvec3(0.));
    for (int y = 0; y < height; ++y)
        for (int i = 0; i < count; ++i)
            z[size_t(i)] += rowSums[size_t(y) * size_t(count) + size_t(i)];

    EnvironmentSh sh;
    sh.order = order;
    sh.radiance.assign(size_t(count), glm::dvec3(0.));
    const auto d = bandRotations(order);
    for (int l = 0; l <= order; ++l)
        for (int m = -l; m <= l; ++m)
            for (int mp = -l; mp <= l; ++mp)
                sh.radiance[size_t(shIndex(l, m))] +=
                    d[size_t(shIndex(l, m))][size_t(mp + l)] * z[size_t(shIndex(l, mp))];
    sh.lambert = lambertCoefficients(order);
    for (double& a : sh.lambert) a *= M_PI;
    sh.irradiance.resize(static_cast<size_t>(count));
    for (int l = 0; l <= order; ++l)
        for (int m = -l; m <= l; ++m)
            sh.irradiance[size_t(shIndex(l, m))] =
                sh.lambert[size_t(l)] * sh.radiance[size_t(shIndex(l, m))];
    return sh;
}

} // namespace ndfmip
