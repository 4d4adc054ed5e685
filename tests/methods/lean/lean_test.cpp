// LEAN mapping: slope moments that mip-map exactly, and the anisotropic Beckmann lobe they give.
#include <cmath>

#include <gtest/gtest.h>

#include "ndfmip/bake.h"
#include "ndfmip/brdf.h"
#include "ndfmip/method_shading.h"
#include "test_support.h"

namespace ndfmip {
namespace {

Material beckmann(float alpha) {
    Material m;
    m.brdf = Brdf::Beckmann;
    m.roughness = alpha;
    m.albedo = glm::vec3(0.f);
    m.specular = glm::vec3(1.f);
    return m;
}

TEST(Lean, MomentsAreFootprintMeansOfTheSlopes) {
    Image map(4, 2, 3);
    const float tilts[8] = {0.1f, -0.3f, 0.5f, 0.2f, 0.f, 0.4f, -0.2f, 0.3f};
    for (int i = 0; i < 8; ++i)
        test::setNormal(map, i % 4, i / 4, std::sin(tilts[i]), 0.5f * std::sin(tilts[7 - i]), 1.f);
    const Pyramid pyramid = buildPyramid(map);
    const Bake bake = bakeLean(pyramid, {});
    ASSERT_EQ(bake.levels.size(), 3u);
    for (int level = 0; level < 3; ++level) {
        const Image& first = *bake.levels[level][0];
        const Image& cross = *bake.levels[level][1];
        for (int y = 0; y < first.height; ++y)
            for (int x = 0; x < first.width; ++x) {
                const Footprint f = footprint(pyramid, level, x, y);
                double m[5] = {0, 0, 0, 0, 0};
                for (int by = f.y0; by < f.y1; ++by)
                    for (int bx = f.x0; bx < f.x1; ++bx) {
                        const float* n = pyramid.base->at(bx, by);
                        const double sx = n[0] / n[2], sy = n[1] / n[2];
                        m[0] += sx, m[1] += sy, m[2] += sx * sx, m[3] += sy * sy, m[4] += sx * sy;
                    }
                for (int c = 0; c < 4; ++c)
                    EXPECT_NEAR(first.at(x, y)[c], m[c] / double(f.count()), 1e-6);
                EXPECT_NEAR(cross.at(x, y)[0], m[4] / double(f.count()), 1e-6);
            }
    }
}

TEST(Lean, OneNormalAlongZIsTheBeckmannLobe) {
    // No spread of its own: the lobe is the material's Beckmann lobe, exactly.
    const float p[5] = {0.f, 0.f, 0.f, 0.f, 0.f};
    for (float alpha : {0.1f, 0.3f})
        for (float t : {0.f, 0.1f, 0.3f}) {
            const glm::vec3 h(std::sin(t) * 0.6f, std::sin(t) * 0.8f, std::cos(t));
            EXPECT_NEAR(leanLobe(beckmann(alpha), p, h), beckmannD(h.z, alpha),
                        1e-4f * beckmannD(1.f, alpha));
        }
}

TEST(Lean, TwoSlopesAlongXWidenTheLobeAlongXOnly) {
    // Normals at slopes +-s along x: slope variance s^2 along x, none along y. The lobe is the
    // Gaussian of slopes with variance alpha^2/2 + s^2 along x and alpha^2/2 along y.
    const float s = 0.2f, alpha = 0.1f;
    const float p[5] = {0.f, 0.f, s * s, 0.f, 0.f};
    const Material m = beckmann(alpha);
    const float along = leanLobe(m, p, glm::normalize(glm::vec3(0.1f, 0.f, 1.f)));
    const float across = leanLobe(m, p, glm::normalize(glm::vec3(0.f, 0.1f, 1.f)));
    EXPECT_GT(along, 2 * across); // exp(-0.11) against exp(-1)
    const float vx = 0.5f * alpha * alpha + s * s, vy = 0.5f * alpha * alpha;
    const float expected = std::exp(-0.5f * 0.01f / vx) / (2 * kPi * std::sqrt(vx * vy));
    const glm::vec3 h = glm::normalize(glm::vec3(0.1f, 0.f, 1.f));
    EXPECT_NEAR(along * std::pow(h.z, 4.f), expected, 1e-4f * expected);
}

} // namespace
} // namespace ndfmip
