// A material's own roughness map in the toksvig bake: alpha^2 averaged over each footprint,
// plus the normals' variance.
#include <cmath>
#include <filesystem>

#include <gtest/gtest.h>

#include "ndfmip/bake.h"
#include "ndfmip/io.h"
#include "ndfmip/roughness.h"
#include "test_support.h"

namespace ndfmip {
namespace {

SharedImage flatNormals(int size) {
    auto n = std::make_shared<Image>(size, size, 3);
    for (size_t i = 0; i < n->texelCount(); ++i) n->pixels[3 * i + 2] = 1.f;
    return n;
}

TEST(RoughnessMap, CheckerOfTwoRoughnessesAveragesTheirSquares) {
    // Flat normals (sigma = 0): level k's alpha is the RMS of the map's alpha over the footprint.
    const float a = 0.1f, b = 0.5f;
    auto map = std::make_shared<Image>(8, 8, 1);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) map->at(x, y)[0] = (x + y) % 2 ? a : b;
    BakeOptions options;
    options.roughnessMap = map;
    const Bake bake = bakeToksvig(buildPyramid(flatNormals(8)), options);
    const int ggx = findPlane(bake.planes, "roughness_ggx");
    EXPECT_NEAR(bake.levels[0][ggx]->at(1, 0)[0], a, 1e-6f);
    EXPECT_NEAR(bake.levels[0][ggx]->at(0, 0)[0], b, 1e-6f);
    for (int k = 1; k < 4; ++k)
        EXPECT_NEAR(bake.levels[k][ggx]->at(0, 0)[0], std::sqrt(0.5f * (a * a + b * b)), 1e-6f)
            << k;
    EXPECT_EQ(bake.parameters.at("roughness_map"), 1.0);
}

TEST(RoughnessMap, ConstantMapEqualsBaseRoughnessAndVariancesAdd) {
    // Bumpy normals: the constant map gives the base-roughness planes, alpha'^2 = a^2 + c sigma^2.
    auto normals = std::make_shared<Image>(16, 16, 3);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) {
            const glm::vec3 n = glm::normalize(
                glm::vec3(0.4f * std::sin(1.7f * float(x)), 0.3f * std::cos(2.3f * float(y)), 1.f));
            float* p = normals->at(x, y);
            p[0] = n.x, p[1] = n.y, p[2] = n.z;
        }
    const Pyramid pyramid = buildPyramid(normals);
    auto map = std::make_shared<Image>(16, 16, 1);
    for (float& v : map->pixels) v = 0.3f;
    BakeOptions withMap, withBase;
    withMap.roughnessMap = map;
    withBase.baseRoughness = 0.3f;
    const Bake a = bakeToksvig(pyramid, withMap), b = bakeToksvig(pyramid, withBase);
    const int ggx = findPlane(a.planes, "roughness_ggx"), mean = findPlane(a.planes, "mean");
    for (size_t k = 0; k < a.levels.size(); ++k)
        for (size_t i = 0; i < a.levels[k][ggx]->texelCount(); ++i) {
            EXPECT_NEAR(a.levels[k][ggx]->pixels[i], b.levels[k][ggx]->pixels[i], 1e-6f);
            const float r = length3(&a.levels[k][mean]->pixels[3 * i]);
            const float expected = std::min(std::sqrt(0.09f + kVarianceScale * (1.f - r) / r), 1.f);
            EXPECT_NEAR(a.levels[k][ggx]->pixels[i], expected, 1e-5f);
        }
}

TEST(RoughnessMap, CliReadsChannelAndEncodingAndRefusesMismatches) {
    test::TempDir dir("ndfmip_roughness_map");
    // A 4x4 normal map (flat, encoded 0.5, 0.5, 1) and a packed map whose green is perceptual
    // roughness 0.6 and alpha Unity smoothness 0.4 (the same alpha, 0.36).
    Image normal(4, 4, 3), packed(4, 4, 4);
    for (size_t i = 0; i < 16; ++i) {
        normal.pixels[3 * i] = normal.pixels[3 * i + 1] = 0.5f;
        normal.pixels[3 * i + 2] = 1.f;
        packed.pixels[4 * i + 1] = 0.6f;
        packed.pixels[4 * i + 3] = 0.4f;
    }
    ASSERT_TRUE(savePng(dir.file("n.png"), normal, 16));
    ASSERT_TRUE(savePng(dir.file("r.png"), packed, 16));
    std::string output;
    for (const std::string& options :
         {std::string("--roughness-channel g"),
          std::string("--roughness-channel a --roughness-encoding smoothness")}) {
        const std::string out = dir.file("bake");
        ASSERT_EQ(test::runCli("bake " + test::shellArg(dir.file("n.png")) + " --roughness-map " +
                                   test::shellArg(dir.file("r.png")) + " " + options + " -q -o " +
                                   test::shellArg(out),
                               &output),
                  0)
            << output;
        ASSERT_EQ(
            test::runCli("inspect " + test::shellArg(out) + " --level 1 --texel 0,0", &output), 0)
            << output;
        EXPECT_NE(output.find("\"roughness_ggx\": 0.36"), std::string::npos)
            << options << ": " << output;
    }
    Image small(2, 2, 1);
    ASSERT_TRUE(savePng(dir.file("small.png"), small, 8));
    test::expectCliRefuses("bake " + test::shellArg(dir.file("n.png")) + " --roughness-map " +
                               test::shellArg(dir.file("small.png")) + " -o " +
                               test::shellArg(dir.file("x")),
                           {"small.png", "2x2", "4x4"});
    Image grey(4, 4, 1);
    ASSERT_TRUE(savePng(dir.file("grey.png"), grey, 8));
    test::expectCliRefuses("bake " + test::shellArg(dir.file("n.png")) + " --roughness-map " +
                               test::shellArg(dir.file("grey.png")) + " --roughness-channel b -o " +
                               test::shellArg(dir.file("x")),
                           {"--roughness-channel b", "1 channel"});
    test::expectCliRefuses(
        "bake " + test::shellArg(dir.file("n.png")) + " --method vmf --roughness-map " +
            test::shellArg(dir.file("r.png")) + " -o " + test::shellArg(dir.file("x")),
        {"--roughness-map", "toksvig"});
}

} // namespace
} // namespace ndfmip
