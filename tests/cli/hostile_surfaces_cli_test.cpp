// The command line under hostile input on its newer surfaces: environment radiance that no float
// (or half float) holds, control characters in paths, shard numbers past their range, a cache
// whose files were deleted, outputs that are links or name folders, a render whose PNG cannot be
// written, and bytes in names that are not text. Each ends in one line naming the file and the
// problem, or in a correct output.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>

#include <stdlib.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include <nlohmann/json.hpp>

#include "gltf_test_asset.h"
#include "ndfmip/io.h"
#include "test_support.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace ndfmip::test {
namespace {

Image flatMap(int width, int height) {
    Image map(width, height, 3);
    for (size_t i = 0; i < map.texelCount(); ++i) {
        map.pixels[3 * i + 0] = 0.5f;
        map.pixels[3 * i + 1] = 0.5f;
        map.pixels[3 * i + 2] = 1.f;
    }
    return map;
}

// An equirectangular map of one radiance everywhere.
Image uniformSky(float radiance) {
    Image sky(64, 32, 3);
    for (float& v : sky.pixels) v = radiance;
    return sky;
}

// A PNG whose IHDR declares width x height 8-bit RGB pixels, followed by `dataBytes` bytes that
// no decoder inflates: any error about its size comes from its header alone.
std::string headerOnlyPng(uint32_t width, uint32_t height, size_t dataBytes) {
    std::string png("\x89PNG\r\n\x1a\n", 8);
    auto be32 = [&](uint32_t v) {
        for (int shift = 24; shift >= 0; shift -= 8) png += char((v >> shift) & 0xFF);
    };
    be32(13);
    png += "IHDR";
    be32(width);
    be32(height);
    png += std::string("\x08\x02\x00\x00\x00", 5); // 8 bits, RGB
    be32(0);                                       // CRC (never reached)
    be32(uint32_t(dataBytes));
    png += "IDAT";
    png += std::string(dataBytes, '\x55');
    return png;
}

class HostileSurfaces : public ::testing::Test {
  protected:
    TempDir tmp{"hostile_surfaces"};
    std::string map = tmp.file("map.png");
    fs::path out = tmp.path / "out";

    void SetUp() override { ASSERT_TRUE(savePng(map, flatMap(8, 8), 16)); }

    std::string envmapArgs(const std::string& input, const std::string& extra) const {
        return "envmap " + shellArg(input) +
               " -q --samples 4 --dfg-size 8 --dfg-samples 4 --size 32 --levels 2 " + extra +
               " -o " + shellArg(out.string());
    }
    std::string bakeArgs(const std::string& input, const std::string& extra = "") const {
        return "bake " + shellArg(input) + " -q " + extra + " -o " + shellArg(out.string());
    }
};

// ---- every float an environment folder holds is finite ----------------------------------------

TEST_F(HostileSurfaces, EnvmapIntensityThatOverflowsIsRefused) {
    const std::string sky = tmp.file("bright.exr");
    ASSERT_TRUE(saveExr(sky, uniformSky(1e33f)));
    // 1e33 is a float; times 1e6 it is not.
    expectCliRefuses(envmapArgs(sky, "--intensity 1e6"), {sky, "intensity", "not a finite number"});
    EXPECT_FALSE(fs::exists(out));
    EXPECT_TRUE(leftovers(tmp.path).empty());
    // Within range it is written, every value finite (JSON has no inf: it would be null).
    std::string output;
    ASSERT_EQ(runCli(envmapArgs(sky, "--intensity 1"), &output), 0) << output;
    const json sh = json::parse(fileBytes(out / "sh.json"));
    for (const json& band : sh["radiance"])
        for (const json& rgb : band)
            for (const json& v : rgb) EXPECT_TRUE(v.is_number()) << v;
}

TEST_F(HostileSurfaces, EnvmapRadianceAboveHalfRangeIsRefusedUnderHalf) {
    const std::string sun = tmp.file("sun.exr");
    ASSERT_TRUE(saveExr(sun, uniformSky(1e5f)));
    // The largest half float is 65504: 1e5 would be stored as inf.
    expectCliRefuses(envmapArgs(sun, "--half"), {sun, "65504", "--half"});
    EXPECT_FALSE(fs::exists(out));
    // The KTX2 textures are half floats too, --half or not.
    expectCliRefuses(envmapArgs(sun, "--ktx2"), {sun, "65504", "KTX2"});
    EXPECT_FALSE(fs::exists(out));
    EXPECT_TRUE(leftovers(tmp.path).empty());
    // As 32-bit floats it is stored as it is; and at 65504, --half holds it (the prefilter's
    // rounding may lift it a little: up to 65520 a half float rounds down to 65504, not to inf).
    std::string output;
    ASSERT_EQ(runCli(envmapArgs(sun, ""), &output), 0) << output;
    Result<SourceImage> level = loadImage((out / "ggx_L0.exr").string());
    ASSERT_TRUE(level) << level.error().message;
    EXPECT_NEAR(level->image.pixels[0], 1e5f, 1e5f * 1e-4f);
    fs::remove_all(out);
    const std::string edge = tmp.file("edge.exr");
    ASSERT_TRUE(saveExr(edge, uniformSky(65504.f)));
    ASSERT_EQ(runCli(envmapArgs(edge, "--half"), &output), 0) << output;
}

// ---- paths with control characters ------------------------------------------------------------

TEST_F(HostileSurfaces, ControlCharactersInPathsAreRefused) {
    // The shell cannot pass a NUL; a newline or an escape it can, and they are refused by name.
    const std::string odd = tmp.file("map\nx.png");
    fs::copy_file(map, odd);
    expectCliRefuses(bakeArgs(odd), {"map?x.png", "control character 0x0A"});
    EXPECT_FALSE(fs::exists(out));
    expectCliRefuses("bake " + shellArg(map) + " -q -o " + shellArg(tmp.file("o\x1b[2Jut")),
                     {"o?[2Jut", "control character 0x1B"});
    EXPECT_FALSE(fs::exists(tmp.file("o\x1b[2Jut")));
    EXPECT_TRUE(leftovers(tmp.path).empty());
}

// ---- shard numbers parsed whole ---------------------------------------------------------------

TEST_F(HostileSurfaces, ShardNumbersOutOfRangeOrEmptyAreRefused) {
    const std::string pattern = shellArg((tmp.path / "o" / "{stem}").string());
    for (const std::string shard : {"1/99999999999", "", "0/4294967297", "-0x1/2", "+1/2", "1/2 ",
                                    " 1/2", "1/", "/2", "2/2", "0/0"}) {
        SCOPED_TRACE(shard);
        expectCliRefuses("bake " + shellArg(map) + " -q --shard " + shellArg(shard) + " -o " +
                             pattern,
                         {"--shard '" + shard + "'", "expected I/N"});
    }
    EXPECT_FALSE(fs::exists(tmp.path / "o"));
    // Indices from an indexed job's environment, parsed whole: INT64_MIN, past INT64_MAX, trailing
    // bytes, exponents and spaces are all refused by name.
    for (const char* variable : {"SLURM_ARRAY_TASK_ID", "JOB_COMPLETION_INDEX"})
        for (const std::string value :
             {"-9223372036854775808", "9223372036854775808", "12abc", "1e3", " 1", "+1"}) {
            SCOPED_TRACE(std::string(variable) + "=" + value);
            ::setenv(variable, value.c_str(), 1);
            expectCliRefuses("bake " + shellArg(map) + " -q --shards 4 -o " + pattern,
                             {std::string(variable) + "='" + value + "'", "not an integer"});
            ::unsetenv(variable);
        }
    // SLURM_ARRAY_TASK_MIN cannot make the difference overflow either.
    ::setenv("SLURM_ARRAY_TASK_ID", "2147483647", 1);
    ::setenv("SLURM_ARRAY_TASK_MIN", "-2147483648", 1);
    expectCliRefuses("bake " + shellArg(map) + " -q --shards 4 -o " + pattern,
                     {"shard index 4294967295"});
    ::unsetenv("SLURM_ARRAY_TASK_ID");
    ::unsetenv("SLURM_ARRAY_TASK_MIN");
    EXPECT_FALSE(fs::exists(tmp.path / "o"));
    // A good one still bakes: shard 0 of 1 holds every map.
    std::string output;
    ASSERT_EQ(runCli("bake " + shellArg(map) + " -q --shard 0/1 -o " + pattern, &output), 0)
        << output;
    EXPECT_TRUE(fs::exists(tmp.path / "o" / "map" / "manifest.json"));
}

// ---- the cache skip checks the files, not only the manifest ----------------------------------

TEST_F(HostileSurfaces, AnUpToDateBakeWithAMissingOrEmptyFileIsBakedAgain) {
    const std::string args =
        "bake " + shellArg(map) + " --export exr,png16 -o " + shellArg(out.string());
    std::string output;
    ASSERT_EQ(runCli(args, &output), 0) << output;
    ASSERT_EQ(runCli(args, &output), 0) << output;
    ASSERT_NE(output.find("up to date"), std::string::npos) << output; // the cache works
    const auto whole = snapshot(out);
    const json manifest = json::parse(fileBytes(out / "manifest.json"));
    const std::string level = manifest["levels"].back()["files"].begin()->get<std::string>();
    const std::string exported = manifest["exports"]["png16"][0].get<std::string>();
    for (const std::string& file : {level, exported}) {
        for (const bool empty : {false, true}) {
            SCOPED_TRACE(file + (empty ? " emptied" : " deleted"));
            if (empty)
                writeBytes(out / file, "");
            else
                fs::remove(out / file);
            ASSERT_EQ(runCli(args, &output), 0) << output;
            EXPECT_EQ(output.find("up to date"), std::string::npos) << output;
            EXPECT_EQ(snapshot(out), whole); // baked again, the same bytes
            EXPECT_EQ(runCli("inspect " + shellArg(out.string()) + " --texel 0,0 --level " +
                                 std::to_string(manifest["levels"].size() - 1),
                             &output),
                      0)
                << output;
        }
    }
}

// ---- outputs that are links or name folders ---------------------------------------------------

TEST_F(HostileSurfaces, AnOutputThatIsALinkIsRefusedAndKept) {
    const fs::path real = tmp.path / "real.bake";
    std::string output;
    ASSERT_EQ(runCli("bake " + shellArg(map) + " -q -o " + shellArg(real.string()), &output), 0)
        << output;
    const auto earlier = snapshot(real);
    fs::create_directory_symlink("real.bake", out);
    expectCliRefuses(bakeArgs(map, "--method naive"), {out.string(), "symbolic link", "real.bake"});
    EXPECT_TRUE(fs::is_symlink(fs::symlink_status(out)));
    EXPECT_EQ(fs::read_symlink(out), fs::path("real.bake"));
    EXPECT_EQ(snapshot(real), earlier);
    // An environment folder is written the same way.
    const std::string sky = tmp.file("sky.exr");
    ASSERT_TRUE(saveExr(sky, uniformSky(1.f)));
    expectCliRefuses(envmapArgs(sky, ""), {out.string(), "symbolic link"});
    EXPECT_TRUE(fs::is_symlink(fs::symlink_status(out)));
    EXPECT_EQ(snapshot(real), earlier);
    EXPECT_TRUE(leftovers(tmp.path).empty());
}

TEST_F(HostileSurfaces, MapNamesWhoseStemIsADotFolderAreRefused) {
    fs::create_directories(tmp.path / "maps");
    const fs::path outs = tmp.path / "outs";
    fs::create_directories(outs);
    writeBytes(outs / "keep.txt", "mine");
    for (const char* name : {"..png", "...png"}) {
        SCOPED_TRACE(name);
        const fs::path odd = tmp.path / "maps" / name;
        fs::copy_file(map, odd);
        expectCliRefuses("bake " + shellArg(odd.string()) + " -q -o " +
                             shellArg((outs / "{stem}").string()),
                         {name, "{stem}", "names a folder"});
        fs::remove(odd);
    }
    EXPECT_EQ(snapshot(outs), (std::map<std::string, std::string>{{"keep.txt", "mine"}}));
    EXPECT_FALSE(fs::exists(tmp.path / "manifest.json"));
    EXPECT_TRUE(leftovers(tmp.path).empty());
}

// A flat plane under one light, 4x4: quick to render.
json planeScene(const std::string& normalMap) {
    return {{"camera",
             {{"type", "orthographic"},
              {"eye", {0, 0, 1}},
              {"target", {0, 0, 0}},
              {"up", {0, 1, 0}},
              {"ortho_height", 2},
              {"width", 4},
              {"height", 4}}},
            {"object", {{"type", "plane"}}},
            {"lights", {{{"type", "directional"}, {"direction", {0, 0, 1}}}}},
            {"normal_map", normalMap}};
}

TEST_F(HostileSurfaces, ARenderThatCannotWriteItsPngKeepsTheEarlierExr) {
    const std::string scene = tmp.file("scene.json");
    writeBytes(scene, planeScene("map.png").dump());
    const std::string exr = tmp.file("r.exr");
    const std::string render =
        "render " + shellArg(scene) + " -q --method groundtruth --spp 1 -o " + shellArg(exr);
    std::string output;
    ASSERT_EQ(runCli(render, &output), 0) << output;
    struct stat before {};
    ASSERT_EQ(::stat(exr.c_str(), &before), 0);
    // The PNG's name is taken by a folder: the render fails, and neither file changes.
    fs::remove(tmp.file("r.png"));
    fs::create_directories(tmp.path / "r.png" / "inside");
    expectCliRefuses(render, {tmp.file("r.png"), "cannot write"});
    struct stat after {};
    ASSERT_EQ(::stat(exr.c_str(), &after), 0);
    EXPECT_EQ(after.st_ino, before.st_ino) << "the EXR was replaced";
    EXPECT_TRUE(fs::is_directory(tmp.path / "r.png" / "inside"));
    EXPECT_TRUE(leftovers(tmp.path).empty());
    // With its name free again both are written.
    fs::remove_all(tmp.path / "r.png");
    ASSERT_EQ(runCli(render, &output), 0) << output;
    EXPECT_TRUE(fs::is_regular_file(tmp.file("r.png")));
    EXPECT_TRUE(leftovers(tmp.path).empty());
}

// ---- messages ---------------------------------------------------------------------------------

TEST_F(HostileSurfaces, BytesThatAreNotTextAreEscapedInMessages) {
    // A Latin-1 0xFF and a cut UTF-8 sequence are shown as \xFF and \xC3; a valid é is kept.
    const std::string name = std::string("missing\xFF") + "\xC3(" + "\xC3\xA9.png";
    std::string output;
    const int status = runCli(bakeArgs(tmp.file(name)), &output);
    expectOneLineError(status, output, {"missing\\xFF\\xC3(\xC3\xA9.png", "No such file"});
    EXPECT_EQ(output.find('\xFF'), std::string::npos) << output;
    EXPECT_EQ(output.find("\xC3("), std::string::npos) << output;
}

TEST_F(HostileSurfaces, AnImageAGltfNamesSaysWhyItCannotBeRead) {
    // Read, but not decodable: the decoder's reason, not a bare "cannot read".
    const fs::path folder = tmp.path / "asset";
    fs::create_directories(folder);
    const std::string gltf =
        writeGltf(folder, quadAsset(), {{"empty.png", ""}, {"orm.png", "GIF89a"}});
    const std::string glb = tmp.file("out.glb");
    expectCliRefuses("gltf " + shellArg(gltf) + " -q -o " + shellArg(glb),
                     {"empty.png", "file is empty"});
    EXPECT_FALSE(fs::exists(glb));
}

} // namespace
} // namespace ndfmip::test

namespace ndfmip::test {
namespace {

// Each command that decodes a map knows its peak from its options and refuses, from the PNG's
// header alone, a map whose pipeline --max-memory cannot hold: the data is never inflated (it
// could not be), and the message gives the estimate.
TEST_F(HostileSurfaces, EveryCommandRefusesFromTheHeaderWhatMaxMemoryCannotHold) {
    const std::string big = tmp.file("big.png");
    writeBytes(big, headerOnlyPng(2048, 1024, 16384)); // 6.3 MB of rows: deflate holds it in 6 KB
    const std::string limit = "--max-memory 0.01 ";
    expectCliRefuses(limit + bakeArgs(big),
                     {big, "a toksvig bake of a 2048x1024 map needs about", "--max-memory"});
    expectCliRefuses(limit + envmapArgs(big, ""),
                     {big, "prefiltering of a 2048x1024 map needs about", "--max-memory"});
    expectCliRefuses(limit + "eval " + shellArg(big) + " -q -o " + shellArg(tmp.file("report")),
                     {big, "the evaluation of a 2048x1024 map needs about", "--max-memory"});
    const json scene = {{"camera",
                         {{"type", "orthographic"},
                          {"eye", {0, 0, 1}},
                          {"target", {0, 0, 0}},
                          {"up", {0, 1, 0}},
                          {"ortho_height", 2},
                          {"width", 4},
                          {"height", 4}}},
                        {"object", {{"type", "plane"}}},
                        {"lights", {{{"type", "directional"}, {"direction", {0, 0, 1}}}}},
                        {"normal_map", "big.png"}};
    writeBytes(tmp.path / "scene.json", scene.dump());
    expectCliRefuses(limit + "render " + shellArg(tmp.file("scene.json")) + " -o " +
                         shellArg(tmp.file("o.exr")),
                     {"big.png", "needs about", "--max-memory"});
    EXPECT_FALSE(fs::exists(out));
    EXPECT_FALSE(fs::exists(tmp.file("o.exr")));
    EXPECT_TRUE(leftovers(tmp.path).empty());
}

// An allocation that fails although the estimate was within --max-memory (here: an address
// space too small for what the estimate allowed) ends in one line naming the file, in a bake
// and in a --json batch line.
TEST_F(HostileSurfaces, RunningOutOfMemoryIsALineNamingTheFile) {
#if defined(__SANITIZE_ADDRESS__)
    GTEST_SKIP() << "AddressSanitizer reserves more address space than the limit allows";
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
    GTEST_SKIP() << "AddressSanitizer reserves more address space than the limit allows";
#endif
#endif
    // A 2048 x 2048 map of flat normals: 48 MiB decoded, an sh bake of order 8 about 1.8 GiB.
    const std::string big = tmp.file("big.png");
    ASSERT_TRUE(savePng(big, flatMap(2048, 2048), 8));
    // The CLI under 1 GiB of address space, which its own mappings fit in (--version runs), with
    // few threads and malloc arenas (each reserves address space, more with more cores).
    auto limited = [](const std::string& args, std::string* output) {
        const std::string command =
            std::string("ulimit -v 1048576; OMP_NUM_THREADS=2 MALLOC_ARENA_MAX=2 exec \"") +
            NDFMIP_CLI_PATH + "\" " + args + " 2>&1";
        FILE* pipe = popen(command.c_str(), "r");
        if (!pipe) return -1;
        output->clear();
        char buffer[4096];
        for (size_t n; (n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0;)
            output->append(buffer, n);
        const int status = pclose(pipe);
        return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    };
    std::string output;
    ASSERT_EQ(limited("--version", &output), 0) << output;
    const std::string sh = " -q --method sh --order 8 ";
    expectOneLineError(
        limited("--max-memory 1000 bake " + shellArg(big) + sh + "-o " + shellArg(out.string()),
                &output),
        output, {big, "out of memory"});
    EXPECT_FALSE(fs::exists(out));
    // In a batch, the map's --json line says the same, and the batch fails.
    const int batch = limited("--max-memory 1000 bake " + shellArg(big) + " " + shellArg(map) + sh +
                                  "--json -o " + shellArg((tmp.path / "batch" / "{stem}").string()),
                              &output);
    EXPECT_NE(batch, 0) << output;
    EXPECT_NE(output.find("\"error\":\"" + big + ": out of memory"), std::string::npos) << output;
}

} // namespace
} // namespace ndfmip::test
