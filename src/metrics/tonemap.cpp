// Reinhard tone mapping and automatic exposure (see tonemap.h). Reinhard's curve is chosen
// over filmic fits because it is monotonic, never clips and has a closed-form inverse, which
// autoExposure uses.
#include "ndfmip/tonemap.h"

#include <cmath>
#include <utility>

#include "percentile.h"

namespace ndfmip {
namespace {

constexpr float kTargetDisplay = 0.8f; // where autoExposure puts the 99th percentile

float srgbEncode(float linear) {
    return linear <= 0.0031308f ? 12.92f * linear : 1.055f * std::pow(linear, 1.f / 2.4f) - 0.055f;
}

float srgbDecode(float encoded) {
    return encoded <= 0.04045f ? encoded / 12.92f : std::pow((encoded + 0.055f) / 1.055f, 2.4f);
}

// Exposed radiance -> display value; NaN and negatives -> 0, +inf -> 1.
float displayValue(float exposed) {
    if (!(exposed > 0.f)) return 0.f;
    if (std::isinf(exposed)) return 1.f;
    return srgbEncode(exposed / (1.f + exposed));
}

// Rec. 709 luminance of texel `t` (the grey value for one or two channels).
float luminance(const Image& image, size_t t) {
    const float* p = &image.pixels[t * size_t(image.channels)];
    if (image.channels < 3) return p[0];
    return 0.2126f * p[0] + 0.7152f * p[1] + 0.0722f * p[2];
}

} // namespace

Image toneMap(const Image& linear, float exposureStops) {
    if (linear.empty()) return Image();
    const float gain = std::exp2(exposureStops);
    const bool grey = linear.channels < 3;
    Image out(linear.width, linear.height, 3);
    for (size_t t = 0; t < linear.texelCount(); ++t) {
        const float* in = &linear.pixels[t * size_t(linear.channels)];
        for (int c = 0; c < 3; ++c)
            out.pixels[3 * t + size_t(c)] = displayValue(gain * in[grey ? 0 : c]);
    }
    return out;
}

float autoExposure(const Image& linear) {
    if (linear.empty()) return 0.f;
    std::vector<float> lum(linear.texelCount());
    for (size_t t = 0; t < lum.size(); ++t) lum[t] = luminance(linear, t);
    float p99 = percentile(std::move(lum), 0.99);
    if (!(p99 > 0.f)) return 0.f;
    // Invert the chain: sRGB decode, then Reinhard's y / (1 - y).
    float curve = srgbDecode(kTargetDisplay);
    return std::log2(curve / (1.f - curve) / p99);
}

} // namespace ndfmip
