// Rotation of functions given by their coefficients on the real SH basis of spherical_harmonics.h
// (orthonormal, no Condon-Shortley phase). Rotation never mixes bands: band l of the rotated
// function is a (2l + 1) x (2l + 1) matrix times band l of the original.
//
// Convention: for a rotation R, rotateSh gives the coefficients of f_R(d) = f(R^T d), the function
// f carried along by R (what f showed along d is seen along R d). So to re-express a function of
// environment directions in a tangent frame whose columns, in the environment frame, are T:
//     f_tangent(d_t) = f(T d_t)   <=>   rotateSh(transpose(T), ...).
// docs/SPHERICAL_HARMONICS.md has the method and its measured accuracy.
#pragma once

#include <vector>

#include <glm/glm.hpp>

namespace ndfmip {

// What rotateSh samples with at one order: band l of f(R^T d) is read at R^T d_k for the points
// d_k and fitted back by pseudoInverse[l], (2l + 1) x points.size() row-major (row m + l), so
// band l's coefficient m is Sum_k pseudoInverse[l][(m + l) points + k] f_l(R^T d_k). Exposed for
// renderers that rotate on their own (the GPU renderer's per-hit rotation, environment.glsl).
struct ShRotationSampling {
    std::vector<glm::dvec3> points;
    std::vector<std::vector<double>> pseudoInverse;
};

// Built once per order and kept. Precondition: 0 <= order <= kMaxShOrder.
const ShRotationSampling& shRotationSampling(int order);

// out = the coefficients of f(R^T d) for f = Sum in[shIndex(l, m)] Y_lm, l <= order.
// Preconditions: 0 <= order <= kMaxShOrder; R orthonormal with det +1 (a reflection would also be
// handled, a non-orthonormal matrix is not a rotation of the sphere); in and out hold
// shCount(order) values and may be the same array.
void rotateSh(const glm::dmat3& R, int order, const double* in, double* out);

// The same for `channels` functions stored interleaved, in[shIndex(l, m) * channels + c] (RGB
// coefficients as glm::dvec3 arrays: channels = 3): the basis is evaluated once for all of them.
// Precondition: 1 <= channels <= 16.
void rotateSh(const glm::dmat3& R, int order, const double* in, double* out, int channels);

} // namespace ndfmip
