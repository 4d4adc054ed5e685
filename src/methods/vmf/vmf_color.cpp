// Colour per vMF lobe (Han et al. 2007, Sec. 7.3, eq. 31): for every texel of every level, the
// responsibility-weighted mean colour of the level-0 texels its footprint covers, one per lobe.
// Runs on the fit's final lobes: one E-step over the footprint, accumulating colours instead of
// normals.
#include <algorithm>
#include <cmath>
#include <limits>

#include <omp.h>

#include "ndfmip/vmf.h"

namespace ndfmip {
namespace {

// A texel's lobes as the E-step evaluates them: log(alpha_j gamma_j(n)) = c_j + kappa_j (mu_j.n -
// 1), c_j = log alpha_j + log(normaliser) + kappa_j. Both parts stay moderate at any kappa, so
// nothing cancels (mu_j.n - 1 is small where the term matters).
struct ColorTerms {
    int count = 0;
    double c[kMaxVmfLobes];
    double kappa[kMaxVmfLobes];
    glm::dvec3 mu[kMaxVmfLobes];
};

ColorTerms termsOf(std::span<const VmfLobe> lobes) {
    ColorTerms terms;
    terms.count = int(std::min<size_t>(lobes.size(), kMaxVmfLobes));
    double alphaSum = 0;
    for (int j = 0; j < terms.count; ++j) alphaSum += std::max(double(lobes[j].alpha), 0.0);
    for (int j = 0; j < terms.count; ++j) {
        const VmfLobe& lobe = lobes[j];
        double kappa = std::max(double(lobe.kappa), 0.0);
        glm::dvec3 mu(lobe.mu);
        double length = glm::length(mu);
        terms.mu[j] = length > 0 ? mu / length : glm::dvec3(0, 0, 1);
        terms.kappa[j] = kappa;
        terms.c[j] = lobe.alpha > 0
                         ? std::log(lobe.alpha / alphaSum) + vmfLogNormalizer(kappa) + kappa
                         : -std::numeric_limits<double>::infinity();
    }
    return terms;
}

// Sums over some level-0 texels: Sum_i z_ij, Sum_i z_ij y_i and Sum_i y_i.
struct ColorSums {
    double z[kMaxVmfLobes];
    glm::dvec3 zy[kMaxVmfLobes];
    glm::dvec3 y{0.0};

    ColorSums() {
        for (int j = 0; j < kMaxVmfLobes; ++j) {
            z[j] = 0;
            zy[j] = glm::dvec3(0.0);
        }
    }

    void add(const ColorSums& other, int lobes) {
        for (int j = 0; j < lobes; ++j) {
            z[j] += other.z[j];
            zy[j] += other.zy[j];
        }
        y += other.y;
    }
};

// The E-step over level-0 texels [x0, x1) of row `row`.
ColorSums sumRow(const ColorTerms& terms, const Image& normals, const Image& albedo, int row,
                 int x0, int x1) {
    ColorSums sums;
    double s[kMaxVmfLobes];
    for (int x = x0; x < x1; ++x) {
        float unit[3];
        normalizeOrFlat(normals.at(x, row), unit); // as fitVmfPyramid reads the map
        glm::dvec3 n(unit[0], unit[1], unit[2]);
        const float* color = albedo.at(x, row);
        glm::dvec3 y(color[0], color[1], color[2]);
        sums.y += y;
        double largest = -std::numeric_limits<double>::infinity();
        for (int j = 0; j < terms.count; ++j) {
            s[j] = terms.c[j] + terms.kappa[j] * (glm::dot(terms.mu[j], n) - 1);
            largest = std::max(largest, s[j]);
        }
        if (!(largest > -std::numeric_limits<double>::infinity()))
            continue; // no lobe with alpha > 0
        double total = 0;
        for (int j = 0; j < terms.count; ++j) total += s[j] = std::exp(s[j] - largest);
        for (int j = 0; j < terms.count; ++j) {
            double z = s[j] / total;
            sums.z[j] += z;
            sums.zy[j] += z * y;
        }
    }
    return sums;
}

// H eq. 31 for the lobes of one texel of a level >= 1. parallelRows: split its rows across the
// threads (the sums are added in row order either way, so the bits do not change).
void colorTexel(const Pyramid& pyramid, const Image& albedo, int level, int x, int y,
                std::span<VmfLobe> lobes, bool parallelRows) {
    const Footprint f = footprint(pyramid, level, x, y);
    const ColorTerms terms = termsOf(lobes);
    const Image& normals = *pyramid.base;
    ColorSums total;
    if (parallelRows) {
        std::vector<ColorSums> rows(size_t(f.height()));
#pragma omp parallel for schedule(static)
        for (int r = 0; r < f.height(); ++r)
            rows[size_t(r)] = sumRow(terms, normals, albedo, f.y0 + r, f.x0, f.x1);
        for (const ColorSums& row : rows) total.add(row, terms.count);
    } else {
        for (int r = f.y0; r < f.y1; ++r)
            total.add(sumRow(terms, normals, albedo, r, f.x0, f.x1), terms.count);
    }
    const glm::dvec3 mean = total.y / double(f.count());
    for (size_t j = 0; j < lobes.size(); ++j) {
        bool explains = int(j) < terms.count && total.z[j] > 0;
        lobes[j].color = glm::vec3(explains ? total.zy[j] / total.z[j] : mean);
    }
}

} // namespace

void fitLobeColors(const Pyramid& pyramid, const Image& albedo, std::vector<VmfLevel>& levels) {
    const Image& base = *pyramid.base;
    bool matches = checkAlbedoSize(albedo, base.width, base.height, "albedo").ok() &&
                   levels.size() == pyramid.levels.size();
    for (size_t k = 0; matches && k < levels.size(); ++k)
        matches = levels[k].width == pyramid.levels[k].width &&
                  levels[k].height == pyramid.levels[k].height &&
                  levels[k].offsets.size() == size_t(levels[k].width) * levels[k].height + 1;
    if (!matches) return;

    const int threads = omp_get_max_threads();
    for (size_t k = 0; k < levels.size(); ++k) {
        VmfLevel& level = levels[k];
        const int width = level.width;
        const size_t texels = size_t(width) * size_t(level.height);
        auto lobesOf = [&](size_t t) {
            return std::span<VmfLobe>(level.lobes.data() + level.offsets[t],
                                      level.lobes.data() + level.offsets[t + 1]);
        };
        if (k == 0) { // one texel each: its own colour
#pragma omp parallel for schedule(static)
            for (size_t t = 0; t < texels; ++t) {
                const float* c = albedo.at(int(t % width), int(t / width));
                for (VmfLobe& lobe : lobesOf(t)) lobe.color = glm::vec3(c[0], c[1], c[2]);
            }
        } else if (texels >= size_t(2 * threads)) {
#pragma omp parallel for schedule(dynamic, 16)
            for (size_t t = 0; t < texels; ++t)
                colorTexel(pyramid, albedo, int(k), int(t % width), int(t / width), lobesOf(t),
                           false);
        } else {
            for (size_t t = 0; t < texels; ++t)
                colorTexel(pyramid, albedo, int(k), int(t % width), int(t / width), lobesOf(t),
                           true);
        }
    }
}

glm::vec3 packLobeColor(const VmfLobe& lobe) {
    return lobe.alpha > 0 ? lobe.alpha * lobe.color : glm::vec3(0.f);
}

glm::vec3 unpackLobeColor(glm::vec3 packed, float alpha) {
    return alpha > 0 ? packed / alpha : glm::vec3(0.f);
}

Status checkAlbedoSize(const Image& albedo, int width, int height, const std::string& name) {
    if (albedo.width != width || albedo.height != height)
        return Status::failure(name + ": albedo map is " + std::to_string(albedo.width) + "x" +
                               std::to_string(albedo.height) + " but the normal map is " +
                               std::to_string(width) + "x" + std::to_string(height));
    if (albedo.channels != 3 && albedo.channels != 4)
        return Status::failure(name + ": albedo map has " + std::to_string(albedo.channels) +
                               " channels, expected 3 (RGB) or 4 (RGBA)");
    return Status::success();
}

} // namespace ndfmip
