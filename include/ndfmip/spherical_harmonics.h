// Real spherical harmonics Y_lm, orthonormal over the sphere, in the convention of
// Ramamoorthi and Hanrahan (2001) used by Han et al. (2007): no Condon-Shortley phase, so
// Y_1,-1 = c y, Y_1,0 = c z, Y_1,1 = c x with c = sqrt(3 / (4 pi)).
// Coefficients of band l are stored at l^2 ... l^2 + 2l, m = -l ... l (shIndex).
#pragma once

#include <vector>

#include <glm/glm.hpp>

namespace ndfmip {

constexpr int kMaxShOrder = 30; // l* up to 30: (l*+1)^2 = 961 coefficients

inline constexpr int shIndex(int l, int m) {
    return l * (l + 1) + m;
}
inline constexpr int shCount(int order) {
    return (order + 1) * (order + 1);
}

// Y_lm(d) for l = 0 ... order, every m, written to out[shIndex(l, m)] (shCount(order) values).
// d must be unit length. Evaluated by the stable three-term recurrence of the associated
// Legendre functions in z, times the real and imaginary parts of (x + i y)^m, so there is no
// division by sin(theta) and no special case at the poles.
void evaluateSh(glm::dvec3 d, int order, double* out);
std::vector<double> evaluateSh(glm::dvec3 d, int order);

} // namespace ndfmip
