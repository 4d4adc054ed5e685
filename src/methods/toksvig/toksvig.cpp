// Toksvig bake: the unnormalised mean normal Na per texel (linear, so it may be trilinearly
// filtered before shading) and, for engines, Beckmann/GGX roughness from its length.

#include <cmath>
#include <optional>

#include "ndfmip/bake.h"
#include "ndfmip/roughness.h"

namespace ndfmip {

Bake bakeToksvig(const Pyramid& pyramid, const BakeOptions& options) {
    Bake bake;
    bake.method = Method::Toksvig;
    bake.parameters["base_roughness"] = options.baseRoughness;
    bake.planes = {
        {"mean",
         {"Na.x", "Na.y", "Na.z"},
         "unnormalised mean normal Na (first moment of the NDF)",
         true},
        {"roughness_beckmann",
         {"alpha"},
         "Beckmann alpha: sqrt(alpha0^2 + sigma^2), sigma^2 = (1-|Na|)/|Na| (calibrated on GGX "
         "truth)",
         false},
        {"roughness_ggx", {"alpha"}, "GGX alpha, same mapping as Beckmann", false},
    };
    const int count = int(pyramid.levels.size());
    bake.levels.resize(count);
    // A roughness map: its alpha^2 averaged over each texel's footprint, level by level.
    std::optional<Image> alpha2;
    if (options.roughnessMap) {
        bake.parameters["roughness_map"] = 1.0;
        alpha2 = Image(options.roughnessMap->width, options.roughnessMap->height, 1);
        for (size_t i = 0; i < alpha2->texelCount(); ++i) {
            const float a =
                options.roughnessMap->pixels[i * size_t(options.roughnessMap->channels)];
            alpha2->pixels[i] = a * a;
        }
    }
    for (int k = 0; k < count; ++k) {
        const Image& mean = levelMean(pyramid, k);
        if (alpha2 && k > 0) alpha2 = averageToLevel(pyramid, *alpha2, k);
        Image beckmann(mean.width, mean.height, 1, Image::Uninitialized{});
        const size_t n = mean.texelCount();
#pragma omp parallel for schedule(static)
        for (size_t i = 0; i < n; ++i) {
            const float base = alpha2 ? std::sqrt(alpha2->pixels[i]) : options.baseRoughness;
            beckmann.pixels[i] = varianceRoughness(length3(&mean.pixels[3 * i]), base);
        }
        // The mean plane is the pyramid's own image; GGX shares Beckmann's (same mapping).
        auto roughness = std::make_shared<const Image>(std::move(beckmann));
        bake.levels[k] = {pyramid.levels[k].mean, roughness, roughness};
        if (options.progress) options.progress(k + 1, count);
    }
    return bake;
}

} // namespace ndfmip
