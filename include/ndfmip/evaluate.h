// Judging a method against the truth where a pixel covers exactly one texel of a level (the
// aligned case): the truth is then the mean of the BRDF over the level-0 normals the texel
// covers (Han et al. eq. 8), and the method shades the texel's own stored parameters.
#pragma once

#include "ndfmip/bake.h"
#include "ndfmip/pyramid.h"
#include "ndfmip/shading.h"

namespace ndfmip {

// The specular lobe (normalised Blinn-Phong, exponent ctx.exponent, no cosine) that the bake's
// method gives every texel of `level` from its stored parameters (one channel).
Image shadeLevel(const Bake& bake, int level, const ShadeContext& ctx);

// The truth for every texel of `level`: the mean over its footprint of the lobe at each
// level-0 normal (one channel).
Image groundTruthLevel(const Pyramid& pyramid, int level, const ShadeContext& ctx);

struct ErrorStats {
    double rmse = 0;        // sqrt(mean (a - b)^2)
    double relativeRmse = 0; // ||a - b|| / ||b||
    double energyRatio = 0;  // mean a / mean b
};

// Compares an image with the truth (same size, first channel).
ErrorStats compareToTruth(const Image& image, const Image& truth);

// The same pooled over several image/truth pairs (e.g. one per light): every pixel of every pair
// counts once, so a pair whose truth is near zero cannot dominate a ratio.
ErrorStats compareToTruth(const std::vector<Image>& images, const std::vector<Image>& truths);

} // namespace ndfmip
