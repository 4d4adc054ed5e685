// Shared by the vMF fit's files: the normals as structure-of-arrays, the E-step kernel and the EM
// loop that runs on them. Not part of the public API (tests use it to check the kernel).
#pragma once

#include <cstddef>
#include <vector>

#include "ndfmip/image.h"
#include "ndfmip/pyramid.h"
#include "ndfmip/vmf.h"

namespace ndfmip::vmf {

// Normals (unit length) and optional weights, one array per component so that the E-step
// reads eight normals per vector load.
struct Samples {
    const float* x = nullptr;
    const float* y = nullptr;
    const float* z = nullptr;
    const float* w = nullptr; // null: every weight 1
    size_t count = 0;
};

// A texel's lobes in the form the E-step evaluates: log(alpha_j gamma_j(n)) = c_j + k_j . n with
// c_j = log alpha_j + vmfLogNormalizer(kappa_j) and k_j = kappa_j mu_j, in double so that the
// cancellation of c_j ~ -kappa against k_j . n ~ +kappa costs nothing at kappa = 1e5.
// m_j: the direction the moments are taken about (the lobe's mu as stored).
struct LobeTerms {
    int count = 0;
    double c[kMaxVmfLobes];
    double kx[kMaxVmfLobes], ky[kMaxVmfLobes], kz[kMaxVmfLobes];
    float mx[kMaxVmfLobes], my[kMaxVmfLobes], mz[kMaxVmfLobes];
};

// What one E-step pass gathers over a range of normals, in double. The first moments are taken
// about m_j: n_i - m_j is small for a sharp lobe and exact in float where n_i is close to m_j,
// so 1 - |r_j| ~ 1/kappa_j survives float sums (about n_i itself it would keep ~6e-8 absolute,
// kappa_j to only 6e-8 kappa_j relative).
struct Moments {
    double n[kMaxVmfLobes];  // Sum_i w_i z_ij
    double rx[kMaxVmfLobes]; // Sum_i w_i z_ij (n_i - m_j)
    double ry[kMaxVmfLobes];
    double rz[kMaxVmfLobes];
    double logLikelihood; // Sum_i w_i log Sum_j alpha_j gamma_j(n_i)

    void clear(int lobes);
    void add(const Moments& other, int lobes);
};

// Normals per partial sum. Ranges of the E-step are cut into chunks of this many from the start
// of the data, each chunk summed on its own and the chunks added in order: the same bits
// whether the chunks run on one thread or many.
constexpr size_t kChunk = 2048;

// The E-step over normals [begin, end) of `samples` (begin a multiple of 8), adding to `out`.
void eStep(const Samples& samples, size_t begin, size_t end, const LobeTerms& lobes, Moments& out);

enum class Kernel { Auto, Portable, Avx2 };
// Which E-step code runs (tests compare them); Avx2 falls back to Portable without the CPU
// support. Returns the kernel now in use.
Kernel selectKernel(Kernel kernel);

// The two implementations behind eStep. eStepAvx2 returns false where it is not compiled in
// (not x86-64), without touching `out`.
void eStepPortable(const Samples& samples, size_t begin, size_t end, const LobeTerms& lobes,
                   Moments& out);
bool eStepAvx2(const Samples& samples, size_t begin, size_t end, const LobeTerms& lobes,
               Moments& out);

// Calls blocks(x, y, z, w, from, to) on the whole blocks of 8 normals in [begin, end) straight
// from the arrays (w null when unweighted), then on the last partial block copied out and padded
// with weight-0 normals.
template <class Blocks>
inline void forEachBlockRange(const Samples& samples, size_t begin, size_t end, Blocks&& blocks) {
    size_t whole = begin + (end - begin) / 8 * 8;
    if (whole > begin) blocks(samples.x, samples.y, samples.z, samples.w, begin, whole);
    if (whole == end) return;
    alignas(32) float x[8] = {}, y[8] = {}, z[8] = {1, 1, 1, 1, 1, 1, 1, 1}, w[8] = {};
    for (size_t i = whole; i < end; ++i) {
        x[i - whole] = samples.x[i];
        y[i - whole] = samples.y[i];
        z[i - whole] = samples.z[i];
        w[i - whole] = samples.w ? samples.w[i] : 1.f;
    }
    blocks(x, y, z, w, size_t(0), size_t(8));
}

// A fixed-capacity set of lobes (no allocation per texel in the pyramid's hot loop).
struct LobeSet {
    int count = 0;
    VmfLobe lobe[kMaxVmfLobes];
};

struct EmOutcome {
    int iterations = 0;
    bool converged = false;
    double logLikelihood = 0;
};

// The EM loop of fitVmfMixture on `samples`, starting from `lobes` (sanitised here) and
// leaving the result there (sorted by decreasing alpha). parallel: split each pass over
// chunks across OpenMP threads. trace may be null.
EmOutcome runEm(const Samples& samples, LobeSet& lobes, const VmfFitOptions& options, bool parallel,
                std::vector<double>* trace);

// What a coherent fit pulls each slot's direction toward (H eq. 32): C align_j, already scaled by
// C = options.coherence. Zero for slots with no neighbour lobe.
struct Alignment {
    glm::dvec3 pull[kMaxVmfLobes] = {};
};

// The EM loop of a coherent fit: lobes.lobe[0 .. count) are slots, kept in place (an empty slot
// has alpha 0 and stays empty; a lobe that drops below minAlpha or merges into a heavier one
// leaves VmfLobe{} behind), and the M-step sets mu_j = normalize(r_j + pull_j). With
// options.coherence > 0 the fit stops once the log-likelihood changes by no more than the
// tolerance either way. The E-step sees the live slots in slot order, so with zero pulls and
// no lobe dropped or merged this is runEm's arithmetic, slot for slot.
EmOutcome runSlotEm(const Samples& samples, LobeSet& lobes, const Alignment& alignment,
                    const VmfFitOptions& options, bool parallel, std::vector<double>* trace);

// farthestPointLobes into a LobeSet (candidates: any number).
void farthestPoint(const VmfLobe* candidates, size_t count, int J, LobeSet& out);

// mergedLobes into a LobeSet (candidates: any number); then, with maxLoss >= 0, further merges
// while the cheapest loses at most maxLoss (VmfFitOptions::lobeBudget).
void mergeCandidates(const VmfLobe* candidates, size_t count, int J, const VmfFitOptions& options,
                     LobeSet& out, double maxLoss = -1);

// The kappa <-> mean resultant length map of the fit: Banerjee's closed form, or with
// options.exactKappa the exact A^-1 / A; kappa capped at options.kappaMax.
double kappaOf(double r, const VmfFitOptions& options);
double meanLengthOf(double kappa, const VmfFitOptions& options);

// ---- the pyramid's footprints (vmf_pyramid.cpp) --------------------------------------------

// Texel (x, y) of level k >= 1 has the children columns[x] .. columns[x + 1] - 1 by
// rows[y] .. rows[y + 1] - 1 in level k - 1 (width + 1 and height + 1 entries).
struct ChildRanges {
    std::vector<int> columns, rows;
};

// Level-0 texels covered by texel (x, y) of `level`.
size_t texelArea(const PyramidLevel& level, int x, int y);

// The level-0 normals of a pyramid, unit length, reordered so that every texel's footprint, at
// every level, is one contiguous run of x[], y[], z[]: a texel's children come one after the
// other, recursively, as in a Morton order but following the pyramid's own footprints (odd sizes
// included). The EM then reads its normals without gathering them.
struct FootprintOrder {
    std::vector<ChildRanges> children;      // [k] for k >= 1 ([0] empty)
    std::vector<std::vector<size_t>> start; // [k][y * width + x]: where the footprint starts
                                            // ([0] left empty: the level-0 order is not needed)
    PixelVector soa;                        // x[], then y[], then z[]

    Samples all() const {
        const size_t count = soa.size() / 3;
        return {soa.data(), soa.data() + count, soa.data() + 2 * count, nullptr, count};
    }
};

FootprintOrder footprintOrder(const Pyramid& pyramid);

} // namespace ndfmip::vmf
