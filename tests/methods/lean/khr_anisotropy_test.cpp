// KHR_materials_anisotropy's texel of an anisotropic GGX lobe: closed forms.
#include <gtest/gtest.h>

#include <cmath>

#include "methods/lean/khr_anisotropy.h"

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

} // namespace
} // namespace ndfmip
