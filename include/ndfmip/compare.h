// Comparing a rendered or filtered image with a reference: error statistics and a
// false-colour picture of where the error lies.
#pragma once

#include "ndfmip/image.h"
#include "ndfmip/result.h"

namespace ndfmip {

// Statistics over all pixels and channels. relativeRmse is 0 when a and b are both zero and
// +inf when only b is; psnr's peak is the largest value of b (1 when that is <= 0) and psnr is
// +inf when a == b.
struct ImageComparison {
    int width = 0, height = 0, channels = 0;
    double rmse = 0;         // sqrt(mean (a - b)^2)
    double relativeRmse = 0; // ||a - b|| / ||b||
    double psnr = 0;         // 10 log10(peak^2 / mse), in dB
    double energyRatio = 0;  // mean a / mean b (1 when both means are 0)
    double maxAbsError = 0;  // max |a - b|
};

// `a` is the image under test, `b` the reference. They must have the same width, height and
// channel count, and hold only finite values; otherwise an Error says which.
Result<ImageComparison> compareImages(const Image& a, const Image& b);

// The per-pixel error |a - b| (mean over channels) as an RGB image in [0, 1] through a
// 7-stop piecewise-linear 'inferno' colormap (black = no error). An error of `scale` or more
// maps to the top colour (pale yellow); scale <= 0 picks the 99th percentile of the error, or
// 1 when that is 0. Non-finite errors show as the top colour. Returns an empty Image when the
// sizes differ.
Image errorImage(const Image& a, const Image& b, float scale = 0.f);

} // namespace ndfmip
