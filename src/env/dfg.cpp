// The split sum's DFG table (environment.h): GGX with height-correlated Smith masking,
// integrated over l for n.v = mu by Hammersley samples of D(h) <n.h> (Karis 2013; Filament's
// cmgen tabulates the same integral).
//
// With h drawn with pdf(h) = D <n.h> and l = reflect(-v, h), pdf(l) = D <n.h> / (4 <v.h>), so
//     f <n.l> / pdf(l) = F Vis <n.l> 4 <v.h> / <n.h>,   Vis = G2 / (4 <n.l> <n.v>)
// and the sum splits over F = f0 (1 - Fc) + f90 Fc, Fc = (1 - v.h)^5.
#include "ndfmip/environment.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <vector>

#include "env/env_internal.h"

namespace ndfmip {
namespace {

// Height-correlated Smith for GGX (Heitz 2014) as a visibility term G2 / (4 n.l n.v).
double visibility(double nv, double nl, double a2) {
    const double lambdaV = nl * std::sqrt(nv * nv * (1. - a2) + a2);
    const double lambdaL = nv * std::sqrt(nl * nl * (1. - a2) + a2);
    return 0.5 / (lambdaV + lambdaL);
}

} // namespace

namespace {

// The half vectors of `samples` Hammersley points for alpha (they do not depend on n.v).
std::vector<glm::dvec3> halfVectors(double alpha, int samples) {
    std::vector<glm::dvec3> h(static_cast<size_t>(samples));
    for (int i = 0; i < samples; ++i) h[size_t(i)] = env::ggxHalfVector(i, samples, alpha);
    return h;
}

glm::dvec2 dfgSum(double mu, double alpha, const std::vector<glm::dvec3>& halfVectors) {
    mu = std::clamp(mu, 1e-6, 1.);
    const double a2 = alpha * alpha;
    const glm::dvec3 v(std::sqrt(1. - mu * mu), 0., mu);
    glm::dvec2 sum(0.);
    for (const glm::dvec3& h : halfVectors) {
        const double vh = glm::dot(v, h);
        const double nl = 2. * vh * h.z - mu; // (2 (v.h) h - v).z
        if (nl <= 0. || vh <= 0.) continue;
        const double weight = visibility(mu, nl, a2) * nl * 4. * vh / h.z;
        const double m = 1. - vh, fc = m * m * m * m * m;
        sum += weight * glm::dvec2(1. - fc, fc);
    }
    return sum / double(halfVectors.size());
}

} // namespace

glm::dvec2 dfgIntegral(double mu, double perceptualRoughness, int samples) {
    assert(samples >= 1);
    const double alpha = perceptualRoughness * perceptualRoughness;
    return dfgSum(mu, alpha, halfVectors(alpha, samples));
}

double tableColumnCosine(TableColumns columns, int x, int size) {
    return columns == TableColumns::Ends ? double(x) / (size - 1) : (x + 0.5) / size;
}

Image dfgTable(int size, int samples, TableColumns columns) {
    assert(size >= (columns == TableColumns::Ends ? 2 : 1) && samples >= 1);
    Image table(size, size, 3);
#pragma omp parallel for schedule(dynamic, 1)
    for (int y = 0; y < size; ++y) {
        const double r = (y + 0.5) / size;
        const std::vector<glm::dvec3> h = halfVectors(r * r, samples);
        for (int x = 0; x < size; ++x) {
            const glm::dvec2 d = dfgSum(tableColumnCosine(columns, x, size), r * r, h);
            float* out = table.at(x, y);
            out[0] = float(d.x);
            out[1] = float(d.y);
            out[2] = float(d.x + d.y);
        }
    }
    return table;
}

} // namespace ndfmip
