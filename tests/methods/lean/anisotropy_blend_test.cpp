// What an engine's hardware blend of stored anisotropy channels gives, against the lobe of the
// blended footprint. A lookup halfway between texels averages the four children of a 2x2 block;
// the lobe of their union is the parent's (the slope moments average exactly). Measured on the
// bundled map and, where ../shared exists, the real maps (printed; docs/RESULTS.md):
//   build/tests/ndfmip_tests --gtest_filter='AnisotropyBlend.*'
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <vector>

#include "methods/lean/engine_anisotropy.h"
#include "ndfmip/bake.h"
#include "ndfmip/method_parameters.h"
#include "ndfmip/normal_map.h"
#include "test_support.h"

namespace ndfmip {
namespace {

// The squared-roughness tensor of a lobe: R diag(alpha_t^2, alpha_b^2) R^T.
glm::dmat2 tensorOf(double alphaT, double alphaB, glm::dvec2 d) {
    d = glm::length(d) > 0.0 ? glm::normalize(d) : glm::dvec2(1.0, 0.0);
    const glm::dvec2 e(-d.y, d.x);
    return alphaT * alphaT * glm::outerProduct(d, d) + alphaB * alphaB * glm::outerProduct(e, e);
}

double frobenius(const glm::dmat2& m) {
    return std::sqrt(m[0][0] * m[0][0] + m[0][1] * m[0][1] + m[1][0] * m[1][0] + m[1][1] * m[1][1]);
}

// 8-bit UNORM, as the RGBA8 files store a channel.
double unorm8(double v) {
    return std::round(std::clamp(v, 0.0, 1.0) * 255.0) / 255.0;
}

// A texel's stored channels, at most five.
struct Channels {
    double value[5] = {};
    int count = 0;
};

// One storage: a texel's channels (what a file holds, blended linearly by the hardware) and the
// tensor an engine rebuilds from blended channels.
struct Storage {
    const char* name;
    std::function<Channels(const AnisotropicLobe&, const float* moments, float cross)> store;
    std::function<glm::dmat2(const Channels&)> rebuild;
};

// The direction as RG8, then an engine's two 8-bit channels.
Channels directionAnd(const AnisotropicLobe& l, double a, double b) {
    return {{unorm8(0.5 * (l.direction.x + 1.0)), unorm8(0.5 * (l.direction.y + 1.0)), unorm8(a),
             unorm8(b)},
            4};
}

glm::dvec2 unpackDirection(const Channels& c) {
    return glm::dvec2(2.0 * c.value[0] - 1.0, 2.0 * c.value[1] - 1.0);
}

std::vector<Storage> storages(float alpha2) {
    return {
        {"slope moments (lean planes, float)",
         [](const AnisotropicLobe&, const float* m, float cross) {
             return Channels{{m[0], m[1], m[2], m[3], cross}, 5};
         },
         [alpha2](const Channels& c) {
             const float m[4] = {float(c.value[0]), float(c.value[1]), float(c.value[2]),
                                 float(c.value[3])};
             const AnisotropicLobe l = anisotropicLobeOfMoments(m, float(c.value[4]), alpha2);
             return tensorOf(l.alphaT, l.alphaB, l.direction);
         }},
        {"alpha^2 tensor (3 channels, float)",
         [](const AnisotropicLobe& l, const float*, float) {
             const glm::dmat2 a = tensorOf(l.alphaT, l.alphaB, l.direction);
             return Channels{{a[0][0], a[1][1], a[0][1]}, 3};
         },
         [](const Channels& c) {
             return glm::dmat2(c.value[0], c.value[2], c.value[2], c.value[1]);
         }},
        {"KHR: RG direction, B strength, roughness sqrt(alpha_b) (8-bit)",
         [](const AnisotropicLobe& l, const float*, float) {
             const KhrAnisotropy k = khrAnisotropy(l);
             return directionAnd(l, k.strength, k.roughness);
         },
         [](const Channels& c) {
             const double alphaB = c.value[3] * c.value[3];
             return tensorOf(alphaB + c.value[2] * c.value[2] * (1.0 - alphaB), alphaB,
                             unpackDirection(c));
         }},
        {"Kulla (Unreal, HDRP): direction, k, roughness (8-bit)",
         [](const AnisotropicLobe& l, const float*, float) {
             const RoughnessAnisotropy k = kullaAnisotropy(l);
             return directionAnd(l, k.anisotropy, k.roughness);
         },
         [](const Channels& c) {
             const double alpha = c.value[3] * c.value[3];
             return tensorOf(alpha * (1.0 + c.value[2]), alpha * (1.0 - c.value[2]),
                             unpackDirection(c));
         }},
        {"Burley (Godot): direction, k, roughness (8-bit)",
         [](const AnisotropicLobe& l, const float*, float) {
             const RoughnessAnisotropy k = burleyAnisotropy(l);
             return directionAnd(l, k.anisotropy, k.roughness);
         },
         [](const Channels& c) {
             const double alpha = c.value[3] * c.value[3],
                          aspect = std::sqrt(1.0 - 0.9 * c.value[2]);
             return tensorOf(alpha / aspect, alpha * aspect, unpackDirection(c));
         }},
    };
}

// Mean relative error ||A_blend - A_union|| / ||A_union|| over every 2x2 block of levels
// 1 .. 6 (whole blocks of even-sized levels), per storage.
Bake leanBake(const Image& normals) {
    BakeOptions options;
    options.parameters = parametersOf(Method::Lean, {});
    return bakeMethod(Method::Lean, buildPyramid(normals), options);
}

std::vector<double> blendErrors(const Bake& bake, float alpha) {
    const int moments = findPlane(bake.planes, "lean_moments");
    const int cross = findPlane(bake.planes, "lean_cross");
    const float alpha2 = alpha * alpha;
    const std::vector<Storage> all = storages(alpha2);
    std::vector<double> sum(all.size(), 0.0);
    size_t blocks = 0;
    for (size_t k = 1; k + 1 < bake.levels.size() && k <= 6; ++k) {
        const Image& m = *bake.levels[k][size_t(moments)];
        const Image& c = *bake.levels[k][size_t(cross)];
        const Image& pm = *bake.levels[k + 1][size_t(moments)];
        const Image& pc = *bake.levels[k + 1][size_t(cross)];
        if (m.width % 2 || m.height % 2) continue;
        for (int y = 0; y + 1 < m.height; y += 2)
            for (int x = 0; x + 1 < m.width; x += 2) {
                const AnisotropicLobe parent =
                    anisotropicLobeOfMoments(pm.at(x / 2, y / 2), pc.at(x / 2, y / 2)[0], alpha2);
                const glm::dmat2 truth = tensorOf(parent.alphaT, parent.alphaB, parent.direction);
                // The four children (row by row) and their lobes, once for every storage.
                const float* childMoments[4];
                float childCross[4];
                AnisotropicLobe lobes[4];
                for (int i = 0; i < 4; ++i) {
                    childMoments[i] = m.at(x + i % 2, y + i / 2);
                    childCross[i] = c.at(x + i % 2, y + i / 2)[0];
                    lobes[i] = anisotropicLobeOfMoments(childMoments[i], childCross[i], alpha2);
                }
                for (size_t s = 0; s < all.size(); ++s) {
                    Channels blended;
                    for (int i = 0; i < 4; ++i) {
                        const Channels ch = all[s].store(lobes[i], childMoments[i], childCross[i]);
                        blended.count = ch.count;
                        for (int j = 0; j < ch.count; ++j) blended.value[j] += 0.25 * ch.value[j];
                    }
                    sum[s] += frobenius(all[s].rebuild(blended) - truth) / frobenius(truth);
                }
                ++blocks;
            }
    }
    for (double& e : sum) e /= double(std::max<size_t>(blocks, 1));
    return sum;
}

void print(const char* map, float alpha, const std::vector<double>& errors) {
    const std::vector<Storage> all = storages(alpha * alpha);
    for (size_t s = 0; s < all.size(); ++s)
        std::printf("anisotropy blend: %s, alpha %.2f, %s: %.4f\n", map, alpha, all[s].name,
                    errors[s]);
}

// The bundled map: the moments blend to the union exactly (float rounding); every other storage
// is off by what its nonlinearity costs, the direction's RG (which shortens where neighbours'
// axes differ) most of all.
TEST(AnisotropyBlend, MomentsBlendToTheUnionAndEngineChannelsDoNot) {
    Result<Image> normals = loadNormalMap(
        std::string(NDFMIP_SOURCE_DIR) + "/data/normalmaps/pyramidwall_256.png", {}, nullptr);
    ASSERT_TRUE(normals) << normals.error().message;
    const Bake bake = leanBake(normals.value());
    for (float alpha : {0.1f, 0.3f}) {
        const std::vector<double> e = blendErrors(bake, alpha);
        print("pyramidwall_256", alpha, e);
        EXPECT_LT(e[0], 1e-4) << alpha; // the moments: exact
        for (size_t s = 1; s < e.size(); ++s) {
            EXPECT_TRUE(std::isfinite(e[s])) << s;
            EXPECT_GT(e[s], 10.0 * e[0]) << s; // the nonlinear storages lose something
        }
    }
}

TEST(AnisotropyBlend, SharedMaps) {
    const auto dir = test::sharedNormalMaps();
    if (dir.empty()) GTEST_SKIP() << "../shared/data/normalmaps not present";
    for (const char* file : {"stktex_generic_rockA_Normal.png", "godot_wool_normal.png",
                             "stk_generic_brickA_Normal.png", "Ground010_1K_Normal.png"}) {
        Result<Image> normals = loadNormalMap((dir / file).string(), {}, nullptr);
        ASSERT_TRUE(normals) << normals.error().message;
        const Bake bake = leanBake(normals.value());
        for (float alpha : {0.1f, 0.3f}) {
            const std::vector<double> e = blendErrors(bake, alpha);
            print(file, alpha, e);
            EXPECT_LT(e[0], 1e-4) << file;
        }
    }
}

} // namespace
} // namespace ndfmip
