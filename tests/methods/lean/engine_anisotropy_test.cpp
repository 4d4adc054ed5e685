// One anisotropic GGX lobe in each engine's inputs (KHR_materials_anisotropy, Kulla's, Burley's):
// closed forms, and each engine's own rebuilding of alpha_t and alpha_b from what is stored.
#include <gtest/gtest.h>

#include <cmath>

#include "methods/lean/engine_anisotropy.h"

namespace ndfmip {
namespace {

// alpha_t as the extension rebuilds it: mix(alpha_b, 1, s^2).
float alphaT(const KhrAnisotropy& k) {
    const float alphaB = k.roughness * k.roughness;
    return alphaB + k.strength * k.strength * (1.f - alphaB);
}

TEST(KhrAnisotropy, AnIsotropicLobeIsItsRoughnessWithNoStrength) {
    const KhrAnisotropy k = khrAnisotropy(0.04f, 0.04f, 0.f);
    EXPECT_NEAR(k.roughness, std::sqrt(0.2f), 1e-6);
    EXPECT_EQ(k.strength, 0.f);
    EXPECT_NEAR(glm::length(k.direction), 1.f, 1e-6);
}

TEST(KhrAnisotropy, TheWideAxisIsTheDirectionAndAlphaTRoundTrips) {
    const KhrAnisotropy x = khrAnisotropy(0.09f, 0.01f, 0.f);
    EXPECT_NEAR(x.roughness * x.roughness, 0.1f, 1e-6); // alpha_b
    EXPECT_NEAR(alphaT(x), 0.3f, 1e-6);
    EXPECT_NEAR(x.direction.x, 1.f, 1e-6);
    EXPECT_NEAR(x.direction.y, 0.f, 1e-6);
    const KhrAnisotropy y = khrAnisotropy(0.01f, 0.09f, 0.f);
    EXPECT_NEAR(std::abs(y.direction.y), 1.f, 1e-6);
    EXPECT_NEAR(alphaT(y), 0.3f, 1e-6);
    // The same lobe turned 30 degrees: R diag(0.09, 0.01) R^T.
    const float c = std::cos(glm::radians(30.f)), s = std::sin(glm::radians(30.f));
    const KhrAnisotropy turned = khrAnisotropy(
        0.09f * c * c + 0.01f * s * s, 0.09f * s * s + 0.01f * c * c, (0.09f - 0.01f) * c * s);
    EXPECT_NEAR(turned.direction.x, c, 1e-5);
    EXPECT_NEAR(turned.direction.y, s, 1e-5);
    EXPECT_NEAR(alphaT(turned), 0.3f, 1e-5);
    EXPECT_NEAR(turned.roughness, x.roughness, 1e-5);
    // -30 degrees: x stays positive, the axis has no sign.
    const KhrAnisotropy back = khrAnisotropy(
        0.09f * c * c + 0.01f * s * s, 0.09f * s * s + 0.01f * c * c, -(0.09f - 0.01f) * c * s);
    EXPECT_NEAR(back.direction.x, c, 1e-5);
    EXPECT_NEAR(back.direction.y, -s, 1e-5);
}

TEST(KhrAnisotropy, LobesWiderThanTheExtensionHoldsAreClamped) {
    const KhrAnisotropy wide = khrAnisotropy(4.f, 0.25f, 0.f);
    EXPECT_NEAR(wide.roughness, std::sqrt(0.5f), 1e-6);
    EXPECT_NEAR(alphaT(wide), 1.f, 1e-6);
    EXPECT_NEAR(wide.strength, 1.f, 1e-6);
    const KhrAnisotropy full = khrAnisotropy(2.f, 2.f, 0.f);
    EXPECT_EQ(full.roughness, 1.f);
    EXPECT_EQ(full.strength, 0.f);
    // A tensor that rounding left slightly indefinite: alpha_b 0, not NaN.
    const KhrAnisotropy flat = khrAnisotropy(0.01f, 0.01f, 0.0101f);
    EXPECT_EQ(flat.roughness, 0.f);
    EXPECT_TRUE(std::isfinite(flat.strength));
}

// Unreal's GetAnisotropicRoughness and Unity HDRP's ConvertAnisotropyToRoughness rebuild the
// lobe exactly: alpha (1 + k), alpha (1 - k) with alpha = roughness^2.
TEST(KullaAnisotropy, UnrealAndHdrpRebuildBothAlphas) {
    for (auto [at, ab] : {std::pair{0.3f, 0.1f}, std::pair{0.5f, 0.5f}, std::pair{0.9f, 0.01f},
                          std::pair{1.f, 0.f}}) {
        const RoughnessAnisotropy k = kullaAnisotropy({at, ab, {0.6f, 0.8f}});
        const float alpha = k.roughness * k.roughness;
        EXPECT_NEAR(alpha * (1.f + k.anisotropy), at, 1e-6f) << at << " " << ab;
        EXPECT_NEAR(alpha * (1.f - k.anisotropy), ab, 1e-6f) << at << " " << ab;
        EXPECT_GE(k.anisotropy, 0.f);
        EXPECT_LE(k.anisotropy, 1.f);
        EXPECT_EQ(k.direction, glm::vec2(0.6f, 0.8f));
    }
    EXPECT_EQ(kullaAnisotropy({0.f, 0.f, {1.f, 0.f}}).anisotropy, 0.f); // a mirror: no NaN
}

// Godot's light_compute: aspect = sqrt(1 - 0.9 k), alpha_t = alpha / aspect, alpha_b = alpha
// aspect; exact up to 10:1, and past it the product alpha_t alpha_b is kept.
TEST(BurleyAnisotropy, GodotRebuildsBothAlphasUpToTenToOne) {
    auto rebuilt = [](const RoughnessAnisotropy& k) {
        const float alpha = k.roughness * k.roughness;
        const float aspect = std::sqrt(1.f - 0.9f * k.anisotropy);
        return std::pair{alpha / aspect, alpha * aspect};
    };
    for (auto [at, ab] : {std::pair{0.3f, 0.1f}, std::pair{0.4f, 0.4f}, std::pair{0.5f, 0.05f}}) {
        const auto [t, b] = rebuilt(burleyAnisotropy({at, ab, {1.f, 0.f}}));
        EXPECT_NEAR(t, at, 1e-5f) << at << " " << ab;
        EXPECT_NEAR(b, ab, 1e-5f) << at << " " << ab;
    }
    const RoughnessAnisotropy far = burleyAnisotropy({0.8f, 0.02f, {1.f, 0.f}}); // 40:1
    EXPECT_EQ(far.anisotropy, 1.f);
    const auto [t, b] = rebuilt(far);
    EXPECT_NEAR(t * b, 0.8f * 0.02f, 1e-6f);
    EXPECT_NEAR(t / b, 10.f, 1e-4f);
}

// The lobe of a tensor: eigenvalues and the major axis, the same for every parametrisation.
TEST(AnisotropicLobe, EigenvaluesAndAxisOfTheTensor) {
    const float c = std::cos(glm::radians(30.f)), s = std::sin(glm::radians(30.f));
    const AnisotropicLobe lobe = anisotropicLobe(0.09f * c * c + 0.01f * s * s,
                                                 0.09f * s * s + 0.01f * c * c, 0.08f * c * s);
    EXPECT_NEAR(lobe.alphaT, 0.3f, 1e-5f);
    EXPECT_NEAR(lobe.alphaB, 0.1f, 1e-5f);
    EXPECT_NEAR(lobe.direction.x, c, 1e-5f);
    EXPECT_NEAR(lobe.direction.y, s, 1e-5f);
    const KhrAnisotropy khr = khrAnisotropy(lobe);
    EXPECT_NEAR(khr.roughness * khr.roughness, lobe.alphaB, 1e-6f);
    EXPECT_EQ(khr.direction, lobe.direction);
}

} // namespace
} // namespace ndfmip
