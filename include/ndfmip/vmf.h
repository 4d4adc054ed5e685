// Mixtures of von Mises-Fisher lobes as NDFs: Han, Sun, Ramamoorthi, Grinspun, "Frequency
// Domain Normal Map Filtering" (SIGGRAPH 2007), Sec. 7 and the appendix. Each texel's NDF is
//     g(n) = Sum_j alpha_j gamma(n; mu_j, kappa_j),  gamma = kappa / (4 pi sinh kappa) exp(kappa
//     mu.n)
// (H eqs. 21-22), fitted by spherical EM (Algorithm 1) to every level-0 normal the texel covers,
// initialised from the finer level's lobes by farthest-point clustering (Sec. 7.1).
// Equation numbers refer to that paper.
//
// kappa and the mean resultant length r (the length of E[n] under one lobe) are tied by one map
// throughout, Banerjee et al.'s closed form kappa = (3r - r^3)/(1 - r^2) (Algorithm 1, line 12),
// and its exact inverse: the fit computes kappa from r with it, packLobe stores the r it came
// from, and a shader recovers kappa from an interpolated r with the same formula. The true mean
// length of a vMF is Langevin's A(kappa) = coth kappa - 1/kappa (H eq. 23); Banerjee's kappa is
// within 0.5 of A^-1(r) (exact as r -> 0, +0.5 as r -> 1). VmfFitOptions::exactKappa fits with
// A^-1 instead.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "ndfmip/pyramid.h"

namespace ndfmip {

// Lobes one fit handles at most (the paper uses 4 to 6).
constexpr int kMaxVmfLobes = 16;

// Lobes a vmf bake stores per texel at most (its --lobes range): the shaders hold a texel's
// lobes in arrays of this size.
constexpr int kMaxVmfBakeLobes = 8;

// Default cap on kappa. A lobe's mean length is stored in float (packLobe): at kappa = 1e5 the
// distance 1 - r = 1e-5 keeps about 7 bits, enough for kappa to 1%. Sharper lobes (angular
// width 1/sqrt(kappa) < 3 mrad) shade like this one under any BRDF narrower than s ~ 1e5.
constexpr float kDefaultKappaMax = 1e5f;

struct VmfLobe {
    float alpha = 0.f;     // amplitude; a texel's alphas sum to 1
    glm::vec3 mu{0, 0, 1}; // central direction, unit length
    float kappa = 0.f;     // concentration (inverse width), 0 = uniform over the sphere
    glm::vec3 color{0.f};  // per-lobe feature (H eq. 31); the fit leaves it 0
};

// ---- one lobe ------------------------------------------------------------------------------

// log(kappa / (4 pi sinh kappa)), the log of the vMF normaliser, for any kappa >= 0: -log(4 pi)
// at 0, log(kappa) - kappa - log(2 pi) - log1p(-exp(-2 kappa)) in general (no sinh, so no
// overflow).
double vmfLogNormalizer(double kappa);

// log gamma(n; mu, kappa) (unit mass over the sphere); n and mu unit length.
double vmfLogDensity(glm::vec3 n, glm::vec3 mu, double kappa);

// log Sum_j alpha_j gamma(n; mu_j, kappa_j) over the first kMaxVmfLobes lobes with alpha > 0, by
// log-sum-exp: finite wherever one alpha > 0 (-infinity where none is).
double vmfMixtureLogDensity(glm::vec3 n, std::span<const VmfLobe> lobes);

// Langevin's A(kappa) = coth kappa - 1/kappa (H eq. 23): the mean resultant length of a vMF,
// by series below kappa = 0.1 and 1 - 1/kappa above 20 (coth = 1 to double precision).
double langevin(double kappa);

// A^-1(r) for 0 <= r < 1 (Newton from Banerjee's estimate; 1/(1 - r) where that is exact).
double inverseLangevin(double r);

// Banerjee et al.'s kappa = (3r - r^3)/(1 - r^2) (Algorithm 1, line 12), clamped to
// [0, kappaMax]: r <= 0 gives 0, r >= 1 gives kappaMax.
double kappaFromMeanLength(double r, double kappaMax = kDefaultKappaMax);

// The exact inverse of kappaFromMeanLength (unclamped): the r in [0, 1) whose Banerjee kappa is
// `kappa`. kappa/3 for small kappa, 1 - 1/(kappa - 1/2) for large.
double meanLengthFromKappa(double kappa);

// kappa of the lobe that level-0 texels of a b-bit unorm normal map stand for. Storing a
// component c = (n + 1)/2 in b bits rounds n to steps of delta = 2/(2^b - 1): an error uniform
// in +-delta/2, variance delta^2/12, in each component. Two of them lie across n, so the stored
// direction deviates by an angle with variance delta^2/12 per tangent axis. A sharp vMF is a 2D
// Gaussian with variance 1/kappa per tangent axis (kappa mu.n ~ kappa - kappa theta^2 / 2), so
//     kappa = 12 / delta^2 = 3 (2^b - 1)^2:   8 bits 1.95e5, 10 bits 3.1e6, 16 bits 1.3e10.
// Every b of practice exceeds kDefaultKappaMax; the fit caps it there.
float quantisationKappa(int bits);

// ---- storage for linear filtering (H eq. 33) ------------------------------------------------
// A lobe is stored as (alpha, alpha r mu), r = meanLengthFromKappa(kappa): both are means over
// the texel's normals (alpha r mu = Sum_i z_ij n_i / N), so trilinear filtering of the four
// channels averages them as the pyramid does, and unpacking the filtered value gives the lobe of
// the merged footprint: alpha~ = T(alpha), r~ = T(alpha r mu) / T(alpha).

glm::vec4 packLobe(const VmfLobe& lobe);

// alpha = p.x; mu = p.yzw / |p.yzw| ((0,0,1) where zero), kappa = kappaFromMeanLength(|p.yzw| /
// alpha) (Algorithm 1, lines 12-13). alpha <= 0 gives an empty lobe (alpha 0, kappa 0).
// unpackLobe(packLobe(l)) returns l up to float rounding of r (relative kappa error about
// 6e-8 kappa for large kappa).
VmfLobe unpackLobe(glm::vec4 packed, float kappaMax = kDefaultKappaMax);

// ---- fitting -------------------------------------------------------------------------------

// How fitVmfPyramid starts each texel's EM from its children's lobes.
enum class VmfSeeding {
    // mergedLobes: the children's lobes merged pairwise, cheapest first, until J are left
    // (moment-preserving, so the seeds add up to the texel's mean normal).
    Merge,
    // farthestPointLobes: Hochbaum-Shmoys clustering of the children's directions (Sec. 7.1).
    // It starts lobes on the most extreme directions, often single outlying normals, and EM then
    // keeps them there as spikes (kappa at its cap, alpha = 1/N) that waste the texel's lobes.
    FarthestPoint,
};

// The smoothing s of mergedLobes' cost (a Blinn-Phong exponent; its vMF concentration).
constexpr float kDefaultMergeSmoothing = 1024.f;

// C of H eq. 32 for lobes read through hardware filtering (eval's engine view, bakes written to
// files): coherent lobes (fitVmfPyramidCoherent) with a light pull, chosen on three maps
// (pyramidwall, Ground010, brickA) from 0.03, 0.1, 0.3 and 1 (docs/RESULTS.md): a stronger pull
// turns the fine levels' sharp lobes off their normals.
constexpr float kHardwareFilteringCoherence = 0.03f;

struct VmfFitOptions {
    int maxIterations = 50; // EM iterations (M-steps) at most
    // Stop once an iteration raises the log-likelihood by no more than
    // tolerance * max(|log-likelihood|, total weight): relative, but never finer than
    // `tolerance` nats per unit of weight, since a log-likelihood can be near 0.
    double tolerance = 1e-5;
    float kappaMax = kDefaultKappaMax;
    // Lobes whose alpha falls below this after an M-step are dropped and the others'
    // alphas renormalised (dropping, not reseeding: a texel that needs fewer lobes keeps fewer,
    // and the fit stays deterministic). Dropping can lower the log-likelihood.
    float minAlpha = 1e-3f;
    // fitVmfPyramid: kappa of the single lobe of each level-0 texel, capped at kappaMax. The
    // principled value is quantisationKappa(bits) of the source map (1.95e5 for 8 bits, so the
    // cap for every common map).
    float levelZeroKappa = kDefaultKappaMax;
    // M-step kappa: false = Banerjee's closed form (the paper; near convergence the log-likelihood
    // can then dip by ~1e-7 relative, which ends the fit); true = the exact maximum-likelihood
    // A^-1(r), which makes each iteration an exact EM step (the log-likelihood never decreases).
    bool exactKappa = false;
    // Coherent lobes (Sec. 7.3): C of H eq. 32, the strength of the pull of each lobe's direction
    // toward the same lobe of its neighbours; 0 = none. Used by fitVmfMixture with an
    // `alignment` and by fitVmfPyramidCoherent; fitVmfPyramid hands the pyramid to the latter
    // when it is > 0.
    float coherence = 0.f;
    // Coherent fits: kappa_j from |r_j| (false: the pull turns a lobe without widening it) or
    // from r_j . mu_j, the length of the lobe's mean along its pulled direction (true: the
    // maximum-likelihood kappa for that mu, which makes each iteration an exact M-step of the
    // appendix's likelihood-times-prior; a turned lobe widens to keep covering its normals, and
    // its packed vector alpha_j (r_j . mu_j) mu_j is the point of its axis nearest alpha_j r_j).
    // The same as false where nothing pulls.
    bool alignedKappa = false;
    // fitVmfPyramid: the start of each texel's EM, and the smoothing of the merge cost.
    VmfSeeding seeding = VmfSeeding::Merge;
    float mergeSmoothing = kDefaultMergeSmoothing;
    // fitVmfPyramid: lobes by error budget. After each texel's EM its lobes are merged further
    // (mergedLobes' rule and loss) while the cheapest merge loses at most this much; the texel
    // keeps fewer than J lobes where more buy little (0 or less: off). The merged lobes keep the
    // moments, so a texel's packed lobes still add up to its Na; they are not refitted.
    float lobeBudget = 0.f;
};

struct VmfFitResult {
    std::vector<VmfLobe> lobes; // by decreasing alpha; alphas sum to 1; at most kMaxVmfLobes
    int iterations = 0;         // M-steps applied
    bool converged = false;     // stopped by the tolerance or at a fixed point, not maxIterations
    // Sum_i w_i log g(n_i) of `lobes`, their alphas scaled to sum 1 and mu to unit length in
    // double (float rounding leaves both ~1e-7 off, which kappa would magnify).
    double logLikelihood = 0;
    // Log-likelihood of the lobes entering each iteration and of the result:
    // iterations + 1 values, the last one logLikelihood.
    std::vector<double> logLikelihoodTrace;
};

// Spherical EM (Algorithm 1) for a mixture of vMF lobes over `count` unit normals with optional
// non-negative weights (null: all 1); `normals` may be null when count is 0. E-step in log
// space: z_ij = alpha_j gamma_j(n_i) / Sum_k alpha_k gamma_k(n_i) by log-sum-exp (the paper's
// line 5 leaves out alpha_j; with it the iteration is the EM of Banerjee et al.). M-step: alpha_j =
// Sum_i w_i z_ij / Sum_i w_i, r_j = Sum_i w_i z_ij n_i / Sum_i w_i z_ij, mu_j = r_j / |r_j|,
// kappa_j from |r_j|, capped at options.kappaMax.
//
// `initial` seeds the fit (e.g. farthestPointLobes); its alphas need not sum to 1. Lobes with
// alpha <= 0 are ignored, and so are all but the kMaxVmfLobes heaviest; with none left the fit
// starts from one lobe at the data's mean. Degenerate data gives finite lobes with alphas
// summing to 1: lobes that become indistinguishable (directions within 1e-3 of their width
// 1/sqrt(kappa), kappas within 0.1%) are merged by adding their means; a lobe whose normals
// cancel (r_j = 0) keeps its direction with kappa = 0; identical normals give kappa = kappaMax.
// No data (count 0 or zero total weight) returns the sanitised `initial` (or, if that is empty,
// the uniform lobe: alpha 1, kappa 0), log-likelihood 0.
//
// Cost: (iterations + 1) passes over the normals, each J exps per normal, vectorised (AVX2 where
// the CPU has it); large inputs are split across OpenMP threads. Deterministic: the same input
// gives the same bits whatever the thread count.
//
// Coherent fit (Sec. 7.3): `alignment` non-null holds one vector per initial lobe (slot),
// align_j = Sum_k alpha_jk mu_jk over the lobes j of already fitted neighbouring texels, and
// line 13 of the M-step becomes mu_j = normalize(r_j + C align_j), C = options.coherence
// (H eq. 32). r_j is, as in the paper's line 11, the mean resultant vector of the lobe's normals,
// Sum_i w_i z_ij n_i / Sum_i w_i z_ij (length <= 1; A(kappa) mu for a vMF), so C weighs align_j
// against a vector no longer than 1, whatever the texel's size. kappa_j still comes from
// |r_j| (or r_j . mu_j: alignedKappa). (The appendix's prior Sum_k C' alpha_jk mu_j . mu_jk gives
// mu_j ~ kappa_j Sum_i z_ij n_i + C' align_j: H eq. 32 with C = C' / (kappa_j Sum_i z_ij); read
// with r_j the sum Sum_i z_ij n_i, as the paper's C = C' / kappa_j suggests, the pull would
// weaken with the number of normals instead.) C <= 0 pulls nothing. A coherent fit keeps the
// lobes in their slots: result.lobes has the first kMaxVmfLobes entries of `initial`, in that
// order, not sorted; a slot that starts with alpha <= 0, drops below minAlpha or merges into an
// indistinguishable lobe (the heavier keeps its slot, ties the lower) holds VmfLobe{} (alpha 0)
// and takes no part in the E-step; alphas of the others sum to 1. The pull
// makes the iteration an EM for the likelihood times the appendix's prior, not for the
// likelihood, so the log-likelihood may fall: with C > 0 the fit stops once an iteration
// changes it by no more than the tolerance either way. C = 0 fits the same lobes as the plain
// fit, slot for slot, where `initial` is sorted by alpha and no lobe is dropped or merged.
// With C > 0 the packed lobes no longer add up to the mean normal exactly: lobe j stores
// alpha_j |r_j| mu_j instead of alpha_j r_j, off by at most 2 C alpha_j |align_j| (with
// alignedKappa alpha_j (r_j . mu_j) mu_j, off by the part of alpha_j r_j across mu_j, at most
// C alpha_j |align_j|).
VmfFitResult fitVmfMixture(const glm::vec3* normals, const float* weights, size_t count,
                           std::vector<VmfLobe> initial, const VmfFitOptions& options = {},
                           const glm::vec3* alignment = nullptr);

// Hochbaum-Shmoys farthest-point clustering of candidate lobes' directions (Sec. 7.1): the
// heaviest candidate first, then repeatedly the one whose smallest angle to those chosen is
// largest (ties: the lower index), until J are chosen or every candidate left points within
// 1.4e-6 rad (a float's precision) of a chosen one. Each chosen lobe keeps its direction, kappa
// and colour; its alpha becomes the total alpha of the candidates nearest to it, normalised to
// sum 1. Candidates with alpha <= 0 are ignored; none left gives an empty result.
// 1 <= J <= kMaxVmfLobes (clamped).
std::vector<VmfLobe> farthestPointLobes(const std::vector<VmfLobe>& candidates, int J);

// Seeds by agglomeration: the candidates (alpha > 0 only) are merged two at a time until J are
// left, each time the pair whose merge loses least. A merge preserves the moments H eq. 33
// filters: alphas add, the mean vectors alpha r mu add, and mu and kappa come from the sum
// (kappa by Banerjee's map, or A^-1 with options.exactKappa). The loss of merging a and b into
// c is Runnalls' bound on the Kullback-Leibler divergence for Gaussian mixtures, read for vMF
// lobes as 2D Gaussians of variance 1/kappa per axis,
//     B = alpha_a log(k_a / k_c) + alpha_b log(k_b / k_c),
// with each kappa first seen through a lobe of concentration s = options.mergeSmoothing,
// k = kappa s / (kappa + s) (H eq. 29's convolution). Unsmoothed, spikes (kappa ~ 1e5, one normal
// each) would look as costly to merge as anything; smoothed, a light outlier merges cheaply and
// the lobes go to where the texel's mass is. Alphas of the result sum to 1, heaviest first; no
// candidates give an empty result. 1 <= J <= kMaxVmfLobes (clamped).
std::vector<VmfLobe> mergedLobes(const std::vector<VmfLobe>& candidates, int J,
                                 const VmfFitOptions& options = {});

// How well lobes stand for a set of normals, judged where shading sees the NDF: both seen through
// a Blinn-Phong-like lobe of concentration s (the normals each as a vMF of kappa s, the lobes by
// H eq. 29's kappa s / (kappa + s)), the relative L2 distance over the sphere,
//     sqrt( Integral (f_s - g_s)^2 / Integral f_s^2 ),
// in closed form (Integral gamma_1 gamma_2 = C(k_1) C(k_2) / C(|k_1 mu_1 + k_2 mu_2|)). Unlike the
// likelihood, which a lobe on one normal raises without end, this is the shading error a mixture
// makes, integrated over every half vector. Cost: count^2 + count J + J^2 lobe products.
double smoothedNdfError(const glm::vec3* normals, size_t count, std::span<const VmfLobe> lobes,
                        double s);

// ---- the whole pyramid ---------------------------------------------------------------------

// The lobes of every texel of one level, packed: texel (x, y), index t = y * width + x, owns
// lobes[offsets[t] .. offsets[t + 1]). fitVmfPyramid: by decreasing alpha, between 1 and J
// lobes. fitVmfPyramidCoherent: exactly J slots, empty ones alpha 0.
struct VmfLevel {
    int width = 0, height = 0;
    std::vector<uint32_t> offsets; // width * height + 1
    std::vector<VmfLobe> lobes;

    std::span<const VmfLobe> texel(int x, int y) const {
        size_t t = size_t(y) * size_t(width) + size_t(x);
        return {lobes.data() + offsets[t], lobes.data() + offsets[t + 1]};
    }
};

struct VmfFitStats {
    uint64_t texels = 0;       // texels fitted by EM (levels >= 1)
    uint64_t iterations = 0;   // EM iterations over all of them
    double meanIterations = 0; // iterations / texels
    int maxIterations = 0;     // most iterations one texel took
    uint64_t notConverged = 0; // texels stopped by options.maxIterations
    uint64_t lobes = 0;        // lobes of levels >= 1 (lobes / texels: the mean lobe count)
};

// vMF lobes for every level of `pyramid`, J lobes at most per texel (1 <= J <= kMaxVmfLobes).
// Level 0: one lobe per texel, alpha 1, mu = the normal, kappa = min(levelZeroKappa, kappaMax).
// Level k >= 1: each texel starts from its children's lobes (alphas weighted by the children's
// footprints), merged to J by mergedLobes (or farthestPointLobes, options.seeding), and runs
// fitVmfMixture over all the level-0 normals of its footprint. Every level costs about the same,
// (normals) x J x (iterations + 1) exps. Parallel over texels (OpenMP), or within a texel's fit for
// the few large texels of the top levels; deterministic. `stats` may be null. options.coherence >
// 0: returns fitVmfPyramidCoherent(pyramid, J, options, stats) instead.
std::vector<VmfLevel> fitVmfPyramid(const Pyramid& pyramid, int J, const VmfFitOptions& options,
                                    VmfFitStats* stats);

// Coherent lobes for hardware interpolation (Sec. 7.3): slot j holds corresponding lobes in
// every texel of every level, so that filtering the packed slots (H eq. 33) across texels and
// levels blends lobes that belong together. Built top-down as the paper does:
// - the top (1x1) texel: fitVmfPyramid's (bottom-up, merge-seeded) lobes, the heaviest in slot 0.
// - every level below it, texels in scanline order: slot j starts as slot j of the parent, and
//   coherent EM over all level-0 normals of the footprint pulls mu_j toward
//   align_j = Sum_k alpha_jk mu_jk over the texels fitted before it: the parent and the left,
//   upper-left, upper and upper-right texels of its level (H eq. 32, C = options.coherence;
//   C = 0 gives the slot-coherent start alone, and then the packed lobes add up to Na as in
//   fitVmfPyramid).
// - level 0: one lobe, alpha 1, mu = n, kappa = min(levelZeroKappa, kappaMax), in the slot
//   whose parent lobe is most responsible for n (largest alpha_j gamma_j(n), ties the lower
//   slot), so that levels 0 and 1 interpolate slot by slot.
// Every texel has exactly J slots (offsets step by J); alphas sum to 1; an empty slot is
// VmfLobe{} (alpha 0). Slots are never reseeded: one empty in a texel stays empty in the
// texels below it. The neighbours above and to the left only make a level's texels depend on
// those of earlier anti-diagonals x + 2y, which are fitted in parallel, one after the other,
// with the same results as a scanline pass; the few large texels of the top levels split
// their E-steps across threads instead. Deterministic whatever the thread count. The EM work
// is that of fitVmfPyramid; level 0 takes J slots per texel (J x the memory). `stats` may be
// null.
//
// Started from the parent, slot j of texels under one parent begins as one lobe and EM moves it
// only as far as the texel's normals ask, so neighbours' slots stay alike without a pull. The
// pull trades likelihood for agreement, most where footprints are small: a lobe of a few normals
// is sharp, and turning it by a fraction of a degree loses them (alignedKappa widens it instead,
// and a widened lobe blends worse). On a 64 x 64 map of two drifting groove patterns, J = 4,
// alignedKappa (tests/methods/vmf/vmf_coherent_test.cpp): lobeMismatch 20.2 degrees
// (fitVmfPyramid), 4.7 (C = 0), 2.2 (C = 1); log-likelihood per normal against fitVmfPyramid's
// the same to 0.07 from level 2 (16 normals a texel) up with C = 0, 0.06-0.36 lower with C = 1;
// the NDF error of two neighbours' slots blended (H eq. 33) against their normals 0.31-0.52
// (fitVmfPyramid), 0.05-0.19 (C = 0), 0.17-0.22 (C = 1).
std::vector<VmfLevel> fitVmfPyramidCoherent(const Pyramid& pyramid, int J,
                                            const VmfFitOptions& options, VmfFitStats* stats);

// How far corresponding lobes of adjacent texels point apart, in degrees: over the levels
// >= firstLevel, every pair of horizontally or vertically adjacent texels and every slot j that
// both hold with alpha > 0, the angle between their mu_j, weighted by min(alpha_j, alpha'_j);
// returns the weighted mean (0 where no pair counts). Slot j is the texel's j-th lobe whatever
// fitted it (for fitVmfPyramid, the j-th heaviest): hardware interpolation of the packed slots
// blends exactly these pairs, and a large angle blends two different lobes into one misplaced
// one.
double lobeMismatch(const std::vector<VmfLevel>& levels, int firstLevel = 1);

} // namespace ndfmip

// ---- colour per lobe (Sec. 7.3, H eq. 31) ----------------------------------------------------
// A texel whose normals come from differently coloured surfaces keeps one colour per lobe: the
// mean colour of the normals each lobe explains, y_j = Sum_i z_ij y_i / Sum_i z_ij. A colour
// does not change which lobe explains a normal, so this runs after the fit, on its final lobes.

#include <string>

#include "ndfmip/result.h"

namespace ndfmip {

// Sets `color` of every lobe of every level of `levels` (fitVmfPyramid of `pyramid`) to H eq. 31
// over all level-0 texels i of the texel's footprint, with y_i the RGB of `albedo` (level 0's
// size, 3 or 4 channels, linear; a fourth channel is ignored) and z_ij the E-step
// responsibilities of the texel's lobes, alpha_j gamma_j(n_i) / Sum_k alpha_k gamma_k(n_i), in
// log space (any kappa up to kDefaultKappaMax and beyond). Level 0: each texel's own colour. A
// lobe no normal falls to (zero total responsibility, alpha <= 0, or past the first
// kMaxVmfLobes) gets the footprint's mean colour. At an EM fixed point alpha_j = Sum_i z_ij / N,
// so Sum_j alpha_j y_j is the footprint's mean colour. Each texel sums its footprint row by row
// in double and adds the rows in order; parallel over texels, or over the rows of the few
// large texels of the top levels (OpenMP): the same bits for any thread count. Cost: one pass
// of J exps per normal per level. Inputs that do not match (checkAlbedoSize, levels not of
// this pyramid) leave `levels` unchanged.
void fitLobeColors(const Pyramid& pyramid, const Image& albedo, std::vector<VmfLevel>& levels);

// Storage for linear filtering: alpha * colour, 3 channels. alpha c_j = Sum_i z_ij y_i / N (at
// a fixed point) is a mean over the texel's normals like the lobe plane (packLobe), so it
// filters the same way; the lobe plane's x channel already holds alpha, filtered alike, so the
// colour needs no alpha channel of its own: unpack with the lobe's filtered alpha.
glm::vec3 packLobeColor(const VmfLobe& lobe);

// packed / alpha; 0 where alpha <= 0 (an empty lobe).
glm::vec3 unpackLobeColor(glm::vec3 packed, float alpha);

// Whether `albedo` can colour the lobes of a width x height normal map: the same size, 3 or 4
// channels. The error names `name` (the albedo's file) and the mismatch.
Status checkAlbedoSize(const Image& albedo, int width, int height, const std::string& name);

} // namespace ndfmip
