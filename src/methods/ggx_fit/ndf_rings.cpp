// A texel's filtered NDF on rings about the lobe's axis (ndf_rings.h).
#include "methods/ggx_fit/ndf_rings.h"

#include "ndfmip/glsl.h"
#include "ndfmip/shading.h"

namespace ndfmip::ndf_rings {

namespace {

constexpr float kHalfPi = 0.5f * kPi;

// GGX over half vectors (Walter et al. 2007, eq. 33), the shaders' own.
inline float ggx(float cosH, float alpha) {
    return glsl().ndfmipGgx(cosH, alpha);
}

} // namespace

RingTable ringTable(float a0, bool secondMode) {
    RingTable table;
    table.steps = std::clamp(int(std::ceil(8.f * kHalfPi / a0)), 256, 512);
    table.step = kHalfPi / float(table.steps);
    const int azimuths = std::clamp(int(std::ceil(8.f * kPi / a0)), 256, 1024);
    const int n = table.steps + 1;
    table.mean.resize(size_t(n) * size_t(n));
    if (secondMode) table.second.resize(size_t(n) * size_t(n));
    // Symmetric in the azimuth: the half ring [0, pi), midpoints.
    std::vector<float> cosPsi(static_cast<size_t>(azimuths)), cos2Psi(cosPsi.size());
    for (int m = 0; m < azimuths; ++m) {
        const float psi = kPi * (float(m) + 0.5f) / float(azimuths);
        cosPsi[size_t(m)] = std::cos(psi), cos2Psi[size_t(m)] = std::cos(2.f * psi);
    }
#pragma omp parallel for schedule(dynamic, 4)
    for (int b = 0; b < n; ++b) {
        const float cb = std::cos(float(b) * table.step), sb = std::sin(float(b) * table.step);
        // R_m is symmetric in theta and beta: each pair once.
        for (int t = b; t < n; ++t) {
            const float ct = std::cos(float(t) * table.step), st = std::sin(float(t) * table.step);
            float sum = 0.f, sum2 = 0.f;
            if (secondMode) {
                for (size_t m = 0; m < cosPsi.size(); ++m) {
                    const float d = ggx(ct * cb + st * sb * cosPsi[m], a0);
                    sum += d, sum2 += d * cos2Psi[m];
                }
            } else {
                for (float c : cosPsi) sum += ggx(ct * cb + st * sb * c, a0);
            }
            const size_t tb = size_t(t) * size_t(n) + size_t(b),
                         bt = size_t(b) * size_t(n) + size_t(t);
            table.mean[tb] = table.mean[bt] = sum / float(azimuths);
            if (secondMode) table.second[tb] = table.second[bt] = sum2 / float(azimuths);
        }
    }
    return table;
}

MaterialLobes materialLobes(const BakeOptions& options, bool secondMode) {
    MaterialLobes lobes;
    lobes.secondMode = secondMode;
    lobes.alpha = std::clamp(options.baseRoughness, kMinFittedRoughness, 1.f);
    if (!options.roughnessMap) {
        lobes.tables.push_back(ringTable(lobes.alpha, secondMode));
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
            ringTable(std::exp(lobes.logFirst + float(k) * std::log(kAlphaRatio)), secondMode));
    return lobes;
}

TexelNormals texelNormals(const MaterialLobes& lobes) {
    TexelNormals normals;
    normals.histograms.resize(lobes.tables.size());
    for (size_t t = 0; t < lobes.tables.size(); ++t) {
        AngleHistogram& h = normals.histograms[t];
        h.counts.assign(size_t(lobes.tables[t].steps) + 1, 0.f);
        if (lobes.secondMode) h.cos2 = h.sin2 = h.counts;
    }
    return normals;
}

void clearTexel(TexelNormals& t) {
    for (int k : t.used) {
        AngleHistogram& h = t.histograms[size_t(k)];
        if (h.last >= h.first) {
            std::fill(h.counts.begin() + h.first, h.counts.begin() + h.last + 1, 0.f);
            if (!h.cos2.empty()) {
                std::fill(h.cos2.begin() + h.first, h.cos2.begin() + h.last + 1, 0.f);
                std::fill(h.sin2.begin() + h.first, h.sin2.begin() + h.last + 1, 0.f);
            }
        }
        h.first = 0, h.last = -1;
        h.few.clear();
        h.fewModes.clear();
        h.entries = 0;
    }
    t.used.clear();
    t.alpha2 = t.total = 0.f;
    t.narrowest = 1.f;
}

} // namespace ndfmip::ndf_rings
