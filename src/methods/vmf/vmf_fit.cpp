// Spherical EM for mixtures of vMF lobes (Han et al. 2007, Sec. 7.1, Algorithm 1), the map
// between kappa and the mean resultant length, farthest-point initialisation and the storage of
// lobes for linear filtering (H eq. 33). The E-step kernel is in vmf_estep.cpp.
#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstring>
#include <limits>

#include <omp.h>

#include "methods/vmf/vmf_internal.h"

namespace ndfmip {
namespace {

constexpr double kPiD = 3.14159265358979323846;
const double kLog2Pi = std::log(2 * kPiD);

// log(kappa / (4 pi sinh kappa)) + kappa = log(kappa / (1 - e^(-2 kappa))) - log(2 pi): moderate
// for every kappa, so that log gamma = this + kappa (mu.n - 1) does not cancel.
double logNormalizerPlusKappa(double kappa) {
    if (!(kappa > 0)) return -std::log(4 * kPiD);
    if (kappa > 20) return std::log(kappa) - kLog2Pi; // 1 - e^(-2 kappa) = 1 to double precision
    return std::log(kappa / -std::expm1(-2 * kappa)) - kLog2Pi;
}

glm::dvec3 unitOrFlat(glm::dvec3 v) {
    double length = glm::length(v);
    if (!(length > 0) || !std::isfinite(length)) return {0, 0, 1};
    return v / length;
}

// Derivative of langevin: 1/kappa^2 - 1/sinh^2 kappa.
double langevinDerivative(double kappa) {
    if (kappa < 0.1) {
        double k2 = kappa * kappa;
        return 1.0 / 3 - k2 / 15 + 2 * k2 * k2 / 189 - k2 * k2 * k2 / 675;
    }
    if (kappa > 20) return 1 / (kappa * kappa);
    double s = std::sinh(kappa);
    return 1 / (kappa * kappa) - 1 / (s * s);
}

} // namespace

// ---- one lobe ------------------------------------------------------------------------------

double vmfLogNormalizer(double kappa) {
    if (!(kappa > 0)) return -std::log(4 * kPiD);
    return logNormalizerPlusKappa(kappa) - kappa;
}

double vmfLogDensity(glm::vec3 n, glm::vec3 mu, double kappa) {
    double cosine = glm::dot(glm::dvec3(n), glm::dvec3(mu));
    return logNormalizerPlusKappa(kappa) + std::max(kappa, 0.0) * (cosine - 1);
}

double vmfMixtureLogDensity(glm::vec3 n, std::span<const VmfLobe> lobes) {
    double terms[kMaxVmfLobes];
    double top = -std::numeric_limits<double>::infinity();
    int count = 0;
    for (const VmfLobe& lobe : lobes) {
        if (!(lobe.alpha > 0) || count == kMaxVmfLobes) continue;
        terms[count] = std::log(double(lobe.alpha)) + vmfLogDensity(n, lobe.mu, lobe.kappa);
        top = std::max(top, terms[count++]);
    }
    if (count == 0) return top;
    double sum = 0;
    for (int j = 0; j < count; ++j) sum += std::exp(terms[j] - top);
    return top + std::log(sum);
}

double langevin(double kappa) {
    if (!(kappa > 0)) return 0;
    if (kappa < 0.1) {
        // coth k - 1/k = k/3 - k^3/45 + 2k^5/945 - k^7/4725 + 2k^9/93555 - ...
        double k2 = kappa * kappa;
        return kappa * (1.0 / 3 + k2 * (-1.0 / 45 +
                                        k2 * (2.0 / 945 + k2 * (-1.0 / 4725 + k2 * 2.0 / 93555))));
    }
    if (kappa > 20) return 1 - 1 / kappa; // coth k = 1 + 2e^(-2k) + ... = 1 to double precision
    return 1 / std::tanh(kappa) - 1 / kappa;
}

double inverseLangevin(double r) {
    if (!(r > 0)) return 0;
    if (r >= 1) return std::numeric_limits<double>::infinity();
    if (r >= 0.95) return 1 / (1 - r); // kappa >= 20: A(kappa) = 1 - 1/kappa exactly
    // A is increasing and concave: Newton from Banerjee's estimate, which is within 0.5 of the
    // root, converges without overshooting after its first step.
    double kappa = r * (3 - r * r) / ((1 - r) * (1 + r));
    for (int i = 0; i < 50; ++i) {
        double step = (langevin(kappa) - r) / langevinDerivative(kappa);
        kappa = std::max(kappa - step, 0.5 * kappa);
        if (std::abs(step) <= 1e-15 * kappa) break;
    }
    return kappa;
}

double kappaFromMeanLength(double r, double kappaMax) {
    if (!(r > 0)) return 0;
    if (r >= 1) return kappaMax;
    double kappa = r * (3 - r * r) / ((1 - r) * (1 + r));
    return std::min(kappa, kappaMax);
}

double meanLengthFromKappa(double kappa) {
    if (!(kappa > 0)) return 0;
    if (!std::isfinite(kappa)) return 1;
    // In e = 1 - r: kappa e (2 - e) = (1 - e)(2 + 2e - e^2), increasing in e on [0, 1] (-2 at
    // 0, kappa at 1). Safeguarded Newton in e keeps 1 - r to full relative precision.
    auto g = [kappa](double e) { return kappa * e * (2 - e) - (1 - e) * (2 + 2 * e - e * e); };
    auto dg = [kappa](double e) { return kappa * (2 - 2 * e) + 6 * e - 3 * e * e; };
    double lo = 0, hi = 1;
    double e = kappa > 1 ? 1 / (kappa - 0.5) : 1 - kappa / 3;
    e = std::clamp(e, 1e-300, 1.0);
    for (int i = 0; i < 100; ++i) {
        double value = g(e);
        if (value == 0) break;
        (value < 0 ? lo : hi) = e;
        double next = e - value / dg(e);
        if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
        bool done = std::abs(next - e) <= 1e-16 * e;
        e = next;
        if (done) break;
    }
    return 1 - e;
}

float quantisationKappa(int bits) {
    assert(bits >= 1);
    bits = std::clamp(bits, 1, 32);
    double steps = std::ldexp(1.0, bits) - 1; // 2^b - 1
    return float(3 * steps * steps);          // 12 / delta^2, delta = 2 / (2^b - 1)
}

// ---- storage -------------------------------------------------------------------------------

glm::vec4 packLobe(const VmfLobe& lobe) {
    if (!(lobe.alpha > 0)) return glm::vec4(0.f);
    glm::dvec3 mean = unitOrFlat(glm::dvec3(lobe.mu)) * meanLengthFromKappa(lobe.kappa);
    return glm::vec4(lobe.alpha, glm::vec3(double(lobe.alpha) * mean));
}

VmfLobe unpackLobe(glm::vec4 packed, float kappaMax) {
    VmfLobe lobe;
    if (!(packed.x > 0)) return lobe;
    glm::dvec3 scaled(packed.y, packed.z, packed.w);
    double length = glm::length(scaled);
    lobe.alpha = packed.x;
    lobe.mu = glm::vec3(unitOrFlat(scaled));
    lobe.kappa = float(kappaFromMeanLength(length / packed.x, kappaMax));
    return lobe;
}

// ---- EM ------------------------------------------------------------------------------------

namespace vmf {

double kappaOf(double r, const VmfFitOptions& options) {
    double kappaMax = std::max(double(options.kappaMax), 0.0);
    if (!options.exactKappa) return kappaFromMeanLength(r, kappaMax);
    return r >= 1 ? kappaMax : std::min(inverseLangevin(r), kappaMax);
}

double meanLengthOf(double kappa, const VmfFitOptions& options) {
    return options.exactKappa ? langevin(kappa) : meanLengthFromKappa(kappa);
}

namespace {

void removeLobe(LobeSet& set, int j) {
    for (int k = j + 1; k < set.count; ++k) set.lobe[k - 1] = set.lobe[k];
    --set.count;
}

// Two lobes that no normal can tell apart: centres closer than 1e-3 of the width 1/sqrt(kappa)
// and kappas within 0.1%. Merged by adding their means alpha r mu (what H eq. 33 filters).
bool indistinguishable(const VmfLobe& a, const VmfLobe& b) {
    double kappa = std::max(a.kappa, b.kappa);
    if (std::abs(double(a.kappa) - double(b.kappa)) > 1e-3 * kappa) return false;
    double chord2 =
        glm::dot(glm::dvec3(a.mu) - glm::dvec3(b.mu), glm::dvec3(a.mu) - glm::dvec3(b.mu));
    return kappa * chord2 <= 1e-6;
}

// `into` with `other` added: alphas summed, the mean resultant vectors averaged by alpha, mu and
// kappa from the sum (other fields, such as the colour, stay `into`'s).
VmfLobe mergedLobe(VmfLobe into, const VmfLobe& other, const VmfFitOptions& options) {
    double alpha = double(into.alpha) + double(other.alpha);
    glm::dvec3 mean =
        (double(into.alpha) * meanLengthOf(into.kappa, options) * glm::dvec3(into.mu) +
         double(other.alpha) * meanLengthOf(other.kappa, options) * glm::dvec3(other.mu)) /
        alpha;
    double length = glm::length(mean);
    into.alpha = float(alpha);
    if (length > 0) into.mu = glm::vec3(mean / length);
    into.kappa = float(kappaOf(length, options));
    return into;
}

void mergeIndistinguishable(LobeSet& set, const VmfFitOptions& options) {
    for (int j = 0; j < set.count; ++j) {
        for (int k = j + 1; k < set.count;) {
            VmfLobe& a = set.lobe[j];
            const VmfLobe& b = set.lobe[k];
            if (!indistinguishable(a, b)) {
                ++k;
                continue;
            }
            a = mergedLobe(a, b, options);
            removeLobe(set, k);
        }
    }
}

void normaliseAlphas(LobeSet& set) {
    double sum = 0;
    for (int j = 0; j < set.count; ++j) sum += set.lobe[j].alpha;
    for (int j = 0; j < set.count; ++j)
        set.lobe[j].alpha = sum > 0 ? float(set.lobe[j].alpha / sum) : 1.f / float(set.count);
}

// Valid lobes only: alpha > 0 and finite, unit mu, kappa in [0, kappaMax], alphas summing to 1,
// no two indistinguishable.
void sanitise(LobeSet& set, const VmfFitOptions& options) {
    const float kappaMax = std::max(options.kappaMax, 0.f);
    for (int j = 0; j < set.count;) {
        VmfLobe& lobe = set.lobe[j];
        if (!(lobe.alpha > 0) || !std::isfinite(lobe.alpha)) {
            removeLobe(set, j);
            continue;
        }
        lobe.mu = glm::vec3(unitOrFlat(glm::dvec3(lobe.mu)));
        lobe.kappa = lobe.kappa >= 0 ? std::min(lobe.kappa, kappaMax) : 0.f; // NaN -> 0
        ++j;
    }
    normaliseAlphas(set);
    mergeIndistinguishable(set, options);
}

LobeTerms termsOf(const LobeSet& set) {
    LobeTerms terms;
    terms.count = set.count;
    double alphaSum = 0;
    for (int j = 0; j < set.count; ++j) alphaSum += set.lobe[j].alpha;
    for (int j = 0; j < set.count; ++j) {
        // The returned floats, read as a normalised mixture of unit directions: the
        // log-likelihood is then exactly that of the lobes the fit hands back.
        const VmfLobe& lobe = set.lobe[j];
        glm::dvec3 mu = unitOrFlat(glm::dvec3(lobe.mu));
        double kappa = lobe.kappa;
        terms.c[j] = std::log(lobe.alpha / alphaSum) + vmfLogNormalizer(kappa);
        terms.kx[j] = kappa * mu.x;
        terms.ky[j] = kappa * mu.y;
        terms.kz[j] = kappa * mu.z;
        terms.mx[j] = lobe.mu.x;
        terms.my[j] = lobe.mu.y;
        terms.mz[j] = lobe.mu.z;
    }
    return terms;
}

// One E-step over all samples, chunk by chunk (see kChunk), partial sums added in order.
void pass(const Samples& samples, const LobeTerms& terms, bool parallel, Moments& total) {
    const size_t chunks = (samples.count + kChunk - 1) / kChunk;
    total.clear(terms.count);
    if (chunks <= 1) {
        eStep(samples, 0, samples.count, terms, total);
        return;
    }
    thread_local std::vector<Moments> partials;
    partials.resize(chunks);
    Moments* part = partials.data();
#pragma omp parallel for schedule(static) if (parallel)
    for (size_t c = 0; c < chunks; ++c) {
        part[c].clear(terms.count);
        eStep(samples, c * kChunk, std::min(samples.count, (c + 1) * kChunk), terms, part[c]);
    }
    for (size_t c = 0; c < chunks; ++c) total.add(part[c], terms.count);
}

// Algorithm 1, lines 9-14, plus dropping lobes lighter than minAlpha and merging
// indistinguishable ones.
LobeSet mStep(const Moments& moments, const LobeSet& current, double totalWeight,
              const VmfFitOptions& options) {
    LobeSet next;
    int heaviest = 0;
    for (int j = 0; j < current.count; ++j) {
        if (moments.n[j] > moments.n[heaviest]) heaviest = j;
        double alpha = moments.n[j] / totalWeight;
        if (!(moments.n[j] > 0) || !(alpha >= options.minAlpha)) continue;
        glm::dvec3 mean = glm::dvec3(current.lobe[j].mu) +
                          glm::dvec3(moments.rx[j], moments.ry[j], moments.rz[j]) / moments.n[j];
        double length = glm::length(mean);
        VmfLobe& lobe = next.lobe[next.count++];
        lobe = current.lobe[j];
        lobe.alpha = float(alpha);
        // r_j = 0: the lobe's normals cancel; it becomes uniform and keeps its direction.
        if (length > 0 && std::isfinite(length)) lobe.mu = glm::vec3(mean / length);
        lobe.kappa = float(kappaOf(length, options));
    }
    if (next.count == 0) { // minAlpha above every alpha: keep the heaviest lobe
        next.lobe[0] = current.lobe[heaviest];
        next.count = 1;
    }
    normaliseAlphas(next);
    mergeIndistinguishable(next, options);
    return next;
}

bool sameLobes(const LobeSet& a, const LobeSet& b) {
    if (a.count != b.count) return false;
    for (int j = 0; j < a.count; ++j) {
        const VmfLobe &p = a.lobe[j], &q = b.lobe[j];
        if (p.alpha != q.alpha || p.mu != q.mu || p.kappa != q.kappa) return false;
    }
    return true;
}

void sortByAlpha(LobeSet& set) {
    std::stable_sort(set.lobe, set.lobe + set.count,
                     [](const VmfLobe& a, const VmfLobe& b) { return a.alpha > b.alpha; });
}

// ---- coherent fits: lobes in fixed slots, empty ones alpha 0 ----------------------------------

int liveSlots(const LobeSet& set) {
    int live = 0;
    for (int j = 0; j < set.count; ++j) live += set.lobe[j].alpha > 0 ? 1 : 0;
    return live;
}

// normaliseAlphas over the live slots: the same sums, in the same order, when no slot is empty.
void normaliseSlotAlphas(LobeSet& set) {
    double sum = 0;
    for (int j = 0; j < set.count; ++j)
        if (set.lobe[j].alpha > 0) sum += set.lobe[j].alpha;
    const int live = liveSlots(set);
    for (int j = 0; j < set.count; ++j)
        if (set.lobe[j].alpha > 0)
            set.lobe[j].alpha = sum > 0 ? float(set.lobe[j].alpha / sum) : 1.f / float(live);
}

// mergeIndistinguishable in place: the merged lobe takes the heavier slot (ties: the lower one),
// the other slot empties.
void mergeIndistinguishableSlots(LobeSet& set, const VmfFitOptions& options) {
    for (int j = 0; j < set.count; ++j) {
        for (int k = j + 1; k < set.count && set.lobe[j].alpha > 0; ++k) {
            if (!(set.lobe[k].alpha > 0) || !indistinguishable(set.lobe[j], set.lobe[k])) continue;
            const int keep = set.lobe[k].alpha > set.lobe[j].alpha ? k : j;
            const VmfLobe merged = mergedLobe(set.lobe[keep], set.lobe[keep == j ? k : j], options);
            set.lobe[j] = set.lobe[k] = VmfLobe{}; // alpha 0
            set.lobe[keep] = merged;
        }
    }
}

void sanitiseSlots(LobeSet& set, const VmfFitOptions& options) {
    const float kappaMax = std::max(options.kappaMax, 0.f);
    for (int j = 0; j < set.count; ++j) {
        VmfLobe& lobe = set.lobe[j];
        if (!(lobe.alpha > 0) || !std::isfinite(lobe.alpha)) {
            lobe = VmfLobe{}; // alpha 0
            continue;
        }
        lobe.mu = glm::vec3(unitOrFlat(glm::dvec3(lobe.mu)));
        lobe.kappa = lobe.kappa >= 0 ? std::min(lobe.kappa, kappaMax) : 0.f; // NaN -> 0
    }
    normaliseSlotAlphas(set);
    mergeIndistinguishableSlots(set, options);
}

// mStep for slots: `moments` holds the live slots in slot order (slotOf maps them back). Line 13
// becomes H eq. 32, mu_j = normalize(r_j + C align_j); kappa_j comes from |r_j| or, with
// alignedKappa, from r_j . mu_j.
LobeSet mStepSlots(const Moments& moments, const int* slotOf, int live, const LobeSet& current,
                   const Alignment& alignment, double totalWeight, const VmfFitOptions& options) {
    LobeSet next = current;
    int heaviest = 0;
    bool any = false;
    for (int c = 0; c < live; ++c) {
        const int j = slotOf[c];
        if (moments.n[c] > moments.n[heaviest]) heaviest = c;
        double alpha = moments.n[c] / totalWeight;
        VmfLobe& lobe = next.lobe[j];
        if (!(moments.n[c] > 0) || !(alpha >= options.minAlpha)) {
            lobe = VmfLobe{}; // dropped: alpha 0
            continue;
        }
        any = true;
        glm::dvec3 mean = glm::dvec3(current.lobe[j].mu) +
                          glm::dvec3(moments.rx[c], moments.ry[c], moments.rz[c]) / moments.n[c];
        double length = glm::length(mean);
        const bool pulled = alignment.pull[j] != glm::dvec3(0);
        glm::dvec3 direction = pulled ? mean + alignment.pull[j] : mean;
        double directionLength = glm::length(direction);
        lobe.alpha = float(alpha);
        // r_j + C align_j = 0: the lobe keeps its direction.
        if (directionLength > 0 && std::isfinite(directionLength))
            lobe.mu = glm::vec3(direction / directionLength);
        double along = length;
        if (pulled && options.alignedKappa)
            along = directionLength > 0 && std::isfinite(directionLength)
                        ? glm::dot(mean, direction / directionLength)
                        : glm::dot(mean, glm::dvec3(lobe.mu));
        lobe.kappa = float(kappaOf(along, options));
    }
    if (!any) { // minAlpha above every alpha: keep the heaviest lobe
        const int j = slotOf[heaviest];
        next.lobe[j] = current.lobe[j];
    }
    normaliseSlotAlphas(next);
    mergeIndistinguishableSlots(next, options);
    return next;
}

} // namespace

void Moments::clear(int lobes) {
    for (int j = 0; j < lobes; ++j) n[j] = rx[j] = ry[j] = rz[j] = 0;
    logLikelihood = 0;
}

void Moments::add(const Moments& other, int lobes) {
    for (int j = 0; j < lobes; ++j) {
        n[j] += other.n[j];
        rx[j] += other.rx[j];
        ry[j] += other.ry[j];
        rz[j] += other.rz[j];
    }
    logLikelihood += other.logLikelihood;
}

EmOutcome runEm(const Samples& samples, LobeSet& lobes, const VmfFitOptions& options, bool parallel,
                std::vector<double>* trace) {
    EmOutcome outcome;
    sanitise(lobes, options);
    double totalWeight = double(samples.count);
    if (samples.w) {
        totalWeight = 0;
        for (size_t i = 0; i < samples.count; ++i) totalWeight += samples.w[i];
    }
    if (lobes.count == 0) { // start from the uniform lobe: the first M-step gives the mean
        lobes.lobe[0] = VmfLobe{1.f, {0, 0, 1}, 0.f, glm::vec3(0.f)};
        lobes.count = 1;
    }
    if (samples.count == 0 || !(totalWeight > 0)) {
        outcome.converged = true;
        sortByAlpha(lobes);
        if (trace) trace->push_back(0);
        return outcome;
    }

    Moments moments;
    double previous = 0;
    bool comparable = false; // the previous log-likelihood belongs to as many lobes
    for (;;) {
        pass(samples, termsOf(lobes), parallel, moments);
        const double logLikelihood = moments.logLikelihood;
        outcome.logLikelihood = logLikelihood;
        if (trace) trace->push_back(logLikelihood);
        double scale = std::max(std::abs(logLikelihood), totalWeight);
        if (comparable && logLikelihood - previous <= options.tolerance * scale) {
            outcome.converged = true;
            break;
        }
        if (outcome.iterations >= options.maxIterations) break;
        LobeSet next = mStep(moments, lobes, totalWeight, options);
        if (sameLobes(next, lobes)) { // a fixed point: nothing more to gain
            outcome.converged = true;
            break;
        }
        comparable = next.count == lobes.count;
        lobes.count = next.count;
        std::copy(next.lobe, next.lobe + next.count, lobes.lobe);
        previous = logLikelihood;
        ++outcome.iterations;
    }
    sortByAlpha(lobes);
    return outcome;
}

EmOutcome runSlotEm(const Samples& samples, LobeSet& lobes, const Alignment& alignment,
                    const VmfFitOptions& options, bool parallel, std::vector<double>* trace) {
    EmOutcome outcome;
    sanitiseSlots(lobes, options);
    double totalWeight = double(samples.count);
    if (samples.w) {
        totalWeight = 0;
        for (size_t i = 0; i < samples.count; ++i) totalWeight += samples.w[i];
    }
    if (liveSlots(lobes) == 0) { // start from the uniform lobe in the first slot
        lobes.count = std::max(lobes.count, 1);
        lobes.lobe[0] = VmfLobe{1.f, {0, 0, 1}, 0.f, glm::vec3(0.f)};
    }
    if (samples.count == 0 || !(totalWeight > 0)) {
        outcome.converged = true;
        if (trace) trace->push_back(0);
        return outcome;
    }

    // The pull moves mu_j off the maximum-likelihood direction, so the log-likelihood may fall
    // while the fit settles: only a change within the tolerance either way ends it.
    const bool pulled = options.coherence > 0;
    Moments moments;
    double previous = 0;
    bool comparable = false;
    for (;;) {
        LobeSet live;
        int slotOf[kMaxVmfLobes];
        for (int j = 0; j < lobes.count; ++j)
            if (lobes.lobe[j].alpha > 0) {
                slotOf[live.count] = j;
                live.lobe[live.count++] = lobes.lobe[j];
            }
        pass(samples, termsOf(live), parallel, moments);
        const double logLikelihood = moments.logLikelihood;
        outcome.logLikelihood = logLikelihood;
        if (trace) trace->push_back(logLikelihood);
        double scale = std::max(std::abs(logLikelihood), totalWeight);
        double change = pulled ? std::abs(logLikelihood - previous) : logLikelihood - previous;
        if (comparable && change <= options.tolerance * scale) {
            outcome.converged = true;
            break;
        }
        if (outcome.iterations >= options.maxIterations) break;
        LobeSet next =
            mStepSlots(moments, slotOf, live.count, lobes, alignment, totalWeight, options);
        if (sameLobes(next, lobes)) {
            outcome.converged = true;
            break;
        }
        comparable = liveSlots(next) == live.count;
        lobes = next;
        previous = logLikelihood;
        ++outcome.iterations;
    }
    return outcome;
}

void farthestPoint(const VmfLobe* candidates, size_t count, int J, LobeSet& out) {
    assert(J >= 1);
    J = std::clamp(J, 1, kMaxVmfLobes);
    out.count = 0;
    // Per candidate: unit direction, cosine to the nearest chosen lobe, which one that is.
    thread_local std::vector<glm::dvec3> direction;
    thread_local std::vector<double> nearestCos;
    thread_local std::vector<int> nearest;
    direction.resize(count);
    nearestCos.assign(count, -2.0); // below any cosine: not yet near anything
    nearest.assign(count, -1);
    int heaviest = -1;
    for (size_t i = 0; i < count; ++i) {
        direction[i] = unitOrFlat(glm::dvec3(candidates[i].mu));
        bool valid = candidates[i].alpha > 0 && std::isfinite(candidates[i].alpha);
        if (!valid)
            nearest[i] = -2; // ignored
        else if (heaviest < 0 || candidates[i].alpha > candidates[heaviest].alpha)
            heaviest = int(i);
    }
    if (heaviest < 0) return;

    auto choose = [&](int c) {
        int slot = out.count++;
        out.lobe[slot] = candidates[c];
        for (size_t i = 0; i < count; ++i) {
            if (nearest[i] == -2) continue;
            double cosine = glm::dot(direction[i], direction[c]);
            if (cosine > nearestCos[i]) nearestCos[i] = cosine, nearest[i] = slot;
        }
        nearestCos[c] = 2.0; // chosen: never picked again
    };
    choose(heaviest);
    while (out.count < J) {
        int farthest = -1;
        for (size_t i = 0; i < count; ++i)
            if (nearest[i] >= 0 && (farthest < 0 || nearestCos[i] < nearestCos[farthest]))
                farthest = int(i);
        // 1 - cos <= 1e-12: within 1.4e-6 rad, a duplicate of a chosen direction.
        if (farthest < 0 || 1 - nearestCos[farthest] <= 1e-12) break;
        choose(farthest);
    }
    // Each chosen lobe weighs what its cluster weighs.
    double weight[kMaxVmfLobes] = {};
    for (size_t i = 0; i < count; ++i)
        if (nearest[i] >= 0) weight[nearest[i]] += candidates[i].alpha;
    double total = 0;
    for (int j = 0; j < out.count; ++j) total += weight[j];
    for (int j = 0; j < out.count; ++j) out.lobe[j].alpha = float(weight[j] / total);
}

} // namespace vmf

// ---- public entry points -------------------------------------------------------------------

VmfFitResult fitVmfMixture(const glm::vec3* normals, const float* weights, size_t count,
                           std::vector<VmfLobe> initial, const VmfFitOptions& options,
                           const glm::vec3* alignment) {
    // Plain: the kMaxVmfLobes heaviest initial lobes (stable: ties keep their order). Coherent:
    // the first kMaxVmfLobes slots, in order.
    if (!alignment)
        std::stable_sort(initial.begin(), initial.end(),
                         [](const VmfLobe& a, const VmfLobe& b) { return a.alpha > b.alpha; });
    vmf::LobeSet lobes;
    lobes.count = int(std::min(initial.size(), size_t(kMaxVmfLobes)));
    std::copy(initial.begin(), initial.begin() + lobes.count, lobes.lobe);
    vmf::Alignment pull;
    if (alignment)
        for (int j = 0; j < lobes.count; ++j)
            pull.pull[j] = (options.coherence > 0 ? double(options.coherence) : 0.0) *
                           glm::dvec3(alignment[j]);

    std::vector<float> x(count), y(count), z(count);
    for (size_t i = 0; i < count; ++i) {
        x[i] = normals[i].x;
        y[i] = normals[i].y;
        z[i] = normals[i].z;
    }
    vmf::Samples samples{x.data(), y.data(), z.data(), weights, count};
    bool parallel = count >= 8 * vmf::kChunk && !omp_in_parallel();

    VmfFitResult result;
    vmf::EmOutcome outcome =
        alignment
            ? vmf::runSlotEm(samples, lobes, pull, options, parallel, &result.logLikelihoodTrace)
            : vmf::runEm(samples, lobes, options, parallel, &result.logLikelihoodTrace);
    result.lobes.assign(lobes.lobe, lobes.lobe + lobes.count);
    result.iterations = outcome.iterations;
    result.converged = outcome.converged;
    result.logLikelihood = outcome.logLikelihood;
    return result;
}

std::vector<VmfLobe> farthestPointLobes(const std::vector<VmfLobe>& candidates, int J) {
    vmf::LobeSet chosen;
    vmf::farthestPoint(candidates.data(), candidates.size(), J, chosen);
    return {chosen.lobe, chosen.lobe + chosen.count};
}

} // namespace ndfmip
