// A texel's exact filtered GGX NDF, read on rings about the lobe's axis (a mode of the
// footprint's normals near their mean, modeAxis): what ggx-fit and ggx-aniso fit their one lobe
// to. Filtering is the spherical convolution of the footprint's
// normal distribution with the material's lobe (Han et al. Sec. 3); with the footprint's normals
// n_i that is the mean of the material's GGX lobes about them, T(h) = mean_i D_a0(h . n_i).
//
// A lobe centred on the axis n is even in the azimuth phi about n, so only T's even
// azimuthal modes on the rings about n meet it: mode 0 (the ring means, all an isotropic lobe
// sees) and mode 2 (T's means times cos 2 phi and sin 2 phi: the elliptic part an anisotropic
// lobe sees). A normal at angle beta from n and azimuth phi_i adds to the ring at theta
// R0(theta, beta) to the mean and R2(theta, beta) (cos 2 phi_i, sin 2 phi_i) to mode 2, where
//   R_m(theta, beta) = 1/(2 pi) Int D_a0(cos theta cos beta + sin theta sin beta cos psi) cos(m
//   psi) dpsi
// depends on a0 alone: tabulated once per bake, each texel is a histogram of its normals'
// angles from n (weighted by cos 2 phi_i and sin 2 phi_i for mode 2). Every level-0 normal
// counts, at any level, in time linear in the footprint.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "ndfmip/bake.h"
#include "ndfmip/pyramid.h"

namespace ndfmip::ndf_rings {

constexpr float kMinAlpha = 1e-3f;

// R0 (and R2 when asked) on a grid of `steps` + 1 angles over [0, pi/2] each. The grid and the
// azimuths resolve the lobe: 8 steps and 8 azimuths across its width a0, down to a0 = 0.025
// (512 steps, 1024 azimuths; narrower lobes are resolved less finely).
struct RingTable {
    int steps = 0;
    float step = 0.f;
    std::vector<float> mean;   // R0 [theta][beta]: a ring's row holds every beta
    std::vector<float> second; // R2, the same layout (empty without mode 2)

    const float* ring(int t) const { return &mean[size_t(t) * size_t(steps + 1)]; }
    const float* secondRing(int t) const { return &second[size_t(t) * size_t(steps + 1)]; }
};

RingTable ringTable(float a0, bool secondMode);

// The material's lobes: one ring table per alpha of a geometric grid (ratio kAlphaRatio) over the
// roughness map's values, each normal's lobe split linearly in log alpha between its two
// neighbouring tables; without a map, one table at the material's alpha.
constexpr float kAlphaRatio = 1.15f;

struct MaterialLobes {
    std::vector<RingTable> tables;
    float logFirst = 0.f; // ln alpha of table 0
    SharedImage map;      // alpha per level-0 texel, clamped (null: every texel the material's)
    float alpha = 0.f;    // the material's alpha without a map
    bool secondMode = false;

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

// A material alpha below kMinFittedRoughness (the commands refuse it) is taken as that.
MaterialLobes materialLobes(const BakeOptions& options, bool secondMode);

// One texel's normals as angles from the axis: a histogram on the table's betas, each
// normal split linearly between its two neighbouring steps; with mode 2 the same weights times
// cos 2 phi_i and sin 2 phi_i.
struct AngleHistogram {
    std::vector<float> counts, cos2, sin2; // table.steps + 1, zero outside [first, last]
    int first = 0, last = -1;
    // The normals' steps, fractions and weights while few (with mode 2 their doubled azimuths'
    // cosines and sines beside them): a sum over them is cheaper than over the histogram's range
    // when that is wider than they are many.
    struct Entry {
        int b;
        float f, w;
    };
    std::vector<Entry> few;
    std::vector<std::pair<float, float>> fewModes; // (cos 2 phi, sin 2 phi), mode 2 only
    size_t entries = 0;                            // normals added, few or not
};

constexpr size_t kFewNormals = 64;
// A normal of the few costs about as much as this many steps of the histogram (whose sums the
// compiler vectorises).
constexpr size_t kFewCost = 8;

// One texel's normals: a histogram per table, and their lobes' mean alpha^2.
struct TexelNormals {
    std::vector<AngleHistogram> histograms;
    std::vector<int> used; // the tables with normals, once each
    float alpha2 = 0.f, total = 0.f;
    float narrowest = 1.f; // the least alpha among them
};

TexelNormals texelNormals(const MaterialLobes& lobes); // empty, sized for the lobes
void clearTexel(TexelNormals& t);

// acos to 7e-5 radians (Abramowitz and Stegun 4.4.45), a hundredth of the table's finest step;
// the histogram takes one per normal per level.
inline float fastAcos(float x) {
    const float a = std::abs(x);
    const float r =
        std::sqrt(1.f - a) * (1.5707288f + a * (-0.2121144f + a * (0.0742610f - 0.0187293f * a)));
    const float reflected = 3.14159265358979f - r; // made either way: a select, not a branch
    return x < 0.f ? reflected : r;
}

// A normal at angle beta from the axis, with weight w (and with mode 2 doubled azimuth (c2, s2)).
template <bool kSecondMode>
[[gnu::always_inline]] inline void addAngle(AngleHistogram& h, const RingTable& table, float beta,
                                            float w, float c2, float s2) {
    const float u = std::min(beta / table.step, float(table.steps));
    const int b = std::min(int(u), table.steps - 1);
    const float f = u - float(b);
    if (h.last < h.first) h.first = h.last = b;
    h.first = std::min(h.first, b), h.last = std::max(h.last, b + 1);
    h.counts[size_t(b)] += w * (1.f - f);
    h.counts[size_t(b) + 1] += w * f;
    if constexpr (kSecondMode) {
        h.cos2[size_t(b)] += w * (1.f - f) * c2;
        h.cos2[size_t(b) + 1] += w * f * c2;
        h.sin2[size_t(b)] += w * (1.f - f) * s2;
        h.sin2[size_t(b) + 1] += w * f * s2;
    }
    if (h.few.size() < kFewNormals) {
        h.few.push_back({b, f, w});
        if constexpr (kSecondMode) h.fewModes.emplace_back(c2, s2);
    }
    ++h.entries;
}

// The frame the azimuths are measured in: `axis` the lobe's (modeAxis), `tangent` and `bitangent`
// (used with mode 2 only) the directions of phi = 0 and phi = pi/2 about it.
struct RingFrame {
    float axis[3];
    float tangent[3];
    float bitangent[3];
};

// A footprint's level-0 normals as three planes (and, with a roughness map, their alphas),
// gathered once per texel for the mode's steps and the histogram: their loops then run over one
// long array instead of short rows of interleaved channels (a level-1 footprint is two rows of
// two). A footprint of more than kPlaneNormals normals is gathered a band of rows at a time.
constexpr size_t kPlaneNormals = size_t(1) << 16;

struct FootprintPlanes {
    std::vector<float> x, y, z, alpha;
    Footprint band{0, 0, 0, -1}; // the rows now gathered (none at first)
    // Scratch of angles, one band's worth: beta from the axis and, with mode 2, doubled azimuths.
    std::vector<float> beta, c2, s2;
    size_t count() const { return x.size(); }
};

inline void gatherBand(const Image& base, const MaterialLobes& lobes, const Footprint& band,
                       FootprintPlanes& p) {
    const size_t count = band.count();
    p.x.resize(count), p.y.resize(count), p.z.resize(count);
    p.alpha.resize(lobes.map ? count : 0);
    const int width = band.width();
    for (int y = band.y0; y < band.y1; ++y) {
        const float* row = base.at(band.x0, y);
        const size_t start = size_t(y - band.y0) * size_t(width);
        float *px = &p.x[start], *py = &p.y[start], *pz = &p.z[start];
        for (int i = 0; i < width; ++i)
            px[i] = row[3 * i], py[i] = row[3 * i + 1], pz[i] = row[3 * i + 2];
        if (lobes.map)
            for (int i = 0; i < width; ++i)
                p.alpha[start + size_t(i)] = lobes.alphaAt(band.x0 + i, y);
    }
    p.band = band;
}

// Calls fn(planes) on f's normals, a band of rows at a time; a footprint that fits in one band is
// gathered once for every call on it.
template <class Fn>
inline void forEachBand(const Image& base, const MaterialLobes& lobes, const Footprint& f,
                        FootprintPlanes& p, const Fn& fn) {
    const int rows = std::max(1, int(kPlaneNormals / size_t(std::max(f.width(), 1))));
    for (int y = f.y0; y < f.y1; y += rows) {
        const Footprint band{f.x0, f.x1, y, std::min(y + rows, f.y1)};
        if (!(band == p.band)) gatherBand(base, lobes, band, p);
        fn(p);
    }
}

// The gathered normals (not necessarily unit; the zero vector reads as the flat normal, as
// normalizeOrFlat has it) as angles `beta` from the frame's axis and, with mode 2, doubled
// azimuths (c2, s2) about it: a loop the compiler vectorises, ahead of the histogram's scattered
// adds. The doubled azimuth's cosine and sine are ratios of the normal's components, so only the
// cosine from the axis divides by its length.
template <bool kSecondMode> inline void bandAngles(const RingFrame& frame, FootprintPlanes& p) {
    const int count = int(p.count());
    p.beta.resize(size_t(count));
    if constexpr (kSecondMode) p.c2.resize(size_t(count)), p.s2.resize(size_t(count));
    const float *nx = p.x.data(), *ny = p.y.data(), *nz = p.z.data();
    float* beta = p.beta.data();
    float* c2 = p.c2.data();
    float* s2 = p.s2.data();
    const float a0 = frame.axis[0], a1 = frame.axis[1], a2 = frame.axis[2];
    const float t0 = frame.tangent[0], t1 = frame.tangent[1], t2 = frame.tangent[2];
    const float b0 = frame.bitangent[0], b1 = frame.bitangent[1], b2 = frame.bitangent[2];
#pragma omp simd
    for (int i = 0; i < count; ++i) {
        const float length2 = nx[i] * nx[i] + ny[i] * ny[i] + nz[i] * nz[i];
        const float length = std::sqrt(length2);
        // Every division made, then selected: a branch around one would keep the loop scalar.
        const bool flat = !(length > 0.f);
        const float u0 = flat ? 0.f : nx[i], u1 = flat ? 0.f : ny[i], u2 = flat ? 1.f : nz[i];
        const float scale = flat ? 1.f : length;
        const float c = (u0 * a0 + u1 * a1 + u2 * a2) / scale;
        beta[i] = fastAcos(std::min(std::max(c, -1.f), 1.f));
        if constexpr (kSecondMode) {
            const float x = u0 * t0 + u1 * t1 + u2 * t2;
            const float y = u0 * b0 + u1 * b1 + u2 * b2;
            const float rho2 = x * x + y * y;
            const bool polar = !(rho2 > 1e-12f * (flat ? 1.f : length2));
            const float r = polar ? 1.f : rho2;
            const float cosine = (x * x - y * y) / r, sine = 2.f * x * y / r;
            c2[i] = polar ? 0.f : cosine;
            s2[i] = polar ? 0.f : sine;
        }
    }
}

// Adds a normal at angle `beta` from the axis (with mode 2 doubled azimuth (c2, s2)) of lobe
// alpha `a`.
template <bool kSecondMode>
[[gnu::always_inline]] inline void addAngleOf(TexelNormals& t, const MaterialLobes& lobes,
                                              float beta, float a, float c2, float s2) {
    t.alpha2 += a * a;
    t.total += 1.f;
    t.narrowest = std::min(t.narrowest, a);
    if (!lobes.map) { // one table
        if (t.used.empty()) t.used.push_back(0);
        addAngle<kSecondMode>(t.histograms.front(), lobes.tables.front(), beta, 1.f, c2, s2);
        return;
    }
    const auto [k, share] = lobes.tableOf(a);
    for (int j = 0; j < 2; ++j) {
        const float w = j == 0 ? 1.f - share : share;
        if (!(w > 0.f)) continue;
        AngleHistogram& h = t.histograms[size_t(k + j)];
        if (h.entries == 0) t.used.push_back(k + j);
        addAngle<kSecondMode>(h, lobes.tables[size_t(k + j)], beta, w, c2, s2);
    }
}

// Adds the footprint's level-0 normals, a band at a time.
template <bool kSecondMode>
inline void addFootprintWithModes(TexelNormals& t, const MaterialLobes& lobes, const Image& base,
                                  const Footprint& f, const RingFrame& frame, FootprintPlanes& p) {
    forEachBand(base, lobes, f, p, [&](FootprintPlanes& band) {
        bandAngles<kSecondMode>(frame, band);
        const size_t count = band.count();
        for (size_t i = 0; i < count; ++i) {
            const float c2 = kSecondMode ? band.c2[i] : 0.f;
            const float s2 = kSecondMode ? band.s2[i] : 0.f;
            addAngleOf<kSecondMode>(t, lobes, band.beta[i], lobes.map ? band.alpha[i] : lobes.alpha,
                                    c2, s2);
        }
    });
}

inline void addFootprint(TexelNormals& t, const MaterialLobes& lobes, const Image& base,
                         const Footprint& f, const RingFrame& frame, FootprintPlanes& p) {
    if (lobes.secondMode)
        addFootprintWithModes<true>(t, lobes, base, f, frame, p);
    else
        addFootprintWithModes<false>(t, lobes, base, f, frame, p);
}

// T's modes on the ring at theta: its mean, and with mode 2 its means times cos 2 phi and
// sin 2 phi; linear in theta between the tables' two rings about it.
struct RingModes {
    float mean = 0.f, cos2 = 0.f, sin2 = 0.f;
};
inline RingModes ringModes(const TexelNormals& normals, const MaterialLobes& lobes, float theta);

// Toksvig's width sqrt(a0^2 + 2 sigma^2) (T eq. 1, roughness.h) for the normals' RMS alpha a0
// and |Na| = r: how far the rings reach.
inline float toksvigWidth(const TexelNormals& normals, float r);
// The same before the normals are gathered: a0 the material's alpha, or with a roughness map
// the RMS of its alphas over footprint f.
inline float lobeWidth(const MaterialLobes& lobes, const Footprint& f, float r);

// The rings a fit reads: `count` (at most kMaxRings) of equal width in theta up to tan(theta) =
// kReach x `width`, with the squared-difference weights of an L2 distance over the sphere (their
// solid angles / 2 pi).
constexpr int kMaxRings = 16;
constexpr float kReach = 3.5f;
struct Rings {
    int count = 0;
    float theta[kMaxRings], cosTheta[kMaxRings], weight[kMaxRings];
};
inline Rings rings(float width, int count);

// An isotropic lobe about the axis against T's ring means on kCount rings: the squared
// differences, weighted by the rings' solid angles (the L2 distance of the two NDFs over the
// sphere).
template <int kCount> struct IsotropicTarget {
    float cos2Theta[kCount], weight[kCount], mean[kCount];
};
template <int kCount>
IsotropicTarget<kCount> isotropicTarget(const Rings& ring, const float* mean) {
    IsotropicTarget<kCount> target;
    for (int j = 0; j < kCount; ++j) {
        target.cos2Theta[j] = ring.cosTheta[j] * ring.cosTheta[j];
        target.weight[j] = ring.weight[j], target.mean[j] = mean[j];
    }
    return target;
}
// The error of alpha = exp(logAlpha): GGX written out (ndfmipGgx: a^2 / (pi (c^2 (a^2 - 1) +
// 1)^2), c > 0 on every ring) in a loop of fixed length the compiler vectorises.
template <int kCount> float isotropicError(const IsotropicTarget<kCount>& target, float logAlpha) {
    const float a2 = std::exp(2.f * logAlpha), k = a2 * (1.f / 3.14159265358979f);
    float e = 0.f;
#pragma omp simd reduction(+ : e)
    for (int j = 0; j < kCount; ++j) {
        const float d = target.cos2Theta[j] * (a2 - 1.f) + 1.f;
        const float difference = k / (d * d) - target.mean[j];
        e += target.weight[j] * difference * difference;
    }
    return e;
}

// The least of f over [lo, hi]: a scan of `scan` + 1 points, then parabolic steps in the bracket
// about its best point (Brent's idea without his safeguards: the errors fitted here are smooth
// with one minimum in the bracket). The scan's end when the least is there.
template <typename F>
float minimiseOnScan(const F& f, float lo, float hi, int scan, int parabolicSteps) {
    float x[17], e[17];
    scan = std::min(scan, 16);
    int best = 0;
    for (int i = 0; i <= scan; ++i) {
        x[i] = lo + (hi - lo) * float(i) / float(scan);
        e[i] = f(x[i]);
        if (e[i] < e[best]) best = i;
    }
    if (best == 0 || best == scan) return x[best];
    float xa = x[best - 1], xb = x[best], xc = x[best + 1];
    float ea = e[best - 1], eb = e[best], ec = e[best + 1];
    for (int i = 0; i < parabolicSteps; ++i) {
        const float p = (xb - xa) * (eb - ec), q = (xb - xc) * (eb - ea);
        const float denominator = 2.f * (p - q);
        if (!(std::abs(denominator) > 0.f)) break;
        float xn = xb - ((xb - xa) * p - (xb - xc) * q) / denominator;
        // Keep the trial inside the bracket and off its best point.
        const float margin = 1e-3f * (xc - xa);
        xn = std::clamp(xn, xa + margin, xc - margin);
        if (std::abs(xn - xb) < margin) xn = xb + (xn < xb ? -margin : margin);
        const float en = f(xn);
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
    return xb;
}

// The lobe's axis: a mode of the footprint's level-0 normals, found by mean shift from their mean
// normal `axis` (unit, overwritten) with a GGX kernel of the lobe's width `width` (Toksvig's for
// the footprint): h <- normalize(Sum_i D_width(h . n_i) n_i). Where the normals are skewed (a
// flat texel with one steep side) their mean leans towards the few and an isotropic lobe about it
// puts its peak, and the highlight, where few normals are; about the mode the peak sits on the
// many and the fitted width takes the rest. kModeSteps steps: more gain nothing measurable
// (docs/RESULTS.md).
constexpr int kModeSteps = 3;

inline void modeAxis(const Image& base, const MaterialLobes& lobes, const Footprint& f, float width,
                     FootprintPlanes& p, float* axis) {
    const float w2m1 = width * width - 1.f;
    float h0 = axis[0], h1 = axis[1], h2 = axis[2];
    for (int step = 0; step < kModeSteps; ++step) {
        float s0 = 0.f, s1 = 0.f, s2 = 0.f;
        forEachBand(base, lobes, f, p, [&](const FootprintPlanes& band) {
            const size_t count = band.count();
            const float *nx = band.x.data(), *ny = band.y.data(), *nz = band.z.data();
            // Float sums of at most kSumRun terms each, then added up.
            constexpr size_t kSumRun = 4096;
            for (size_t start = 0; start < count; start += kSumRun) {
                const int run = int(std::min(kSumRun, count - start));
                const float *ux = nx + start, *uy = ny + start, *uz = nz + start;
                float r0 = 0.f, r1 = 0.f, r2 = 0.f;
#pragma omp simd reduction(+ : r0, r1, r2)
                for (int i = 0; i < run; ++i) {
                    const float c = std::max(ux[i] * h0 + uy[i] * h1 + uz[i] * h2, 0.f);
                    const float d = 1.f + w2m1 * c * c;
                    const float w = 1.f / (d * d); // D_width(c) up to its constant factor
                    r0 += w * ux[i], r1 += w * uy[i], r2 += w * uz[i];
                }
                s0 += r0, s1 += r1, s2 += r2;
            }
        });
        const float length = std::sqrt(s0 * s0 + s1 * s1 + s2 * s2);
        if (!(length > 0.f) || !std::isfinite(length)) return; // keep the mean normal
        const float moved =
            std::abs(s0 / length - h0) + std::abs(s1 / length - h1) + std::abs(s2 / length - h2);
        h0 = s0 / length, h1 = s1 / length, h2 = s2 / length;
        axis[0] = h0, axis[1] = h1, axis[2] = h2;
        if (moved < 1e-4f) return; // settled: a further step moves it less
    }
}

// The loop a fit's bake runs per level: every texel's lobe axis into `normal` (3 channels: its
// unit mean normal moved to a mode, modeAxis); at level 0 `own(i, x, y)` (one normal: the
// material's own lobe), above it `fit(i, normals, r)` with the texel's normals gathered on the
// rings of `frameOf(axis)` and r = |Na|.
template <class FrameOf, class Fit, class Own>
void fitLevel(const Pyramid& pyramid, const MaterialLobes& lobes, int k, Image& normal,
              const FrameOf& frameOf, const Fit& fit, const Own& own);

// ---- the inline definitions, on every texel's path ----------------------------------------

namespace detail {

// The table's value at entry e of a row.
inline float at(const float* row, const AngleHistogram::Entry& e) {
    return row[e.b] + e.f * (row[e.b + 1] - row[e.b]);
}

} // namespace detail

inline RingModes ringModes(const TexelNormals& normals, const MaterialLobes& lobes, float theta) {
    RingModes sum;
    for (int k : normals.used) {
        const AngleHistogram& h = normals.histograms[size_t(k)];
        const RingTable& table = lobes.tables[size_t(k)];
        const float u = std::min(theta / table.step, float(table.steps));
        const int t = std::min(int(u), table.steps - 1);
        const float s = u - float(t);
        const float* below = table.ring(t);
        const float* above = table.ring(t + 1);
        const bool few =
            h.entries <= kFewNormals && kFewCost * h.entries < size_t(h.last - h.first + 1);
        float meanBelow = 0.f, meanAbove = 0.f;
        if (few) {
            if (lobes.map) {
                for (const AngleHistogram::Entry& e : h.few)
                    meanBelow += e.w * detail::at(below, e),
                        meanAbove += e.w * detail::at(above, e);
            } else { // every weight 1
                for (const AngleHistogram::Entry& e : h.few)
                    meanBelow += detail::at(below, e), meanAbove += detail::at(above, e);
            }
        } else {
            const float* counts = h.counts.data();
#pragma omp simd reduction(+ : meanBelow, meanAbove)
            for (int b = h.first; b <= h.last; ++b) {
                meanBelow += counts[b] * below[b];
                meanAbove += counts[b] * above[b];
            }
        }
        sum.mean += meanBelow + s * (meanAbove - meanBelow);
        if (!lobes.secondMode) continue;
        const float* secondBelow = table.secondRing(t);
        const float* secondAbove = table.secondRing(t + 1);
        float cb = 0.f, ca = 0.f, sb = 0.f, sa = 0.f;
        if (few) {
            for (size_t i = 0; i < h.few.size(); ++i) {
                const AngleHistogram::Entry& e = h.few[i];
                const auto [c2, s2] = h.fewModes[i];
                const float rb = e.w * detail::at(secondBelow, e),
                            ra = e.w * detail::at(secondAbove, e);
                cb += rb * c2, ca += ra * c2, sb += rb * s2, sa += ra * s2;
            }
        } else {
            const float* cos2 = h.cos2.data();
            const float* sin2 = h.sin2.data();
#pragma omp simd reduction(+ : cb, ca, sb, sa)
            for (int b = h.first; b <= h.last; ++b) {
                cb += cos2[b] * secondBelow[b], ca += cos2[b] * secondAbove[b];
                sb += sin2[b] * secondBelow[b], sa += sin2[b] * secondAbove[b];
            }
        }
        sum.cos2 += cb + s * (ca - cb);
        sum.sin2 += sb + s * (sa - sb);
    }
    sum.mean /= normals.total, sum.cos2 /= normals.total, sum.sin2 /= normals.total;
    return sum;
}

namespace detail {
// sqrt(a0^2 + 2 sigma^2) for mean squared alpha a2 and |Na| = r, at most 2.
inline float widthOf(float a2, float r) {
    return std::min(std::sqrt(a2 + 2.f * (1.f - r) / std::max(r, 1e-3f)), 2.f);
}
} // namespace detail

inline float toksvigWidth(const TexelNormals& normals, float r) {
    return detail::widthOf(normals.alpha2 / normals.total, r);
}

inline float lobeWidth(const MaterialLobes& lobes, const Footprint& f, float r) {
    if (!lobes.map) return detail::widthOf(lobes.alpha * lobes.alpha, r);
    double sum = 0.;
    for (int y = f.y0; y < f.y1; ++y)
        for (int x = f.x0; x < f.x1; ++x) sum += double(lobes.alphaAt(x, y)) * lobes.alphaAt(x, y);
    return detail::widthOf(float(sum / double(f.count())), r);
}

inline Rings rings(float width, int count) {
    Rings out;
    out.count = count;
    // Edges' cosines by rotation; each ring's weight its solid angle / 2 pi.
    const float reach = std::atan(kReach * width), dTheta = reach / float(count);
    const float cosStep = std::cos(dTheta), sinStep = std::sin(dTheta);
    const float cosHalf = std::cos(0.5f * dTheta), sinHalf = std::sin(0.5f * dTheta);
    float cosLo = 1.f, sinLo = 0.f;
    for (int j = 0; j < count; ++j) {
        const float cosHi = cosLo * cosStep - sinLo * sinStep;
        const float sinHi = sinLo * cosStep + cosLo * sinStep;
        out.theta[j] = dTheta * (float(j) + 0.5f);
        out.cosTheta[j] = cosLo * cosHalf - sinLo * sinHalf;
        out.weight[j] = cosLo - cosHi;
        cosLo = cosHi, sinLo = sinHi;
    }
    return out;
}

template <class FrameOf, class Fit, class Own>
void fitLevel(const Pyramid& pyramid, const MaterialLobes& lobes, int k, Image& normal,
              const FrameOf& frameOf, const Fit& fit, const Own& own) {
    const Image& mean = levelMean(pyramid, k);
    const Image& base = *pyramid.base;
    const int width = mean.width;
    const int64_t texels = int64_t(mean.texelCount());
#pragma omp parallel
    {
        TexelNormals normals = texelNormals(lobes);
        FootprintPlanes planes;
#pragma omp for schedule(dynamic, 16)
        for (int64_t i = 0; i < texels; ++i) {
            const float* na = &mean.pixels[3 * size_t(i)];
            float* n = &normal.pixels[3 * size_t(i)];
            normalizeOrFlat(na, n);
            const int x = int(i % width), y = int(i / width);
            if (k == 0) {
                own(size_t(i), x, y);
                continue;
            }
            const Footprint f = footprint(pyramid, k, x, y);
            const float r = std::min(length3(na), 1.f);
            modeAxis(base, lobes, f, lobeWidth(lobes, f, r), planes, n);
            const RingFrame frame = frameOf(n);
            addFootprint(normals, lobes, base, f, frame, planes);
            fit(size_t(i), normals, r);
            clearTexel(normals);
        }
    }
}

} // namespace ndfmip::ndf_rings
