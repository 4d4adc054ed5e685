// Bake folders edited by hand or by an attacker: inspect and render must refuse each one with a
// single line naming the file and the problem, never read outside the folder or past an image.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <limits>
#include <string>

#include <nlohmann/json.hpp>

#include "ndfmip/io.h"
#include "test_support.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace ndfmip::test {
namespace {

// A unit-normal map of gentle bumps, encoded c = (n + 1) / 2.
Image bumpyMap(int width, int height) {
    Image map(width, height, 3);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            setNormal(map, x, y, 0.3f * std::sin(float(x)), 0.2f * std::cos(float(y)), 1.f);
            for (int c = 0; c < 3; ++c) map.at(x, y)[c] = 0.5f * (map.at(x, y)[c] + 1.f);
        }
    return map;
}

class TamperedBake : public ::testing::Test {
  protected:
    TempDir tmp{"tampered"};
    fs::path pristine = tmp.path / "pristine", bake = tmp.path / "bake";
    std::string map = tmp.file("map.png");

    void SetUp() override { ASSERT_TRUE(savePng(map, bumpyMap(8, 8), 16)); }

    // Bakes `args` into `pristine` once; each test then works on a fresh copy in `bake`.
    void makeBake(const std::string& args) {
        std::string output;
        ASSERT_EQ(
            runCli("bake " + shellArg(map) + " -q " + args + " -o " + shellArg(pristine.string()),
                   &output),
            0)
            << output;
        fresh();
    }

    void fresh() {
        fs::remove_all(bake);
        fs::copy(pristine, bake, fs::copy_options::recursive);
    }

    // Rewrites bake/manifest.json through `edit`.
    void tamper(const std::function<void(json&)>& edit) {
        json m = json::parse(fileBytes(bake / "manifest.json"));
        edit(m);
        writeBytes(bake / "manifest.json", m.dump(2));
    }

    std::string manifest() const { return (bake / "manifest.json").string(); }
    std::string inspectArgs(int level = 0) const {
        return "inspect " + shellArg(bake.string()) + " --level " + std::to_string(level) +
               " --texel 0,0";
    }

    // A render of the flat scene with this bake.
    std::string renderArgs() {
        json scene = {{"camera",
                       {{"type", "orthographic"},
                        {"eye", {0, 0, 1}},
                        {"target", {0, 0, 0}},
                        {"up", {0, 1, 0}},
                        {"ortho_height", 2},
                        {"width", 4},
                        {"height", 4}}},
                      {"object", {{"type", "plane"}}},
                      {"lights", {{{"type", "directional"}, {"direction", {0, 0, 1}}}}},
                      {"normal_map", "map.png"}};
        writeBytes(tmp.path / "scene.json", scene.dump());
        return "render " + shellArg(tmp.file("scene.json")) + " -q --bake " +
               shellArg(bake.string()) + " -o " + shellArg(tmp.file("out.exr"));
    }

    // inspect (and render) refuse the tampered bake, naming each of `mentions`.
    void expectRefused(std::initializer_list<std::string> mentions, bool alsoRender = true) {
        expectCliRefuses(inspectArgs(), mentions);
        if (alsoRender) expectCliRefuses(renderArgs(), mentions);
        EXPECT_FALSE(fs::exists(tmp.path / "out.exr"));
    }
};

TEST_F(TamperedBake, UntouchedBakeIsRead) {
    makeBake("--method toksvig");
    std::string output;
    EXPECT_EQ(runCli(inspectArgs(3), &output), 0) << output;
    EXPECT_EQ(runCli(renderArgs(), &output), 0) << output;
}

TEST_F(TamperedBake, LevelSizesMustFollowTheSourceAndTheFiles) {
    makeBake("--method toksvig");
    // The level list alone disagrees with the source size.
    tamper([](json& m) { m["levels"][0]["width"] = 32; });
    expectRefused({manifest(), "'levels[0].width'", "from 8 to 8", "32"});
    // A consistent manifest for a 4x wider source: the files are then too small.
    fresh();
    tamper([](json& m) {
        m["source"]["width"] = 32;
        json levels = json::array();
        int w = 32, h = 8;
        for (int k = 0; k < 6; ++k, w = std::max(1, w / 2), h = std::max(1, h / 2)) {
            json files;
            for (const char* plane : {"mean", "roughness_beckmann", "roughness_ggx"})
                files[plane] = std::string(plane) + "_L" + std::to_string(std::min(k, 3)) + ".exr";
            levels.push_back({{"level", k}, {"width", w}, {"height", h}, {"files", files}});
        }
        m["levels"] = levels;
    });
    expectRefused({(bake / "mean_L0.exr").string(), "is 8x8", "32x8"});
    // Fewer levels than the mip chain has.
    fresh();
    tamper([](json& m) { m["levels"].erase(3); });
    expectRefused({manifest(), "'levels' has 3 entries", "4 levels"});
}

TEST_F(TamperedBake, ImageFilesMustMatchTheirLevelAndPlane) {
    makeBake("--method toksvig");
    ASSERT_TRUE(saveExr((bake / "mean_L0.exr").string(), Image(1, 1, 3)));
    expectRefused({(bake / "mean_L0.exr").string(), "is 1x1", "8x8"});
    fresh();
    ASSERT_TRUE(saveExr((bake / "roughness_ggx_L0.exr").string(), Image(8, 8, 3)));
    expectRefused({(bake / "roughness_ggx_L0.exr").string(), "3 channels", "with 1"});
    fresh();
    Image nan(8, 8, 3);
    nan.at(5, 6)[1] = std::numeric_limits<float>::quiet_NaN();
    ASSERT_TRUE(saveExr((bake / "mean_L0.exr").string(), nan));
    expectRefused({(bake / "mean_L0.exr").string(), "(5, 6)", "not a finite number"});
}

TEST_F(TamperedBake, ShOrderMustBeInRangeAndMatchThePlanes) {
    makeBake("--method sh --order 1");
    for (const char* order : {"50", "100000", "0", "2.5", "1e300"}) {
        SCOPED_TRACE(order);
        fresh();
        tamper([&](json& m) { m["parameters"]["order"] = json::parse(order); });
        expectRefused({manifest(), "'parameters.order'", "from 1 to 30"});
    }
    // In range, but the planes are those of order 1.
    fresh();
    tamper([](json& m) { m["parameters"]["order"] = 3; });
    expectRefused({manifest(), "'planes' do not match a sh bake of order 3", "sh3 (4)"});
    fresh();
    tamper([](json& m) { m["parameters"].erase("order"); });
    expectRefused({manifest(), "missing key 'parameters.order'"});
}

TEST_F(TamperedBake, VmfLobesMustBeInRange) {
    makeBake("--method vmf --lobes 1");
    for (const char* lobes : {"1e300", "9", "0", "-1"}) {
        SCOPED_TRACE(lobes);
        fresh();
        tamper([&](json& m) { m["parameters"]["lobes"] = json::parse(lobes); });
        expectRefused({manifest(), "'parameters.lobes'", "from 1 to 8"});
    }
}

TEST_F(TamperedBake, PlanesMustBeTheMethods) {
    makeBake("--method toksvig");
    tamper([](json& m) { m["planes"] = json::array(); });
    expectRefused({manifest(), "'planes' do not match a toksvig bake", "found none"});
    fresh();
    tamper([](json& m) { m["planes"][0]["channels"].push_back("extra"); });
    expectRefused({manifest(), "'planes' do not match", "mean (4)"});
    fresh();
    tamper([](json& m) { m["planes"][1]["linear"] = true; });
    expectRefused({manifest(), "'planes' do not match", "not linear"});
}

TEST_F(TamperedBake, AnOlderGgxAnisoBakeIsRefusedWithAHint) {
    // ggx-aniso bakes before alpha_moments held the tensor alone, as alpha_tensor: read as
    // moments it would shade another lobe, so it is refused, saying what to do.
    makeBake("--method ggx-aniso --base-roughness 0.2");
    tamper([](json& m) { m["planes"][1]["name"] = "alpha_tensor"; });
    expectRefused({manifest(), "'planes' do not match a ggx-aniso bake", "alpha_tensor (3)",
                   "bake it again"});
}

TEST_F(TamperedBake, LevelFilesMustBePlainNamesInsideTheFolder) {
    makeBake("--method toksvig");
    writeBytes(tmp.path / "outside.exr", fileBytes(bake / "mean_L0.exr"));
    for (const std::string& name :
         {std::string("/etc/passwd"), std::string("../outside.exr"), std::string("sub/mean_L0.exr"),
          std::string(".."), std::string("")}) {
        SCOPED_TRACE(name);
        fresh();
        tamper([&](json& m) { m["levels"][0]["files"]["mean"] = name; });
        expectRefused({manifest(), "'levels[0].files.mean'", "not a plain file name"});
    }
    // A plain name that is a link to a file elsewhere is refused too.
    fresh();
    fs::remove(bake / "mean_L0.exr");
    fs::create_symlink(tmp.path / "outside.exr", bake / "mean_L0.exr");
    expectRefused({(bake / "mean_L0.exr").string(), "symbolic link"});
}

TEST_F(TamperedBake, MissingKeysAreNamedNotInternalErrors) {
    makeBake("--method toksvig");
    const std::vector<std::vector<std::string>> keys = {{"method"},      {"tool"},
                                                        {"parameters"},  {"planes"},
                                                        {"source"},      {"source", "width"},
                                                        {"conventions"}, {"conventions", "address"},
                                                        {"levels"}};
    for (const auto& key : keys) {
        fresh();
        std::string dotted;
        for (const std::string& k : key) dotted += (dotted.empty() ? "" : ".") + k;
        SCOPED_TRACE(dotted);
        tamper([&](json& m) {
            json* parent = &m;
            for (size_t i = 0; i + 1 < key.size(); ++i) parent = &(*parent)[key[i]];
            parent->erase(key.back());
        });
        std::string output;
        int status = runCliWithin(60, inspectArgs(), &output);
        expectOneLineError(status, output, {manifest(), "missing key '" + dotted + "'"});
        EXPECT_EQ(output.find("internal error"), std::string::npos) << output;
        EXPECT_EQ(status, 1) << output;
    }
}

TEST_F(TamperedBake, HostileManifestTextStaysShort) {
    makeBake("--method toksvig");
    // A method name of a megabyte is quoted in a few dozen characters.
    tamper([](json& m) { m["method"] = std::string(1 << 20, 'x'); });
    std::string output;
    expectOneLineError(runCliWithin(60, inspectArgs(), &output), output,
                       {manifest(), "unknown method 'xxx"});
    EXPECT_LT(output.size(), 400u) << output.substr(0, 400);
    // Deep nesting is refused before any parser or printer recurses into it.
    writeBytes(bake / "manifest.json", std::string(100000, '[') + std::string(100000, ']'));
    expectOneLineError(runCliWithin(60, inspectArgs(), &output), output,
                       {manifest(), "nested deeper than 64 levels"});
    // Not a file at all.
    fs::remove(bake / "manifest.json");
    fs::create_directory(bake / "manifest.json");
    expectRefused({manifest(), "is a directory"}, false);
}

TEST_F(TamperedBake, RenderRefusesAPlanesMemoryAboveTheLimit) {
    // 10.7 KiB: the 8x8 map's decoded file, normals and pyramid fit (2.8 KiB, checked before
    // it is decoded); the order-8 planes (21 RGBA planes a level, 28 KiB) do not.
    makeBake("--method sh --order 8");
    expectCliRefuses("--max-memory 0.00001 " + renderArgs(),
                     {"planes need", "above the limit of", "--max-memory"});
}

} // namespace
} // namespace ndfmip::test
