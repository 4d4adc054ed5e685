// Toksvig's 2D lookup table (T eq. 9), indexed by Na.H and Na.Na, with the optional phase-out
// of T eqs. 10-11 where 8- or 16-bit normals make |Na| too imprecise for the Toksvig factor.
#include <algorithm>
#include <cmath>

#include "ndfmip/method_shading.h"
#include "ndfmip/toksvig.h"

namespace ndfmip {

float toksvigLutValue(float naDotH, float naDotNa, float s) {
    float length = std::sqrt(std::clamp(naDotNa, 0.f, 1.f));
    float ft = toksvigFactor(length, s);
    float cosine = length > 0.f ? std::clamp(naDotH, 0.f, length) / length : 1.f;
    return (1.f + ft * s) / (1.f + s) * std::pow(cosine, ft * s);
}

float toksvigIntensitySensitivity(float length, float s) {
    float d = length + s * (1.f - length);
    return s * s / ((1.f + s) * d * d);
}

float lengthQuantisationError(int bitDepth) {
    float steps = float((1 << (bitDepth - 1)) - 1); // largest signed value, 127 for 8 bits
    return std::sqrt(3.f) / (2.f * steps);
}

float toksvigLutEntry(float naDotH, float naDotNa, const ToksvigLutOptions& options) {
    const float s = options.exponent;
    float antialiased = toksvigLutValue(naDotH, naDotNa, s);
    if (options.bitDepth <= 0) return antialiased;
    float length = std::sqrt(std::clamp(naDotNa, 0.f, 1.f));
    float error =
        lengthQuantisationError(options.bitDepth) * toksvigIntensitySensitivity(length, s);
    if (error <= options.threshold) return antialiased;
    // T eq. 11: fall back towards the traditional lookup (Na.H/|Na|)^s as the error grows.
    float cosine = length > 0.f ? std::clamp(naDotH, 0.f, length) / length : 1.f;
    float aliased = std::pow(cosine, s);
    float w = options.threshold / error;
    return w * antialiased + (1.f - w) * aliased;
}

Image toksvigLut(const ToksvigLutOptions& options) {
    const int n = options.size;
    Image lut(n, n, 1);
    for (int j = 0; j < n; ++j) {
        float naDotNa = (j + 0.5f) / n;
        for (int i = 0; i < n; ++i)
            lut.at(i, j)[0] = toksvigLutEntry((i + 0.5f) / n, naDotNa, options);
    }
    return lut;
}

namespace {

// Bilinear read of a one-channel table over [0, 1]^2 (texel centres at (i + 0.5)/N), clamped.
float sampleTable(const Image& table, float u, float v) {
    const float x = std::clamp(u * float(table.width) - 0.5f, 0.f, float(table.width - 1));
    const float y = std::clamp(v * float(table.height) - 0.5f, 0.f, float(table.height - 1));
    const int x0 = int(x), y0 = int(y);
    const int x1 = std::min(x0 + 1, table.width - 1), y1 = std::min(y0 + 1, table.height - 1);
    const float fx = x - float(x0), fy = y - float(y0);
    const float top = (1 - fx) * table.at(x0, y0)[0] + fx * table.at(x1, y0)[0];
    const float bottom = (1 - fx) * table.at(x0, y1)[0] + fx * table.at(x1, y1)[0];
    return (1 - fy) * top + fy * bottom;
}

} // namespace

float toksvigLutLobe(const Material& m, glm::vec3 na, const Image& lut, glm::vec3 h) {
    const glm::vec2 uv = glsl().ndfmipToksvigLutCoordinates(na, h);
    return glsl().ndfmipToksvigLutLobe(m.exponent, sampleTable(lut, uv.x, uv.y));
}

glm::vec3 shadeToksvigLut(const Material& m, glm::vec3 albedo, glm::vec3 na, const Image& lut,
                          glm::vec3 l, glm::vec3 v) {
    return shadeToksvigLobe(m, albedo, na, l, v, toksvigLutLobe(m, na, lut, glm::normalize(l + v)));
}

} // namespace ndfmip
