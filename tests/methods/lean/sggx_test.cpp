// sggx: the lean bake's slope moments read as one anisotropic GGX lobe.
#include <cmath>

#include <gtest/gtest.h>

#include "ndfmip/bake.h"
#include "ndfmip/brdf.h"
#include "ndfmip/method_shading.h"
#include "test_support.h"

namespace ndfmip {
namespace {

Material ggx(float alpha) {
    Material m;
    m.brdf = Brdf::Ggx;
    m.roughness = alpha;
    m.albedo = glm::vec3(0.f);
    m.specular = glm::vec3(1.f);
    return m;
}

TEST(Sggx, OneNormalAlongZIsTheMaterialsGgxLobe) {
    const float p[5] = {0.f, 0.f, 0.f, 0.f, 0.f};
    for (float alpha : {0.05f, 0.1f, 0.3f})
        for (float t : {0.f, 0.1f, 0.3f, 0.8f}) {
            const glm::vec3 h(std::sin(t) * 0.6f, std::sin(t) * 0.8f, std::cos(t));
            EXPECT_NEAR(sggxLobe(ggx(alpha), p, h), test::ggxReference(h.z, alpha),
                        1e-5 * test::ggxReference(1., alpha))
                << "alpha " << alpha << " angle " << t;
        }
}

TEST(Sggx, TwoNormalsAtPlusMinusThetaAboutXWidenAlongXOnly) {
    // Normals at slopes +-s along x: covariance s^2 along x, none along y; the tensor is
    // diag(alpha^2 + 2 s^2, alpha^2), so alpha_x = sqrt(alpha^2 + 2 s^2) > alpha_y = alpha.
    const float s = std::tan(0.2f), alpha = 0.1f;
    const float p[5] = {0.f, 0.f, s * s, 0.f, 0.f};
    const Material m = ggx(alpha);
    const glm::vec3 hx = glm::normalize(glm::vec3(0.1f, 0.f, 1.f));
    const glm::vec3 hy = glm::normalize(glm::vec3(0.f, 0.1f, 1.f));
    const float along = sggxLobe(m, p, hx), across = sggxLobe(m, p, hy);
    EXPECT_GT(along, 2 * across);
    const double ax2 = alpha * alpha + 2. * s * s, ay2 = alpha * alpha;
    const double q = 0.01 / ax2;
    const double expected =
        1. / (kPi * std::sqrt(ax2 * ay2) * std::pow(double(hx.z), 4.) * (1. + q) * (1. + q));
    EXPECT_NEAR(along, expected, 1e-4 * expected);
}

TEST(Sggx, AnyMomentsKeepUnitProjectedArea) {
    // The integral of D(h) h.z over the hemisphere is the integral of the slope density: 1 for
    // any mean slope and covariance.
    const float sets[3][5] = {{0.f, 0.f, 0.02f, 0.01f, 0.f},
                              {0.2f, -0.1f, 0.05f + 0.04f, 0.03f + 0.01f, -0.02f - 0.02f},
                              {0.f, 0.3f, 0.1f, 0.09f + 0.2f, 0.05f}};
    for (const auto& p : sets)
        for (float alpha : {0.1f, 0.3f}) {
            const Material m = ggx(alpha);
            const int nt = 2000, np = 400;
            double sum = 0.;
            for (int i = 0; i < nt; ++i) {
                const double t = (i + 0.5) * (0.5 * kPi) / nt;
                for (int j = 0; j < np; ++j) {
                    const double f = (j + 0.5) * 2. * kPi / np;
                    const glm::vec3 h(std::sin(t) * std::cos(f), std::sin(t) * std::sin(f),
                                      std::cos(t));
                    sum += sggxLobe(m, p, h) * std::cos(t) * std::sin(t);
                }
            }
            sum *= (0.5 * kPi / nt) * (2. * kPi / np);
            EXPECT_NEAR(sum, 1., 0.01)
                << "alpha " << alpha << " mean slope " << p[0] << "," << p[1];
        }
}

TEST(Sggx, BakeOfAFlatMapShadesAsGgx) {
    // A bake of flat normals: every level's moments are 0, the lobe the material's own.
    Image map(8, 8, 3);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) test::setNormal(map, x, y, 0.f, 0.f, 1.f);
    const Bake bake = bakeLean(buildPyramid(map), {});
    const glm::vec3 h = glm::normalize(glm::vec3(0.2f, 0.1f, 1.f));
    for (const auto& level : bake.levels) {
        float p[5];
        for (int c = 0; c < 4; ++c) p[c] = level[0]->at(0, 0)[c];
        p[4] = level[1]->at(0, 0)[0];
        EXPECT_NEAR(sggxLobe(ggx(0.2f), p, h), test::ggxReference(h.z, 0.2), 1e-4);
    }
}

} // namespace
} // namespace ndfmip
