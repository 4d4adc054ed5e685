// One anisotropic GGX lobe in each engine's inputs (KHR_materials_anisotropy, Kulla's, Burley's):
// closed forms, each engine's own rebuilding of alpha_t and alpha_b from what is stored (in C++
// and in the shaders' decoders), and the directions' signs that a sampler's blend of them needs.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "methods/lean/engine_anisotropy.h"
#include "ndfmip/glsl.h"

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

// The lobe at `degrees` from x with alpha_t 0.3, alpha_b 0.1, as anisotropicLobe stores it (x >=
// 0): R diag(0.09, 0.01) R^T.
AnisotropicLobe lobeAt(float degrees, float alphaT = 0.3f, float alphaB = 0.1f) {
    const float c = std::cos(glm::radians(degrees)), s = std::sin(glm::radians(degrees));
    const float t2 = alphaT * alphaT, b2 = alphaB * alphaB;
    return anisotropicLobe(t2 * c * c + b2 * s * s, t2 * s * s + b2 * c * c, (t2 - b2) * c * s);
}

// The direction three.js reads from a blend of anisotropyTexture texels: normalize(2 RG - 1).
glm::vec2 blendedDirection(const std::vector<glm::vec2>& directions) {
    glm::vec2 rg(0.f);
    for (const glm::vec2& d : directions) rg += 0.5f * (d + 1.f) / float(directions.size());
    return glm::normalize(2.f * rg - 1.f);
}

// A checkerboard of lobes at 85 and 95 degrees (stored as 85 and -85): every neighbour's stored
// direction points against the texel's, and the blend of two reads a direction along x, 90
// degrees off both. With the directions chosen, every neighbour agrees and the blend reads along
// y; each is its lobe's axis.
TEST(CoherentDirections, NeighboursAcrossTheVerticalAgree) {
    const int side = 8;
    std::vector<AnisotropicLobe> lobes;
    for (int y = 0; y < side; ++y)
        for (int x = 0; x < side; ++x) lobes.push_back(lobeAt((x + y) % 2 ? 95.f : 85.f));
    EXPECT_LT(glm::dot(lobes[0].direction, lobes[1].direction), -0.9f);
    EXPECT_NEAR(std::abs(blendedDirection({lobes[0].direction, lobes[1].direction}).x), 1.f, 1e-4f);
    const StoredDirections chosen =
        coherentDirections({{side, side}}, [&](size_t, size_t i) { return lobes[i]; });
    ASSERT_EQ(chosen.levels.size(), 1u);
    ASSERT_EQ(chosen.levels[0].size(), 2 * lobes.size());
    auto at = [&](int x, int y) { return chosen.at(0, size_t(y * side + x)); };
    for (int y = 0; y < side; ++y)
        for (int x = 0; x < side; ++x) {
            const glm::vec2 own = lobes[size_t(y * side + x)].direction;
            EXPECT_NEAR(std::abs(glm::dot(at(x, y), own)), 1.f, 1e-4f);
            if (x + 1 < side) {
                EXPECT_GT(glm::dot(at(x, y), at(x + 1, y)), 0.9f);
            }
            if (y + 1 < side) {
                EXPECT_GT(glm::dot(at(x, y), at(x, y + 1)), 0.9f);
            }
        }
    const glm::vec2 blend = blendedDirection({at(3, 3), at(4, 3)});
    EXPECT_NEAR(std::abs(blend.y), 1.f, 1e-4f); // 90 degrees, between the two
}

// Across levels: a coarse texel at 100 degrees (stored -80) over three at 92 and 88 degrees and an
// isotropic one; the three take the parent's sign, so the blend of two levels turns between them
// too, and the isotropic one (no direction of its own) stores the parent's.
TEST(CoherentDirections, ChildrenAgreeWithTheirParentAndIsotropicOnesTakeIts) {
    const std::vector<AnisotropicLobe> fine = {lobeAt(92.f), lobeAt(88.f), lobeAt(88.f),
                                               lobeAt(0.f, 0.2f, 0.2f)};
    const AnisotropicLobe coarse = lobeAt(100.f);
    const StoredDirections chosen = coherentDirections(
        {{2, 2}, {1, 1}}, [&](size_t k, size_t i) { return k == 0 ? fine[i] : coarse; });
    ASSERT_EQ(chosen.levels.size(), 2u);
    const glm::vec2 parent = chosen.at(1, 0);
    EXPECT_NEAR(std::abs(glm::dot(parent, coarse.direction)), 1.f, 1e-4f);
    for (size_t i = 0; i < 3; ++i) EXPECT_GT(glm::dot(chosen.at(0, i), parent), 0.9f) << i;
    EXPECT_NEAR(glm::dot(chosen.at(0, 3), parent), 1.f, 1e-4f);
}

// A lobe that is not finite (a damaged bake) or isotropic has no direction of its own: it pulls
// nothing. In a 2 x 2 level of 85 degrees, such a lobe, an isotropic one and 95 degrees, the last
// agrees with the first (its neighbour above and to the left) across them.
TEST(CoherentDirections, LobesWithoutADirectionPullNothing) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const std::vector<AnisotropicLobe> lobes = {
        lobeAt(85.f), {nan, nan, {nan, nan}}, lobeAt(0.f, 0.2f, 0.2f), lobeAt(95.f)};
    const StoredDirections chosen =
        coherentDirections({{2, 2}}, [&](size_t, size_t i) { return lobes[i]; });
    ASSERT_EQ(chosen.levels[0].size(), 8u);
    for (size_t i = 0; i < 4; ++i) EXPECT_NEAR(glm::length(chosen.at(0, i)), 1.f, 1e-4f) << i;
    EXPECT_GT(glm::dot(chosen.at(0, 0), chosen.at(0, 3)), 0.9f);
}

// What each engine decodes from its inputs (ggx_aniso.glsl: glTF's KHR_materials_anisotropy as
// three.js does, Kulla's as Unreal and HDRP do, Burley's as Godot does) is the tensor the lobe came
// from, R diag(alpha_t^2, alpha_b^2) R^T, for either sign of the direction (Burley's within its
// 10:1 stretch).
TEST(EngineAnisotropy, EachEnginesDecodedTensorIsTheLobesForEitherSign) {
    for (float degrees : {0.f, 30.f, 89.f, 135.f}) {
        for (auto [at, ab] :
             {std::pair{0.3f, 0.1f}, std::pair{0.5f, 0.06f}, std::pair{0.2f, 0.2f}}) {
            const float c = std::cos(glm::radians(degrees)), s = std::sin(glm::radians(degrees));
            const glm::vec3 tensor(at * at * c * c + ab * ab * s * s, (at * at - ab * ab) * c * s,
                                   at * at * s * s + ab * ab * c * c);
            AnisotropicLobe lobe = anisotropicLobe(tensor.x, tensor.z, tensor.y);
            for (float sign : {1.f, -1.f}) {
                lobe.direction *= sign;
                const KhrAnisotropy khr = khrAnisotropy(lobe);
                float rgba[4];
                khrAnisotropyTexel(khr, rgba);
                const RoughnessAnisotropy kulla = kullaAnisotropy(lobe);
                const RoughnessAnisotropy burley = burleyAnisotropy(lobe);
                auto channels = [](const RoughnessAnisotropy& r) {
                    return glm::vec4(r.roughness, 0.5f * (r.direction.x + 1.f),
                                     0.5f * (r.direction.y + 1.f), r.anisotropy);
                };
                const glm::vec3 decoded[3] = {
                    glsl().ndfmipKhrAnisotropyTensor(
                        glm::vec4(khr.roughness, rgba[0], rgba[1], rgba[2])),
                    glsl().ndfmipKullaAnisotropyTensor(channels(kulla)),
                    glsl().ndfmipBurleyAnisotropyTensor(channels(burley))};
                for (int engine = 0; engine < 3; ++engine)
                    for (int c3 = 0; c3 < 3; ++c3)
                        EXPECT_NEAR(decoded[engine][c3], tensor[c3], 1e-5f)
                            << "engine " << engine << ", " << degrees << " degrees, " << at << " / "
                            << ab << ", sign " << sign;
            }
        }
    }
}

} // namespace
} // namespace ndfmip
