// End-to-end tests of the ndfmip command-line tool: each test writes its inputs into a fresh
// temporary folder, runs the built binary and checks what it printed and wrote.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "ndfmip/image.h"
#include "ndfmip/io.h"
#include "ndfmip/method_parameters.h"
#include "ndfmip/toksvig.h"
#include "test_support.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace ndfmip::test {
namespace {

struct CliRun {
    int status = -1;
    std::string output;
};

std::string shellQuoted(const std::string& text) {
    return "'" + text + "'";
}

CliRun cli(const std::string& args) {
    CliRun run;
    run.status = runCli(args, &run.output);
    return run;
}

// Encodes unit normals (3 channels, values in [-1,1]) as stored colours c = (n + 1)/2.
Image encodeNormals(const Image& normals) {
    Image out = normals;
    for (float& v : out.pixels) v = 0.5f * (v + 1.f);
    return out;
}

void writePng16(const std::string& path, const Image& image) {
    Status s = savePng(path, image, 16);
    ASSERT_TRUE(s.ok()) << s.error;
}

void writeExr(const std::string& path, const Image& image) {
    Status s = saveExr(path, image);
    ASSERT_TRUE(s.ok()) << s.error;
}

std::string readFile(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

void writeFile(const fs::path& path, const std::string& bytes) {
    std::ofstream out(path, std::ios::binary);
    out << bytes;
}

json readManifest(const fs::path& dir) {
    std::ifstream in(dir / "manifest.json");
    EXPECT_TRUE(in.good()) << (dir / "manifest.json");
    return json::parse(in, nullptr, /*allow_exceptions=*/false);
}

// A map whose 2x2 blocks hold normals tilted by +theta and -theta about z in the x direction,
// in a checkerboard, so every block averages to (0, 0, cos theta).
Image checkerTiltNormals(int width, int height, float theta) {
    Image normals(width, height, 3);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            float sign = (x + y) % 2 == 0 ? 1.f : -1.f;
            setNormal(normals, x, y, sign * std::sin(theta), 0.f, std::cos(theta));
        }
    return normals;
}

Image flatNormals(int width, int height) {
    Image normals(width, height, 3);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) setNormal(normals, x, y, 0.f, 0.f, 1.f);
    return normals;
}

// Smoothly varying bumps with both x and y components.
Image bumpyNormals(int width, int height) {
    Image normals(width, height, 3);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            float nx = 0.5f * std::sin(0.9f * float(x) + 0.3f * float(y));
            float ny = 0.4f * std::cos(0.7f * float(y) - 0.5f * float(x));
            setNormal(normals, x, y, nx, ny, 1.f);
        }
    return normals;
}

// Runs inspect and parses its JSON; fails the test when it does not succeed.
json inspect(const fs::path& dir, int level, const std::string& texel,
             const std::string& extra = "") {
    CliRun r = cli("inspect " + shellQuoted(dir.string()) + " --level " + std::to_string(level) +
                   " --texel " + texel + " " + extra);
    EXPECT_EQ(r.status, 0) << r.output;
    json out = json::parse(r.output, nullptr, /*allow_exceptions=*/false);
    EXPECT_FALSE(out.is_discarded()) << "inspect printed no JSON: " << r.output;
    return out;
}

float vecLength(const json& v) {
    float x = v.at(0).get<float>(), y = v.at(1).get<float>(), z = v.at(2).get<float>();
    return std::sqrt(x * x + y * y + z * z);
}

size_t lineCount(const std::string& text) {
    return size_t(std::count(text.begin(), text.end(), '\n'));
}

// A clean refusal: a non-zero exit that is not a crash, and exactly one line of output that
// names each of `mentions` (the file or option, and the problem).
void expectCleanFailure(const CliRun& r, std::initializer_list<std::string> mentions) {
    EXPECT_NE(r.status, 0) << r.output;
    EXPECT_GT(r.status, 0) << "could not run the CLI";
    EXPECT_LT(r.status, 128) << "killed by a signal: " << r.output;
    EXPECT_EQ(lineCount(r.output), 1u) << "expected one error line, got:\n" << r.output;
    EXPECT_TRUE(!r.output.empty() && r.output.back() == '\n') << r.output;
    for (const std::string& m : mentions)
        EXPECT_NE(r.output.find(m), std::string::npos) << "'" << m << "' not in: " << r.output;
}

// No staging folders, temporary files or set-aside old bakes anywhere below `root`.
void expectNoLeftovers(const fs::path& root) {
    for (const auto& entry : fs::recursive_directory_iterator(root)) {
        std::string name = entry.path().filename().string();
        EXPECT_EQ(name.find(".partial-"), std::string::npos) << "left behind: " << entry.path();
        EXPECT_EQ(name.find(".tmp-"), std::string::npos) << "left behind: " << entry.path();
        EXPECT_EQ(name.find(".old-"), std::string::npos) << "left behind: " << entry.path();
    }
}

// Nothing written by a failed command: no output at `out` and no leftovers below `root`.
void expectNothingWritten(const fs::path& root, const fs::path& out) {
    EXPECT_FALSE(fs::exists(out)) << out << " was created";
    expectNoLeftovers(root);
}

std::set<std::string> listNames(const fs::path& dir) {
    std::set<std::string> names;
    for (const auto& entry : fs::recursive_directory_iterator(dir))
        names.insert(fs::relative(entry.path(), dir).string());
    return names;
}

constexpr float kTheta = 0.5f;    // tilt of the checkerboard map, radians
constexpr float kTol16 = 1.5e-4f; // 16-bit quantisation of the stored normals

// ---- bake + inspect -------------------------------------------------------------------------

TEST(Cli, BakeToksvigWritesManifestAndInspectReadsItBack) {
    TempDir tmp("cli_bake");
    const std::string map = tmp.file("map.png");
    writePng16(map, encodeNormals(checkerTiltNormals(6, 4, kTheta)));
    const fs::path dir = tmp.path / "bake";

    CliRun bake =
        cli("bake " + shellQuoted(map) + " --method toksvig -o " + shellQuoted(dir.string()));
    ASSERT_EQ(bake.status, 0) << bake.output;

    json m = readManifest(dir);
    ASSERT_FALSE(m.is_discarded());
    EXPECT_EQ(m.at("method"), "toksvig");
    const std::string sha = m.at("source").at("sha256");
    EXPECT_EQ(sha.size(), 64u);
    EXPECT_TRUE(std::all_of(sha.begin(), sha.end(), [](char c) {
        return std::isxdigit(static_cast<unsigned char>(c));
    })) << sha;
    Result<std::string> expectedSha = sha256File(map);
    ASSERT_TRUE(expectedSha.ok());
    EXPECT_EQ(sha, expectedSha.value());
    EXPECT_EQ(m.at("source").at("width"), 6);
    EXPECT_EQ(m.at("source").at("height"), 4);

    // 6x4 -> 3x2 -> 1x1.
    const std::vector<std::pair<int, int>> sizes = {{6, 4}, {3, 2}, {1, 1}};
    const json& levels = m.at("levels");
    ASSERT_EQ(levels.size(), sizes.size());
    for (size_t k = 0; k < sizes.size(); ++k) {
        EXPECT_EQ(levels[k].at("level"), k);
        EXPECT_EQ(levels[k].at("width"), sizes[k].first) << "level " << k;
        EXPECT_EQ(levels[k].at("height"), sizes[k].second) << "level " << k;
        for (auto& [plane, file] : levels[k].at("files").items()) {
            EXPECT_TRUE(fs::is_regular_file(dir / file.get<std::string>())) << file;
            Result<SourceImage> image = loadImage((dir / file.get<std::string>()).string());
            ASSERT_TRUE(image.ok()) << image.error().message;
            EXPECT_EQ(image->image.width, sizes[k].first) << plane;
            EXPECT_EQ(image->image.height, sizes[k].second) << plane;
        }
    }

    std::map<std::string, std::vector<std::string>> channels;
    for (const json& p : m.at("planes"))
        channels[p.at("name")] = p.at("channels").get<std::vector<std::string>>();
    ASSERT_EQ(channels.size(), 3u);
    EXPECT_EQ(channels["mean"], (std::vector<std::string>{"Na.x", "Na.y", "Na.z"}));
    EXPECT_EQ(channels["roughness_beckmann"], std::vector<std::string>{"alpha"});
    EXPECT_EQ(channels["roughness_ggx"], std::vector<std::string>{"alpha"});

    // Level 1: every texel averages one 2x2 block, Na = (0, 0, cos theta).
    const float cosTheta = std::cos(kTheta);
    const float s = 32.f;
    for (const char* texel : {"0,0", "2,1"}) {
        SCOPED_TRACE(texel);
        json t = inspect(dir, 1, texel, "--exponent 32");
        for (const char* key : {"mean_normal", "length", "sigma2", "toksvig_factor"})
            ASSERT_TRUE(t.contains(key)) << key << " missing from " << t.dump();
        EXPECT_EQ(t.at("method"), "toksvig");
        float length = t.at("length");
        EXPECT_NEAR(length, cosTheta, kTol16);
        EXPECT_NEAR(vecLength(t.at("mean_normal")), length, 1e-6f);
        EXPECT_NEAR(t.at("mean_normal").at(0).get<float>(), 0.f, kTol16);
        EXPECT_NEAR(t.at("mean_normal").at(1).get<float>(), 0.f, kTol16);
        EXPECT_NEAR(t.at("mean_normal").at(2).get<float>(), cosTheta, kTol16);
        EXPECT_NEAR(t.at("sigma2").get<float>(), (1.f - cosTheta) / cosTheta, 3 * kTol16);
        const float factor = cosTheta / (cosTheta + s * (1.f - cosTheta));
        EXPECT_NEAR(t.at("toksvig_factor").get<float>(), factor, 10 * kTol16);
        // and from the printed length itself, to float precision
        EXPECT_NEAR(t.at("toksvig_factor").get<float>(), length / (length + s * (1.f - length)),
                    1e-6f);
    }

    // Level 0 holds the map's own unit normals.
    json t0 = inspect(dir, 0, "0,0", "--exponent 32");
    EXPECT_NEAR(t0.at("length").get<float>(), 1.f, 1e-5f);
    EXPECT_NEAR(t0.at("mean_normal").at(0).get<float>(), std::sin(kTheta), kTol16);
    EXPECT_NEAR(t0.at("toksvig_factor").get<float>(), 1.f, 1e-3f);
    // Without --exponent there is no factor to report.
    EXPECT_FALSE(inspect(dir, 1, "0,0").contains("toksvig_factor"));
}

TEST(Cli, BakeNaiveStoresUnitNormals) {
    TempDir tmp("cli_naive");
    const std::string map = tmp.file("map.png");
    writePng16(map, encodeNormals(checkerTiltNormals(4, 4, kTheta)));
    const fs::path dir = tmp.path / "bake";
    CliRun bake =
        cli("bake " + shellQuoted(map) + " --method naive -o " + shellQuoted(dir.string()));
    ASSERT_EQ(bake.status, 0) << bake.output;
    EXPECT_EQ(readManifest(dir).at("method"), "naive");

    for (int level : {0, 1, 2}) {
        SCOPED_TRACE(level);
        json t = inspect(dir, level, "0,0");
        EXPECT_EQ(t.at("method"), "naive");
        ASSERT_TRUE(t.contains("normal")) << t.dump();
        EXPECT_FALSE(t.contains("length"));
        EXPECT_NEAR(vecLength(t.at("normal")), 1.f, 1e-5f);
    }
    // The averaged (shortened) mean is renormalised to straight up.
    EXPECT_NEAR(inspect(dir, 1, "1,1").at("normal").at(2).get<float>(), 1.f, 1e-5f);
}

TEST(Cli, TexelAddressingIsColumnThenRowFromTheTop) {
    TempDir tmp("cli_texel");
    Image normals = flatNormals(4, 4);
    setNormal(normals, 0, 0, 0.6f, 0.f, 0.8f);  // top-left texel of the file
    setNormal(normals, 1, 0, 0.f, 0.6f, 0.8f);  // its right neighbour
    setNormal(normals, 0, 1, -0.6f, 0.f, 0.8f); // the texel below it
    const std::string map = tmp.file("map.png");
    writePng16(map, encodeNormals(normals));
    const fs::path dir = tmp.path / "bake";
    ASSERT_EQ(cli("bake " + shellQuoted(map) + " -q -o " + shellQuoted(dir.string())).status, 0);

    auto mean = [&](const std::string& texel) { return inspect(dir, 0, texel).at("mean_normal"); };
    json topLeft = mean("0,0"), right = mean("1,0"), below = mean("0,1"), other = mean("3,3");
    EXPECT_NEAR(topLeft.at(0).get<float>(), 0.6f, kTol16);
    EXPECT_NEAR(topLeft.at(1).get<float>(), 0.f, kTol16);
    EXPECT_NEAR(right.at(0).get<float>(), 0.f, kTol16);
    EXPECT_NEAR(right.at(1).get<float>(), 0.6f, kTol16);
    EXPECT_NEAR(below.at(0).get<float>(), -0.6f, kTol16);
    EXPECT_NEAR(below.at(1).get<float>(), 0.f, kTol16);
    EXPECT_NEAR(other.at(2).get<float>(), 1.f, kTol16);

    // Level 1 texel (1,0) covers columns 2-3 of the top two rows.
    json t = inspect(dir, 1, "1,0");
    EXPECT_EQ(t.at("texel"), json({1, 0}));
    const json& f = t.at("footprint");
    EXPECT_EQ(f.at("x0"), 2);
    EXPECT_EQ(f.at("x1"), 4);
    EXPECT_EQ(f.at("y0"), 0);
    EXPECT_EQ(f.at("y1"), 2);
    EXPECT_EQ(f.at("count"), 4);
    // Level 1 texel (0,0) averages the three tilted texels with one flat one.
    json tl = inspect(dir, 1, "0,0").at("mean_normal");
    EXPECT_NEAR(tl.at(0).get<float>(), 0.f, kTol16);
    EXPECT_NEAR(tl.at(1).get<float>(), 0.6f / 4.f, kTol16);
    EXPECT_NEAR(tl.at(2).get<float>(), (3 * 0.8f + 1.f) / 4.f, kTol16);
}

TEST(Cli, OddSizedMapFollowsThePyramidRule) {
    TempDir tmp("cli_odd");
    Image normals = flatNormals(5, 3);
    setNormal(normals, 4, 0, 0.6f, 0.f, 0.8f); // last column: folded into level-1 texel 1
    const std::string map = tmp.file("map.png");
    writePng16(map, encodeNormals(normals));
    const fs::path dir = tmp.path / "bake";
    ASSERT_EQ(cli("bake " + shellQuoted(map) + " -q -o " + shellQuoted(dir.string())).status, 0);

    json m = readManifest(dir);
    const std::vector<std::pair<int, int>> sizes = {{5, 3}, {2, 1}, {1, 1}};
    ASSERT_EQ(m.at("levels").size(), sizes.size());
    for (size_t k = 0; k < sizes.size(); ++k) {
        EXPECT_EQ(m.at("levels")[k].at("width"), sizes[k].first);
        EXPECT_EQ(m.at("levels")[k].at("height"), sizes[k].second);
    }
    // Level-1 texel 1 takes columns 2, 3 and 4, and all three rows.
    json t = inspect(dir, 1, "1,0");
    const json& f = t.at("footprint");
    EXPECT_EQ(f.at("x0"), 2);
    EXPECT_EQ(f.at("x1"), 5);
    EXPECT_EQ(f.at("y0"), 0);
    EXPECT_EQ(f.at("y1"), 3);
    EXPECT_EQ(f.at("count"), 9);
    EXPECT_NEAR(t.at("mean_normal").at(0).get<float>(), 0.6f / 9.f, kTol16);
    EXPECT_NEAR(inspect(dir, 1, "0,0").at("length").get<float>(), 1.f, kTol16);
}

// ---- conventions and exports ----------------------------------------------------------------

TEST(Cli, GreenDownNegatesY) {
    TempDir tmp("cli_green");
    const std::string map = tmp.file("map.png");
    writePng16(map, encodeNormals(bumpyNormals(8, 8)));
    const fs::path up = tmp.path / "up", down = tmp.path / "down";
    ASSERT_EQ(cli("bake " + shellQuoted(map) + " -q -o " + shellQuoted(up.string())).status, 0);
    CliRun r =
        cli("bake " + shellQuoted(map) + " -q --green-down -o " + shellQuoted(down.string()));
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_EQ(readManifest(up).at("conventions").at("green_down"), false);
    EXPECT_EQ(readManifest(down).at("conventions").at("green_down"), true);

    for (auto [level, texel] :
         std::vector<std::pair<int, std::string>>{{0, "0,0"}, {0, "3,1"}, {0, "5,6"}, {1, "2,1"}}) {
        SCOPED_TRACE(std::to_string(level) + " " + texel);
        json a = inspect(up, level, texel).at("mean_normal");
        json b = inspect(down, level, texel).at("mean_normal");
        EXPECT_GT(std::abs(a.at(1).get<float>()), 1e-2f) << "pick a texel with y != 0";
        EXPECT_FLOAT_EQ(b.at(0).get<float>(), a.at(0).get<float>());
        EXPECT_FLOAT_EQ(b.at(1).get<float>(), -a.at(1).get<float>());
        EXPECT_FLOAT_EQ(b.at(2).get<float>(), a.at(2).get<float>());
    }
}

TEST(Cli, GreenDownExportKeepsTheSourceConvention) {
    TempDir tmp("cli_green_png16");
    const std::string map = tmp.file("map.png");
    Image stored = encodeNormals(bumpyNormals(4, 4)); // read as DirectX-style below
    writePng16(map, stored);
    const fs::path dir = tmp.path / "bake";
    CliRun r = cli("bake " + shellQuoted(map) + " -q --green-down --export png16 -o " +
                   shellQuoted(dir.string()));
    ASSERT_EQ(r.status, 0) << r.output;
    Result<SourceImage> n0 = loadImage((dir / "png16/normal_L0.png").string());
    ASSERT_TRUE(n0.ok()) << n0.error().message;
    ASSERT_EQ(n0->image.pixels.size(), stored.pixels.size());
    for (size_t i = 0; i < stored.pixels.size(); ++i)
        EXPECT_NEAR(n0->image.pixels[i], stored.pixels[i], 2e-4f) << "sample " << i;
}

TEST(Cli, ExportPng16WritesNormalAndRoughnessMips) {
    TempDir tmp("cli_png16");
    const std::string map = tmp.file("map.png");
    Image normals = bumpyNormals(8, 4);
    writePng16(map, encodeNormals(normals));
    const fs::path dir = tmp.path / "bake";
    CliRun r =
        cli("bake " + shellQuoted(map) + " -q --export png16 -o " + shellQuoted(dir.string()));
    ASSERT_EQ(r.status, 0) << r.output;

    json m = readManifest(dir);
    ASSERT_TRUE(m.contains("exports")) << m.dump(2);
    std::vector<std::string> listed = m.at("exports").at("png16");
    const std::vector<std::pair<int, int>> sizes = {{8, 4}, {4, 2}, {2, 1}, {1, 1}};
    ASSERT_EQ(m.at("levels").size(), sizes.size());
    for (size_t k = 0; k < sizes.size(); ++k) {
        for (const char* stem : {"normal", "roughness"}) {
            std::string name = "png16/" + std::string(stem) + "_L" + std::to_string(k) + ".png";
            SCOPED_TRACE(name);
            EXPECT_NE(std::find(listed.begin(), listed.end(), name), listed.end());
            Result<SourceImage> image = loadImage((dir / name).string());
            ASSERT_TRUE(image.ok()) << image.error().message;
            EXPECT_EQ(image->format, "png");
            EXPECT_EQ(image->bitsPerChannel, 16);
            EXPECT_EQ(image->image.width, sizes[k].first);
            EXPECT_EQ(image->image.height, sizes[k].second);
            EXPECT_EQ(image->image.channels, std::string(stem) == "normal" ? 3 : 1);
        }
    }
    EXPECT_EQ(listed.size(), 2 * sizes.size());

    // Level 0 of the export is the map itself, encoded the same way.
    Result<SourceImage> n0 = loadImage((dir / "png16/normal_L0.png").string());
    ASSERT_TRUE(n0.ok());
    Image expected = encodeNormals(normals);
    for (size_t i = 0; i < expected.pixels.size(); ++i)
        EXPECT_NEAR(n0->image.pixels[i], expected.pixels[i], 2e-4f) << "sample " << i;
    // Unit normals at level 0: no roughness there.
    Result<SourceImage> r0 = loadImage((dir / "png16/roughness_L0.png").string());
    ASSERT_TRUE(r0.ok());
    for (float v : r0->image.pixels) EXPECT_LT(v, 0.02f);
}

TEST(Cli, GgxFitNeedsTheMaterialsRoughnessAndExportsItsFit) {
    TempDir tmp("cli_ggx_fit");
    const std::string map = tmp.file("map.png");
    writePng16(map, encodeNormals(bumpyNormals(8, 8)));
    const fs::path dir = tmp.path / "bake";
    CliRun missing =
        cli("bake " + shellQuoted(map) + " --method ggx-fit -o " + shellQuoted(dir.string()));
    EXPECT_NE(missing.status, 0);
    EXPECT_NE(missing.output.find("--base-roughness"), std::string::npos) << missing.output;
    EXPECT_FALSE(fs::exists(dir));
    CliRun r = cli("bake " + shellQuoted(map) + " -q --method ggx-fit --base-roughness 0.09 " +
                   "--export exr,png16 -o " + shellQuoted(dir.string()));
    ASSERT_EQ(r.status, 0) << r.output;
    // Level 0 is the material's own lobe: perceptual sqrt(0.09) = 0.3; the bumps widen level 1.
    Result<SourceImage> r0 = loadImage((dir / "png16/roughness_L0.png").string());
    Result<SourceImage> r1 = loadImage((dir / "png16/roughness_L1.png").string());
    ASSERT_TRUE(r0.ok() && r1.ok());
    for (float v : r0->image.pixels) EXPECT_NEAR(v, 0.3f, 1e-4f);
    for (float v : r1->image.pixels) EXPECT_GT(v, 0.3f);
    json texel = inspect(dir, 1, "0,0");
    EXPECT_EQ(texel.at("method"), "ggx-fit");
    EXPECT_NEAR(texel.at("perceptual_roughness").get<float>(),
                std::sqrt(texel.at("roughness_ggx").get<float>()), 1e-6f);
}

TEST(Cli, GgxAnisoNeedsTheMaterialsRoughnessAndInspectsItsLobe) {
    TempDir tmp("cli_ggx_aniso");
    const std::string map = tmp.file("map.png");
    writePng16(map, encodeNormals(bumpyNormals(8, 8)));
    const fs::path dir = tmp.path / "bake";
    CliRun missing =
        cli("bake " + shellQuoted(map) + " --method ggx-aniso -o " + shellQuoted(dir.string()));
    EXPECT_NE(missing.status, 0);
    EXPECT_NE(missing.output.find("--base-roughness"), std::string::npos) << missing.output;
    EXPECT_FALSE(fs::exists(dir));
    CliRun r = cli("bake " + shellQuoted(map) + " -q --method ggx-aniso --base-roughness 0.09 -o " +
                   shellQuoted(dir.string()));
    ASSERT_EQ(r.status, 0) << r.output;
    // Level 0 is the material's own lobe; the bumps widen level 1 along some axis.
    json level0 = inspect(dir, 0, "0,0");
    EXPECT_NEAR(level0.at("alpha_t").get<float>(), 0.09f, 1e-6f);
    EXPECT_NEAR(level0.at("alpha_b").get<float>(), 0.09f, 1e-6f);
    json texel = inspect(dir, 1, "0,0");
    EXPECT_EQ(texel.at("method"), "ggx-aniso");
    EXPECT_GE(texel.at("alpha_t").get<float>(), texel.at("alpha_b").get<float>());
    EXPECT_GT(texel.at("alpha_t").get<float>(), 0.09f);
    const json& a = texel.at("alpha_tensor");
    const float t = a[0][0].get<float>() + a[1][1].get<float>();
    EXPECT_NEAR(t,
                std::pow(texel.at("alpha_t").get<float>(), 2.f) +
                    std::pow(texel.at("alpha_b").get<float>(), 2.f),
                1e-4f * t); // the trace is the sum of the squared roughnesses
}

// ---- bad input --------------------------------------------------------------------------------

class CliBadInput : public ::testing::Test {
  protected:
    TempDir tmp{"cli_bad"};
    fs::path out = tmp.path / "out";
    std::string good; // a valid normal map

    void SetUp() override {
        good = tmp.file("good.png");
        writePng16(good, encodeNormals(bumpyNormals(8, 8)));
    }

    // Runs `bake FILE ARGS -o out` and checks it failed cleanly, naming `mentions`.
    void expectBakeRefused(const std::string& file, const std::string& args,
                           std::initializer_list<std::string> mentions) {
        std::string command =
            "bake " + shellQuoted(file) + " " + args + " -o " + shellQuoted(out.string());
        SCOPED_TRACE(command);
        expectCleanFailure(cli(command), mentions);
        expectNothingWritten(tmp.path, out);
    }
};

TEST_F(CliBadInput, MissingFile) {
    std::string missing = tmp.file("missing.png");
    expectBakeRefused(missing, "", {missing, "No such file"});
}

TEST_F(CliBadInput, TruncatedPng) {
    std::mt19937 random(7);
    Image noise(32, 32, 3);
    for (float& v : noise.pixels) v = float(random() % 65536) / 65535.f;
    std::string full = tmp.file("full.png");
    writePng16(full, noise);
    std::string bytes = readFile(full);
    std::string cut = tmp.file("cut.png");
    writeFile(cut, bytes.substr(0, bytes.size() / 2));
    expectBakeRefused(cut, "", {cut, "truncated"});
}

TEST_F(CliBadInput, CorruptFile) {
    std::mt19937 random(11);
    std::string bytes(4096, '\0');
    for (char& c : bytes) c = char(random() & 0xFF);
    std::string file = tmp.file("noise.png");
    writeFile(file, bytes);
    CliRun r = cli("bake " + shellQuoted(file) + " -o " + shellQuoted(out.string()));
    expectCleanFailure(r, {file});
    expectNothingWritten(tmp.path, out);
}

TEST_F(CliBadInput, EmptyFile) {
    std::string file = tmp.file("empty.png");
    writeFile(file, "");
    expectBakeRefused(file, "", {file, "empty"});
}

TEST_F(CliBadInput, GreyscaleWithoutHeight) {
    std::string file = tmp.file("grey.png");
    Image grey(8, 8, 1);
    std::fill(grey.pixels.begin(), grey.pixels.end(), 0.5f);
    writePng16(file, grey);
    expectBakeRefused(file, "", {file, "channel"});
    // ... which --height accepts.
    CliRun r = cli("bake " + shellQuoted(file) + " -q --height 2 -o " + shellQuoted(out.string()));
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_EQ(readManifest(out).at("conventions").at("height"), true);
}

TEST_F(CliBadInput, GreyAlphaWithoutTwoChannel) {
    std::string file = tmp.file("grey_alpha.png");
    Image ga(8, 8, 2);
    std::fill(ga.pixels.begin(), ga.pixels.end(), 0.5f);
    writePng16(file, ga);
    expectBakeRefused(file, "", {file, "channel"});
    // ... which --two-channel accepts, rebuilding z from x and y.
    Image rg(8, 8, 2);
    for (size_t i = 0; i < rg.texelCount(); ++i) {
        rg.pixels[2 * i] = 0.5f * (0.6f + 1.f);
        rg.pixels[2 * i + 1] = 0.5f;
    }
    writePng16(file, rg);
    CliRun r =
        cli("bake " + shellQuoted(file) + " -q --two-channel -o " + shellQuoted(out.string()));
    ASSERT_EQ(r.status, 0) << r.output;
    json n = inspect(out, 0, "2,3").at("mean_normal");
    EXPECT_NEAR(n.at(0).get<float>(), 0.6f, kTol16);
    EXPECT_NEAR(n.at(1).get<float>(), 0.f, kTol16);
    EXPECT_NEAR(n.at(2).get<float>(), 0.8f, kTol16);
}

TEST_F(CliBadInput, ExrWithNaN) {
    std::string file = tmp.file("nan.exr");
    Image image = encodeNormals(flatNormals(4, 4));
    image.at(2, 1)[1] = std::numeric_limits<float>::quiet_NaN();
    writeExr(file, image);
    expectBakeRefused(file, "", {file, "NaN", "(2, 1)"});
}

TEST_F(CliBadInput, AllZeroNormals) {
    std::string file = tmp.file("zero.exr");
    Image image(4, 4, 3);
    std::fill(image.pixels.begin(), image.pixels.end(), 0.5f); // n = 2c - 1 = 0 exactly
    writeExr(file, image);
    expectBakeRefused(file, "", {file, "zero-length"});
}

TEST_F(CliBadInput, AbsurdBakeParameters) {
    expectBakeRefused(good, "--height -1", {"--height"});
    expectBakeRefused(good, "--base-roughness 5", {"--base-roughness"});
    expectBakeRefused(good, "--method foo", {"method", "foo"});
    expectBakeRefused(good, "--export jpeg", {"--export"});
    expectBakeRefused(good, "--max-exponent 0", {"--max-exponent"});
    expectBakeRefused(good, "--gloss " + shellQuoted(good), {"--gloss", "--max-exponent"});
}

TEST_F(CliBadInput, GlossMapOfAnotherSize) {
    std::string gloss = tmp.file("gloss.png");
    Image g(4, 8, 1);
    std::fill(g.pixels.begin(), g.pixels.end(), 0.5f);
    writePng16(gloss, g);
    expectBakeRefused(good, "--gloss " + shellQuoted(gloss) + " --max-exponent 64",
                      {gloss, "4x8", "8x8"});
}

TEST_F(CliBadInput, MissingGlossMap) {
    std::string gloss = tmp.file("no_gloss.png");
    expectBakeRefused(good, "--gloss " + shellQuoted(gloss) + " --max-exponent 64", {gloss});
}

TEST_F(CliBadInput, AbsurdLutParameters) {
    const fs::path lut = tmp.path / "lut.exr";
    for (const std::string args : {"--exponent 32 --size 0", "--exponent -3", "--exponent 0",
                                   "--exponent 32 --bits 1", "--exponent 32 --threshold -1"}) {
        SCOPED_TRACE(args);
        CliRun r = cli("lut " + args + " -o " + shellQuoted(lut.string()));
        std::string option = args.substr(args.rfind("--"));
        expectCleanFailure(r, {option.substr(0, option.find(' '))});
        expectNothingWritten(tmp.path, lut);
    }
}

TEST_F(CliBadInput, AbsurdInspectParameters) {
    const fs::path dir = tmp.path / "bake";
    ASSERT_EQ(cli("bake " + shellQuoted(good) + " -q -o " + shellQuoted(dir.string())).status, 0);
    const std::set<std::string> before = listNames(tmp.path);
    const std::string d = shellQuoted(dir.string());

    expectCleanFailure(cli("inspect " + d + " --level 99 --texel 0,0"), {"level 99"});
    expectCleanFailure(cli("inspect " + d + " --level -1 --texel 0,0"), {"level -1"});
    expectCleanFailure(cli("inspect " + d + " --texel 5"), {"--texel", "'5'"});
    expectCleanFailure(cli("inspect " + d + " --texel 1,2,3"), {"--texel", "1,2,3"});
    expectCleanFailure(cli("inspect " + d + " --texel 9999,0"), {"9999,0", "outside"});
    expectCleanFailure(cli("inspect " + d + " --texel 0,-1"), {"0,-1", "outside"});
    expectCleanFailure(cli("inspect " + d + " --level 1 --texel 4,0"), {"4,0", "outside"});
    expectCleanFailure(cli("inspect " + d + " --texel 0,0 --exponent -2"), {"--exponent"});
    std::string notBake = tmp.path.string();
    expectCleanFailure(cli("inspect " + shellQuoted(notBake) + " --texel 0,0"), {"manifest.json"});
    EXPECT_EQ(listNames(tmp.path), before);
}

TEST_F(CliBadInput, OutputUnderMissingFolder) {
    // bake makes missing parent folders (asset pipelines write out/<kind>/<map>.bake); a
    // parent that cannot exist (under a file) is refused by name.
    const std::string made = (tmp.path / "new" / "deeper" / "out.bake").string();
    CliRun ok = cli("bake " + shellQuoted(good) + " -q -o " + shellQuoted(made));
    EXPECT_EQ(ok.status, 0) << ok.output;
    EXPECT_TRUE(fs::exists(made + "/manifest.json"));
    std::ofstream(tmp.path / "plain_file") << "x";
    const std::string underFile = (tmp.path / "plain_file" / "sub" / "out").string();
    expectCleanFailure(cli("bake " + shellQuoted(good) + " -o " + shellQuoted(underFile)),
                       {"plain_file"});

    const std::string target = "/nonexistent_dir/sub/out";
    CliRun lut = cli("lut --exponent 8 -o " + target + ".exr");
    expectCleanFailure(lut, {target + ".exr"});
    EXPECT_FALSE(fs::exists("/nonexistent_dir"));
}

TEST_F(CliBadInput, UnwritableOutput) {
    // /proc refuses new entries even to root.
    if (fs::is_directory("/proc/self")) {
        const std::string proc = "/proc/ndfmip_cli_test_out";
        expectCleanFailure(cli("bake " + shellQuoted(good) + " -o " + proc),
                           {proc, "cannot write"});
        expectCleanFailure(cli("lut --exponent 8 -o " + proc + ".exr"),
                           {proc + ".exr", "cannot write"});
        EXPECT_FALSE(fs::exists(proc));
    }

    // A regular file where a parent folder should be.
    writeFile(tmp.path / "file.txt", "text\n");
    const std::string under = (tmp.path / "file.txt" / "out").string();
    expectCleanFailure(cli("bake " + shellQuoted(good) + " -o " + shellQuoted(under)),
                       {under, "not a folder"});
    EXPECT_EQ(readFile(tmp.path / "file.txt"), "text\n");

    // A lookup table onto an existing folder.
    fs::create_directory(out);
    expectCleanFailure(cli("lut --exponent 8 -o " + shellQuoted(out.string())), {out.string()});
    EXPECT_TRUE(fs::is_directory(out));
    EXPECT_TRUE(fs::is_empty(out));
    expectNoLeftovers(tmp.path);
}

TEST_F(CliBadInput, InspectOfADamagedBake) {
    ASSERT_EQ(cli("bake " + shellQuoted(good) + " -q -o " + shellQuoted(out.string())).status, 0);
    const std::string d = shellQuoted(out.string());
    fs::remove(out / "mean_L1.exr");
    expectCleanFailure(cli("inspect " + d + " --level 1 --texel 0,0"), {"mean_L1.exr"});
    EXPECT_EQ(cli("inspect " + d + " --level 0 --texel 0,0").status, 0); // other levels still read

    std::string manifest = readFile(out / "manifest.json");
    writeFile(out / "manifest.json", manifest.substr(0, manifest.size() / 2));
    expectCleanFailure(cli("inspect " + d + " --texel 0,0"), {"manifest.json", "malformed"});
    writeFile(out / "manifest.json", "{\"method\": \"median\"}");
    expectCleanFailure(cli("inspect " + d + " --texel 0,0"), {"manifest.json", "median"});
}

TEST_F(CliBadInput, OutputIsAnExistingFile) {
    writeFile(out, "not a folder\n");
    CliRun r = cli("bake " + shellQuoted(good) + " -o " + shellQuoted(out.string()));
    expectCleanFailure(r, {out.string(), "not a directory"});
    EXPECT_TRUE(fs::is_regular_file(out));
    EXPECT_EQ(readFile(out), "not a folder\n");
    expectNoLeftovers(tmp.path);
}

TEST_F(CliBadInput, OutputFolderWithUserFilesIsLeftAlone) {
    fs::create_directories(out / "sub");
    writeFile(out / "notes.txt", "keep me\n");
    writeFile(out / "sub" / "data.bin", "precious");
    const std::set<std::string> before = listNames(out);

    CliRun r = cli("bake " + shellQuoted(good) + " -o " + shellQuoted(out.string()));
    expectCleanFailure(r, {out.string(), "not an ndfmip bake"});
    EXPECT_EQ(listNames(out), before);
    EXPECT_EQ(readFile(out / "notes.txt"), "keep me\n");
    EXPECT_EQ(readFile(out / "sub" / "data.bin"), "precious");
    expectNoLeftovers(tmp.path);
}

TEST_F(CliBadInput, FailedBakeKeepsAnEarlierBake) {
    ASSERT_EQ(cli("bake " + shellQuoted(good) + " -q -o " + shellQuoted(out.string())).status, 0);
    const std::string manifest = readFile(out / "manifest.json");
    std::string missing = tmp.file("missing.png");
    expectCleanFailure(cli("bake " + shellQuoted(missing) + " -o " + shellQuoted(out.string())),
                       {missing});
    EXPECT_EQ(readFile(out / "manifest.json"), manifest);
}

TEST(Cli, RebakeReplacesAnEarlierBake) {
    TempDir tmp("cli_rebake");
    const std::string map = tmp.file("map.png");
    writePng16(map, encodeNormals(bumpyNormals(8, 8)));
    const fs::path dir = tmp.path / "bake";
    ASSERT_EQ(
        cli("bake " + shellQuoted(map) + " -q --method toksvig -o " + shellQuoted(dir.string()))
            .status,
        0);
    EXPECT_TRUE(fs::exists(dir / "mean_L0.exr"));

    CliRun r =
        cli("bake " + shellQuoted(map) + " -q --method naive -o " + shellQuoted(dir.string()));
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_EQ(readManifest(dir).at("method"), "naive");
    EXPECT_TRUE(fs::exists(dir / "normal_L0.exr"));
    EXPECT_FALSE(fs::exists(dir / "mean_L0.exr")) << "the earlier bake was merged, not replaced";
    // Only the bake folder and the map remain beside it.
    std::set<std::string> top;
    for (const auto& entry : fs::directory_iterator(tmp.path))
        top.insert(entry.path().filename().string());
    EXPECT_EQ(top, (std::set<std::string>{"bake", "map.png"}));

    // An empty existing folder is taken too, and a trailing slash names the same folder.
    const fs::path empty = tmp.path / "empty";
    fs::create_directory(empty);
    r = cli("bake " + shellQuoted(map) + " -q -o " + shellQuoted(empty.string() + "/"));
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_EQ(readManifest(empty).at("method"), "toksvig");
}

// ---- lut ----------------------------------------------------------------------------------------

// Toksvig eq. (9) written out: ((1 + ft s)/(1 + s)) (x / sqrt(y))^(ft s),
// ft = sqrt(y) / (sqrt(y) + s (1 - sqrt(y))), x = Na.H clamped to [0, |Na|], y = Na.Na.
double toksvigFormula(double x, double y, double s) {
    double length = std::sqrt(y);
    double ft = length / (length + s * (1.0 - length));
    double cosine = std::min(x, length) / length;
    return (1.0 + ft * s) / (1.0 + s) * std::pow(cosine, ft * s);
}

TEST(Cli, LutMatchesToksvigsFormula) {
    TempDir tmp("cli_lut");
    const std::string file = tmp.file("lut.exr");
    const int n = 64;
    const float s = 32.f;
    CliRun r = cli("lut --exponent 32 --size 64 -o " + shellQuoted(file));
    ASSERT_EQ(r.status, 0) << r.output;

    Result<SourceImage> loaded = loadImage(file);
    ASSERT_TRUE(loaded.ok()) << loaded.error().message;
    const Image& lut = loaded->image;
    ASSERT_EQ(lut.width, n);
    ASSERT_EQ(lut.height, n);
    ASSERT_EQ(lut.channels, 1);
    EXPECT_TRUE(loaded->isFloat);

    for (int j = 0; j < n; ++j) {
        const float y = (float(j) + 0.5f) / float(n); // row j samples Na.Na, row 0 on top
        for (int i = 0; i < n; ++i) {
            const float x = (float(i) + 0.5f) / float(n); // column i samples Na.H
            const float v = lut.at(i, j)[0];
            EXPECT_FLOAT_EQ(v, toksvigLutValue(x, y, s)) << "at (" << i << ", " << j << ")";
            const double expected = toksvigFormula(x, y, s);
            EXPECT_NEAR(v, expected, 1e-5 + 1e-4 * expected) << "at (" << i << ", " << j << ")";
        }
    }
    // The last row is nearly unfiltered (|Na| close to 1): its right end is the highlight peak,
    // far above the same column on the top row, where the lobe is nearly flat.
    EXPECT_GT(lut.at(n - 1, n - 1)[0], 0.5f);
    EXPECT_LT(lut.at(n - 1, 0)[0], 0.1f);

    // A PNG table holds the same values to 16 bits.
    const std::string png = tmp.file("lut.png");
    ASSERT_EQ(cli("lut --exponent 32 --size 64 -o " + shellQuoted(png)).status, 0);
    Result<SourceImage> p = loadImage(png);
    ASSERT_TRUE(p.ok()) << p.error().message;
    EXPECT_EQ(p->bitsPerChannel, 16);
    for (size_t k = 0; k < lut.pixels.size(); ++k)
        EXPECT_NEAR(p->image.pixels[k], std::clamp(lut.pixels[k], 0.f, 1.f), 1e-5f);
}

// ---- demo ---------------------------------------------------------------------------------------

TEST(Cli, DemoWritesComparisonAndTable) {
    TempDir tmp("cli_demo");
    const std::string map = tmp.file("map.png");
    const int w = 16, h = 16;
    writePng16(map, encodeNormals(bumpyNormals(w, h)));
    const fs::path dir = tmp.path / "demo";
    CliRun r = cli("demo " + shellQuoted(map) + " -o " + shellQuoted(dir.string()));
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("toksvig"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("naive"), std::string::npos) << r.output;
    // One table row per level below the map: 16x16 has levels 1 to 4.
    std::istringstream lines(r.output);
    std::string line;
    std::vector<int> rows;
    while (std::getline(lines, line))
        if (!line.empty() && std::isdigit(static_cast<unsigned char>(line[0])))
            rows.push_back(std::stoi(line));
    EXPECT_EQ(rows, (std::vector<int>{1, 2, 3, 4})) << r.output;

    Result<SourceImage> picture = loadImage((dir / "comparison.png").string());
    ASSERT_TRUE(picture.ok()) << picture.error().message;
    EXPECT_NE(r.output.find("sh"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("vmf"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("lean"), std::string::npos) << r.output;
    EXPECT_EQ(picture->image.width,
              6 * w + 5 * 4); // truth, naive, toksvig, sh, vmf, lean, 4-texel gaps
    EXPECT_EQ(picture->image.height, h);
}

TEST(Cli, DemoRefusesABadMap) {
    TempDir tmp("cli_demo_bad");
    std::string missing = tmp.file("missing.png");
    const fs::path dir = tmp.path / "demo";
    CliRun r = cli("demo " + shellQuoted(missing) + " -o " + shellQuoted(dir.string()));
    expectCleanFailure(r, {missing});
    EXPECT_FALSE(fs::exists(dir)) << "a failed demo left its output folder";
}

// ---- gloss maps (T eq. 12) ----------------------------------------------------------------------

TEST(Cli, GlossMapRoundTripsThroughToksvigFactor) {
    TempDir tmp("cli_gloss");
    const std::string map = tmp.file("flat.exr");
    writeExr(map, encodeNormals(flatNormals(8, 8))); // c = (0.5, 0.5, 1): n = (0, 0, 1) exactly
    const std::string glossFile = tmp.file("gloss.exr");
    const float g = 0.2f, s0 = 64.f;
    Image gloss(8, 8, 1);
    std::fill(gloss.pixels.begin(), gloss.pixels.end(), g);
    writeExr(glossFile, gloss);

    const fs::path dir = tmp.path / "bake";
    CliRun r = cli("bake " + shellQuoted(map) + " -q --gloss " + shellQuoted(glossFile) +
                   " --max-exponent 64 -o " + shellQuoted(dir.string()));
    ASSERT_EQ(r.status, 0) << r.output;
    json m = readManifest(dir);
    EXPECT_EQ(m.at("parameters").at("max_exponent"), 64.0);
    EXPECT_EQ(m.at("source").at("gloss"), glossFile);

    const float s = g * s0;
    const float expectedLength = s * s0 / (s * s0 + s0 - s);
    for (int level : {0, 1, 3}) {
        SCOPED_TRACE(level);
        json t = inspect(dir, level, "0,0", "--exponent 64");
        EXPECT_NEAR(t.at("length").get<float>(), expectedLength, 1e-5f);
        EXPECT_NEAR(t.at("toksvig_factor").get<float>(), g, 1e-5f);
    }

    // A gloss of 1 leaves the normals at unit length.
    std::fill(gloss.pixels.begin(), gloss.pixels.end(), 1.f);
    writeExr(glossFile, gloss);
    r = cli("bake " + shellQuoted(map) + " -q --gloss " + shellQuoted(glossFile) +
            " --max-exponent 64 -o " + shellQuoted(dir.string()));
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NEAR(inspect(dir, 0, "3,3", "--exponent 64").at("toksvig_factor").get<float>(), 1.f,
                1e-6f);
}

TEST(Cli, GlossMapWithNaNIsRefused) {
    TempDir tmp("cli_gloss_nan");
    const std::string map = tmp.file("flat.exr");
    writeExr(map, encodeNormals(flatNormals(4, 4)));
    const std::string glossFile = tmp.file("gloss.exr");
    Image gloss(4, 4, 1);
    std::fill(gloss.pixels.begin(), gloss.pixels.end(), 0.5f);
    gloss.at(1, 2)[0] = std::numeric_limits<float>::quiet_NaN();
    writeExr(glossFile, gloss);
    const fs::path dir = tmp.path / "bake";
    CliRun r = cli("bake " + shellQuoted(map) + " --gloss " + shellQuoted(glossFile) +
                   " --max-exponent 64 -o " + shellQuoted(dir.string()));
    expectCleanFailure(r, {glossFile, "NaN", "(1, 2)"});
    expectNothingWritten(tmp.path, dir);
}

// ---- render and eval ----------------------------------------------------------------------------

// A scene file over `map`: an orthographic top-down view, each pixel covering `block`^2 texels.
std::string alignedSceneJson(const std::string& map, int pixels, const std::string& method) {
    json scene = {
        {"camera",
         {{"type", "orthographic"},
          {"eye", {0, 0, 5}},
          {"target", {0, 0, 0}},
          {"up", {0, 1, 0}},
          {"ortho_height", 1},
          {"width", pixels},
          {"height", pixels}}},
        {"object", {{"type", "plane"}, {"size", {1, 1}}}},
        {"lights", {{{"type", "directional"}, {"direction", {0.3, 0.2, 1.0}}}}},
        {"material", {{"brdf", "ggx"}, {"roughness", 0.2}, {"albedo", 0.1}, {"specular", 1}}},
        {"normal_map", map},
        {"method", method}};
    return scene.dump(2);
}

TEST(Cli, RenderWritesExrAndPngAndGroundTruthMatchesMethodsOnAFlatMap) {
    TempDir tmp("render");
    const std::string map = tmp.file("flat.png");
    writePng16(map, encodeNormals(flatNormals(32, 32)));
    writeFile(tmp.path / "scene.json", alignedSceneJson("flat.png", 8, "toksvig"));
    const std::string scene = shellQuoted(tmp.file("scene.json"));
    CliRun r = cli("render " + scene + " -q -o " + shellQuoted(tmp.file("toksvig.exr")));
    ASSERT_EQ(r.status, 0) << r.output;
    r = cli("render " + scene + " -q --method groundtruth --spp 16 -o " +
            shellQuoted(tmp.file("truth.exr")));
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_TRUE(fs::exists(tmp.path / "truth.png"));
    Result<SourceImage> a = loadImage(tmp.file("toksvig.exr"));
    Result<SourceImage> b = loadImage(tmp.file("truth.exr"));
    ASSERT_TRUE(a.ok() && b.ok());
    ASSERT_EQ(a->image.width, 8);
    ASSERT_EQ(a->image.channels, 3);
    float peak = 0.f;
    for (size_t i = 0; i < a->image.pixels.size(); ++i) {
        EXPECT_NEAR(a->image.pixels[i], b->image.pixels[i],
                    1e-4f * std::max(1.f, b->image.pixels[i]));
        peak = std::max(peak, b->image.pixels[i]);
    }
    EXPECT_GT(peak, 0.1f); // the highlight is in view
    Result<SourceImage> png = loadImage(tmp.file("truth.png"));
    ASSERT_TRUE(png.ok());
    EXPECT_EQ(png->image.width, 8);
}

// A small grey sky with a brighter top, as an EXR file.
void writeSky(const std::string& path) {
    Image sky(32, 16, 3);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 32; ++x)
            for (int c = 0; c < 3; ++c) sky.at(x, y)[c] = y < 8 ? 2.f : 0.5f;
    ASSERT_TRUE(saveExr(path, sky));
}

TEST(Cli, RenderUnderAnEnvironmentWithEveryRuleAndWay) {
    TempDir tmp("render-env");
    writePng16(tmp.file("flat.png"), encodeNormals(flatNormals(32, 32)));
    writeSky(tmp.file("sky.exr"));
    writeFile(tmp.path / "scene.json", alignedSceneJson("flat.png", 8, "toksvig"));
    const std::string scene = shellQuoted(tmp.file("scene.json")),
                      sky = " --environment " + shellQuoted(tmp.file("sky.exr"));
    CliRun r = cli("render " + scene + sky + " -q --method groundtruth --spp 16 -o " +
                   shellQuoted(tmp.file("truth.exr")));
    ASSERT_EQ(r.status, 0) << r.output;
    Result<SourceImage> truth = loadImage(tmp.file("truth.exr"));
    ASSERT_TRUE(truth.ok());
    const float centre = truth->image.at(4, 4)[0];
    EXPECT_GT(centre, 0.f);
    for (const char* args :
         {"--method naive", "--method toksvig --env-lod log2sigma",
          "--method toksvig --env-lod unity", "--method toksvig --env-lod unreal",
          "--method vmf --vmf-environment sh", "--method vmf --env-lod filament", "--method sh",
          "--method sh --sh-views 18", "--method vmf --vmf-environment sh --sh-views 6",
          "--method sh --sh-cosine mean-normal",
          "--method vmf --vmf-environment sh --sh-cosine "
          "half-vector --env-sh-order 12"}) {
        r = cli("render " + scene + sky + " -q " + args + " -o " + shellQuoted(tmp.file("m.exr")));
        ASSERT_EQ(r.status, 0) << args << ": " << r.output;
        Result<SourceImage> image = loadImage(tmp.file("m.exr"));
        ASSERT_TRUE(image.ok());
        // A flat map: each method sees the truth's single normal (within the split sum's and
        // the SH truncation's approximations).
        EXPECT_NEAR(image->image.at(4, 4)[0], centre, 0.15f * centre) << args;
    }
    // A render under the sky with these arguments, into x.exr (which must never appear).
    auto renderWith = [&](const std::string& args) {
        return cli("render " + scene + sky + " " + args + " -o " + shellQuoted(tmp.file("x.exr")));
    };
    expectCleanFailure(renderWith("--env-lod bilinear"), {"--env-lod", "bilinear"});
    expectCleanFailure(renderWith("--method vmf --vmf-environment cube"),
                       {"--vmf-environment", "cube"});
    for (const char* views : {"-1", "1027", "many"})
        expectCleanFailure(renderWith(std::string("--method sh --sh-views ") + views),
                           {"--sh-views"});
    expectCleanFailure(renderWith("--method sh --sh-cosine mean"), {"--sh-cosine", "mean"});
    expectCleanFailure(renderWith("--env-direction sideways"), {"--env-direction", "sideways"});
    for (const char* order : {"0", "31", "eight"})
        expectCleanFailure(renderWith(std::string("--method sh --env-sh-order ") + order),
                           {"--env-sh-order"});
    expectCleanFailure(
        cli("render " + scene + sky + " --method lean -o " + shellQuoted(tmp.file("x.exr"))),
        {"lean", "environment"});
    expectCleanFailure(cli("render " + scene + " --environment " +
                           shellQuoted(tmp.file("nosky.exr")) + " -o " +
                           shellQuoted(tmp.file("x.exr"))),
                       {"nosky.exr"});
    EXPECT_FALSE(fs::exists(tmp.path / "x.exr"));
    // --env-direction reaches the split sum: from a grazing camera under a sky brighter towards
    // the zenith the mirror direction reads another part of it than the dominant direction (the
    // default); from above they agree.
    Image gradient(32, 16, 3);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 32; ++x)
            for (int c = 0; c < 3; ++c) gradient.at(x, y)[c] = 0.2f + 0.3f * float(16 - y);
    ASSERT_TRUE(saveExr(tmp.file("gradient.exr"), gradient));
    json grazing = json::parse(fileBytes(tmp.path / "scene.json"));
    grazing["camera"] = {{"type", "perspective"}, {"eye", {0, -3, 1.2}}, {"target", {0, 0, 0}},
                         {"up", {0, 0, 1}},       {"fov", 45},           {"width", 16},
                         {"height", 16}};
    grazing["object"]["size"] = {8, 8};
    writeFile(tmp.path / "grazing.json", grazing.dump());
    auto centreOf = [&](const std::string& sceneFile, const std::string& direction) {
        const CliRun run = cli("render " + shellQuoted(tmp.file(sceneFile)) + " --environment " +
                               shellQuoted(tmp.file("gradient.exr")) + " -q --method naive" +
                               direction + " -o " + shellQuoted(tmp.file("d.exr")));
        EXPECT_EQ(run.status, 0) << run.output;
        Result<SourceImage> image = loadImage(tmp.file("d.exr"));
        if (!image.ok()) return -1.f;
        return image->image.at(image->image.width / 2, image->image.height / 2)[0];
    };
    EXPECT_EQ(centreOf("grazing.json", ""), centreOf("grazing.json", " --env-direction dominant"));
    EXPECT_GT(std::abs(centreOf("grazing.json", " --env-direction mirror") -
                       centreOf("grazing.json", "")),
              1e-3f * centreOf("grazing.json", ""));
    EXPECT_NEAR(centreOf("scene.json", " --env-direction mirror"), centreOf("scene.json", ""),
                1e-5f * centreOf("scene.json", ""));
}

// An --external-roughness row under --environment is lit by it (it once failed: "environment ...
// is not loaded"): on a flat map a chain holding the material's own roughness renders as naive.
TEST(Cli, EvalExternalRoughnessUnderAnEnvironmentIsNaiveOnAFlatMap) {
    TempDir tmp("eval-env-roughness");
    writePng16(tmp.file("flat.png"), encodeNormals(flatNormals(16, 16)));
    writeSky(tmp.file("sky.exr"));
    for (int level = 0, size = 16; size >= 1; ++level, size /= 2) {
        Image r(size, size, 1);
        for (float& v : r.pixels) v = std::sqrt(0.3f); // perceptual roughness of alpha 0.3
        writePng16(tmp.file("r_" + std::to_string(level) + ".png"), r);
    }
    CliRun run = cli("eval " + shellQuoted(tmp.file("flat.png")) + " --environment " +
                     shellQuoted(tmp.file("sky.exr")) +
                     " -q --methods naive --brdfs ggx --roughness 0.3 --footprints 4 --frames 0 "
                     "--pixels 8 --spp 64 --external-roughness " +
                     shellQuoted("const=" + tmp.file("r_{level}.png")) + " -o " +
                     shellQuoted(tmp.file("r")));
    ASSERT_EQ(run.status, 0) << run.output;
    const json report = json::parse(fileBytes(tmp.path / "r" / "report.json"));
    double naive = -1., external = -1.;
    for (const json& c : report["cases"]) {
        if (c["method"] == "naive") naive = c["rel_rmse"].get<double>();
        if (c["method"] == "const") external = c["rel_rmse"].get<double>();
    }
    ASSERT_GE(naive, 0.);
    ASSERT_GE(external, 0.);
    EXPECT_NEAR(external, naive, 1e-3);
}

TEST(Cli, EvalUnderAnEnvironmentHasARowPerVariantAndSkipsTheRest) {
    TempDir tmp("eval-env");
    writePng16(tmp.file("flat.png"), encodeNormals(flatNormals(16, 16)));
    writeSky(tmp.file("sky.exr"));
    const std::string map = shellQuoted(tmp.file("flat.png")),
                      sky = " --environment " + shellQuoted(tmp.file("sky.exr"));
    CliRun r = cli("eval " + map + sky +
                   " -q --methods naive,toksvig@unity,vmf:2@sh,lean --brdfs ggx --roughness 0.3 "
                   "--footprints 4 --frames 0 --pixels 8 --spp 64 -o " +
                   shellQuoted(tmp.file("r")));
    ASSERT_EQ(r.status, 0) << r.output;
    const json report = json::parse(fileBytes(tmp.path / "r" / "report.json"));
    std::set<std::string> methods;
    for (const json& c : report["cases"]) methods.insert(c["method"].get<std::string>());
    EXPECT_EQ(methods,
              (std::set<std::string>{"groundtruth", "naive", "toksvig@unity", "vmf:2@sh"}));
    ASSERT_EQ(report["skipped"].size(), 1u);
    EXPECT_EQ(report["skipped"][0]["method"], "lean");
    // The SH lighting's choices are on record.
    EXPECT_EQ(report["setup"]["environment"]["sh_cosine"], "reflecting");
    EXPECT_EQ(report["setup"]["environment"]["env_sh_order"], 8);
    EXPECT_EQ(report["setup"]["environment"]["sh_views"], 0);
    EXPECT_EQ(report["setup"]["environment"]["env_direction"], "dominant");
    // eval's views fix every direction but the normal's: the truth is tabulated by default, with
    // far less noise than 64 samples per pixel give (on a flat map, its four nodes' alone).
    EXPECT_EQ(report["setup"]["environment"]["env_truth"], "table");
    EXPECT_LT(report["setup"]["truth_max_rel_std_error"].get<double>(), 0.05);
    expectCleanFailure(cli("eval " + map + sky + " -q --methods naive --env-truth exact -o " +
                           shellQuoted(tmp.file("r4"))),
                       {"--env-truth"});
    // A variant needs an environment; an unknown variant is refused.
    expectCleanFailure(
        cli("eval " + map + " -q --methods toksvig@unity -o " + shellQuoted(tmp.file("r2"))),
        {"toksvig@unity", "--environment"});
    expectCleanFailure(
        cli("eval " + map + sky + " -q --methods sh@unity -o " + shellQuoted(tmp.file("r3"))),
        {"sh@unity"});
    EXPECT_FALSE(fs::exists(tmp.path / "r2"));
    // --sh-views reaches the rows: eval looks straight down, a view of every set, so 6 views give
    // the one prepared view's error.
    const std::string sh = " -q --methods sh:4 --brdfs ggx --roughness 0.3 --footprints 4 --frames "
                           "0 --pixels 8 --spp 64";
    ASSERT_EQ(cli("eval " + map + sky + sh + " -o " + shellQuoted(tmp.file("one"))).status, 0);
    ASSERT_EQ(
        cli("eval " + map + sky + sh + " --sh-views 6 -o " + shellQuoted(tmp.file("six"))).status,
        0);
    auto shError = [&](const std::string& dir) {
        const json rows = json::parse(fileBytes(tmp.path / dir / "report.json"));
        for (const json& c : rows["cases"])
            if (c["method"] == "sh:4") return c["rel_rmse"].get<double>();
        return -1.;
    };
    EXPECT_GT(shError("one"), 0.);
    EXPECT_NEAR(shError("six"), shError("one"), 1e-4);
    // --sh-cosine and --env-sh-order reach the rows: another cosine or order, another image.
    for (const char* option : {" --sh-cosine none", " --env-sh-order 3"}) {
        ASSERT_EQ(
            cli("eval " + map + sky + sh + option + " -o " + shellQuoted(tmp.file("other"))).status,
            0);
        EXPECT_GT(std::abs(shError("other") - shError("one")), 1e-3) << option;
    }
    expectCleanFailure(
        cli("eval " + map + sky + sh + " --sh-views 2000 -o " + shellQuoted(tmp.file("r4"))),
        {"--sh-views"});
}

// --view names a set of options: the engine view is one trilinear lookup with the parameters
// blended and vmf's lobes coherent, exactly what those options give by hand; options given
// beside it win.
TEST(Cli, EvalViewsAreNamesForTheirOptions) {
    TempDir tmp("eval-view");
    const std::string map =
        shellQuoted(std::string(NDFMIP_SOURCE_DIR) + "/data/normalmaps/pyramidwall_256.png");
    const std::string common =
        " -q --no-webgl --methods toksvig,vmf:2 --brdfs ggx --roughness 0.3 --footprints 4 "
        "--frames 0 --pixels 16 -o ";
    auto run = [&](const std::string& name, const std::string& options) {
        CliRun r = cli("eval " + map + " " + options + common + shellQuoted(tmp.file(name)));
        EXPECT_EQ(r.status, 0) << r.output;
        return json::parse(fileBytes(tmp.path / name / "report.json"));
    };
    auto errors = [](const json& report) {
        std::map<std::string, double> e;
        for (const json& c : report["cases"])
            e[c["method"].get<std::string>()] = c["rel_rmse"].get<double>();
        return e;
    };
    const json engine = run("engine", "--view engine");
    const json& setup = engine["setup"];
    EXPECT_EQ(setup["eval_view"], "engine");
    EXPECT_EQ(setup["taps"], 1);
    EXPECT_EQ(setup["lod_bias"], 0.0);
    EXPECT_EQ(setup["lobe_filter"], "parameter");
    EXPECT_NEAR(setup["coherent"].get<double>(), 0.03, 1e-7);
    const json byHand =
        run("by-hand", "--taps 1 --lod-bias 0 --lobe-filter parameter --coherent 0.03");
    EXPECT_EQ(byHand["setup"]["eval_view"], "lab");
    EXPECT_EQ(errors(engine), errors(byHand));
    // Plain (not coherent) lobes in the same view differ: the view's bake is its own.
    const json plain = run("plain", "--view engine --coherent 0");
    EXPECT_NE(errors(plain).at("vmf:2"), errors(engine).at("vmf:2"));
    EXPECT_EQ(errors(plain).at("toksvig"), errors(engine).at("toksvig"));
    const json lab = run("lab", "--view engine --taps 2 --lod-bias -0.5 --lobe-filter texel");
    EXPECT_EQ(lab["setup"]["taps"], 2);
    EXPECT_EQ(lab["setup"]["lobe_filter"], "texel");
    const json aligned = run("aligned", "--view aligned");
    EXPECT_EQ(aligned["setup"]["aligned"], true);
    EXPECT_EQ(aligned["setup"]["taps"], 1);
    expectCleanFailure(
        cli("eval " + map + " --aligned --view engine" + common + shellQuoted(tmp.file("bad"))),
        {"--view engine"});
    expectCleanFailure(
        cli("eval " + map + " --view grazing" + common + shellQuoted(tmp.file("bad"))), {"--view"});
    EXPECT_FALSE(fs::exists(tmp.path / "bad"));
}

// A tilted view: the truth stays one exact integral per pixel, a flat map is drawn exactly by
// every method, and exact is still the floor of the bumpy map's rows.
TEST(Cli, EvalAtAnElevationKeepsAnExactTruth) {
    TempDir tmp("eval-elevation");
    writePng16(tmp.file("flat.png"), encodeNormals(flatNormals(16, 16)));
    const std::string bumpy =
        shellQuoted(std::string(NDFMIP_SOURCE_DIR) + "/data/normalmaps/pyramidwall_256.png");
    const std::string options =
        " -q --no-webgl --elevation 30 --methods naive,toksvig,vmf:2,exact --brdfs ggx "
        "--roughness 0.3 --footprints 4,16 --frames 0 --pixels 32 -o ";
    CliRun r = cli("eval " + shellQuoted(tmp.file("flat.png")) + " " + bumpy + options +
                   shellQuoted(tmp.file("r")));
    ASSERT_EQ(r.status, 0) << r.output;
    const json report = json::parse(fileBytes(tmp.path / "r" / "report.json"));
    EXPECT_EQ(report["setup"]["elevation_degrees"], 30.0);
    EXPECT_EQ(report["setup"]["view"], "orthographic, 30 deg above the plane");
    EXPECT_EQ(report["setup"]["truth_spp"], "exact integral, no samples");
    std::map<std::pair<int, std::string>, double> bumpyError;
    for (const json& c : report["cases"]) {
        const std::string method = c["method"];
        if (method == "groundtruth") continue;
        if (c["map"].get<std::string>().find("flat") !=
            std::string::npos) // vmf: its kappa cap's width
            EXPECT_LT(c["rel_rmse"].get<double>(), method.rfind("vmf", 0) == 0 ? 1e-3 : 1e-5)
                << method;
        else
            bumpyError[{c["footprint"].get<int>(), method}] = c["rel_rmse"].get<double>();
    }
    for (int f : {4, 16}) {
        EXPECT_GT(bumpyError.at({f, "naive"}), 0.0);
        EXPECT_LE(bumpyError.at({f, "exact"}), bumpyError.at({f, "toksvig"}) + 1e-9) << f;
        EXPECT_LE(bumpyError.at({f, "exact"}), bumpyError.at({f, "naive"}) + 1e-9) << f;
    }
    expectCleanFailure(
        cli("eval " + bumpy + " --aligned --elevation 30" + options + shellQuoted(tmp.file("bad"))),
        {"--elevation"});
    EXPECT_FALSE(fs::exists(tmp.path / "bad"));
}

// The straight-down view's light at another angle: the report says so, a flat map is still drawn
// exactly by every method, the bumpy map's errors move with the light, and a tilted view (whose
// light follows its mirror direction) refuses it.
TEST(Cli, EvalLightPolarMovesTheStraightDownLight) {
    TempDir tmp("eval-light-polar");
    writePng16(tmp.file("flat.png"), encodeNormals(flatNormals(16, 16)));
    const std::string maps =
        shellQuoted(tmp.file("flat.png")) + " " +
        shellQuoted(std::string(NDFMIP_SOURCE_DIR) + "/data/normalmaps/pyramidwall_256.png");
    const std::string options = " -q --no-webgl --methods naive,toksvig,exact --brdfs ggx "
                                "--roughness 0.3 --footprints 16 --frames 0 --pixels 32 -o ";
    auto naiveError = [&](const std::string& extra, const std::string& name) {
        CliRun r = cli("eval " + maps + extra + options + shellQuoted(tmp.file(name)));
        EXPECT_EQ(r.status, 0) << r.output;
        const json report = json::parse(fileBytes(tmp.path / name / "report.json"));
        double bumpy = -1.;
        for (const json& c : report["cases"]) {
            const std::string method = c["method"];
            if (method == "groundtruth") continue;
            if (c["map"].get<std::string>().find("flat") != std::string::npos)
                EXPECT_LT(c["rel_rmse"].get<double>(), 1e-5) << name << " " << method;
            else if (method == "naive")
                bumpy = c["rel_rmse"].get<double>();
        }
        return std::make_pair(report, bumpy);
    };
    const auto [tilted, tiltedError] = naiveError(" --light-polar 60", "polar60");
    EXPECT_EQ(tilted["setup"]["light_polar_degrees"], 60.0);
    EXPECT_EQ(tilted["setup"]["light"], "directional, 60 deg off the normal");
    const auto [standard, standardError] = naiveError("", "polar25");
    EXPECT_EQ(standard["setup"]["light_polar_degrees"], 25.0);
    EXPECT_GT(tiltedError, 0.0);
    EXPECT_GT(standardError, 0.0);
    EXPECT_GT(std::abs(tiltedError - standardError), 1e-3 * standardError);
    expectCleanFailure(cli("eval " + maps + " --elevation 30 --light-polar 10" + options +
                           shellQuoted(tmp.file("bad"))),
                       {"--light-polar"});
    expectCleanFailure(
        cli("eval " + maps + " --light-polar 89" + options + shellQuoted(tmp.file("bad"))),
        {"--light-polar"});
    EXPECT_FALSE(fs::exists(tmp.path / "bad"));
}

TEST(Cli, RenderReportsBadScenesInOneLine) {
    TempDir tmp("render-bad");
    writeFile(tmp.path / "bad.json", R"({"camera": {"width": "abc"}})");
    CliRun r = cli("render " + shellQuoted(tmp.file("bad.json")) + " -o " +
                   shellQuoted(tmp.file("out.exr")));
    expectCleanFailure(r, {"bad.json", "camera"});
    json scene = json::parse(alignedSceneJson("missing.png", 8, "toksvig"));
    scene["material"]["brdf"] = "velvet";
    writeFile(tmp.path / "brdf.json", scene.dump());
    expectCleanFailure(cli("render " + shellQuoted(tmp.file("brdf.json")) + " -o " +
                           shellQuoted(tmp.file("o.exr"))),
                       {"brdf.json", "material.brdf", "velvet"});
    writeFile(tmp.path / "nomap.json", alignedSceneJson("missing.png", 8, "toksvig"));
    expectCleanFailure(cli("render " + shellQuoted(tmp.file("nomap.json")) + " -o " +
                           shellQuoted(tmp.file("o.exr"))),
                       {"missing.png"});
    writeFile(tmp.path / "method.json", alignedSceneJson("missing.png", 8, "sparkle"));
    expectCleanFailure(cli("render " + shellQuoted(tmp.file("method.json")) + " -o " +
                           shellQuoted(tmp.file("o.exr"))),
                       {"sparkle"});
    EXPECT_FALSE(fs::exists(tmp.path / "o.exr"));
    EXPECT_FALSE(fs::exists(tmp.path / "out.exr"));
}

TEST(Cli, RenderExampleScenesShipWithTheRepository) {
    TempDir tmp("render-examples");
    for (const char* name : {"aligned_ortho", "sphere"}) {
        const std::string scene = std::string(NDFMIP_SOURCE_DIR) + "/scenes/" + name + ".json";
        CliRun r = cli("render " + shellQuoted(scene) + " -q --frames 2 -o " +
                       shellQuoted(tmp.file(std::string(name) + ".exr")));
        ASSERT_EQ(r.status, 0) << r.output;
        EXPECT_NE(r.output.find("flicker"), std::string::npos) << r.output;
    }
}

TEST(Cli, ShBakeStoresYlmAndInspectPrintsThemBandByBand) {
    TempDir tmp("sh");
    const std::string map = tmp.file("map.png");
    writePng16(map, encodeNormals(checkerTiltNormals(8, 8, kTheta)));
    const fs::path dir = tmp.path / "bake";
    CliRun r = cli("bake " + shellQuoted(map) + " --method sh --order 3 --half -q -o " +
                   shellQuoted(dir.string()));
    ASSERT_EQ(r.status, 0) << r.output;
    json manifest = readManifest(dir);
    EXPECT_EQ(manifest.at("storage"), "half");
    EXPECT_EQ(manifest.at("planes").size(), 4u); // 16 coefficients, 4 per plane
    // Level 1: the block's two normals (+-theta in x) average Y_lm; band 1 is sqrt(3/4pi) (y, z,
    // x).
    json texel = inspect(dir, 1, "0,0", "--ndf " + shellQuoted(tmp.file("ndf.png")));
    ASSERT_EQ(texel.at("sh").size(), 16u);
    const float c1 = std::sqrt(3.f / (4.f * 3.14159265f));
    EXPECT_NEAR(texel.at("sh").at(0).get<float>(), 1.f / std::sqrt(4.f * 3.14159265f), 1e-3f);
    EXPECT_NEAR(texel.at("sh").at(2).get<float>(), c1 * std::cos(kTheta), 2e-3f);
    EXPECT_NEAR(texel.at("sh").at(3).get<float>(), 0.f, 1e-3f);
    EXPECT_NEAR(texel.at("length").get<float>(), std::cos(kTheta), 2e-3f);
    Result<SourceImage> ndf = loadImage(tmp.file("ndf.png"));
    ASSERT_TRUE(ndf.ok());
    EXPECT_EQ(ndf->image.width, 2 * 256 + 2);
    expectCleanFailure(cli("bake " + shellQuoted(map) + " --method sh --order 31 -o " +
                           shellQuoted((tmp.path / "b2").string())),
                       {"--order"});
    expectCleanFailure(cli("bake " + shellQuoted(map) + " --method naive --order 3 -o " +
                           shellQuoted((tmp.path / "b3").string())),
                       {"--order"});
    EXPECT_FALSE(fs::exists(tmp.path / "b2"));
}

TEST(Cli, VmfBakeWithAlbedoPrintsLobesWithColours) {
    TempDir tmp("vmf");
    const std::string map = tmp.file("map.png");
    writePng16(map, encodeNormals(checkerTiltNormals(8, 8, kTheta)));
    Image albedo(8, 8, 3);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) albedo.at(x, y)[(x + y) % 2 == 0 ? 0 : 2] = 1.f;
    writePng16(tmp.file("albedo.png"), albedo);
    writePng16(tmp.file("small.png"), Image(4, 4, 3));
    const fs::path dir = tmp.path / "bake";
    CliRun r = cli("bake " + shellQuoted(map) + " --method vmf --lobes 2 --albedo " +
                   shellQuoted(tmp.file("albedo.png")) + " -q -o " + shellQuoted(dir.string()));
    ASSERT_EQ(r.status, 0) << r.output;
    json texel = inspect(dir, 1, "0,0");
    ASSERT_EQ(texel.at("lobes").size(), 2u);
    for (const json& lobe : texel.at("lobes")) {
        // Each lobe sits on one of the two tilts and carries that tilt's colour.
        const float mx = lobe.at("mu").at(0).get<float>();
        EXPECT_NEAR(std::abs(mx), std::sin(kTheta), 1e-3f) << lobe.dump();
        EXPECT_NEAR(lobe.at("alpha").get<float>(), 0.5f, 1e-3f);
        const json& c = lobe.at("color");
        EXPECT_NEAR(c.at(mx > 0 ? 0 : 2).get<float>(), 1.f, 1e-3f) << lobe.dump();
        EXPECT_NEAR(c.at(mx > 0 ? 2 : 0).get<float>(), 0.f, 1e-3f) << lobe.dump();
    }
    expectCleanFailure(cli("bake " + shellQuoted(map) + " --method vmf --albedo " +
                           shellQuoted(tmp.file("small.png")) + " -o " +
                           shellQuoted((tmp.path / "b2").string())),
                       {"small.png", "4x4", "8x8"});
    expectCleanFailure(cli("bake " + shellQuoted(map) + " --method vmf --lobes 9 -o " +
                           shellQuoted((tmp.path / "b3").string())),
                       {"--lobes"});
    expectCleanFailure(cli("bake " + shellQuoted(map) + " --method vmf --lobes 0 -o " +
                           shellQuoted((tmp.path / "b4").string())),
                       {"--lobes"});
    expectCleanFailure(cli("bake " + shellQuoted(map) + " --method toksvig --lobes 2 -o " +
                           shellQuoted((tmp.path / "b5").string())),
                       {"--lobes"});
    // Every option of the method's table applies to it alone, EM's limits too.
    expectCleanFailure(cli("bake " + shellQuoted(map) + " --method toksvig --max-iterations 5 -o " +
                           shellQuoted((tmp.path / "b6").string())),
                       {"--max-iterations applies to --method vmf only"});
    expectCleanFailure(cli("bake " + shellQuoted(map) +
                           " --method vmf --coherent 1 --lobe-budget 0.01 -o " +
                           shellQuoted((tmp.path / "b7").string())),
                       {"--lobe-budget does not apply to coherent lobes"});
    EXPECT_FALSE(fs::exists(tmp.path / "b2"));
    EXPECT_FALSE(fs::exists(tmp.path / "b6"));
}

// The methods' own options come from their parameter tables: each flag once, with the table's
// range and default in its help, on every command that takes it.
TEST(Cli, MethodOptionsComeFromTheParameterTables) {
    const CliRun bake = cli("bake --help");
    ASSERT_EQ(bake.status, 0);
    for (const auto& [method, p] : allMethodParameters()) {
        if (!(p->commands & kParameterBake)) continue;
        EXPECT_NE(bake.output.find(p->flag), std::string::npos) << p->flag;
        EXPECT_NE(bake.output.find(p->help), std::string::npos) << p->help;
    }
    EXPECT_NE(bake.output.find("vmf: lobes per texel J (default 4)"), std::string::npos);
    const CliRun render = cli("render --help");
    ASSERT_EQ(render.status, 0);
    EXPECT_NE(render.output.find("sh baked on the fly: highest band l*"), std::string::npos);
    EXPECT_EQ(render.output.find("--max-iterations"), std::string::npos); // bake only
}

// Coherent lobes (H eq. 32, the engine view's C): slot j of neighbouring texels matches far
// better, and where lookups blend the lobes' parameters, as hardware filtering does, the rendered
// error against the truth falls (geometric mean over the cases; with texel filtering the slots
// never meet, and the plain lobes fit better).
TEST(Cli, CoherentLobesMatchAcrossTexelsAtNoCostInImageError) {
    TempDir tmp("coherent");
    const std::string map = std::string(NDFMIP_SOURCE_DIR) + "/data/normalmaps/pyramidwall_256.png";
    double mismatch[2], error[2];
    for (int c = 0; c < 2; ++c) {
        const std::string coherence = c ? " --coherent 0.03" : " --coherent 0";
        const fs::path bake = tmp.path / ("bake" + std::to_string(c));
        CliRun r = cli("bake " + shellQuoted(map) + " --green-down --method vmf -q" + coherence +
                       " -o " + shellQuoted(bake.string()));
        ASSERT_EQ(r.status, 0) << r.output;
        mismatch[c] = readManifest(bake).at("parameters").at("lobe_mismatch_degrees").get<double>();
        const fs::path report = tmp.path / ("report" + std::to_string(c));
        r = cli("eval " + shellQuoted(map) +
                " --green-down --methods vmf:4 --footprints 4,16,64 --exponents 32,128 "
                "--roughness 0.1 --frames 0 --lobe-filter parameter -q" +
                coherence + " -o " + shellQuoted(report.string()));
        ASSERT_EQ(r.status, 0) << r.output;
        json cases = json::parse(readFile(report / "report.json")).at("cases");
        double logSum = 0;
        int n = 0;
        for (const json& k : cases)
            if (k.at("method") == "vmf:4") logSum += std::log(k.at("rel_rmse").get<double>()), ++n;
        ASSERT_EQ(n, 9);
        error[c] = std::exp(logSum / n);
    }
    // Measured: mismatch 10.7 -> 5.4 degrees, error 0.115 -> 0.099.
    EXPECT_LT(mismatch[1], 0.6 * mismatch[0]) << mismatch[0] << " -> " << mismatch[1];
    EXPECT_LT(error[1], 0.95 * error[0]) << error[0] << " -> " << error[1];
    expectCleanFailure(cli("bake " + shellQuoted(map) + " --method vmf --coherent -1 -o " +
                           shellQuoted((tmp.path / "bad").string())),
                       {"--coherent"});
}

TEST(Cli, EvalWritesReportWhoseFlatMapCasesAreExact) {
    TempDir tmp("eval");
    writePng16(tmp.file("flat.png"), encodeNormals(flatNormals(32, 32)));
    writePng16(tmp.file("bumpy.png"), encodeNormals(bumpyNormals(32, 32)));
    const fs::path out = tmp.path / "report";
    CliRun r =
        cli("eval " + shellQuoted(tmp.file("flat.png")) + " " + shellQuoted(tmp.file("bumpy.png")) +
            " -q --methods naive,toksvig --footprints 1,4 --exponents 16 --roughness 0.2 --frames "
            "2 --pixels 16 -o " +
            shellQuoted(out.string()));
    ASSERT_EQ(r.status, 0) << r.output;
    ASSERT_TRUE(fs::exists(out / "report.html"));
    json report = json::parse(readFile(out / "report.json"), nullptr, false);
    ASSERT_FALSE(report.is_discarded());
    const json& cases = report.at("cases");
    // 2 maps x 2 footprints x 2 settings x (truth + 2 methods).
    ASSERT_EQ(cases.size(), 24u);
    std::set<std::string> methods;
    for (const json& c : cases) {
        for (const char* key : {"map", "footprint", "method", "brdf", "exponent", "rel_rmse",
                                "energy_ratio", "flicker"})
            EXPECT_TRUE(c.contains(key)) << key;
        methods.insert(c.at("method").get<std::string>());
        if (c.at("map") == "flat.png" && c.at("method") != "groundtruth") {
            EXPECT_LT(c.at("rel_rmse").get<double>(), 1e-4) << c.dump();
            EXPECT_NEAR(c.at("energy_ratio").get<double>(), 1.0, 1e-4) << c.dump();
            EXPECT_LT(c.at("flicker").get<double>(), 1e-4) << c.dump();
        }
        if (c.at("map") == "bumpy.png" && c.at("method") != "groundtruth" &&
            c.at("footprint") == 4) {
            EXPECT_GT(c.at("rel_rmse").get<double>(), 1e-3)
                << "filtering a bumpy map is not exact: " << c.dump();
        }
    }
    EXPECT_EQ(methods, (std::set<std::string>{"groundtruth", "naive", "toksvig"}));
    const std::string html = readFile(out / "report.html");
    EXPECT_NE(html.find("data:image/png;base64,"), std::string::npos);
}

// The reference and peer rows on a flat map in the aligned view: 'exact' is the truth, Toksvig's
// table matches the truth (|Na| = 1: no widening) for Blinn-Phong only, sggx (the lean bake as
// one GGX lobe) is the GGX truth, and an external roughness chain holding the material's own
// roughness is the GGX truth.
TEST(Cli, EvalReferenceAndExternalRoughnessRows) {
    TempDir tmp("eval-rows");
    writePng16(tmp.file("flat.png"), encodeNormals(flatNormals(32, 32)));
    for (int level = 0, size = 32; size >= 1; ++level, size /= 2) {
        Image r(size, size, 1);
        for (float& v : r.pixels) v = std::sqrt(0.2f); // perceptual roughness of alpha 0.2
        writePng16(tmp.file("r_" + std::to_string(level) + ".png"), r);
    }
    const fs::path out = tmp.path / "report";
    CliRun run = cli(
        "eval " + shellQuoted(tmp.file("flat.png")) +
        " -q --aligned --methods toksvig,toksvig-lut,sggx,exact --footprints 1,4 --exponents 16 "
        "--roughness 0.2 --frames 0 --pixels 8 --external-roughness " +
        shellQuoted("const=" + tmp.file("r_{level}.png")) + " -o " + shellQuoted(out.string()));
    ASSERT_EQ(run.status, 0) << run.output;
    const json report = json::parse(readFile(out / "report.json"));
    EXPECT_EQ(report.at("setup").at("truth"), "box");
    EXPECT_EQ(report.at("setup").at("aligned"), true);
    EXPECT_EQ(report.at("setup").at("taps"), 1);
    int lut = 0, external = 0, exact = 0, sggx = 0;
    for (const json& c : report.at("cases")) {
        const std::string method = c.at("method");
        if (method == "groundtruth") continue;
        if (method == "sggx") {
            // A GGX lobe of Blinn-Phong's alpha stands for Blinn-Phong: not that truth.
            if (c.at("brdf") == "ggx") {
                EXPECT_LT(c.at("rel_rmse").get<double>(), 1e-3) << c.dump();
            }
            ++sggx;
            continue;
        }
        // Toksvig's table: its last row is |Na| = 0.999, not 1, and the phase-out blends.
        EXPECT_LT(c.at("rel_rmse").get<double>(), method == "toksvig-lut" ? 0.02 : 1e-3)
            << c.dump();
        if (method == "toksvig-lut") {
            ++lut;
            EXPECT_EQ(c.at("brdf"), "blinnphong");
        }
        if (method == "const") {
            ++external;
            EXPECT_EQ(c.at("brdf"), "ggx");
        }
        exact += method == "exact";
    }
    EXPECT_EQ(lut, 2);      // footprints 1 and 4, Blinn-Phong
    EXPECT_EQ(external, 2); // footprints 1 and 4, GGX
    EXPECT_EQ(exact, 4);
    EXPECT_EQ(sggx, 4);
    // A level the pattern names but the folder lacks: one line naming the file.
    fs::remove(tmp.file("r_3.png"));
    expectCleanFailure(cli("eval " + shellQuoted(tmp.file("flat.png")) +
                           " -q --methods toksvig --brdfs ggx " + "--external-roughness " +
                           shellQuoted("const=" + tmp.file("r_{level}.png")) + " -o " +
                           shellQuoted(tmp.file("r2"))),
                       {"r_3.png"});
}

TEST(Cli, EvalRejectsBadOptions) {
    TempDir tmp("eval-bad");
    writePng16(tmp.file("flat.png"), encodeNormals(flatNormals(8, 8)));
    const std::string map = shellQuoted(tmp.file("flat.png"));
    const std::string out = " -o " + shellQuoted(tmp.file("r"));
    expectCleanFailure(cli("eval " + map + " --methods naive,magic" + out), {"magic"});
    expectCleanFailure(cli("eval " + map + " --methods sh:99" + out), {"sh:99"});
    expectCleanFailure(cli("eval " + map + " --methods toksvig:3" + out), {"toksvig:3"});
    expectCleanFailure(cli("eval " + map + " --methods vmf:9" + out), {"vmf:9"});
    expectCleanFailure(cli("eval " + map + " --brdfs velvet" + out), {"velvet"});
    expectCleanFailure(cli("eval " + map + " --footprints 0" + out), {"footprints"});
    expectCleanFailure(cli("eval " + shellQuoted(tmp.file("none.png")) + out), {"none.png"});
    expectCleanFailure(cli("eval " + map + " --truth smooth" + out), {"--truth"});
    expectCleanFailure(cli("eval " + map + " --lobe-filter fancy" + out), {"--lobe-filter"});
    expectCleanFailure(cli("eval " + map + " --aligned --footprints 3" + out), {"--aligned"});
    expectCleanFailure(cli("eval " + map + " --external-roughness nopattern" + out),
                       {"NAME=PATTERN"});
    expectCleanFailure(cli("eval " + map + " --external-roughness x=r.png" + out), {"{level}"});
    expectCleanFailure(cli("eval " + map + " --taps 0" + out), {"--taps"});
    EXPECT_FALSE(fs::exists(tmp.path / "r"));
}

// ---- general ----------------------------------------------------------------------------------

TEST(Cli, UnknownSubcommandAndMissingArgumentsFailInOneLine) {
    expectCleanFailure(cli("frobnicate"), {"subcommand"});
    expectCleanFailure(cli("bake missing.png -o out --no-such-flag"), {"--no-such-flag"});
    expectCleanFailure(cli("bake"), {"input"});
    expectCleanFailure(cli(""), {"subcommand"});
    CliRun version = cli("--version");
    EXPECT_EQ(version.status, 0);
    EXPECT_NE(version.output.find("ndfmip"), std::string::npos);
}

} // namespace
} // namespace ndfmip::test
