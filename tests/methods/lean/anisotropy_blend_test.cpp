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

// One storage: a texel's channels (what a file holds, blended linearly by the hardware) and the
// tensor an engine rebuilds from blended channels.
struct Storage {
    const char* name;
    std::function<std::vector<double>(const AnisotropicLobe&, const float* moments, float cross)>
        store;
    std::function<glm::dmat2(const std::vector<double>&)> rebuild;
};

std::vector<Storage> storages(float alpha2) {
    auto dir = [](const AnisotropicLobe& l) {
        return std::vector<double>{unorm8(0.5 * (l.direction.x + 1.0)),
                                   unorm8(0.5 * (l.direction.y + 1.0))};
    };
    auto unpackDir = [](const std::vector<double>& c) {
        return glm::dvec2(2.0 * c[0] - 1.0, 2.0 * c[1] - 1.0);
    };
    return {
        {"slope moments (lean planes, float)",
         [](const AnisotropicLobe&, const float* m, float cross) {
             return std::vector<double>{m[0], m[1], m[2], m[3], cross};
         },
         [alpha2](const std::vector<double>& c) {
             const float m[4] = {float(c[0]), float(c[1]), float(c[2]), float(c[3])};
             const AnisotropicLobe l = anisotropicLobeOfMoments(m, float(c[4]), alpha2);
             return tensorOf(l.alphaT, l.alphaB, l.direction);
         }},
        {"alpha^2 tensor (3 channels, float)",
         [](const AnisotropicLobe& l, const float*, float) {
             const glm::dmat2 a = tensorOf(l.alphaT, l.alphaB, l.direction);
             return std::vector<double>{a[0][0], a[1][1], a[0][1]};
         },
         [](const std::vector<double>& c) { return glm::dmat2(c[0], c[2], c[2], c[1]); }},
        {"KHR: RG direction, B strength, roughness sqrt(alpha_b) (8-bit)",
         [dir](const AnisotropicLobe& l, const float*, float) {
             const KhrAnisotropy k = khrAnisotropy(l);
             std::vector<double> c = dir(l);
             c.push_back(unorm8(k.strength));
             c.push_back(unorm8(k.roughness));
             return c;
         },
         [unpackDir](const std::vector<double>& c) {
             const double alphaB = c[3] * c[3];
             return tensorOf(alphaB + c[2] * c[2] * (1.0 - alphaB), alphaB, unpackDir(c));
         }},
        {"Kulla (Unreal, HDRP): direction, k, roughness (8-bit)",
         [dir](const AnisotropicLobe& l, const float*, float) {
             const RoughnessAnisotropy k = kullaAnisotropy(l);
             std::vector<double> c = dir(l);
             c.push_back(unorm8(k.anisotropy));
             c.push_back(unorm8(k.roughness));
             return c;
         },
         [unpackDir](const std::vector<double>& c) {
             const double alpha = c[3] * c[3];
             return tensorOf(alpha * (1.0 + c[2]), alpha * (1.0 - c[2]), unpackDir(c));
         }},
        {"Burley (Godot): direction, k, roughness (8-bit)",
         [dir](const AnisotropicLobe& l, const float*, float) {
             const RoughnessAnisotropy k = burleyAnisotropy(l);
             std::vector<double> c = dir(l);
             c.push_back(unorm8(k.anisotropy));
             c.push_back(unorm8(k.roughness));
             return c;
         },
         [unpackDir](const std::vector<double>& c) {
             const double alpha = c[3] * c[3], aspect = std::sqrt(1.0 - 0.9 * c[2]);
             return tensorOf(alpha / aspect, alpha * aspect, unpackDir(c));
         }},
    };
}

// Mean relative error ||A_blend - A_union|| / ||A_union|| over every 2x2 block of levels
// 1 .. 6 (whole blocks of even-sized levels), per storage.
std::vector<double> blendErrors(const Image& normals, float alpha) {
    const Pyramid pyramid = buildPyramid(normals);
    BakeOptions options;
    options.parameters = parametersOf(Method::Lean, {});
    const Bake bake = bakeMethod(Method::Lean, pyramid, options);
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
                for (size_t s = 0; s < all.size(); ++s) {
                    std::vector<double> blended;
                    for (int dy = 0; dy < 2; ++dy)
                        for (int dx = 0; dx < 2; ++dx) {
                            const float* mi = m.at(x + dx, y + dy);
                            const float ci = c.at(x + dx, y + dy)[0];
                            const std::vector<double> ch =
                                all[s].store(anisotropicLobeOfMoments(mi, ci, alpha2), mi, ci);
                            blended.resize(ch.size(), 0.0);
                            for (size_t i = 0; i < ch.size(); ++i) blended[i] += 0.25 * ch[i];
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
    for (float alpha : {0.1f, 0.3f}) {
        const std::vector<double> e = blendErrors(normals.value(), alpha);
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
        for (float alpha : {0.1f, 0.3f}) {
            const std::vector<double> e = blendErrors(normals.value(), alpha);
            print(file, alpha, e);
            EXPECT_LT(e[0], 1e-4) << file;
        }
    }
}

} // namespace
} // namespace ndfmip
