// ggx-fit: per texel and level, one isotropic GGX lobe that matches the texel's exact filtered
// NDF. Filtering is the spherical convolution of the footprint's normal distribution with the
// material's lobe (Han et al. Sec. 3); with the footprint's normals n_i that is the mean of the
// material's GGX lobes about them, T(h) = mean_i D_a0(h . n_i). The lobe's axis n is a mode of
// the footprint's normals near their mean (ndf_rings.h's modeAxis: where the highlight peaks),
// stored as the level's normal (what an engine's normal mip holds); its alpha minimises the L2
// distance over the sphere between D_alpha(h . n) and T(h): one lobe an engine loads as it is,
// in place of Toksvig's alpha^2 = a0^2 + 2 sigma^2 about the mean normal, which follows the
// footprint's variance but not its shape.
//
// The lobe fitted is isotropic about n, so only T's ring means about n matter (mode 0 of
// ndf_rings.h, tabulated once per bake: time linear in the footprint).
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "methods/ggx_fit/ndf_rings.h"
#include "ndfmip/bake.h"

namespace ndfmip {

namespace {

using namespace ndf_rings;

constexpr int kRings = 16; // rings of the fit about the axis

// The fitted alpha of one texel: `r` its mean normal's length |Na|. The error is the squared
// difference on the rings about the axis, weighted by their solid angles: the L2
// distance of the two NDFs over the sphere.
float fitTexel(const TexelNormals& normals, const MaterialLobes& lobes, float r) {
    if (!(normals.total > 0.f)) return lobes.alpha;
    const Rings ring = rings(toksvigWidth(normals, r), kRings);
    float mean[kRings];
    for (int j = 0; j < kRings; ++j) mean[j] = ringModes(normals, lobes, ring.theta[j]).mean;
    const auto target = isotropicTarget<kRings>(ring, mean);
    auto error = [&](float logAlpha) { return isotropicError(target, logAlpha); };
    const float lo = std::log(std::max(0.5f * normals.narrowest, kMinAlpha));
    return std::min(std::exp(minimiseOnScan(error, lo, 0.f, 8, 6)), 1.f);
}

} // namespace

Bake bakeGgxFit(const Pyramid& pyramid, const BakeOptions& options) {
    Bake bake;
    bake.method = Method::GgxFit;
    bake.parameters["base_roughness"] = options.baseRoughness;
    if (options.roughnessMap) bake.parameters["roughness_map"] = 1.0;
    bake.planes = {
        {"normal",
         {"n.x", "n.y", "n.z"},
         "the lobe's axis: a mode of the footprint's normals near their mean, unit length",
         true},
        {"roughness_ggx",
         {"alpha"},
         "GGX alpha of the one lobe about the normal closest to the texel's filtered NDF",
         true},
    };
    // A material alpha below kMinFittedRoughness (the commands refuse it) is fitted as that.
    const MaterialLobes lobes = materialLobes(options, false);
    const int count = int(pyramid.levels.size());
    bake.levels.resize(count);
    for (int k = 0; k < count; ++k) {
        const Image& mean = levelMean(pyramid, k);
        Image normal(mean.width, mean.height, 3, Image::Uninitialized{});
        Image alpha(mean.width, mean.height, 1, Image::Uninitialized{});
        fitLevel(
            pyramid, lobes, k, normal,
            [](const float* n) {
                RingFrame frame{};
                std::copy(n, n + 3, frame.axis);
                return frame;
            },
            [&](size_t i, const TexelNormals& normals, float r) {
                alpha.pixels[i] = fitTexel(normals, lobes, r);
            },
            [&](size_t i, int x, int y) {
                alpha.pixels[i] = lobes.alphaAt(x, y); // one normal: its own lobe
            });
        bake.levels[k] = {std::make_shared<const Image>(std::move(normal)),
                          std::make_shared<const Image>(std::move(alpha))};
        if (options.progress) options.progress(k + 1, count);
    }
    return bake;
}

} // namespace ndfmip
