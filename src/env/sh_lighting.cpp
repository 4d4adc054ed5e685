// The lighting of the paper's environment shading (environment_sh_shading.h): the radiance's SH
// coefficients and the reparameterised lighting L' of H eq. 36 for one view.
#include <atomic>
#include <cassert>
#include <cmath>

#include "core/quadrature.h"
#include "env/sh_lighting_internal.h"
#include "ndfmip/spherical_harmonics.h"

namespace ndfmip {

uint64_t nextShLightingId() {
    static std::atomic<uint64_t> next{1};
    return next++;
}

namespace {

// The weight of L(w_i) in the integral over w_i of L' Y_lm(h) for set k of the cosine (its
// reparameterisedSets): the Jacobian 4 (w_i.h) cancels against dh = dw_i / (4 (w_i.h)), leaving
// the cosine c alone. The axes' sets are the components of w_i.
bool hasAxes(SpecularCosine cosine) {
    return cosine == SpecularCosine::MeanNormal || cosine == SpecularCosine::Reflecting;
}

double cosineFactor(SpecularCosine cosine, double halfCosine, glm::dvec3 wi, int k) {
    if (hasAxes(cosine) && k < 3) return wi[k];
    return cosine == SpecularCosine::None ? 1. : halfCosine;
}

// The summed projections, set after set, into the lighting's sets.
void store(ShLighting& lighting, const std::vector<glm::dvec3>& sums, int count) {
    for (int k = 0; k < reparameterisedSets(lighting.cosine); ++k)
        reparameterisedSet(lighting, k)
            .assign(sums.begin() + k * count, sums.begin() + (k + 1) * count);
}

// Two unit vectors completing w to a right-handed orthonormal frame.
void frameAbout(glm::dvec3 w, glm::dvec3& t1, glm::dvec3& t2) {
    t1 = glm::normalize(std::fabs(w.x) < 0.9 ? glm::cross(glm::dvec3(1., 0., 0.), w)
                                             : glm::cross(glm::dvec3(0., 1., 0.), w));
    t2 = glm::cross(w, t1);
}

} // namespace

const char* specularCosineName(SpecularCosine cosine) {
    switch (cosine) {
    case SpecularCosine::HalfVector:
        return "half-vector";
    case SpecularCosine::MeanNormal:
        return "mean-normal";
    case SpecularCosine::None:
        return "none";
    case SpecularCosine::Reflecting:
        return "reflecting";
    }
    return "none";
}

int reparameterisedSets(SpecularCosine cosine) {
    if (cosine == SpecularCosine::MeanNormal) return 3;
    return cosine == SpecularCosine::Reflecting ? 4 : 1;
}

const std::vector<glm::dvec3>& reparameterisedSet(const ShLighting& lighting, int k) {
    assert(k >= 0 && k < reparameterisedSets(lighting.cosine));
    return hasAxes(lighting.cosine) && k < 3 ? lighting.reparameterisedAxes[k]
                                             : lighting.reparameterised;
}

std::vector<glm::dvec3>& reparameterisedSet(ShLighting& lighting, int k) {
    return const_cast<std::vector<glm::dvec3>&>(
        reparameterisedSet(static_cast<const ShLighting&>(lighting), k));
}

std::vector<double> interleavedShLighting(const ShLighting& lighting, int order) {
    assert(order <= lighting.order);
    const int sets = reparameterisedSets(lighting.cosine);
    const int count = shCount(order), channels = 3 * (1 + sets);
    std::vector<double> values(size_t(channels) * size_t(count));
    for (int i = 0; i < count; ++i) {
        double* p = &values[size_t(channels) * size_t(i)];
        for (int c = 0; c < 3; ++c) {
            p[c] = lighting.radiance[size_t(i)][c];
            for (int k = 0; k < sets; ++k)
                p[3 + 3 * k + c] = reparameterisedSet(lighting, k)[size_t(i)][c];
        }
    }
    return values;
}

ShLighting prepareShLighting(const Environment& env, int order, glm::dvec3 fixedView,
                             SpecularCosine cosine) {
    ShLighting lighting = prepareReparameterisedSh(env, order, fixedView, cosine);
    lighting.radiance = projectEnvironmentSh(env, order).radiance;
    return lighting;
}

ShLighting prepareReparameterisedSh(const Environment& env, int order, glm::dvec3 fixedView,
                                    SpecularCosine cosine) {
    assert(order >= 0 && order <= kMaxShOrder && glm::length(fixedView) > 0.);
    ShLighting lighting;
    lighting.id = nextShLightingId();
    lighting.order = order;
    lighting.view = glm::normalize(fixedView);
    lighting.cosine = cosine;

    // L'_lm = sum over texels of L c Y_lm(h) dw_i at the texel centre, w_i the texel's direction as
    // seen (Environment::rotation applied). Rows summed in order afterwards: thread-independent.
    const Image& map = env.radiance;
    const int width = map.width, height = map.height, count = shCount(order);
    const glm::dvec3 o = lighting.view;
    const int sets = reparameterisedSets(cosine), stride = sets * count;
    std::vector<glm::dvec3> rowSums(size_t(height) * size_t(stride), glm::dvec3(0.));
#pragma omp parallel for schedule(dynamic, 4)
    for (int y = 0; y < height; ++y) {
        const double solidAngle = equirectTexelSolidAngle(width, height, y);
        glm::dvec3* sum = &rowSums[size_t(y) * size_t(stride)];
        double basis[shCount(kMaxShOrder)];
        for (int x = 0; x < width; ++x) {
            const glm::dvec3 wi = rotateAboutY(
                equirectDirection((x + 0.5) / width, (y + 0.5) / height), env.rotation);
            const glm::dvec3 half = wi + o; // |w_i + w_o| = 2 (w_i.h)
            const double length = glm::length(half);
            if (!(length > 1e-12)) continue; // w_i = -w_o: h undefined, a set of measure zero
            const float* p = map.at(x, y);
            const glm::dvec3 radiance(p[0], p[1], p[2]);
            evaluateSh(half / length, order, basis);
            for (int k = 0; k < sets; ++k) {
                const glm::dvec3 weighted =
                    radiance * (cosineFactor(cosine, 0.5 * length, wi, k) * solidAngle);
                for (int i = 0; i < count; ++i) sum[k * count + i] += weighted * basis[i];
            }
        }
    }
    std::vector<glm::dvec3> sums(size_t(stride), glm::dvec3(0.));
    for (int y = 0; y < height; ++y)
        for (int i = 0; i < stride; ++i)
            sums[size_t(i)] += rowSums[size_t(y) * size_t(stride) + size_t(i)];
    store(lighting, sums, count);
    return lighting;
}

ShLighting prepareShLighting(const RadianceFunction& radiance, int order, glm::dvec3 fixedView,
                             SpecularCosine cosine, int nodes) {
    assert(order >= 0 && order <= kMaxShOrder && glm::length(fixedView) > 0. && nodes >= order + 1);
    ShLighting lighting;
    lighting.id = nextShLightingId();
    lighting.order = order;
    lighting.view = glm::normalize(fixedView);
    lighting.cosine = cosine;
    const int count = shCount(order), phis = 2 * nodes;
    const int sets = reparameterisedSets(cosine);
    lighting.radiance.assign(size_t(count), glm::dvec3(0.));
    std::vector<glm::dvec3> sums(size_t(sets * count), glm::dvec3(0.));
    const glm::dvec3 o = lighting.view;
    glm::dvec3 t1, t2;
    frameAbout(o, t1, t2);
    std::vector<double> z, w;
    gaussLegendre(nodes, z, w);
    std::vector<double> basis(static_cast<size_t>(count));
    for (int i = 0; i < nodes; ++i)
        for (int k = 0; k < phis; ++k) {
            const double phi = 2. * M_PI * (k + 0.5) / phis, dphi = 2. * M_PI / phis;
            const glm::dvec3 around = std::cos(phi) * t1 + std::sin(phi) * t2;
            // L over the sphere: cos of the angle to w_o = z in [-1, 1].
            {
                const double c = z[size_t(i)], s = std::sqrt(std::max(0., 1. - c * c));
                const glm::dvec3 d = c * o + s * around;
                evaluateSh(d, order, basis.data());
                const glm::dvec3 value = radiance(d) * (w[size_t(i)] * dphi);
                for (int j = 0; j < count; ++j)
                    lighting.radiance[size_t(j)] += value * basis[size_t(j)];
            }
            // L' over the half vectors with h.w_o = c in [0, 1] (the rule mapped from [-1, 1]).
            {
                const double c = 0.5 * (z[size_t(i)] + 1.), s = std::sqrt(std::max(0., 1. - c * c));
                const glm::dvec3 h = c * o + s * around, wi = glm::normalize(2. * c * h - o);
                evaluateSh(h, order, basis.data());
                const glm::dvec3 value = radiance(wi) * (4. * c * 0.5 * w[size_t(i)] * dphi);
                for (int set = 0; set < sets; ++set)
                    for (int j = 0; j < count; ++j)
                        sums[size_t(set * count + j)] +=
                            value * (cosineFactor(cosine, c, wi, set) * basis[size_t(j)]);
            }
        }
    store(lighting, sums, count);
    return lighting;
}

} // namespace ndfmip
