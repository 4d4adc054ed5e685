// The BRDF side of spherical-harmonic NDF filtering (Han et al. 2007, Sec. 4.3 and 5): the
// Legendre coefficients A_l of radially symmetric lobes, how many of them a lobe needs, and
// tabulated (measured, factored f(theta_h) g(theta_d)) lobes. Equation numbers refer to that paper.
//
// Convention. A transfer function r(t) of t = w.n (w is the light direction for the diffuse
// term, the half vector for a specular lobe) is described by
//     A_l = sqrt(4 pi / (2l + 1)) r_l = 2 pi Integral_{-1}^{1} r(t) P_l(t) dt          (H eq. 16)
// where r_l are its coefficients on Y_l0 about the pole (H eq. 14) and P_l the Legendre polynomial.
// By the addition theorem, P_l(w.n) = 4 pi / (2l + 1) Sum_m Y_lm(w) Y_lm(n), so
//     r(w.n) = Sum_l A_l Sum_m Y_lm(w) Y_lm(n)
// with the Y_lm of spherical_harmonics.h, and a texel whose NDF has coefficients g_lm (one normal
// n: g_lm = Y_lm(n); a mip texel: the average over the normals it covers) has the effective BRDF
//     r_eff(w) = Sum_{l <= l*} A_l Sum_m g_lm Y_lm(w)                                   (H eq. 17).
// A_0 is the integral of the lobe over the sphere; A_1 is its integral against cos.
// docs/SPHERICAL_HARMONICS.md has the derivations, the measured accuracies and the table format.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "ndfmip/result.h"
#include "ndfmip/scene.h"
#include "ndfmip/spherical_harmonics.h"

namespace ndfmip {

// Highest Legendre degree a projection goes to. Far above kMaxShOrder because measuring how much
// of a sharp lobe a bake of order l* leaves out needs its coefficients well past l*.
constexpr int kMaxTransferOrder = 4096;

// ---- numeric projection ----------------------------------------------------------------------

struct TransferProjectionOptions {
    int nodesPerPanel = 32; // Gauss-Legendre nodes on each panel, at least 4
    // Extra panel ends in theta = acos(t), in radians, where r has a kink or a jump (a table's
    // rows). The rule already puts one at pi/2, the kink of every lobe clamped to t >= 0.
    std::vector<double> breaksRadians;
};

// A_0 ... A_order of r by Gauss-Legendre quadrature in theta (t = cos theta, dt = sin theta
// dtheta) over [0, pi]: panels no wider than min(pi/16, 4/(order + 1)) so P_l is resolved;
// below the first of them panels halving 40 times towards theta = 0, so a lobe of any width
// about t = 1 is resolved without knowing its width, and likewise from below towards pi/2 (the
// clamp of max(t, 0)^s, singular there for fractional s). P_l by the three-term recurrence.
// With the defaults the result is converged to ~1e-12 of max |A_l| for Blinn-Phong s <= 1e4 and
// Beckmann/GGX alpha >= 0.01 (tests double the nodes and compare with closed forms).
// Preconditions: 0 <= order <= kMaxTransferOrder; r finite on [-1, 1]; r smooth between the
// panel ends except near t = 1.
std::vector<double> projectTransfer(const std::function<double(double)>& r, int order,
                                    const TransferProjectionOptions& options = {});

// ---- lobes of the renderer, in double ------------------------------------------------------
// The formulas of brdf.h / shading.h evaluated in double precision: float rounding noise at the
// quadrature nodes (and float cancellation in cos^2 - 1 for Beckmann) would cap the projection
// of sharp lobes at ~1e-4. Zero for t <= 0.

double lambertTransfer(double t);                // max(t, 0) / pi
double blinnPhongTransfer(double t, double s);   // (s + 1)/(2 pi) max(t, 0)^s
double beckmannTransfer(double t, double alpha); // exp(-tan^2/a^2) / (pi a^2 t^4)
double ggxTransfer(double t, double alpha);      // a^2 / (pi (t^2 (a^2 - 1) + 1)^2)

// ---- closed forms ----------------------------------------------------------------------------
// Preconditions: 0 <= order <= kMaxTransferOrder; s finite and >= 0.

// The clamped cosine max(t, 0)/pi (Ramamoorthi and Hanrahan 2001, divided by pi): A_0 = 1,
// A_1 = 2/3, A_l = 0 for odd l > 1, and for even l >= 2
//     A_l = 2 (-1)^(l/2 - 1) / ((l + 2)(l - 1)) * l! / (2^l ((l/2)!)^2).
std::vector<double> lambertCoefficients(int order);

// The normalised Blinn-Phong lobe (s + 1)/(2 pi) max(t, 0)^s, exactly: A_0 = 1,
// A_1 = (s + 1)/(s + 2), A_{l+2} = A_l (s - l)/(s + l + 3) (from the integral of t^s P_l over
// [0, 1] as a ratio of Gamma functions). s = 1 is lambertCoefficients.
std::vector<double> blinnPhongCoefficients(double s, int order);

// The paper's approximation A_l ~= A_0 exp(-l^2 / (2 s)) with A_0 = 1, the integral of the
// normalised lobe. Measured against the exact values, docs/SPHERICAL_HARMONICS.md.
// Precondition: s > 0.
std::vector<double> blinnPhongApproxCoefficients(double s, int order);

// ---- the renderer's materials ----------------------------------------------------------------

// A_0 ... A_order of a material's lobe: Lambert is the clamped cosine over w = the light
// direction (lambertCoefficients); Blinn-Phong (exponent s) is exact (blinnPhongCoefficients);
// Beckmann and GGX (alpha) are projected with projectTransfer, over w = the half vector.
// Errors: order outside [0, kMaxTransferOrder], exponent outside (0, 1e6] or alpha outside
// (0, 1] (the ranges scene files accept), NaN.
Result<std::vector<double>> brdfCoefficients(Brdf brdf, float exponent, float alpha, int order);

// ---- truncation ------------------------------------------------------------------------------
// The zonal function r(w.n) has energy Integral_{S^2} r(w.n)^2 dw = Sum_l (2l + 1)/(4 pi) A_l^2
// (Parseval), band l holding (2l + 1)/(4 pi) A_l^2. Keeping l <= l* is the best least-squares
// approximation of that order, and what it leaves out is the energy of the bands above l*.

// Sum_{order < l < A.size()} (2l+1) A_l^2 / Sum_{l < A.size()} (2l+1) A_l^2: the fraction of the
// lobe's energy that a bake of order `order` drops, for one normal (a filtered NDF is smoother and
// loses less). Its square root is the RMS error over the sphere of the truncated lobe relative to
// the lobe's RMS. Measured against A's own length, so A must reach far enough for its own tail to
// be negligible (brdfOrderNeeded takes care of that). 0 when order >= A.size() - 1 or A is zero.
// Precondition: order >= 0.
double truncationEnergyLoss(const std::vector<double>& A, int order);

// The smallest l* with truncationEnergyLoss(A, l*) <= tolerance. Preconditions: A non-empty,
// tolerance >= 0.
int orderNeeded(const std::vector<double>& A, double tolerance);

// orderNeeded for a material's lobe, with coefficients projected far enough (doubling the order
// from 64 until the bands in the upper half of the projection hold under 1% of the tolerance, or
// kMaxTransferOrder is reached) that the answer does not depend on where they stop.
// Errors: those of brdfCoefficients, tolerance not in (0, 1).
Result<int> brdfOrderNeeded(Brdf brdf, float exponent, float alpha, double tolerance);

// ---- tabulated lobes -------------------------------------------------------------------------
// A factored BRDF f(theta_h) g(theta_d) (H eq. 6, Lawrence et al. 2006): f is a lobe about n
// (t = cos theta_h), filtered like any other; g depends on the light and view only and multiplies
// the filtered result at shading time, unfiltered.
//
// File format (plain text, docs/SPHERICAL_HARMONICS.md): '#' starts a comment line; blank lines
// are skipped; the first other line is the header `theta_h_degrees NAME` (an f table) or
// `theta_d_degrees NAME` (a g table); then rows `angle value`, angles in degrees strictly
// increasing from 0 up to at most 90, values finite and >= 0. Linear interpolation in the angle
// between rows; 0 beyond the last row.

struct TabulatedTransfer {
    std::string path;                  // as loaded, for messages
    std::string angle;                 // "theta_h" or "theta_d"
    std::string valueName;             // second word of the header
    std::vector<double> anglesDegrees; // strictly increasing, first 0, last <= 90
    std::vector<double> values;        // same count, finite, >= 0
};

// Errors, one line naming the file (and the line, for a bad line): unreadable file, missing or
// malformed header, a row without exactly two numbers, non-numeric, NaN or infinite entries,
// negative values, angles outside [0, 90], a first angle other than 0, angles that do not
// increase, fewer than 2 rows.
// Only a regular file is read (limits.h bounds its size).
Result<TabulatedTransfer> loadTabulatedTransfer(const std::string& path);

// The same from the file's text; `path` names it in messages.
Result<TabulatedTransfer> parseTabulatedTransfer(const std::string& text, const std::string& path);

// The table at acos(t) (t clamped to [-1, 1]): f(theta_h) for t = n.h.
double evaluate(const TabulatedTransfer& table, double t);

// g(theta_d) with theta_d in radians, the factor of H eq. 6 applied after the convolution.
double tabulatedFactor(const TabulatedTransfer& g, double thetaD);

// A_0 ... A_order of an f table as r(t) = evaluate(f, t), projected with its rows as panel ends
// (so the kinks of the interpolation cost no accuracy). Errors: a theta_d table (a g factor is
// not filtered), order outside [0, kMaxTransferOrder].
Result<std::vector<double>> tabulatedCoefficients(const TabulatedTransfer& f, int order);

} // namespace ndfmip
