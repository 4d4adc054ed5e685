// A bake read back, texel by texel, through the public functions inspect uses: the normal a
// level-0 texel stands for, and the NDF a texel stores (SH series, vMF mixture) or none.
#include <gtest/gtest.h>

#include <cmath>

#include "ndfmip/bake.h"
#include "ndfmip/method_parameters.h"
#include "test_support.h"

namespace ndfmip::test {
namespace {

TEST(BakeTexel, LevelZeroNormalAndStoredNdfOfEveryMethod) {
    // Every normal the same tilted one: each method's level 0 holds exactly that normal.
    const glm::vec3 n = glm::normalize(glm::vec3(0.3f, -0.2f, 1.f));
    Image map(4, 4, 3);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) setNormal(map, x, y, n.x, n.y, n.z);
    const Pyramid pyramid = buildPyramid(map);
    TempDir tmp("bake-texel");
    for (Method method : allMethods()) {
        SCOPED_TRACE(methodName(method));
        BakeOptions options;
        options.parameters = parametersOf(method, {});
        const Bake bake = bakeMethod(method, pyramid, options);
        const std::string dir = tmp.file(std::string(methodName(method)) + ".bake");
        BakeSource source;
        source.path = "map.png";
        source.sha256 = std::string(64, '0');
        source.width = source.height = 4;
        ASSERT_TRUE(writeBake(dir, bake, source));
        Result<LoadedBake> level0 = readBake(dir, 0);
        ASSERT_TRUE(level0) << level0.error().message;
        std::vector<float> texel;
        for (const Image& plane : level0->level)
            texel.insert(texel.end(), plane.at(1, 2), plane.at(1, 2) + plane.channels);
        const glm::vec3 stored = glm::normalize(bakeLevelZeroNormal(method, texel.data()));
        EXPECT_GT(glm::dot(stored, n), 0.99999f);

        const std::optional<double> atNormal = bakeNdfDensity(level0.value(), 1, 2, glm::dvec3(n));
        const std::optional<double> opposite = bakeNdfDensity(level0.value(), 1, 2, -glm::dvec3(n));
        if (method == Method::Sh || method == Method::Vmf) {
            ASSERT_TRUE(atNormal && opposite);
            EXPECT_GT(*atNormal, 4.0 * std::abs(*opposite)); // peaked at the normal
        } else {
            EXPECT_FALSE(atNormal); // naive, toksvig, lean store no NDF of their own
        }
    }
}

} // namespace
} // namespace ndfmip::test
