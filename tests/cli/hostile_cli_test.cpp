// The command line under hostile input: NaN in every float option, special files as inputs,
// declared sizes above the limits, deeply nested or enormous scene text, and output folders
// that are someone else's work. Each must end in one line naming the problem, and leave nothing.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "ndfmip/io.h"
#include "test_support.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace ndfmip::test {
namespace {

Image flatMap(int width, int height) {
    Image map(width, height, 3);
    for (size_t i = 0; i < map.texelCount(); ++i) map.pixels[3 * i + 2] = 1.f;
    for (float& v : map.pixels) v = 0.5f * (v + 1.f);
    return map;
}

json sceneJson(const std::string& normalMap, int width = 4, int height = 4) {
    return {{"camera",
             {{"type", "orthographic"},
              {"eye", {0, 0, 1}},
              {"target", {0, 0, 0}},
              {"up", {0, 1, 0}},
              {"ortho_height", 2},
              {"width", width},
              {"height", height}}},
            {"object", {{"type", "plane"}}},
            {"lights", {{{"type", "directional"}, {"direction", {0, 0, 1}}}}},
            {"normal_map", normalMap}};
}

class HostileCli : public ::testing::Test {
  protected:
    TempDir tmp{"hostile_cli"};
    std::string map = tmp.file("map.png");
    fs::path out = tmp.path / "out";

    void SetUp() override { ASSERT_TRUE(savePng(map, flatMap(8, 8), 16)); }

    std::string bakeArgs(const std::string& input, const std::string& extra = "") const {
        return "bake " + shellArg(input) + " -q " + extra + " -o " + shellArg(out.string());
    }

    void expectNothingWritten() {
        EXPECT_FALSE(fs::exists(out));
        EXPECT_TRUE(leftovers(tmp.path).empty());
    }
};

// The FLOAT options `ndfmip SUB --help` lists (every floating-point option has that type).
std::vector<std::string> floatOptions(const std::string& sub) {
    std::string help;
    runCli(sub + " --help", &help);
    std::vector<std::string> names;
    std::istringstream lines(help);
    for (std::string line; std::getline(lines, line);) {
        std::istringstream words(line);
        std::string names0, type;
        words >> names0 >> type;
        if (type.rfind("FLOAT", 0) != 0) continue;
        names.push_back(
            names0.substr(names0.rfind(',') == std::string::npos ? 0 : names0.rfind(',') + 1));
    }
    return names;
}

TEST_F(HostileCli, NaNAndInfinityFailEveryFloatOption) {
    ASSERT_EQ(runCli(bakeArgs(map), nullptr), 0);
    writeBytes(tmp.path / "scene.json", sceneJson("map.png").dump());
    const std::string o = shellArg(tmp.file("o.exr"));
    // Each subcommand with arguments that would otherwise let it run.
    const std::vector<std::pair<std::string, std::string>> commands = {
        {"bake", "bake " + shellArg(map) + " -o " + shellArg(out.string() + "2")},
        {"inspect", "inspect " + shellArg(out.string()) + " --texel 0,0"},
        {"lut", "lut --exponent 8 -o " + o},
        {"demo", "demo " + shellArg(map) + " -o " + shellArg(tmp.file("demo"))},
        {"compare", "compare " + shellArg(map) + " " + shellArg(map)},
        {"render", "render " + shellArg(tmp.file("scene.json")) + " -o " + o},
        {"eval", "eval " + shellArg(map) + " -o " + shellArg(tmp.file("report"))},
        {"envmap", "envmap " + shellArg(map) + " -o " + shellArg(tmp.file("env"))},
        {"", "lut --exponent 8 -o " + o}, // the options before the subcommand
    };
    size_t checked = 0;
    for (const auto& [sub, args] : commands) {
        const std::vector<std::string> options = floatOptions(sub);
        if (sub != "demo" && sub != "lut") {
            EXPECT_FALSE(options.empty()) << sub;
        }
        for (const std::string& option : options) {
            for (const std::string value : {"nan", "-inf", "1e999"}) {
                // Options the lut command line already gives are repeated last: the last wins.
                const std::string line = sub.empty() ? option + " " + value + " " + args
                                                     : args + " " + option + " " + value;
                // NaN passes every range check, so it must meet the finite check; infinities
                // may meet an option's range first.
                if (value == "nan")
                    expectCliRefuses(line, {option, "must be a finite number, not 'nan'"});
                else
                    expectCliRefuses(line, {option, value});
                ++checked;
            }
        }
    }
    EXPECT_GE(checked, 3u * 16u) << "fewer float options than the CLI has";
    EXPECT_FALSE(fs::exists(tmp.path / "o.exr"));
    EXPECT_FALSE(fs::exists(out.string() + "2"));
    EXPECT_FALSE(fs::exists(tmp.path / "report"));
    EXPECT_FALSE(fs::exists(tmp.path / "env"));
}

TEST_F(HostileCli, SpecialFilesAsInputsFailAtOnce) {
    const std::string fifo = tmp.file("fifo");
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    const std::string dir = tmp.path.string();
    for (const std::string& input : {fifo, std::string("/dev/zero"), dir}) {
        SCOPED_TRACE(input);
        const std::string why = input == fifo  ? "(a FIFO)"
                                : input == dir ? "is a directory"
                                               : "(a character device)";
        // A folder given to bake is a batch of its images, which needs an output pattern.
        if (input == dir)
            expectCliRefuses(bakeArgs(input), {"{stem}"});
        else
            expectCliRefuses(bakeArgs(input), {input, why});
        expectCliRefuses(bakeArgs(map, "--gloss " + shellArg(input) + " --max-exponent 8"),
                         {input, why});
        expectCliRefuses("compare " + shellArg(map) + " " + shellArg(input), {input, why});
        expectCliRefuses("render " + shellArg(input) + " -o " + shellArg(tmp.file("o.exr")),
                         {input, why});
        json scene = sceneJson(input);
        writeBytes(tmp.path / "scene.json", scene.dump());
        expectCliRefuses("render " + shellArg(tmp.file("scene.json")) + " -o " +
                             shellArg(tmp.file("o.exr")),
                         {input, why});
        scene = sceneJson("map.png");
        scene["material"] = {{"brdf", "tabulated"}, {"table", input}};
        writeBytes(tmp.path / "scene.json", scene.dump());
        expectCliRefuses("render " + shellArg(tmp.file("scene.json")) + " -o " +
                             shellArg(tmp.file("o.exr")),
                         {input, why});
    }
    // A bake folder whose manifest is a FIFO.
    fs::create_directory(tmp.path / "bake");
    ASSERT_EQ(::mkfifo((tmp.path / "bake" / "manifest.json").c_str(), 0600), 0);
    expectCliRefuses("inspect " + shellArg(tmp.file("bake")) + " --texel 0,0",
                     {"manifest.json", "(a FIFO)"});
    expectNothingWritten();
    EXPECT_FALSE(fs::exists(tmp.path / "o.exr"));
}

TEST_F(HostileCli, ImageSizeLimitsHoldAndCanBeRaised) {
    const std::string big = tmp.file("big.png");
    ASSERT_TRUE(savePng(big, flatMap(64, 64), 8));
    expectCliRefuses("--max-pixels 1000 " + bakeArgs(big),
                     {big, "64x64", "1000 pixels", "--max-pixels"});
    expectNothingWritten();
    // The option also works after the subcommand, and raising the limit lets the map through.
    expectCliRefuses(bakeArgs(big, "--max-pixels 1000"), {big, "64x64"});
    std::string output;
    EXPECT_EQ(runCli(bakeArgs(big, "--max-pixels 4096"), &output), 0) << output;
}

TEST_F(HostileCli, ShOrderTimesMapSizeIsCheckedBeforeBaking) {
    const std::string big = tmp.file("big.png");
    ASSERT_TRUE(savePng(big, flatMap(512, 512), 8));
    // l* = 30: 241 planes of 16 bytes per texel and level, about 1.3 GiB for 512x512.
    expectCliRefuses(bakeArgs(big, "--method sh --order 30 --max-memory 1"),
                     {big, "sh bake of order 30", "512x512", "GiB", "above the limit of 1.0 GiB",
                      "--max-memory"});
    expectNothingWritten();
}

TEST_F(HostileCli, CameraSizeIsLimited) {
    writeBytes(tmp.path / "scene.json", sceneJson("map.png", 16384, 16384).dump());
    expectCliRefuses("render " + shellArg(tmp.file("scene.json")) + " -o " +
                         shellArg(tmp.file("o.exr")),
                     {"scene.json", "camera", "16384x16384", "above the limit", "--max-pixels"});
    writeBytes(tmp.path / "scene.json", sceneJson("map.png", 100, 100).dump());
    expectCliRefuses("--max-pixels 5000 render " + shellArg(tmp.file("scene.json")) + " -o " +
                         shellArg(tmp.file("o.exr")),
                     {"100x100", "5000 pixels"});
    EXPECT_FALSE(fs::exists(tmp.path / "o.exr"));
}

TEST_F(HostileCli, DeepOrHugeSceneTextGivesAShortError) {
    const std::string scene = tmp.file("scene.json");
    const std::string render = "render " + shellArg(scene) + " -o " + shellArg(tmp.file("o.exr"));
    // 200 KB of nesting, inside a value that an error message would print.
    writeBytes(scene, "{\"camera\": " + std::string(100000, '[') + std::string(100000, ']') + "}");
    expectCliRefuses(render, {scene, "nested deeper than 64 levels"});
    // A 2 MB unknown key, and 2 MB names, are quoted in a short line.
    json doc = sceneJson("map.png");
    doc["camera"][std::string(2 << 20, 'k')] = 1;
    writeBytes(scene, doc.dump());
    std::string output;
    expectOneLineError(runCliWithin(60, render, &output), output, {scene, "unknown key"});
    EXPECT_LT(output.size(), 600u) << output.substr(0, 600);
    for (const char* field : {"method", "normal_map"}) {
        doc = sceneJson("map.png");
        doc[field] = std::string(2 << 20, 'n');
        writeBytes(scene, doc.dump());
        expectOneLineError(runCliWithin(60, render, &output), output, {scene, field});
        EXPECT_LT(output.size(), 600u) << output.substr(0, 600);
    }
    doc = sceneJson("map.png");
    doc["material"] = {{"brdf", std::string(2 << 20, 'b')}};
    writeBytes(scene, doc.dump());
    expectOneLineError(runCliWithin(60, render, &output), output, {scene, "unknown BRDF 'bbb"});
    EXPECT_LT(output.size(), 600u);
    EXPECT_FALSE(fs::exists(tmp.path / "o.exr"));
}

TEST_F(HostileCli, LongCommandLineValuesAreQuotedShort) {
    const std::string longText(100000, 'm');
    for (const std::string& args :
         {bakeArgs(map, "--method " + longText), bakeArgs(map, "--export " + longText),
          "render " + longText + " -o " + shellArg(tmp.file("o.exr")),
          "inspect " + shellArg(map) + " --texel " + longText}) {
        std::string output;
        expectOneLineError(runCliWithin(60, args, &output), output, {"mmm"});
        // Every message is cut at about 1 KB, whatever it quotes.
        EXPECT_LT(output.size(), 1100u) << output.substr(0, 1100);
    }
    expectNothingWritten();
}

TEST_F(HostileCli, ExrValuesOfOverflowingSizeAreAnError) {
    const std::string exr = tmp.file("big_values.exr");
    Image image = flatMap(4, 4);
    image.at(3, 2)[1] = 1e30f;
    ASSERT_TRUE(saveExr(exr, image));
    expectCliRefuses(bakeArgs(exr), {exr, "texel (3, 2)", "1e+30", "too large for a normal"});
    image.at(3, 2)[1] = std::numeric_limits<float>::infinity();
    ASSERT_TRUE(saveExr(exr, image));
    expectCliRefuses(bakeArgs(exr), {exr, "(3, 2)", "not a finite number"});
    expectNothingWritten();
}

TEST_F(HostileCli, FileNamesThatAreNotUtf8StillBake) {
    // Linux file names are bytes; the manifest (JSON, so UTF-8) shows the odd one as U+FFFD.
    const std::string odd = tmp.file("map\xFF\xFE.png");
    fs::copy_file(map, odd);
    std::string output;
    ASSERT_EQ(runCli(bakeArgs(odd), &output), 0) << output;
    EXPECT_NE(fileBytes(out / "manifest.json").find("map\xEF\xBF\xBD"), std::string::npos);
    EXPECT_EQ(runCli("inspect " + shellArg(out.string()) + " --texel 1,1", &output), 0) << output;
}

TEST_F(HostileCli, TheNextBakeRestoresAFolderAKillLeftAside) {
    // What a kill between the two renames of a swap leaves where the file system has no atomic
    // exchange: no DIR, the earlier bake as DIR.old-PID, the new one as DIR.partial-PID.
    ASSERT_EQ(runCli(bakeArgs(map), nullptr), 0);
    const auto earlier = snapshot(out);
    pid_t child = ::fork();
    if (child == 0) ::_exit(0);
    ::waitpid(child, nullptr, 0); // a process number no one has now
    const std::string pid = std::to_string(child);
    fs::rename(out, out.string() + ".old-" + pid);
    fs::create_directory(out.string() + ".partial-" + pid);
    writeBytes(out.string() + ".partial-" + pid + "/mean_L0.exr", "half written");
    // Even a run that then fails on its input puts the earlier bake back first.
    expectCliRefuses(bakeArgs(tmp.file("missing.png")), {"missing.png"});
    EXPECT_EQ(snapshot(out), earlier);
    EXPECT_TRUE(leftovers(tmp.path).empty());
}

// ---- bake output folders that are not earlier bakes are never replaced ------------------------

TEST_F(HostileCli, AFolderWithAnyManifestIsNotTakenForABake) {
    fs::create_directories(out / "photos");
    writeBytes(out / "manifest.json", "{\"name\": \"my project\"}");
    writeBytes(out / "photos" / "a.jpg", "precious");
    const auto before = snapshot(out);
    expectCliRefuses(bakeArgs(map), {out.string(), "not an ndfmip bake", "not replacing it"});
    EXPECT_EQ(snapshot(out), before);
    EXPECT_TRUE(leftovers(tmp.path).empty());
}

TEST_F(HostileCli, AnEarlierBakeWithAddedFilesIsNotReplaced) {
    ASSERT_EQ(runCli(bakeArgs(map, "--export png16"), nullptr), 0);
    for (const std::string& extra :
         {std::string("notes.txt"), std::string("png16/mine.png"), std::string("sub/deep.bin")}) {
        SCOPED_TRACE(extra);
        fs::create_directories((out / extra).parent_path());
        writeBytes(out / extra, "mine");
        const auto before = snapshot(out);
        const std::string named = extra == "sub/deep.bin" ? "'sub'" : "'" + extra + "'";
        expectCliRefuses(bakeArgs(map, "--method naive"), {out.string(), named, "does not list"});
        EXPECT_EQ(snapshot(out), before);
        fs::remove(out / extra);
        if (extra == "sub/deep.bin") fs::remove(out / "sub");
    }
    // Without them it is an earlier bake again, exports included, and is replaced.
    std::string output;
    ASSERT_EQ(runCli(bakeArgs(map, "--method naive"), &output), 0) << output;
    EXPECT_NE(fileBytes(out / "manifest.json").find("\"naive\""), std::string::npos);
    EXPECT_FALSE(fs::exists(out / "png16"));
    EXPECT_TRUE(leftovers(tmp.path).empty());
}

} // namespace
} // namespace ndfmip::test
