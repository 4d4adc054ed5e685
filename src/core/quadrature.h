// Gauss-Legendre quadrature, shared by the SH projections (sh_brdf.cpp, environment_sh.cpp).
#pragma once

#include <cmath>
#include <vector>

namespace ndfmip {

// Nodes and weights of the n-point rule on [-1, 1] (exact for polynomials of degree 2n - 1),
// Newton on P_n from Chebyshev-like starts.
inline void gaussLegendre(int n, std::vector<double>& x, std::vector<double>& w) {
    x.resize(n);
    w.resize(n);
    for (int i = 0; i < n; ++i) {
        double z = std::cos(M_PI * (i + 0.75) / (n + 0.5)), derivative = 1.0;
        for (int iteration = 0; iteration < 100; ++iteration) {
            double p0 = 1.0, p1 = z;
            for (int k = 2; k <= n; ++k) {
                double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
                p0 = p1;
                p1 = p2;
            }
            derivative = n * (z * p1 - p0) / (z * z - 1.0);
            double step = p1 / derivative;
            z -= step;
            if (std::fabs(step) < 1e-16) break;
        }
        x[i] = z;
        w[i] = 2.0 / ((1.0 - z * z) * derivative * derivative);
    }
}

} // namespace ndfmip
