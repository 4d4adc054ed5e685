#include <algorithm>
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "ndfmip/io.h"
#include "ndfmip/normal_map.h"
#include "ndfmip/pyramid.h"
#include "ndfmip/toksvig.h"
#include "test_support.h"

namespace ndfmip {
namespace {

Image randomNormals(int w, int h, unsigned seed) {
    Image map(w, h, 3);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-1.f, 1.f);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) test::setNormal(map, x, y, u(rng), u(rng), 1.5f + u(rng));
    return map;
}

// Mean of the level-0 normals in a footprint, summed in double the obvious way.
void bruteForceMean(const Image& map, const Footprint& f, double out[3]) {
    out[0] = out[1] = out[2] = 0;
    for (int y = f.y0; y < f.y1; ++y)
        for (int x = f.x0; x < f.x1; ++x)
            for (int c = 0; c < 3; ++c) out[c] += map.at(x, y)[c];
    for (int c = 0; c < 3; ++c) out[c] /= double(f.count());
}

void expectMeansMatchBruteForce(const Image& map) {
    Pyramid pyramid = buildPyramid(map);
    for (int k = 0; k < int(pyramid.levels.size()); ++k) {
        const PyramidLevel& level = pyramid.levels[k];
        const Image& mean = levelMean(pyramid, k);
        ASSERT_EQ(mean.width, level.width);
        for (int y = 0; y < level.height; ++y)
            for (int x = 0; x < level.width; ++x) {
                double expected[3];
                bruteForceMean(map, footprint(pyramid, k, x, y), expected);
                for (int c = 0; c < 3; ++c)
                    ASSERT_NEAR(mean.at(x, y)[c], expected[c], 2e-6)
                        << map.width << "x" << map.height << " level " << k << " texel " << x << ","
                        << y;
            }
    }
}

TEST(Pyramid, LevelSizesFollowTheGpuRule) {
    Pyramid p = buildPyramid(randomNormals(745, 5, 1));
    std::vector<std::pair<int, int>> expected = {{745, 5}, {372, 2}, {186, 1}, {93, 1}, {46, 1},
                                                 {23, 1},  {11, 1},  {5, 1},   {2, 1},  {1, 1}};
    ASSERT_EQ(p.levels.size(), expected.size());
    for (size_t k = 0; k < expected.size(); ++k) {
        EXPECT_EQ(p.levels[k].width, expected[k].first) << k;
        EXPECT_EQ(p.levels[k].height, expected[k].second) << k;
    }
    EXPECT_EQ(levelCount(1, 1), 1);
    EXPECT_EQ(levelCount(4096, 4096), 13);
}

TEST(Pyramid, FootprintsPartitionLevelZeroAndNest) {
    for (auto [w, h] : {std::pair{13, 7}, {745, 3}, {1, 9}, {6, 6}}) {
        Pyramid p = buildPyramid(randomNormals(w, h, 2));
        for (int k = 0; k < int(p.levels.size()); ++k) {
            std::vector<int> covered(size_t(w) * h, 0);
            for (int y = 0; y < p.levels[k].height; ++y)
                for (int x = 0; x < p.levels[k].width; ++x) {
                    Footprint f = footprint(p, k, x, y);
                    Footprint g = footprintOf(w, h, k, x, y);
                    EXPECT_EQ(f.x0, g.x0);
                    EXPECT_EQ(f.y1, g.y1);
                    for (int by = f.y0; by < f.y1; ++by)
                        for (int bx = f.x0; bx < f.x1; ++bx) covered[size_t(by) * w + bx]++;
                    if (k > 0) { // the union of its children: both edges are finer edges
                        const PyramidLevel& fine = p.levels[k - 1];
                        auto has = [](const std::vector<int>& e, int v) {
                            return std::find(e.begin(), e.end(), v) != e.end();
                        };
                        EXPECT_TRUE(has(fine.columnEdges, f.x0) && has(fine.columnEdges, f.x1));
                        EXPECT_TRUE(has(fine.rowEdges, f.y0) && has(fine.rowEdges, f.y1));
                    }
                }
            for (int c : covered) ASSERT_EQ(c, 1) << w << "x" << h << " level " << k;
        }
    }
}

TEST(Pyramid, PowerOfTwoLevelsCoverExactBlocks) {
    Pyramid p = buildPyramid(randomNormals(16, 8, 3));
    for (int k = 0; k < int(p.levels.size()); ++k) {
        int bw = std::min(1 << k, 16), bh = std::min(1 << k, 8);
        Footprint f = footprint(p, k, p.levels[k].width - 1, p.levels[k].height - 1);
        EXPECT_EQ(f.width(), bw);
        EXPECT_EQ(f.height(), bh);
        EXPECT_EQ(f.x1, 16);
        EXPECT_EQ(f.y1, 8);
    }
}

TEST(Pyramid, MeansEqualBruteForceBlockMeans) {
    expectMeansMatchBruteForce(randomNormals(13, 7, 4));  // odd, non-square
    expectMeansMatchBruteForce(randomNormals(64, 32, 5)); // power of two, fast path
    expectMeansMatchBruteForce(randomNormals(1, 11, 6));  // a single column
    expectMeansMatchBruteForce(randomNormals(30, 2, 7));  // even, then odd (15) widths
}

TEST(Pyramid, BlockOfNormalsAtPlusMinusThetaHasLengthCosTheta) {
    for (float theta : {0.05f, 0.3f, 0.8f, 1.3f}) {
        Image map(2, 2, 3);
        test::setNormal(map, 0, 0, std::sin(theta), 0, std::cos(theta));
        test::setNormal(map, 1, 0, -std::sin(theta), 0, std::cos(theta));
        test::setNormal(map, 0, 1, 0, std::sin(theta), std::cos(theta));
        test::setNormal(map, 1, 1, 0, -std::sin(theta), std::cos(theta));
        Pyramid p = buildPyramid(map);
        const float* na = levelMean(p, 1).at(0, 0);
        float length = std::sqrt(na[0] * na[0] + na[1] * na[1] + na[2] * na[2]);
        EXPECT_NEAR(length, std::cos(theta), 1e-6f);
        EXPECT_NEAR(toksvigSigma2(length), (1 - std::cos(theta)) / std::cos(theta), 1e-5f);
    }
}

TEST(Pyramid, AddressModeDoesNotChangeFootprintsOrMeans) {
    // The footprints partition the map, so nothing outside it is ever read: wrap and clamp
    // give the same pyramid for a normal map (they differ for height maps and sampling).
    SourceImage source;
    source.image = Image(9, 5, 3);
    std::mt19937 rng(8);
    std::uniform_real_distribution<float> u(0.2f, 0.8f);
    for (float& v : source.image.pixels) v = u(rng);
    for (size_t i = 0; i < source.image.texelCount(); ++i) source.image.pixels[3 * i + 2] = 1.f;
    DecodeOptions wrap, clamp;
    clamp.address = AddressMode::Clamp;
    Result<Image> a = decodeNormalMap(source, wrap, "a", nullptr);
    Result<Image> b = decodeNormalMap(source, clamp, "b", nullptr);
    ASSERT_TRUE(a.ok() && b.ok());
    Pyramid pa = buildPyramid(a.value()), pb = buildPyramid(b.value());
    for (int k = 1; k < int(pa.levels.size()); ++k)
        EXPECT_EQ(levelMean(pa, k).pixels, levelMean(pb, k).pixels);
    expectMeansMatchBruteForce(a.value());
}

TEST(Pyramid, RealNonPowerOfTwoMapTopLevelIsTheMapMean) {
    auto dir = test::sharedNormalMaps();
    if (dir.empty()) GTEST_SKIP() << "../shared/data/normalmaps not present";
    Result<Image> map = loadNormalMap((dir / "godot_aluminium_normal.png").string(), {}, nullptr);
    ASSERT_TRUE(map.ok()) << map.error().message;
    ASSERT_EQ(map->width, 745);
    Pyramid p = buildPyramid(map.value());
    double expected[3];
    bruteForceMean(map.value(), {0, 745, 0, 745}, expected);
    const float* top = levelMean(p, int(p.levels.size()) - 1).at(0, 0);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(top[c], expected[c], 1e-6);
    // Every level of a 745x745 map against brute force, on a sample of texels.
    for (int k = 1; k < int(p.levels.size()); ++k) {
        const PyramidLevel& l = p.levels[k];
        for (int y = 0; y < l.height; y += std::max(1, l.height / 7))
            for (int x = 0; x < l.width; x += std::max(1, l.width / 7)) {
                bruteForceMean(map.value(), footprint(p, k, x, y), expected);
                for (int c = 0; c < 3; ++c)
                    ASSERT_NEAR(levelMean(p, k).at(x, y)[c], expected[c], 2e-6) << k;
            }
    }
}

} // namespace
} // namespace ndfmip
