// One anisotropic GGX lobe in each engine's own inputs (engine_anisotropy.h).
#include "methods/lean/engine_anisotropy.h"

#include <algorithm>
#include <cmath>

#include "ndfmip/method_shading.h"

namespace ndfmip {

AnisotropicLobe anisotropicLobe(float axx, float ayy, float axy) {
    // Eigenvalues of the symmetric 2x2 tensor: mean +- the half difference's length.
    const double mean = 0.5 * (double(axx) + double(ayy));
    const double half = 0.5 * (double(axx) - double(ayy));
    const double spread = std::sqrt(half * half + double(axy) * double(axy));
    const double alphaT = std::clamp(std::sqrt(std::max(mean + spread, 0.0)), 0.0, 1.0);
    const double alphaB = std::clamp(std::sqrt(std::max(mean - spread, 0.0)), 0.0, alphaT);
    // The major axis at angle atan2(2 axy, axx - ayy) / 2, in (-90, 90] degrees (x >= 0): the
    // half angle of (half, axy), the direction of (spread + half, axy), with no trigonometry.
    const double x = spread + half, y = double(axy);
    const double length = std::sqrt(x * x + y * y);
    const glm::vec2 direction = !(spread > 0.0) ? glm::vec2(1.f, 0.f)
                                : length > 0.0  ? glm::vec2(float(x / length), float(y / length))
                                                : glm::vec2(0.f, 1.f);
    return {float(alphaT), float(alphaB), direction};
}

AnisotropicLobe anisotropicLobeOfMoments(const float* m, float cross, float alpha2) {
    const glm::vec3 own = glsl().ndfmipLeanCovariance(glm::vec4(m[0], m[1], m[2], m[3]), cross);
    return anisotropicLobe(alpha2 + 2.f * own.x, alpha2 + 2.f * own.y, 2.f * own.z);
}

AnisotropicLobe anisotropicLobeOfGgxAniso(const float* m, const float* n) {
    const glm::vec3 a =
        glsl().ndfmipGgxAnisoTensor(glm::vec3(m[0], m[1], m[2]), glm::vec3(n[0], n[1], n[2]));
    return anisotropicLobe(a.x, a.z, a.y);
}

StoredDirections
coherentDirections(const std::vector<std::pair<int, int>>& sizes,
                   const std::function<AnisotropicLobe(size_t k, size_t i)>& lobe) {
    StoredDirections out;
    out.levels.resize(sizes.size());
    // A level's anisotropies (255 w), a byte each, for the level being chosen and its parent.
    std::vector<uint8_t> weight, parentWeight;
    for (size_t k = sizes.size(); k-- > 0;) {
        const auto [width, height] = sizes[k];
        const int64_t count = int64_t(width) * int64_t(height);
        std::vector<int16_t>& direction = out.levels[k];
        direction.resize(2 * size_t(count));
        weight.resize(size_t(count));
        // The lobes, texel by texel in parallel; only the signs' scan is in order.
#pragma omp parallel for schedule(static)
        for (int64_t i = 0; i < count; ++i) {
            const AnisotropicLobe l = lobe(k, size_t(i));
            const float sum = l.alphaT + l.alphaB;
            float w = sum > 0.f ? (l.alphaT - l.alphaB) / sum : 0.f;
            glm::vec2 d = l.direction;
            // No anisotropy, or a lobe that is not finite (a damaged bake): no direction.
            if (!(w > 0.f) || !(w <= 1.f) || !std::isfinite(d.x) || !std::isfinite(d.y))
                w = 0.f, d = glm::vec2(1.f, 0.f);
            direction[2 * size_t(i)] = int16_t(std::lround(32767.f * std::clamp(d.x, -1.f, 1.f)));
            direction[2 * size_t(i) + 1] =
                int16_t(std::lround(32767.f * std::clamp(d.y, -1.f, 1.f)));
            weight[size_t(i)] = uint8_t(std::lround(255.f * w));
        }
        const std::vector<int16_t>* parentDirection =
            k + 1 < sizes.size() ? &out.levels[k + 1] : nullptr;
        auto weighted = [](const std::vector<int16_t>& d, const std::vector<uint8_t>& w, size_t i) {
            return float(w[i]) * glm::vec2(float(d[2 * i]), float(d[2 * i + 1]));
        };
        const int parentWidth = parentDirection ? sizes[k + 1].first : 0;
        const int parentHeight = parentDirection ? sizes[k + 1].second : 0;
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x) {
                const size_t i = size_t(y) * size_t(width) + size_t(x);
                size_t parent = 0;
                if (parentDirection) {
                    const int px = std::min(int(int64_t(x) * parentWidth / width), parentWidth - 1);
                    const int py =
                        std::min(int(int64_t(y) * parentHeight / height), parentHeight - 1);
                    parent = size_t(py) * size_t(parentWidth) + size_t(px);
                }
                if (weight[i] == 0) { // no direction of its own: the parent's
                    if (parentDirection) {
                        direction[2 * i] = (*parentDirection)[2 * parent];
                        direction[2 * i + 1] = (*parentDirection)[2 * parent + 1];
                    }
                    continue;
                }
                glm::vec2 around(0.f);
                if (x > 0) around += weighted(direction, weight, i - 1);
                if (y > 0) {
                    const size_t above = i - size_t(width);
                    around += weighted(direction, weight, above);
                    if (x > 0) around += weighted(direction, weight, above - 1);
                    if (x + 1 < width) around += weighted(direction, weight, above + 1);
                }
                if (parentDirection) around += weighted(*parentDirection, parentWeight, parent);
                const glm::vec2 own{float(direction[2 * i]), float(direction[2 * i + 1])};
                if (glm::dot(around, own) < 0.f) {
                    direction[2 * i] = int16_t(-direction[2 * i]);
                    direction[2 * i + 1] = int16_t(-direction[2 * i + 1]);
                }
            }
        std::swap(weight, parentWeight);
    }
    return out;
}

KhrAnisotropy khrAnisotropy(const AnisotropicLobe& lobe) {
    const double alphaT = lobe.alphaT, alphaB = lobe.alphaB;
    KhrAnisotropy out;
    out.roughness = float(std::sqrt(alphaB));
    // alpha_t = alpha_b + s^2 (1 - alpha_b).
    out.strength = alphaB < 1.0 ? float(std::sqrt((alphaT - alphaB) / (1.0 - alphaB))) : 0.f;
    out.direction = lobe.direction;
    return out;
}

KhrAnisotropy khrAnisotropy(float axx, float ayy, float axy) {
    return khrAnisotropy(anisotropicLobe(axx, ayy, axy));
}

KhrAnisotropy khrAnisotropyOfMoments(const float* m, float cross, float alpha2) {
    return khrAnisotropy(anisotropicLobeOfMoments(m, cross, alpha2));
}

void khrAnisotropyTexel(const KhrAnisotropy& lobe, float* rgba) {
    rgba[0] = 0.5f * (lobe.direction.x + 1.f);
    rgba[1] = 0.5f * (lobe.direction.y + 1.f);
    rgba[2] = lobe.strength;
    rgba[3] = 1.f;
}

RoughnessAnisotropy kullaAnisotropy(const AnisotropicLobe& lobe) {
    const double sum = double(lobe.alphaT) + double(lobe.alphaB);
    RoughnessAnisotropy out;
    out.roughness = float(std::sqrt(0.5 * sum));
    out.anisotropy = sum > 0.0 ? float((double(lobe.alphaT) - double(lobe.alphaB)) / sum) : 0.f;
    out.direction = lobe.direction;
    return out;
}

RoughnessAnisotropy burleyAnisotropy(const AnisotropicLobe& lobe) {
    const double alphaT = lobe.alphaT, alphaB = lobe.alphaB;
    RoughnessAnisotropy out;
    out.roughness = float(std::sqrt(std::sqrt(alphaT * alphaB)));
    out.anisotropy = alphaT > 0.0 ? float(std::min((1.0 - alphaB / alphaT) / 0.9, 1.0)) : 0.f;
    out.direction = lobe.direction;
    return out;
}

} // namespace ndfmip
