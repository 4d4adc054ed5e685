// Seeding a texel's EM by agglomeration of its children's lobes (see mergedLobes in vmf.h).
#include <algorithm>
#include <cmath>
#include <vector>

#include "methods/vmf/vmf_internal.h"

namespace ndfmip {
namespace vmf {
namespace {

// A lobe as the merge sees it: its moments and the log of its smoothed concentration.
struct Cluster {
    double alpha = 0;
    glm::dvec3 mean{0.0}; // alpha r mu
    VmfLobe lobe;         // mu and kappa from the moments (other fields: the first candidate's)
    double logSmoothed = 0;
    bool live = false;
};

double smoothedKappa(double kappa, double s) {
    return std::max(kappa * s / (kappa + s), 1e-12);
}

// The lobe of a cluster's moments.
void settle(Cluster& c, const VmfFitOptions& options, double s) {
    const double length = glm::length(c.mean);
    if (length > 0 && std::isfinite(length)) c.lobe.mu = glm::vec3(c.mean / length);
    c.lobe.alpha = float(c.alpha);
    c.lobe.kappa = float(kappaOf(length / c.alpha, options));
    c.logSmoothed = std::log(smoothedKappa(c.lobe.kappa, s));
}

// Runnalls' loss of merging a and b (vmf.h).
double mergeLoss(const Cluster& a, const Cluster& b, const VmfFitOptions& options, double s) {
    const double alpha = a.alpha + b.alpha;
    const double kappa = kappaOf(glm::length(a.mean + b.mean) / alpha, options);
    return alpha * -std::log(smoothedKappa(kappa, s)) + a.alpha * a.logSmoothed +
           b.alpha * b.logSmoothed;
}

} // namespace

void mergeCandidates(const VmfLobe* candidates, size_t count, int J, const VmfFitOptions& options,
                     LobeSet& out, double maxLoss) {
    J = std::clamp(J, 1, kMaxVmfLobes);
    const double s = std::max(double(options.mergeSmoothing), 1e-6);
    thread_local std::vector<Cluster> clusters;
    thread_local std::vector<double> loss; // n x n, upper triangle used
    clusters.clear();
    for (size_t i = 0; i < count; ++i) {
        const VmfLobe& lobe = candidates[i];
        if (!(lobe.alpha > 0) || !std::isfinite(lobe.alpha)) continue;
        Cluster c;
        c.alpha = lobe.alpha;
        c.lobe = lobe;
        const double length = glm::length(glm::dvec3(lobe.mu));
        const glm::dvec3 mu = length > 0 ? glm::dvec3(lobe.mu) / length : glm::dvec3(0, 0, 1);
        c.lobe.mu = glm::vec3(mu);
        c.lobe.kappa = std::clamp(std::isnan(lobe.kappa) ? 0.f : lobe.kappa, 0.f,
                                  std::max(options.kappaMax, 0.f));
        c.mean = c.alpha * meanLengthOf(c.lobe.kappa, options) * mu;
        c.logSmoothed = std::log(smoothedKappa(c.lobe.kappa, s));
        c.live = true;
        clusters.push_back(c);
    }
    const size_t n = clusters.size();
    size_t live = n;
    if (live > size_t(J) || (live > 1 && maxLoss >= 0)) {
        loss.assign(n * n, 0.0);
        for (size_t i = 0; i < n; ++i)
            for (size_t j = i + 1; j < n; ++j)
                loss[i * n + j] = mergeLoss(clusters[i], clusters[j], options, s);
        while (live > 1) {
            size_t bi = 0, bj = 0;
            double best = INFINITY;
            for (size_t i = 0; i < n; ++i) {
                if (!clusters[i].live) continue;
                for (size_t j = i + 1; j < n; ++j)
                    if (clusters[j].live && loss[i * n + j] < best)
                        best = loss[i * n + j], bi = i, bj = j;
            }
            if (bi == bj) break;                                // only NaN losses left
            if (live <= size_t(J) && !(best <= maxLoss)) break; // J reached, the rest cost too much
            Cluster& into = clusters[bi];
            into.alpha += clusters[bj].alpha;
            into.mean += clusters[bj].mean;
            settle(into, options, s);
            clusters[bj].live = false;
            --live;
            for (size_t k = 0; k < n; ++k) {
                if (k == bi || !clusters[k].live) continue;
                const double l = mergeLoss(into, clusters[k], options, s);
                loss[std::min(k, bi) * n + std::max(k, bi)] = l;
            }
        }
    }
    out.count = 0;
    double total = 0;
    for (const Cluster& c : clusters)
        if (c.live) total += c.alpha;
    for (const Cluster& c : clusters) {
        if (!c.live || out.count == kMaxVmfLobes) continue;
        VmfLobe& lobe = out.lobe[out.count++];
        lobe = c.lobe;
        lobe.alpha = float(c.alpha / total);
    }
    std::stable_sort(out.lobe, out.lobe + out.count,
                     [](const VmfLobe& a, const VmfLobe& b) { return a.alpha > b.alpha; });
}

} // namespace vmf

std::vector<VmfLobe> mergedLobes(const std::vector<VmfLobe>& candidates, int J,
                                 const VmfFitOptions& options) {
    vmf::LobeSet merged;
    vmf::mergeCandidates(candidates.data(), candidates.size(), J, options, merged);
    return {merged.lobe, merged.lobe + merged.count};
}

} // namespace ndfmip
