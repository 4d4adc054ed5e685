// Temporal stability: how much a pixel's value changes when the camera moves by less than a
// pixel — the sparkle that motivated Toksvig's filtering.
#include <cmath>

#include "ndfmip/render.h"

namespace ndfmip {

namespace {

double luminance(const Image& image, size_t i) {
    const float* p = &image.pixels[i * image.channels];
    if (image.channels < 3) return p[0];
    return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
}

} // namespace

double temporalFlicker(const std::vector<Image>& frames, double floor) {
    if (frames.size() < 2) return 0.0;
    const size_t n = frames.front().texelCount();
    const double count = double(frames.size());
    std::vector<double> mean(n, 0.0), square(n, 0.0);
    double overall = 0.0;
    for (const Image& frame : frames) {
        for (size_t i = 0; i < n; ++i) {
            double y = luminance(frame, i);
            mean[i] += y / count;
            square[i] += y * y / count;
            overall += y;
        }
    }
    overall /= count * double(n);
    const double threshold = floor * overall;
    double sum = 0.0;
    size_t used = 0;
    for (size_t i = 0; i < n; ++i) {
        if (!(mean[i] > threshold) || mean[i] <= 0.0) continue;
        // Population variance over the frames, guarded against rounding below zero.
        double variance = std::max(0.0, square[i] - mean[i] * mean[i]);
        sum += std::sqrt(variance) / mean[i];
        ++used;
    }
    return used ? sum / double(used) : 0.0;
}

std::vector<glm::vec2> flickerShifts(int count) {
    // R2 sequence (Roberts 2018): well spread for any count, the same on every run.
    const double g = 1.32471795724474602596; // plastic number
    std::vector<glm::vec2> shifts;
    for (int i = 0; i < count; ++i) {
        double a = std::fmod(0.5 + (i + 1) / g, 1.0);
        double b = std::fmod(0.5 + (i + 1) / (g * g), 1.0);
        shifts.emplace_back(float(a - 0.5), float(b - 0.5));
    }
    return shifts;
}

} // namespace ndfmip
