// The tabulated ground truth under an environment (environment_truth_table.h).
#include "environment_truth_table.h"

#include <algorithm>
#include <cmath>
#include <mutex>
#include <numeric>
#include <thread>
#include <utility>

#include "core/splitmix.h"
#include "environment_truth.h"

namespace ndfmip {

namespace {

constexpr int kSize = kEnvironmentTruthTableSize;

// Node (x, y) sits at octahedral (-1 + 2x/(size - 1), -1 + 2y/(size - 1)).
float nodeCoordinate(int i) {
    return -1.f + 2.f * float(i) / float(kSize - 1);
}

bool sameMaterial(const Material& a, const Material& b) {
    return a.brdf == b.brdf && a.exponent == b.exponent && a.roughness == b.roughness &&
           a.albedo == b.albedo && a.specular == b.specular && a.table == b.table &&
           a.factor == b.factor;
}

bool sameKey(const EnvironmentTruthKey& a, const EnvironmentTruthKey& b) {
    return a.lighting == b.lighting && sameMaterial(a.material, b.material) && a.view == b.view &&
           a.toEnvironment == b.toEnvironment && a.samples == b.samples &&
           a.estimator == b.estimator && a.seed == b.seed;
}

} // namespace

glm::vec2 octahedralEncode(glm::vec3 n) {
    const float sum = std::abs(n.x) + std::abs(n.y) + std::abs(n.z);
    if (!(sum > 0.f)) return glm::vec2(0.f);
    glm::vec2 p(n.x / sum, n.y / sum);
    if (n.z < 0.f) // the lower hemisphere folded over the diamond's edges
        p = glm::vec2((1.f - std::abs(p.y)) * (p.x < 0.f ? -1.f : 1.f),
                      (1.f - std::abs(p.x)) * (p.y < 0.f ? -1.f : 1.f));
    return p;
}

glm::vec3 octahedralDecode(glm::vec2 p) {
    glm::vec3 n(p.x, p.y, 1.f - std::abs(p.x) - std::abs(p.y));
    if (n.z < 0.f)
        n = glm::vec3((1.f - std::abs(p.y)) * (p.x < 0.f ? -1.f : 1.f),
                      (1.f - std::abs(p.x)) * (p.y < 0.f ? -1.f : 1.f), n.z);
    return glm::normalize(n);
}

EnvironmentTruthTable::EnvironmentTruthTable(const EnvironmentTruthKey& key)
    : key_(key), nodes_(size_t(kSize) * size_t(kSize)),
      state_(new std::atomic<int>[size_t(kSize) * size_t(kSize)]) {
    for (size_t i = 0; i < nodes_.size(); ++i) state_[i].store(0, std::memory_order_relaxed);
}

// The node's mean of `samples` estimates, its environment and BRDF numbers stratified on one
// jittered grid each (the BRDF's cells in a shuffled order, so the pairs do not line up), and
// the variance of its luminance's mean (the per-estimate spread over the count: stratification
// makes it an upper bound, as for the sampled truth's pixels).
void EnvironmentTruthTable::estimate(size_t index, Node& out) const {
    const int x = int(index % size_t(kSize)), y = int(index / size_t(kSize));
    const glm::vec3 n = octahedralDecode(glm::vec2(nodeCoordinate(x), nodeCoordinate(y)));
    const int count = std::max(key_.samples, 1);
    int gx = 1, gy = 1;
    strataGrid(count, gx, gy);
    SplitMix64 random{key_.seed * 0x9E3779B97F4A7C15ull + uint64_t(index) * 0xD1B54A32D192ED03ull};
    std::vector<int> order(static_cast<size_t>(count));
    std::iota(order.begin(), order.end(), 0);
    for (size_t i = order.size(); i > 1; --i) // Fisher-Yates
        std::swap(order[i - 1], order[size_t(random.next() % uint64_t(i))]);
    glm::dvec3 sum(0.);
    double sumY = 0., sumY2 = 0.;
    for (int i = 0; i < count; ++i) {
        const int j = order[size_t(i)];
        double u[5];
        u[0] = (double(i % gx) + random.uniformDouble()) / double(gx);
        u[1] = (double(i / gx) + random.uniformDouble()) / double(gy);
        u[2] = (double(j % gx) + random.uniformDouble()) / double(gx);
        u[3] = (double(j / gx) + random.uniformDouble()) / double(gy);
        u[4] = random.uniformDouble();
        const glm::vec3 r =
            estimateEnvironmentRadiance(*key_.lighting, key_.toEnvironment, key_.material,
                                        key_.material.albedo, n, key_.view, key_.estimator, u);
        sum += glm::dvec3(r);
        const double lum = rec709Luminance(glm::dvec3(r));
        sumY += lum;
        sumY2 += lum * lum;
    }
    const double c = double(count);
    out.radiance = glm::vec3(sum / c);
    out.variance = count > 1 ? std::max(0., (sumY2 - sumY * sumY / c) / (c - 1.)) / c : 0.;
}

const EnvironmentTruthTable::Node& EnvironmentTruthTable::node(int x, int y) const {
    const size_t i = size_t(y) * size_t(kSize) + size_t(x);
    if (state_[i].load(std::memory_order_acquire) == 2) return nodes_[i];
    int expected = 0;
    if (state_[i].compare_exchange_strong(expected, 1, std::memory_order_acq_rel)) {
        estimate(i, nodes_[i]);
        state_[i].store(2, std::memory_order_release);
    } else {
        while (state_[i].load(std::memory_order_acquire) != 2) std::this_thread::yield();
    }
    return nodes_[i];
}

void EnvironmentTruthNoise::add(size_t node, double w) {
    if (weight.empty()) weight.assign(size_t(kSize) * size_t(kSize), 0.);
    if (weight[node] == 0.) read.push_back(node);
    weight[node] += w;
}

double EnvironmentTruthNoise::take(const EnvironmentTruthTable& table) {
    double sum = 0.;
    for (size_t node : read) {
        sum += weight[node] * weight[node] * table.variance(node);
        weight[node] = 0.;
    }
    read.clear();
    return sum;
}

glm::vec3 EnvironmentTruthTable::radiance(glm::vec3 n, EnvironmentTruthNoise* noise,
                                          double weight) const {
    const glm::vec2 p = (octahedralEncode(n) + 1.f) * (0.5f * float(kSize - 1));
    const int x0 = std::clamp(int(std::floor(p.x)), 0, kSize - 2);
    const int y0 = std::clamp(int(std::floor(p.y)), 0, kSize - 2);
    const float fx = std::clamp(p.x - float(x0), 0.f, 1.f),
                fy = std::clamp(p.y - float(y0), 0.f, 1.f);
    const float w[4] = {(1.f - fx) * (1.f - fy), fx * (1.f - fy), (1.f - fx) * fy, fx * fy};
    const int dx[4] = {0, 1, 0, 1}, dy[4] = {0, 0, 1, 1};
    glm::vec3 out(0.f);
    for (int k = 0; k < 4; ++k) {
        if (!(w[k] > 0.f)) continue;
        const int x = x0 + dx[k], y = y0 + dy[k];
        out += w[k] * node(x, y).radiance;
        if (noise) noise->add(size_t(y) * size_t(kSize) + size_t(x), weight * double(w[k]));
    }
    return out;
}

size_t EnvironmentTruthTable::nodesEstimated() const {
    size_t count = 0;
    for (size_t i = 0; i < nodes_.size(); ++i)
        count += state_[i].load(std::memory_order_acquire) == 2 ? 1 : 0;
    return count;
}

std::shared_ptr<const EnvironmentTruthTable> environmentTruthTable(const EnvironmentTruthKey& key) {
    // A kept table's key does not own its lighting, so that a lighting no longer held anywhere
    // (an evaluation's environment once the evaluation is done) is freed, and its tables are
    // dropped at the next lookup; what a caller gets holds the lighting with the table.
    struct Kept {
        std::weak_ptr<const EnvironmentLighting> lighting;
        std::shared_ptr<const EnvironmentTruthTable> table;
    };
    constexpr size_t kKept = 4;
    static std::mutex mutex;
    static std::vector<Kept> kept; // most recent last
    auto held = [&key](const std::shared_ptr<const EnvironmentTruthTable>& table) {
        using Both = std::pair<std::shared_ptr<const EnvironmentTruthTable>,
                               std::shared_ptr<const EnvironmentLighting>>;
        auto both = std::make_shared<const Both>(table, key.lighting);
        return std::shared_ptr<const EnvironmentTruthTable>(both, both->first.get());
    };
    std::lock_guard<std::mutex> lock(mutex);
    // Before any match: a lighting made where a freed one was must not find the freed one's tables.
    std::erase_if(kept, [](const Kept& k) { return k.lighting.expired(); });
    for (size_t i = 0; i < kept.size(); ++i)
        if (sameKey(kept[i].table->key(), key)) {
            Kept found = kept[i];
            kept.erase(kept.begin() + long(i));
            kept.push_back(found);
            return held(found.table);
        }
    EnvironmentTruthKey unowned = key;
    unowned.lighting = std::shared_ptr<const EnvironmentLighting>(
        std::shared_ptr<const EnvironmentLighting>(), key.lighting.get());
    auto made = std::make_shared<const EnvironmentTruthTable>(unowned);
    kept.push_back({key.lighting, made});
    if (kept.size() > kKept) kept.erase(kept.begin());
    return held(made);
}

} // namespace ndfmip
