// ggx-aniso: per texel and level, the one anisotropic GGX lobe about the level's axis (ggx-fit's:
// a mode of the footprint's normals near their mean, ndf_rings.h's modeAxis) that
// best matches the texel's exact filtered NDF (ndf_rings.h): two roughnesses and the direction of
// the wider, as the squared-roughness tensor A in the frame (t, b) about the normal
// (shaders/ggx_aniso.glsl), stored with its axis's moment added (below).
//
// The error is ggx-fit's, the L2 distance of the two NDFs over the sphere, read through the
// azimuthal modes 0 and 2 on the rings about the normal. The lobe, centred on the normal, has
// only even modes; about its own axes (a1 along phi_d, a2 across) it is
//   D = K / (P + Q cos 2(phi - phi_d))^2,  K = 1 / (pi a1 a2 cos^4 theta),
//   P = 1 + tan^2 theta (a1^-2 + a2^-2) / 2,  Q = tan^2 theta (a1^-2 - a2^-2) / 2,
// whose ring mean and cos 2 mode are closed forms (1/2pi Int (P + Q cos psi)^-2 dpsi =
// P / (P^2 - Q^2)^3/2, and with cos psi, -Q / (P^2 - Q^2)^3/2). By Parseval on each ring the
// squared error is (D0 - T0)^2 + 2 |D2 - T2|^2 plus the modes the lobe cannot have (odd ones) or
// that are left out (4 and above, small beside mode 2 for the lobes met here).
//
// The direction is mode 2's own (its weighted sum over the rings); the isotropic alpha (mode 0,
// ggx-fit's fit) starts the search over the geometric mean and the log ratio of a1 and a2.
//
// Stored is not A but A + 2 n_xy n_xy^T (ggx_aniso.glsl's ndfmipGgxAnisoMoments), so that a
// hardware blend of neighbouring texels also widens the lobe by the spread between their axes.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "methods/ggx_fit/ndf_rings.h"
#include "ndfmip/bake.h"
#include "ndfmip/glsl.h"
#include "ndfmip/shading.h"

namespace ndfmip {

namespace {

using namespace ndf_rings;

// Rings of the fit about the mean normal: 12, as close to a multi-start fit on real maps as 16
// (ggx-fit's) at three quarters of the cost.
constexpr int kRings = 12;
constexpr float kMaxLogRatio = 2.5f; // a1 / a2 up to e^5
constexpr int kRounds = 1;           // of the geometric mean, then the ratio, refined in turn

struct Tensor {
    float tt, tb, bb;
};

Tensor isotropic(float alpha) {
    return {alpha * alpha, 0.f, alpha * alpha};
}

// The fitted lobe of one texel: `r` its mean normal's length |Na|.
Tensor fitTexel(const TexelNormals& normals, const MaterialLobes& lobes, float r) {
    if (!(normals.total > 0.f)) return isotropic(lobes.alpha);
    const Rings ring = rings(toksvigWidth(normals, r), kRings);
    float mean[kRings], cos2[kRings], sin2[kRings];
    float tan2[kRings], inverseCos4[kRings];
    for (int j = 0; j < kRings; ++j) {
        const RingModes modes = ringModes(normals, lobes, ring.theta[j]);
        mean[j] = modes.mean, cos2[j] = modes.cos2, sin2[j] = modes.sin2;
        const float c2 = ring.cosTheta[j] * ring.cosTheta[j];
        tan2[j] = (1.f - c2) / c2, inverseCos4[j] = 1.f / (c2 * c2);
    }
    // Isotropic first: mode 0 alone (an isotropic lobe has no mode 2).
    const auto target = isotropicTarget<kRings>(ring, mean);
    auto isotropicFit = [&](float logAlpha) { return isotropicError(target, logAlpha); };
    const float lo = std::log(std::max(0.5f * normals.narrowest, kMinAlpha));
    float u = minimiseOnScan(isotropicFit, lo, 0.f, 6, 4);
    // The direction: mode 2 summed over the rings with the weights a small stretch of the
    // isotropic lobe changes its mode 2 by (dD2/dv at v = 0, up to a constant:
    // tan^2 theta / (cos^4 theta P^3), P = 1 + tan^2 theta / alpha^2).
    const float inverseAlpha2 = std::exp(-2.f * u);
    float sumCos2 = 0.f, sumSin2 = 0.f;
    for (int j = 0; j < kRings; ++j) {
        const float p = 1.f + tan2[j] * inverseAlpha2;
        const float g = ring.weight[j] * tan2[j] * inverseCos4[j] / (p * p * p);
        sumCos2 += g * cos2[j], sumSin2 += g * sin2[j];
    }
    const float length = std::hypot(sumCos2, sumSin2);
    if (!(length > 0.f)) return isotropic(std::min(std::exp(u), 1.f));
    // Mode 2 along the direction: a1 (the wider) at phi_d, cos 2 phi_d = sumCos2 / length.
    const float c = sumCos2 / length, s = sumSin2 / length;
    float along[kRings];
    for (int j = 0; j < kRings; ++j) along[j] = cos2[j] * c + sin2[j] * s;
    // u = ln sqrt(a1 a2), v = ln sqrt(a1 / a2).
    auto error = [&](float uu, float vv) {
        const float eu = std::exp(-2.f * uu), ev = std::exp(-2.f * vv);
        const float inverse1 = eu * ev, inverse2 = eu / ev; // a1^-2, a2^-2
        const float sum = 0.5f * (inverse1 + inverse2), difference = 0.5f * (inverse1 - inverse2);
        const float k = eu * (1.f / kPi);
        // Ring by ring, a loop the compiler vectorises.
        float e = 0.f;
#pragma omp simd reduction(+ : e)
        for (int j = 0; j < kRings; ++j) {
            const float p = 1.f + tan2[j] * sum, q = tan2[j] * difference;
            const float x = (p - q) * (p + q);
            const float g = k * inverseCos4[j] / (x * std::sqrt(x));
            const float d0 = g * p - mean[j], d2 = -g * q - along[j];
            e += ring.weight[j] * (d0 * d0 + 2.f * d2 * d2);
        }
        return e;
    };
    // Each roughness within [kMinAlpha, 1] (no engine input stores a wider lobe).
    auto maxRatio = [&](float uu) {
        return std::max(std::min({kMaxLogRatio, -uu, uu - std::log(kMinAlpha)}), 0.f);
    };
    // The log ratio scanned as w |w|: denser near the isotropic lobe, where most texels' optima
    // lie; negative where the wider axis is across the direction after all.
    const float last = std::sqrt(maxRatio(u));
    const float root =
        minimiseOnScan([&](float w) { return error(u, w * std::abs(w)); }, -last, last, 8, 4);
    float v = root * std::abs(root);
    for (int round = 0; round < kRounds; ++round) {
        u = minimiseOnScan([&](float uu) { return error(uu, v); }, std::max(u - 0.15f, lo),
                           std::min(u + 0.15f, -std::abs(v)), 2, 3);
        v = minimiseOnScan([&](float vv) { return error(u, vv); },
                           std::max(v - 0.15f, -maxRatio(u)), std::min(v + 0.15f, maxRatio(u)), 2,
                           3);
    }
    const float a1 = std::min(std::exp(u + v), 1.f), a2 = std::min(std::exp(u - v), 1.f);
    const float middle = 0.5f * (a1 * a1 + a2 * a2), half = 0.5f * (a1 * a1 - a2 * a2);
    return {middle + half * c, half * s, middle - half * c};
}

} // namespace

Bake bakeGgxAniso(const Pyramid& pyramid, const BakeOptions& options) {
    Bake bake;
    bake.method = Method::GgxAniso;
    bake.parameters["base_roughness"] = options.baseRoughness;
    if (options.roughnessMap) bake.parameters["roughness_map"] = 1.0;
    bake.planes = {
        {"normal",
         {"n.x", "n.y", "n.z"},
         "the lobe's axis: a mode of the footprint's normals near their mean, unit length",
         true},
        {"alpha_moments",
         {"M_tt", "M_tb", "M_bb"},
         "A + 2 n_xy n_xy^T: A the squared-roughness tensor of the one anisotropic GGX lobe about "
         "the normal closest to the texel's filtered NDF, in the frame t = the texture's x made "
         "orthogonal to the normal, b = n x t; n_xy the normal's x and y (a blend of this and of "
         "the normals keeps the spread between the blended axes)",
         true},
    };
    const MaterialLobes lobes = materialLobes(options, true);
    const int count = int(pyramid.levels.size());
    bake.levels.resize(count);
    for (int k = 0; k < count; ++k) {
        const Image& mean = levelMean(pyramid, k);
        Image normal(mean.width, mean.height, 3, Image::Uninitialized{});
        Image moments(mean.width, mean.height, 3, Image::Uninitialized{});
        // What the level stores: the fitted tensor plus its axis's moment (fitLevel has written
        // the texel's axis before it fits the lobe).
        auto store = [&moments, &normal](size_t i, const Tensor& a) {
            const float* n = &normal.pixels[3 * i];
            const glm::vec3 m = glsl().ndfmipGgxAnisoMoments(glm::vec3(a.tt, a.tb, a.bb),
                                                             glm::vec3(n[0], n[1], n[2]));
            float* out = &moments.pixels[3 * i];
            out[0] = m.x;
            out[1] = m.y;
            out[2] = m.z;
        };
        fitLevel(
            pyramid, lobes, k, normal,
            [](const float* n) {
                // The frame the tensor A is fitted in (ggx_aniso.glsl).
                const glm::vec3 axis(n[0], n[1], n[2]);
                const glm::vec3 t = glsl().ndfmipAnisoTangent(axis);
                const glm::vec3 b = glm::cross(axis, t);
                return RingFrame{{n[0], n[1], n[2]}, {t.x, t.y, t.z}, {b.x, b.y, b.z}};
            },
            [&](size_t i, const TexelNormals& normals, float r) {
                store(i, fitTexel(normals, lobes, r));
            },
            [&](size_t i, int x, int y) {
                store(i, isotropic(lobes.alphaAt(x, y))); // one normal: its own lobe
            });
        bake.levels[k] = {std::make_shared<const Image>(std::move(normal)),
                          std::make_shared<const Image>(std::move(moments))};
        if (options.progress) options.progress(k + 1, count);
    }
    return bake;
}

} // namespace ndfmip
