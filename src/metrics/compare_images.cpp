// Image-against-reference statistics and false-colour error images (see compare.h).
#include "ndfmip/compare.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

#include "percentile.h"

namespace ndfmip {
namespace {

std::string sizeText(const Image& image) {
    return std::to_string(image.width) + "x" + std::to_string(image.height) + ", " +
           std::to_string(image.channels) + " channel" + (image.channels == 1 ? "" : "s");
}

bool consistent(const Image& image) {
    return !image.empty() && image.pixels.size() == image.texelCount() * size_t(image.channels);
}

bool sameSize(const Image& a, const Image& b) {
    return a.width == b.width && a.height == b.height && a.channels == b.channels;
}

// An Error naming the first non-finite value of `image`, or none.
Result<bool> checkFinite(const Image& image, const char* role) {
    auto bad = std::find_if(image.pixels.begin(), image.pixels.end(),
                            [](float v) { return !std::isfinite(v); });
    if (bad == image.pixels.end()) return true;
    size_t i = size_t(bad - image.pixels.begin());
    size_t texel = i / size_t(image.channels);
    return Error{std::string(role) + " has a non-finite value at pixel (" +
                 std::to_string(texel % size_t(image.width)) + ", " +
                 std::to_string(texel / size_t(image.width)) + "), channel " +
                 std::to_string(i % size_t(image.channels))};
}

// matplotlib's 'inferno' sampled at 7 evenly spaced points, the first made pure black.
constexpr std::array<std::array<float, 3>, 7> kInferno = {{
    {0x00 / 255.f, 0x00 / 255.f, 0x00 / 255.f},
    {0x32 / 255.f, 0x0a / 255.f, 0x5e / 255.f},
    {0x78 / 255.f, 0x1c / 255.f, 0x6d / 255.f},
    {0xbc / 255.f, 0x37 / 255.f, 0x54 / 255.f},
    {0xed / 255.f, 0x69 / 255.f, 0x25 / 255.f},
    {0xfb / 255.f, 0xb6 / 255.f, 0x1a / 255.f},
    {0xfc / 255.f, 0xff / 255.f, 0xa4 / 255.f},
}};

void inferno(float t, float* rgb) {
    float u = std::clamp(t, 0.f, 1.f) * float(kInferno.size() - 1);
    size_t i = std::min(size_t(u), kInferno.size() - 2);
    float f = u - float(i);
    for (int c = 0; c < 3; ++c) rgb[c] = kInferno[i][c] + f * (kInferno[i + 1][c] - kInferno[i][c]);
}

} // namespace

Result<ImageComparison> compareImages(const Image& a, const Image& b) {
    if (!consistent(a) || !consistent(b)) return Error{"cannot compare an empty image"};
    if (!sameSize(a, b))
        return Error{"image sizes differ (" + sizeText(a) + " vs " + sizeText(b) + ")"};
    if (auto finite = checkFinite(a, "the image under test"); !finite) return finite.error();
    if (auto finite = checkFinite(b, "the reference"); !finite) return finite.error();

    // Sums in double: a 4k RGB image has 25M values.
    double squaredError = 0, squaredB = 0, sumA = 0, sumB = 0, maxError = 0;
    double peak = -std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < a.pixels.size(); ++i) {
        double va = a.pixels[i], vb = b.pixels[i], d = va - vb;
        squaredError += d * d;
        squaredB += vb * vb;
        sumA += va;
        sumB += vb;
        maxError = std::max(maxError, std::abs(d));
        peak = std::max(peak, vb);
    }
    const double inf = std::numeric_limits<double>::infinity();
    const auto n = double(a.pixels.size());
    const double mse = squaredError / n;
    if (peak <= 0) peak = 1;
    ImageComparison out;
    out.width = a.width;
    out.height = a.height;
    out.channels = a.channels;
    out.rmse = std::sqrt(mse);
    out.relativeRmse = squaredB > 0       ? std::sqrt(squaredError / squaredB)
                       : squaredError > 0 ? inf
                                          : 0;
    out.psnr = mse > 0 ? 10 * std::log10(peak * peak / mse) : inf;
    out.energyRatio = sumA == 0 && sumB == 0 ? 1 : (sumA / n) / (sumB / n);
    out.maxAbsError = maxError;
    return out;
}

Image errorImage(const Image& a, const Image& b, float scale) {
    if (!consistent(a) || !consistent(b) || !sameSize(a, b)) return Image();
    std::vector<float> error(a.texelCount());
    for (size_t t = 0; t < error.size(); ++t) {
        float sum = 0;
        for (int c = 0; c < a.channels; ++c) {
            size_t i = t * size_t(a.channels) + size_t(c);
            sum += std::abs(a.pixels[i] - b.pixels[i]);
        }
        error[t] = sum / float(a.channels);
    }
    if (scale <= 0) {
        scale = percentile(error, 0.99);
        if (scale <= 0) scale = 1;
    }
    Image out(a.width, a.height, 3);
    for (size_t t = 0; t < error.size(); ++t)
        inferno(std::isfinite(error[t]) ? error[t] / scale : 1.f, &out.pixels[3 * t]);
    return out;
}

} // namespace ndfmip
