// ggx-fit: per texel and level, the one isotropic GGX lobe about the level's mean normal that
// best matches the texel's exact filtered NDF. Filtering is the spherical convolution of the
// footprint's normal distribution with the material's lobe (Han et al. Sec. 3); with the
// footprint's normals n_i that is the mean of the material's GGX lobes about them,
// T(h) = mean_i D_a0(h . n_i). The stored alpha minimises the L2 distance over the sphere between
// D_alpha(h . n) and T(h), n the footprint's mean normal (what an engine's normal mip holds): one
// lobe an engine loads as it is, in place of Toksvig's alpha^2 = a0^2 + 2 sigma^2, which follows
// the footprint's variance but not its shape.
//
// The lobe fitted is isotropic about n, so only T's means over rings about n matter. A normal at
// angle beta from n adds to the ring at angle theta the material's lobe averaged over the ring,
// R(theta, beta), which depends on a0 alone: it is tabulated once per bake, and each texel is a
// histogram of its normals' angles from n. Every level-0 normal counts, at any level, in time
// linear in the footprint.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "ndfmip/bake.h"
#include "ndfmip/glsl.h"
#include "ndfmip/shading.h"

namespace ndfmip {

namespace {

constexpr float kHalfPi = 0.5f * kPi;
constexpr int kRings = 16;     // rings of the fit about the mean normal
constexpr float kReach = 3.5f; // they reach tan(theta) = kReach x Toksvig's width
constexpr float kMinAlpha = 1e-3f;

// GGX over half vectors (Walter et al. 2007, eq. 33), the shaders' own.
inline float ggx(float cosH, float alpha) {
    return glsl().ndfmipGgx(cosH, alpha);
}

// R(theta, beta) on a grid of `steps` + 1 angles over [0, pi/2] each: the material's lobe about a
// direction at beta from the axis, averaged over the ring at theta about it. The grid and the
// azimuths resolve the lobe: 8 steps and 8 azimuths across its width a0, down to a0 = 0.025
// (512 steps, 1024 azimuths; narrower lobes are resolved less finely).
struct RingTable {
    int steps = 0;
    float step = 0.f;
    std::vector<float> values; // [theta][beta]: a ring's row holds every beta

    const float* ring(int t) const { return &values[size_t(t) * size_t(steps + 1)]; }
};

RingTable ringTable(float a0) {
    RingTable table;
    table.steps = std::clamp(int(std::ceil(8.f * kHalfPi / a0)), 256, 512);
    table.step = kHalfPi / float(table.steps);
    const int azimuths = std::clamp(int(std::ceil(8.f * kPi / a0)), 256, 1024);
    const int n = table.steps + 1;
    table.values.resize(size_t(n) * size_t(n));
    // Symmetric in the azimuth: the half ring [0, pi), midpoints.
    std::vector<float> cosPhi(static_cast<size_t>(azimuths));
    for (int m = 0; m < azimuths; ++m)
        cosPhi[size_t(m)] = std::cos(kPi * (float(m) + 0.5f) / float(azimuths));
#pragma omp parallel for schedule(dynamic, 4)
    for (int b = 0; b < n; ++b) {
        const float cb = std::cos(float(b) * table.step), sb = std::sin(float(b) * table.step);
        // R is symmetric in theta and beta: each pair once.
        for (int t = b; t < n; ++t) {
            const float ct = std::cos(float(t) * table.step), st = std::sin(float(t) * table.step);
            float sum = 0.f;
            for (float c : cosPhi) sum += ggx(ct * cb + st * sb * c, a0);
            table.values[size_t(t) * size_t(n) + size_t(b)] = sum / float(azimuths);
            table.values[size_t(b) * size_t(n) + size_t(t)] = sum / float(azimuths);
        }
    }
    return table;
}

// One texel's normals as angles from its mean normal: a histogram on the table's betas, each
// normal split linearly between its two neighbouring steps.
struct AngleHistogram {
    std::vector<float> counts; // table.steps + 1, zero outside [first, last]
    int first = 0, last = -1;
    // The normals' steps, fractions and weights while few: a sum over them is cheaper than over
    // the histogram's range when that is wider than they are many.
    struct Entry {
        int b;
        float f, w;
    };
    std::vector<Entry> few;
    size_t entries = 0; // normals added, few or not
};

constexpr size_t kFewNormals = 64;

// acos to 7e-5 radians (Abramowitz and Stegun 4.4.45), a hundredth of the table's finest step;
// the histogram takes one per normal per level.
inline float fastAcos(float x) {
    const float a = std::abs(x);
    const float r =
        std::sqrt(1.f - a) * (1.5707288f + a * (-0.2121144f + a * (0.0742610f - 0.0187293f * a)));
    return x < 0.f ? kPi - r : r;
}

// A normal at angle beta from the axis, with weight w.
inline void addAngle(AngleHistogram& h, const RingTable& table, float beta, float w) {
    const float u = std::min(beta / table.step, float(table.steps));
    const int b = std::min(int(u), table.steps - 1);
    const float f = u - float(b);
    if (h.last < h.first) h.first = h.last = b;
    h.first = std::min(h.first, b), h.last = std::max(h.last, b + 1);
    h.counts[size_t(b)] += w * (1.f - f);
    h.counts[size_t(b) + 1] += w * f;
    if (h.few.size() < kFewNormals) h.few.push_back({b, f, w});
    ++h.entries;
}

void clearHistogram(AngleHistogram& h) {
    if (h.last >= h.first)
        std::fill(h.counts.begin() + h.first, h.counts.begin() + h.last + 1, 0.f);
    h.first = 0, h.last = -1;
    h.few.clear();
    h.entries = 0;
}

// The material's lobes: one ring table per alpha of a geometric grid (ratio kAlphaRatio) over the
// roughness map's values, each normal's lobe split linearly in log alpha between its two
// neighbouring tables; without a map, one table at the material's alpha.
constexpr float kAlphaRatio = 1.15f;

struct MaterialLobes {
    std::vector<RingTable> tables;
    float logFirst = 0.f; // ln alpha of table 0
    SharedImage map;      // alpha per level-0 texel, clamped (null: every texel the material's)
    float alpha = 0.f;    // the material's alpha without a map

    float alphaAt(int x, int y) const { return map ? map->at(x, y)[0] : alpha; }
    // Table k and the share of table k + 1 for a lobe of alpha a.
    std::pair<int, float> tableOf(float a) const {
        if (tables.size() == 1) return {0, 0.f};
        const float u = std::clamp((std::log(a) - logFirst) / std::log(kAlphaRatio), 0.f,
                                   float(tables.size() - 1));
        const int k = std::min(int(u), int(tables.size()) - 2);
        return {k, u - float(k)};
    }
};

MaterialLobes materialLobes(const BakeOptions& options) {
    MaterialLobes lobes;
    lobes.alpha = std::clamp(options.baseRoughness, kMinFittedRoughness, 1.f);
    if (!options.roughnessMap) {
        lobes.tables.push_back(ringTable(lobes.alpha));
        lobes.logFirst = std::log(lobes.alpha);
        return lobes;
    }
    // The map's own alpha, its first channel (as toksvig reads it).
    const Image& given = *options.roughnessMap;
    auto map = std::make_shared<Image>(given.width, given.height, 1, Image::Uninitialized{});
    float lo = 1.f, hi = kMinFittedRoughness;
    for (size_t i = 0; i < map->texelCount(); ++i) {
        const float a =
            std::clamp(given.pixels[i * size_t(given.channels)], kMinFittedRoughness, 1.f);
        map->pixels[i] = a;
        lo = std::min(lo, a), hi = std::max(hi, a);
    }
    lobes.map = std::move(map);
    lobes.logFirst = std::log(lo);
    const int count = 1 + int(std::ceil(std::log(hi / lo) / std::log(kAlphaRatio) - 1e-4f));
    for (int k = 0; k < count; ++k)
        lobes.tables.push_back(
            ringTable(std::exp(lobes.logFirst + float(k) * std::log(kAlphaRatio))));
    return lobes;
}

// One texel's normals: a histogram per table, and their lobes' mean alpha^2.
struct TexelNormals {
    std::vector<AngleHistogram> histograms;
    std::vector<int> used; // the tables with normals, once each
    float alpha2 = 0.f, total = 0.f;
    float narrowest = 1.f; // the least alpha among them
};

inline void addNormal(TexelNormals& t, const MaterialLobes& lobes, const float* n, float a,
                      const float axis[3]) {
    float unit[3];
    normalizeOrFlat(n, unit);
    const float c = unit[0] * axis[0] + unit[1] * axis[1] + unit[2] * axis[2];
    const float beta = fastAcos(std::clamp(c, -1.f, 1.f));
    t.alpha2 += a * a;
    t.total += 1.f;
    t.narrowest = std::min(t.narrowest, a);
    if (!lobes.map) { // one table
        if (t.used.empty()) t.used.push_back(0);
        addAngle(t.histograms.front(), lobes.tables.front(), beta, 1.f);
        return;
    }
    const auto [k, share] = lobes.tableOf(a);
    for (int j = 0; j < 2; ++j) {
        const float w = j == 0 ? 1.f - share : share;
        if (!(w > 0.f)) continue;
        AngleHistogram& h = t.histograms[size_t(k + j)];
        if (h.entries == 0) t.used.push_back(k + j);
        addAngle(h, lobes.tables[size_t(k + j)], beta, w);
    }
}

void clearTexel(TexelNormals& t) {
    for (int k : t.used) clearHistogram(t.histograms[size_t(k)]);
    t.used.clear();
    t.alpha2 = t.total = 0.f;
    t.narrowest = 1.f;
}

// T on the ring at theta: the normals' ring means, table by table, linear in theta between the
// table's two rings about it.
float ringTarget(const TexelNormals& normals, const MaterialLobes& lobes, float theta) {
    float sum = 0.f;
    for (int k : normals.used) {
        const AngleHistogram& h = normals.histograms[size_t(k)];
        const RingTable& table = lobes.tables[size_t(k)];
        const float u = std::min(theta / table.step, float(table.steps));
        const int t = std::min(int(u), table.steps - 1);
        const float* below = table.ring(t);
        const float* above = table.ring(t + 1);
        float sumBelow = 0.f, sumAbove = 0.f;
        if (h.entries <= kFewNormals && 2 * h.entries < size_t(h.last - h.first + 1)) {
            if (lobes.map) {
                for (const AngleHistogram::Entry& e : h.few) {
                    sumBelow += e.w * (below[e.b] + e.f * (below[e.b + 1] - below[e.b]));
                    sumAbove += e.w * (above[e.b] + e.f * (above[e.b + 1] - above[e.b]));
                }
            } else { // every weight 1
                for (const AngleHistogram::Entry& e : h.few) {
                    sumBelow += below[e.b] + e.f * (below[e.b + 1] - below[e.b]);
                    sumAbove += above[e.b] + e.f * (above[e.b + 1] - above[e.b]);
                }
            }
        } else {
            for (int b = h.first; b <= h.last; ++b) {
                sumBelow += h.counts[size_t(b)] * below[b];
                sumAbove += h.counts[size_t(b)] * above[b];
            }
        }
        sum += sumBelow + (u - float(t)) * (sumAbove - sumBelow);
    }
    return sum / normals.total;
}

// The fitted alpha of one texel: `r` its mean normal's length |Na|. The error is the squared
// difference on kRings rings about the mean normal, weighted by their solid angles: the L2
// distance of the two NDFs over the sphere.
float fitTexel(const TexelNormals& normals, const MaterialLobes& lobes, float r) {
    if (!(normals.total > 0.f)) return lobes.alpha;
    const float a0 = std::sqrt(normals.alpha2 / normals.total); // RMS alpha
    // Rings of equal width in theta up to tan(theta) = kReach x Toksvig's width, sqrt(a0^2 +
    // 2 sigma^2) (T eq. 1, roughness.h); their edges' cosines by rotation, the weights being the
    // rings' solid angles / 2 pi.
    const float width = std::min(std::sqrt(a0 * a0 + 2.f * (1.f - r) / std::max(r, 1e-3f)), 2.f);
    float cosTheta[kRings], target[kRings], weight[kRings];
    const float reach = std::atan(kReach * width), dTheta = reach / float(kRings);
    const float cosStep = std::cos(dTheta), sinStep = std::sin(dTheta);
    const float cosHalf = std::cos(0.5f * dTheta), sinHalf = std::sin(0.5f * dTheta);
    float cosLo = 1.f, sinLo = 0.f;
    for (int j = 0; j < kRings; ++j) {
        const float cosHi = cosLo * cosStep - sinLo * sinStep;
        const float sinHi = sinLo * cosStep + cosLo * sinStep;
        const float theta = dTheta * (float(j) + 0.5f);
        cosTheta[j] = cosLo * cosHalf - sinLo * sinHalf;
        weight[j] = cosLo - cosHi;
        cosLo = cosHi, sinLo = sinHi;
        target[j] = ringTarget(normals, lobes, theta);
    }
    auto error = [&](float logAlpha) {
        const float a = std::exp(logAlpha);
        float e = 0.f;
        for (int j = 0; j < kRings; ++j) {
            const float d = ggx(cosTheta[j], a) - target[j];
            e += weight[j] * d * d;
        }
        return e;
    };
    // A scan over log alpha, then parabolic steps in the bracket about its best point (Brent's
    // idea without his safeguards: the error is smooth and has one minimum in the bracket).
    const float lo = std::log(std::max(0.5f * normals.narrowest, kMinAlpha)), hi = 0.f;
    constexpr int kScan = 8, kParabolicSteps = 6;
    float x[kScan + 1], e[kScan + 1];
    int best = 0;
    for (int i = 0; i <= kScan; ++i) {
        x[i] = lo + (hi - lo) * float(i) / kScan;
        e[i] = error(x[i]);
        if (e[i] < e[best]) best = i;
    }
    if (best == 0 || best == kScan) return std::min(std::exp(x[best]), 1.f);
    float xa = x[best - 1], xb = x[best], xc = x[best + 1];
    float ea = e[best - 1], eb = e[best], ec = e[best + 1];
    for (int i = 0; i < kParabolicSteps; ++i) {
        const float p = (xb - xa) * (eb - ec), q = (xb - xc) * (eb - ea);
        const float denominator = 2.f * (p - q);
        if (!(std::abs(denominator) > 0.f)) break;
        float xn = xb - ((xb - xa) * p - (xb - xc) * q) / denominator;
        // Keep the trial inside the bracket and off its best point.
        const float margin = 1e-3f * (xc - xa);
        xn = std::clamp(xn, xa + margin, xc - margin);
        if (std::abs(xn - xb) < margin) xn = xb + (xn < xb ? -margin : margin);
        const float en = error(xn);
        if (en < eb) {
            if (xn < xb)
                xc = xb, ec = eb;
            else
                xa = xb, ea = eb;
            xb = xn, eb = en;
        } else {
            if (xn < xb)
                xa = xn, ea = en;
            else
                xc = xn, ec = en;
        }
    }
    return std::min(std::exp(xb), 1.f);
}

} // namespace

Bake bakeGgxFit(const Pyramid& pyramid, const BakeOptions& options) {
    Bake bake;
    bake.method = Method::GgxFit;
    bake.parameters["base_roughness"] = options.baseRoughness;
    if (options.roughnessMap) bake.parameters["roughness_map"] = 1.0;
    bake.planes = {
        {"normal", {"n.x", "n.y", "n.z"}, "mean normal renormalised to unit length", true},
        {"roughness_ggx",
         {"alpha"},
         "GGX alpha of the one lobe about the normal closest to the texel's filtered NDF",
         true},
    };
    // A material alpha below kMinFittedRoughness (the commands refuse it) is fitted as that.
    const MaterialLobes lobes = materialLobes(options);
    const Image& base = *pyramid.base;
    const int count = int(pyramid.levels.size());
    bake.levels.resize(count);
    for (int k = 0; k < count; ++k) {
        const Image& mean = levelMean(pyramid, k);
        Image normal(mean.width, mean.height, 3, Image::Uninitialized{});
        Image alpha(mean.width, mean.height, 1, Image::Uninitialized{});
        const int width = mean.width;
        const int64_t texels = int64_t(mean.texelCount());
#pragma omp parallel
        {
            TexelNormals normals;
            normals.histograms.resize(lobes.tables.size());
            for (size_t t = 0; t < lobes.tables.size(); ++t)
                normals.histograms[t].counts.assign(size_t(lobes.tables[t].steps) + 1, 0.f);
#pragma omp for schedule(dynamic, 16)
            for (int64_t i = 0; i < texels; ++i) {
                const float* na = &mean.pixels[3 * size_t(i)];
                float* n = &normal.pixels[3 * size_t(i)];
                normalizeOrFlat(na, n);
                const int x = int(i % width), y = int(i / width);
                if (k == 0) {
                    alpha.pixels[size_t(i)] = lobes.alphaAt(x, y); // one normal: its own lobe
                    continue;
                }
                const Footprint f = footprint(pyramid, k, x, y);
                for (int by = f.y0; by < f.y1; ++by)
                    for (int bx = f.x0; bx < f.x1; ++bx)
                        addNormal(normals, lobes, base.at(bx, by), lobes.alphaAt(bx, by), n);
                alpha.pixels[size_t(i)] = fitTexel(normals, lobes, std::min(length3(na), 1.f));
                clearTexel(normals);
            }
        }
        bake.levels[k] = {std::make_shared<const Image>(std::move(normal)),
                          std::make_shared<const Image>(std::move(alpha))};
        if (options.progress) options.progress(k + 1, count);
    }
    return bake;
}

} // namespace ndfmip
