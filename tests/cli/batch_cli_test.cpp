// bake over many maps: output patterns, parallel maps, the cache key that skips up-to-date
// bakes, shards, JSON lines, and one map's failure not stopping the others.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "test_support.h"

namespace ndfmip {
namespace {

namespace fs = std::filesystem;

const std::string kMap = std::string(NDFMIP_SOURCE_DIR) + "/data/normalmaps/pyramidwall_256.png";

std::string bytesOf(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), {});
}

// Every file under `dir` by its relative name.
std::map<std::string, std::string> filesOf(const fs::path& dir) {
    std::map<std::string, std::string> files;
    for (const auto& entry : fs::recursive_directory_iterator(dir))
        if (entry.is_regular_file())
            files[entry.path().lexically_relative(dir).string()] = bytesOf(entry.path());
    return files;
}

// The JSON lines of an output (stderr is mixed in by the test runner).
std::vector<nlohmann::json> jsonLines(const std::string& output) {
    std::vector<nlohmann::json> lines;
    std::istringstream in(output);
    for (std::string line; std::getline(in, line);)
        if (!line.empty() && line[0] == '{') lines.push_back(nlohmann::json::parse(line));
    return lines;
}

// Three copies of the bundled map (one in a subfolder) and a corrupt one.
struct Library {
    test::TempDir dir{"ndfmip_batch"};
    std::string maps = dir.file("maps");
    Library() {
        fs::create_directories(maps);
        for (const char* name : {"a.png", "b.png", "c.png"}) fs::copy_file(kMap, maps + "/" + name);
        std::ofstream(maps + "/broken.png") << "not a png";
    }
};

TEST(BatchCli, ManyMapsInParallelMatchSingleBakesAndOneFailureStopsNothing) {
    Library lib;
    std::string output;
    const std::string out = lib.dir.file("out");
    EXPECT_EQ(test::runCli("bake " + test::shellArg(lib.maps) +
                               " --green-down --jobs 2 --json -o " +
                               test::shellArg(out + "/deeper/{stem}.bake"),
                           &output),
              1)
        << output;
    const std::vector<nlohmann::json> lines = jsonLines(output);
    ASSERT_EQ(lines.size(), 5u) << output;
    std::map<std::string, std::string> status;
    for (size_t i = 0; i < 4; ++i)
        status[fs::path(lines[i]["map"].get<std::string>()).filename()] = lines[i]["status"];
    EXPECT_EQ(
        status,
        (std::map<std::string, std::string>{
            {"a.png", "baked"}, {"b.png", "baked"}, {"c.png", "baked"}, {"broken.png", "failed"}}));
    const nlohmann::json& summary = lines[4]["summary"];
    EXPECT_EQ(summary["baked"], 3);
    EXPECT_EQ(summary["failed"], 1);
    ASSERT_EQ(summary["failures"].size(), 1u);
    EXPECT_NE(summary["failures"][0].get<std::string>().find("broken.png"), std::string::npos);
    // Byte for byte the bake one process writes for the same map.
    ASSERT_EQ(test::runCli("bake " + test::shellArg(lib.maps + "/b.png") + " --green-down -q -o " +
                               test::shellArg(lib.dir.file("single.bake")),
                           &output),
              0)
        << output;
    EXPECT_EQ(filesOf(out + "/deeper/b.bake"), filesOf(lib.dir.file("single.bake")));
}

TEST(BatchCli, UpToDateBakesAreSkippedUntilSourceOrOptionsChange) {
    Library lib;
    fs::remove(lib.maps + "/broken.png");
    const std::string pattern = test::shellArg(lib.dir.file("out/{stem}.bake"));
    std::string output;
    ASSERT_EQ(test::runCli("bake " + test::shellArg(lib.maps) + " --json -o " + pattern, &output),
              0)
        << output;
    const auto before = filesOf(lib.dir.file("out"));
    ASSERT_EQ(test::runCli("bake " + test::shellArg(lib.maps) + " --json -o " + pattern, &output),
              0)
        << output;
    EXPECT_EQ(jsonLines(output).back()["summary"]["skipped"], 3) << output;
    EXPECT_EQ(filesOf(lib.dir.file("out")), before);
    // A changed source: only that map again. (The new bytes: the map as ndfmip re-encodes it.)
    ASSERT_EQ(test::runCli("bake " + test::shellArg(kMap) + " --export png16 -q -o " +
                               test::shellArg(lib.dir.file("png")),
                           &output),
              0)
        << output;
    fs::copy_file(lib.dir.file("png/png16/normal_L0.png"), lib.maps + "/b.png",
                  fs::copy_options::overwrite_existing);
    ASSERT_EQ(test::runCli("bake " + test::shellArg(lib.maps) + " --json -o " + pattern, &output),
              0)
        << output;
    std::set<std::string> baked;
    for (const nlohmann::json& line : jsonLines(output))
        if (line.contains("status") && line["status"] == "baked")
            baked.insert(fs::path(line["map"].get<std::string>()).filename());
    EXPECT_EQ(baked, (std::set<std::string>{"b.png"})) << output;
    // Other options: everything again; --force: everything again.
    ASSERT_EQ(
        test::runCli("bake " + test::shellArg(lib.maps) + " --json --green-down -o " + pattern,
                     &output),
        0)
        << output;
    EXPECT_EQ(jsonLines(output).back()["summary"]["baked"], 3) << output;
    ASSERT_EQ(test::runCli("bake " + test::shellArg(lib.maps) + " --json --green-down --force -o " +
                               pattern,
                           &output),
              0)
        << output;
    EXPECT_EQ(jsonLines(output).back()["summary"]["baked"], 3) << output;
    // One map, as before: a plain line saying so.
    ASSERT_EQ(test::runCli("bake " + test::shellArg(lib.maps + "/a.png") + " --green-down -o " +
                               test::shellArg(lib.dir.file("out/a.bake")),
                           &output),
              0);
    EXPECT_NE(output.find("up to date"), std::string::npos) << output;
}

TEST(BatchCli, ShardsSplitTheMapsStablyAndWholly) {
    Library lib;
    fs::remove(lib.maps + "/broken.png");
    for (int i = 0; i < 5; ++i)
        fs::copy_file(kMap, lib.maps + "/extra" + std::to_string(i) + ".png");
    std::multiset<std::string> all;
    for (int shard = 0; shard < 3; ++shard) {
        std::string output;
        ASSERT_EQ(test::runCli("bake " + test::shellArg(lib.maps) + " --json --shard " +
                                   std::to_string(shard) + "/3 -o " +
                                   test::shellArg(lib.dir.file("out/{stem}.bake")),
                               &output),
                  0)
            << output;
        for (const nlohmann::json& line : jsonLines(output))
            if (line.contains("map")) all.insert(line["map"].get<std::string>());
    }
    EXPECT_EQ(all.size(), 8u);
    EXPECT_EQ(std::set<std::string>(all.begin(), all.end()).size(),
              8u); // each map in exactly one shard
    // The index from an indexed job's environment: the same split as --shard.
    std::string byFlag, byEnv;
    ASSERT_EQ(test::runCli("bake " + test::shellArg(lib.maps) + " --json --shard 1/3 -o " +
                               test::shellArg(lib.dir.file("a/{stem}.bake")),
                           &byFlag),
              0);
    setenv("JOB_COMPLETION_INDEX", "1", 1);
    const int status = test::runCli("bake " + test::shellArg(lib.maps) + " --json --shards 3 -o " +
                                        test::shellArg(lib.dir.file("b/{stem}.bake")),
                                    &byEnv);
    unsetenv("JOB_COMPLETION_INDEX");
    ASSERT_EQ(status, 0) << byEnv;
    auto maps = [](const std::string& output) {
        std::set<std::string> m;
        for (const nlohmann::json& line : jsonLines(output))
            if (line.contains("map")) m.insert(line["map"].get<std::string>());
        return m;
    };
    EXPECT_EQ(maps(byFlag), maps(byEnv));
}

TEST(BatchCli, BadPatternsAndShardsAreRefusedBeforeAnyBake) {
    Library lib;
    const std::string maps = test::shellArg(lib.maps);
    test::expectCliRefuses("bake " + maps + " -o " + test::shellArg(lib.dir.file("out")),
                           {"{stem}"});
    test::expectCliRefuses("bake " + maps + " -o " + test::shellArg(lib.dir.file("out/{parent}/x")),
                           {"{stem}"});
    test::expectCliRefuses("bake " + maps + " " + maps + " -o " +
                               test::shellArg(lib.dir.file("o/{stem}")),
                           {"would both be baked"});
    test::expectCliRefuses("bake " + maps + " --shard 3/3 -o " +
                               test::shellArg(lib.dir.file("o/{stem}")),
                           {"--shard"});
    unsetenv("JOB_COMPLETION_INDEX");
    unsetenv("SLURM_ARRAY_TASK_ID");
    test::expectCliRefuses("bake " + maps + " --shards 3 -o " +
                               test::shellArg(lib.dir.file("o/{stem}")),
                           {"JOB_COMPLETION_INDEX"});
    test::expectCliRefuses("bake " + test::shellArg(lib.dir.file("none*.png")) + " -o " +
                               test::shellArg(lib.dir.file("o/{stem}")),
                           {"no file matches"});
    EXPECT_FALSE(fs::exists(lib.dir.file("out")));
    EXPECT_FALSE(fs::exists(lib.dir.file("o")));
}

} // namespace
} // namespace ndfmip
