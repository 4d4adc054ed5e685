// Real spherical harmonics by recurrence (see spherical_harmonics.h).
//
// With P~_l^m(z) = P_l^m(z) / sin^m(theta) (no Condon-Shortley phase):
//   P~_m^m     = (2m - 1)!!
//   P~_{m+1}^m = (2m + 1) z P~_m^m
//   P~_l^m     = ((2l - 1) z P~_{l-1}^m - (l + m - 1) P~_{l-2}^m) / (l - m)
// and sin^m(theta) e^{i m phi} = (x + i y)^m, so
//   Y_l0 = K_l0 P~_l^0,  Y_lm = sqrt(2) K_lm P~_l^m Re (x+iy)^m,  Y_l,-m = sqrt(2) K_lm P~_l^m Im
//   (x+iy)^m
// with K_lm = sqrt((2l + 1)/(4 pi) (l - m)!/(l + m)!).
#include "ndfmip/spherical_harmonics.h"

#include <cassert>
#include <cmath>

namespace ndfmip {
namespace {

// K_lm, built up as a running product so no factorial overflows.
double normalisation(int l, int m) {
    double ratio = 1.0; // (l - m)! / (l + m)!
    for (int k = l - m + 1; k <= l + m; ++k) ratio /= double(k);
    return std::sqrt((2.0 * l + 1.0) / (4.0 * M_PI) * ratio);
}

// K_lm for every l, m <= kMaxShOrder (sqrt(2) folded in for m > 0), computed once: bakes
// evaluate the basis for every texel.
struct NormalisationTable {
    double k[kMaxShOrder + 1][kMaxShOrder + 1];
    NormalisationTable() {
        for (int l = 0; l <= kMaxShOrder; ++l)
            for (int m = 0; m <= l; ++m) k[l][m] = (m > 0 ? M_SQRT2 : 1.0) * normalisation(l, m);
    }
};

const NormalisationTable& normalisations() {
    static const NormalisationTable table;
    return table;
}

} // namespace

void evaluateSh(glm::dvec3 d, int order, double* out) {
    assert(order >= 0 && order <= kMaxShOrder);
    const NormalisationTable& table = normalisations();
    double re = 1.0, im = 0.0; // (x + i y)^m
    double pmm = 1.0;          // P~_m^m
    for (int m = 0; m <= order; ++m) {
        if (m > 0) {
            double nextRe = re * d.x - im * d.y;
            im = re * d.y + im * d.x;
            re = nextRe;
            pmm *= double(2 * m - 1);
        }
        double previous = 0.0, current = pmm; // P~_{l-1}^m, P~_l^m starting at l = m
        for (int l = m; l <= order; ++l) {
            if (l > m) {
                double next =
                    l == m + 1
                        ? double(2 * m + 1) * d.z * current
                        : (double(2 * l - 1) * d.z * current - double(l + m - 1) * previous) /
                              double(l - m);
                previous = current;
                current = next;
            }
            const double k = table.k[l][m] * current;
            if (m == 0) {
                out[shIndex(l, 0)] = k;
            } else {
                out[shIndex(l, m)] = k * re;
                out[shIndex(l, -m)] = k * im;
            }
        }
    }
}

std::vector<double> evaluateSh(glm::dvec3 d, int order) {
    std::vector<double> out(shCount(order));
    evaluateSh(d, order, out.data());
    return out;
}

} // namespace ndfmip
