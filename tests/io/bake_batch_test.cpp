// The batch runner in the library (bake_batch.h): expanding inputs, output patterns, shards,
// the plan's refusals, and a run in which one bad map fails alone.
#include <gtest/gtest.h>

#include <filesystem>
#include <set>

#include "ndfmip/bake_batch.h"
#include "ndfmip/io.h"
#include "test_support.h"

namespace fs = std::filesystem;

namespace ndfmip::test {
namespace {

void writeFlatMap(const std::string& path) {
    Image map(8, 8, 3);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) setNormal(map, x, y, 0.1f * float(x % 3), 0.f, 1.f);
    ASSERT_TRUE(savePng(path, map, 8));
}

TEST(BakeBatch, FoldersAndGlobsExpandToTheirImagesSorted) {
    TempDir tmp("batch-expand");
    fs::create_directory(tmp.path / "maps");
    for (const char* name : {"b.png", "a.PNG", "c.exr", "notes.txt"})
        writeBytes(tmp.path / "maps" / name, "x");
    Result<BakeInputs> folder = expandBakeInputs({tmp.file("maps")});
    ASSERT_TRUE(folder) << folder.error().message;
    EXPECT_TRUE(folder->expanded);
    EXPECT_EQ(folder->maps,
              (std::vector<std::string>{tmp.file("maps/a.PNG"), tmp.file("maps/b.png"),
                                        tmp.file("maps/c.exr")}));
    Result<BakeInputs> glob = expandBakeInputs({tmp.file("maps/*.png")});
    ASSERT_TRUE(glob);
    EXPECT_TRUE(glob->expanded);
    EXPECT_EQ(glob->maps, std::vector<std::string>{tmp.file("maps/b.png")});
    Result<BakeInputs> plain = expandBakeInputs({"one.png", "two.png"});
    ASSERT_TRUE(plain);
    EXPECT_FALSE(plain->expanded);
    EXPECT_EQ(plain->maps.size(), 2u);
    EXPECT_FALSE(expandBakeInputs({tmp.file("maps/*.tga")})); // a glob that matches nothing
    fs::create_directory(tmp.path / "empty");
    EXPECT_FALSE(expandBakeInputs({tmp.file("empty")}));
}

TEST(BakeBatch, PatternsNameEachMapsFolder) {
    EXPECT_EQ(bakeOutputFor("out/{parent}/{stem}.bake", "maps/rock/a.png").value(),
              "out/rock/a.bake");
    EXPECT_EQ(bakeOutputFor("{name}-{name}", "x/a.png").value(), "a.png-a.png");
    Result<std::string> dot = bakeOutputFor("out/{stem}", "maps/..png");
    ASSERT_FALSE(dot);
    EXPECT_NE(dot.error().message.find("names a folder"), std::string::npos);
}

TEST(BakeBatch, EveryMapIsInExactlyOneShardAndStaysThere) {
    std::vector<std::string> maps;
    for (int i = 0; i < 200; ++i) maps.push_back("maps/m" + std::to_string(i) + ".png");
    std::vector<int> count(7, 0);
    for (const std::string& m : maps) {
        const int s = bakeShardOf(m, 7);
        ASSERT_GE(s, 0);
        ASSERT_LT(s, 7);
        EXPECT_EQ(bakeShardOf(m, 7), s);
        EXPECT_EQ(bakeShardOf(m, 1), 0);
        ++count[size_t(s)];
    }
    for (int c : count) EXPECT_GT(c, 10); // spread over the shards, not all in one
    // The plan keeps exactly the shard's maps, in input order, and the shards cover every map.
    std::set<std::string> covered;
    for (int shard = 0; shard < 7; ++shard) {
        Result<std::vector<BakeBatchMap>> plan =
            planBakeBatch(BakeInputs{maps, true}, "out/{stem}.bake", shard, 7);
        ASSERT_TRUE(plan);
        for (const BakeBatchMap& m : plan.value()) {
            EXPECT_EQ(bakeShardOf(m.input, 7), shard);
            EXPECT_TRUE(covered.insert(m.input).second);
        }
    }
    EXPECT_EQ(covered.size(), maps.size());
}

TEST(BakeBatch, PlansRefuseAmbiguousOutputs) {
    const BakeInputs two{{"a/x.png", "b/x.png"}, false};
    EXPECT_FALSE(planBakeBatch(two, "out.bake", 0, 1));        // many maps, one folder
    EXPECT_FALSE(planBakeBatch(two, "out/{stem}.bake", 0, 1)); // both x
    EXPECT_TRUE(planBakeBatch(two, "out/{parent}-{stem}.bake", 0, 1));
    EXPECT_FALSE(planBakeBatch(two, "out/{parent}-{stem}.bake", 2, 2));         // no shard 2 of 2
    EXPECT_FALSE(planBakeBatch(BakeInputs{{"a.png"}, true}, "out.bake", 0, 1)); // from a folder
}

TEST(BakeBatch, OneBadMapFailsAloneAndARerunSkips) {
    TempDir tmp("batch-run");
    writeFlatMap(tmp.file("a.png"));
    writeFlatMap(tmp.file("c.png"));
    writeBytes(tmp.path / "b.png", "not a png");
    Result<std::vector<BakeBatchMap>> plan =
        planBakeBatch(BakeInputs{{tmp.file("a.png"), tmp.file("b.png"), tmp.file("c.png")}, false},
                      tmp.file("{stem}.bake"), 0, 1);
    ASSERT_TRUE(plan);
    BakeFileOptions options;
    options.method = "toksvig";
    std::vector<size_t> ended;
    runBakeBatch(plan.value(), options, 2,
                 [&](const BakeBatchMap&, size_t done, size_t) { ended.push_back(done); });
    EXPECT_EQ(ended, (std::vector<size_t>{1, 2, 3}));
    const std::vector<BakeBatchMap>& maps = plan.value();
    EXPECT_EQ(maps[0].status, "baked");
    EXPECT_EQ(maps[1].status, "failed");
    EXPECT_EQ(maps[1].error.rfind(tmp.file("b.png"), 0), 0u) << maps[1].error;
    EXPECT_EQ(maps[2].status, "baked");
    EXPECT_TRUE(fs::exists(tmp.path / "a.bake" / "manifest.json"));
    EXPECT_FALSE(fs::exists(tmp.path / "b.bake"));

    for (BakeBatchMap& m : plan.value()) m.status.clear(), m.error.clear();
    runBakeBatch(plan.value(), options, 1);
    EXPECT_EQ(maps[0].status, "skipped"); // same source, options and version
    EXPECT_EQ(maps[2].status, "skipped");
    EXPECT_EQ(maps[1].status, "failed");
}

} // namespace
} // namespace ndfmip::test
