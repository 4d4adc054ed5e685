// ndfmip gltf: a real normal map in a small asset, filtered into a GLB that the Khronos
// validator accepts, with everything else kept and every level checked against bake.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <functional>
#include <initializer_list>
#include <set>
#include <string>
#include <tuple>

#include <glm/glm.hpp>
#include <gtest/gtest.h>

#include "gltf_test_asset.h"
#include "methods/lean/engine_anisotropy.h"
#include "ndfmip/bake.h"
#include "ndfmip/io.h"
#include "ndfmip/normal_map.h"
#include "ndfmip/pyramid.h"
#include "test_support.h"

namespace ndfmip {
namespace {

namespace fs = std::filesystem;
using test::OrderedJson;

constexpr uint32_t kDxgiBc5 = 83, kDxgiRgba8 = 28;
// The DDS output these tests check (MSFT_texture_dds; no Basis encoder needed).
const std::string kDds = " --texture-format dds";

// A shared map of odd size (745x745: odd levels all the way down) when the shared data is
// there, else the bundled 256x256 one.
std::string normalMapPath() {
    const fs::path shared = test::sharedNormalMaps();
    if (!shared.empty() && fs::exists(shared / "godot_aluminium_normal.png"))
        return (shared / "godot_aluminium_normal.png").string();
    return std::string(NDFMIP_SOURCE_DIR) + "/data/normalmaps/pyramidwall_256.png";
}

// The packed map of material 'Wall': R occlusion, G perceptual roughness (0.15 .. 0.9 in
// stripes), B metallic (a checker), 8-bit.
Image materialMap(int width, int height) {
    Image m(width, height, 3);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            float* p = m.at(x, y);
            p[0] = 0.6f + 0.4f * std::sin(0.05f * float(x + y));
            p[1] = 0.15f + 0.75f * float((x + 2 * y) % 97) / 96.f;
            p[2] = float((x / 16 + y / 16) % 2);
        }
    return m;
}

uint32_t u32(const std::string& bytes, size_t at) {
    uint32_t v = 0;
    std::memcpy(&v, bytes.data() + at, 4);
    return v;
}

// A DDS with the DX10 header taken apart: its format and every level's bytes.
struct Dds {
    uint32_t width = 0, height = 0, dxgi = 0;
    std::vector<std::string> levels;
};

Dds parseDds(const std::string& bytes) {
    Dds d;
    if (bytes.size() < 148 || bytes.compare(0, 4, "DDS ") != 0 || u32(bytes, 4) != 124 ||
        bytes.compare(84, 4, "DX10") != 0)
        return d;
    d.height = u32(bytes, 12), d.width = u32(bytes, 16), d.dxgi = u32(bytes, 128);
    const uint32_t mips = u32(bytes, 28);
    EXPECT_EQ(u32(bytes, 132), 3u); // D3D10_RESOURCE_DIMENSION_TEXTURE2D
    EXPECT_EQ(u32(bytes, 140), 1u); // array size
    size_t at = 148;
    for (uint32_t k = 0; k < mips; ++k) {
        const size_t w = std::max<size_t>(d.width >> k, 1), h = std::max<size_t>(d.height >> k, 1);
        const size_t size = d.dxgi == kDxgiBc5 ? (w + 3) / 4 * ((h + 3) / 4) * 16 : w * h * 4;
        if (at + size > bytes.size()) return Dds{};
        d.levels.push_back(bytes.substr(at, size));
        at += size;
    }
    EXPECT_EQ(at, bytes.size()) << "bytes after the last level";
    return d;
}

// The DDS image that texture `t` names through MSFT_texture_dds.
Dds textureDds(const test::Glb& glb, size_t t) {
    const OrderedJson& texture = glb.json["textures"][t];
    EXPECT_TRUE(texture.contains("extensions")) << texture.dump();
    if (!texture.contains("extensions")) return {};
    const size_t image = texture["extensions"]["MSFT_texture_dds"]["source"].get<size_t>();
    EXPECT_EQ(glb.json["images"][image]["mimeType"], "image/vnd-ms.dds");
    return parseDds(test::glbImage(glb, image));
}

// The quad asset around the normal map and 'Wall''s packed map, as .gltf with external files.
struct Fixture {
    test::TempDir dir{"gltf_cli"};
    std::string normalPng, materialPng, gltf;
    int width = 0, height = 0;
    test::TestAsset asset = test::quadAsset();

    Fixture() {
        normalPng = test::fileBytes(normalMapPath());
        Result<SourceImage> normal = decodeImage(normalPng, "normal");
        width = normal->image.width, height = normal->image.height;
        materialPng = encodePng(materialMap(width, height), 8).value();
        gltf =
            test::writeGltf(dir.path, asset, {{"normal.png", normalPng}, {"orm.png", materialPng}});
    }
};

// The Khronos glTF validator's counts for a GLB file (node and the npm package gltf-validator,
// which scripts/setup installs into .npm), or "" when they are not installed.
std::string validatorReport(const test::TempDir& dir, const std::string& glb) {
    const char* modules = std::getenv("NDFMIP_NODE_MODULES");
    const std::string path =
        (modules ? modules : std::string(NDFMIP_SOURCE_DIR) + "/.npm/node_modules") +
        "/gltf-validator";
    if (!fs::exists("/usr/bin/node") || !fs::exists(path + "/index.js")) return "";
    const std::string script = dir.file("validate.js");
    test::writeBytes(
        script,
        "const v = require(process.argv[2]);\n"
        "const bytes = new Uint8Array(require('fs').readFileSync(process.argv[3]));\n"
        "v.validateBytes(bytes, {maxIssues: 0}).then(r => console.log(JSON.stringify({errors: "
        "r.issues.numErrors, "
        "warnings: r.issues.numWarnings, infos: r.issues.numInfos, hints: r.issues.numHints, "
        "codes: r.issues.messages.map(m => m.code + ' ' + (m.pointer || ''))})))\n"
        "  .catch(e => { console.log(JSON.stringify({failed: String(e)})); process.exit(1); });\n");
    const std::string out = dir.file("validator.json");
    const std::string command = "node " + test::shellArg(script) + " " + test::shellArg(path) +
                                " " + test::shellArg(glb) + " > " + test::shellArg(out) + " 2>&1";
    EXPECT_EQ(std::system(command.c_str()), 0) << test::fileBytes(out);
    return test::fileBytes(out);
}

TEST(GltfCli, FilteredAssetKeepsEverythingElseAndMatchesBake) {
    Fixture f;
    const std::string out = f.dir.file("out.glb");
    std::string output;
    ASSERT_EQ(test::runCli("gltf " + test::shellArg(f.gltf) + " -o " + test::shellArg(out) + kDds,
                           &output),
              0)
        << output;
    std::printf("%s", output.c_str());
    EXPECT_NE(output.find("Wall"), std::string::npos) << output;
    EXPECT_NE(output.find("Plain"), std::string::npos) << output;
    const test::Glb glb = test::parseGlb(test::fileBytes(out));
    ASSERT_TRUE(glb.ok);
    const OrderedJson& in = f.asset.json;

    // Everything but the textures' extensions (and, for 'Plain', its made map) as it was.
    for (const char* key :
         {"asset", "scene", "scenes", "nodes", "meshes", "samplers", "accessors", "extras"})
        EXPECT_EQ(glb.json[key], in[key]) << key;
    EXPECT_EQ(glb.json["materials"][0], in["materials"][0]);
    EXPECT_EQ(glb.json["materials"][1], in["materials"][1]);
    EXPECT_EQ(glb.json["extensionsUsed"], OrderedJson::array({"MSFT_texture_dds"}));
    EXPECT_FALSE(glb.json.contains("extensionsRequired"));
    for (size_t t = 0; t < 2; ++t) {
        OrderedJson texture = glb.json["textures"][t];
        texture.erase("extensions");
        EXPECT_EQ(texture, in["textures"][t]);
    }
    // The original images, byte for byte, still each texture's core source.
    EXPECT_EQ(test::glbImage(glb, 0), f.normalPng);
    EXPECT_EQ(test::glbImage(glb, 1), f.materialPng);
    EXPECT_EQ(glb.json["images"][0]["mimeType"], "image/png");
    EXPECT_EQ(glb.json["images"][0]["name"], "normal image");

    // Every level in the DDS files.
    const int levels = levelCount(f.width, f.height);
    const Dds normal = textureDds(glb, 0), material = textureDds(glb, 1);
    EXPECT_EQ(normal.dxgi, kDxgiBc5);
    EXPECT_EQ(material.dxgi, kDxgiRgba8);
    for (const Dds* d : {&normal, &material}) {
        EXPECT_EQ(int(d->levels.size()), levels);
        EXPECT_EQ(int(d->width), f.width);
        EXPECT_EQ(int(d->height), f.height);
    }

    // 'Plain' (roughnessFactor 0.5, no map) got a map of its own: factor 1, G the roughness.
    const OrderedJson& plain = glb.json["materials"][2];
    EXPECT_EQ(plain["normalTexture"], in["materials"][2]["normalTexture"]);
    EXPECT_EQ(plain["pbrMetallicRoughness"]["roughnessFactor"], 1.0);
    EXPECT_EQ(plain["pbrMetallicRoughness"]["metallicFactor"], 0);
    const size_t made =
        plain["pbrMetallicRoughness"]["metallicRoughnessTexture"]["index"].get<size_t>();
    EXPECT_EQ(made, 2u);
    EXPECT_EQ(glb.json["textures"][made]["sampler"], 0);
    const Dds plainDds = textureDds(glb, made);
    ASSERT_EQ(int(plainDds.levels.size()), levels);

    // Independent: bake with the same roughness (G times the factor, 16-bit) and read each
    // level's roughness_ggx alpha. The DDS holds sqrt(alpha) / factor, at most 1, in G.
    const float factor = 0.9f;
    Image reference = materialMap(f.width, f.height);
    Image scaled(f.width, f.height, 1);
    for (size_t i = 0; i < scaled.texelCount(); ++i)
        scaled.pixels[i] = std::round(reference.pixels[3 * i + 1] * 255.f) / 255.f * factor;
    ASSERT_TRUE(savePng(f.dir.file("roughness16.png"), scaled, 16));
    test::writeBytes(f.dir.path / "normal_copy.png", f.normalPng);
    const std::string bake = f.dir.file("wall.bake"), plainBake = f.dir.file("plain.bake");
    ASSERT_EQ(test::runCli("bake " + test::shellArg(f.dir.file("normal_copy.png")) +
                               " --method toksvig -q --roughness-map " +
                               test::shellArg(f.dir.file("roughness16.png")) + " -o " +
                               test::shellArg(bake),
                           &output),
              0)
        << output;
    ASSERT_EQ(test::runCli("bake " + test::shellArg(f.dir.file("normal_copy.png")) +
                               " --method toksvig -q --base-roughness 0.25 -o " +
                               test::shellArg(plainBake),
                           &output),
              0)
        << output;
    double worstWall = 0.0, worstPlain = 0.0, worstMetallic = 0.0, worstOcclusion = 0.0;
    size_t clamped = 0;
    for (int k = 0; k < levels; ++k) {
        Result<SourceImage> alpha =
            loadImage(bake + "/roughness_ggx_L" + std::to_string(k) + ".exr");
        Result<SourceImage> plainAlpha =
            loadImage(plainBake + "/roughness_ggx_L" + std::to_string(k) + ".exr");
        ASSERT_TRUE(alpha && plainAlpha);
        const Image& a = alpha->image;
        const std::string& wall = material.levels[size_t(k)];
        const std::string& own = plainDds.levels[size_t(k)];
        ASSERT_EQ(wall.size(), a.texelCount() * 4);
        for (int y = 0; y < a.height; ++y)
            for (int x = 0; x < a.width; ++x) {
                const size_t i = size_t(y) * size_t(a.width) + size_t(x);
                const double expected = std::sqrt(double(a.pixels[i])) / factor;
                clamped += expected > 1.0;
                worstWall = std::max(worstWall, std::abs(std::min(expected, 1.0) -
                                                         (unsigned char)wall[4 * i + 1] / 255.0));
                worstPlain = std::max(
                    worstPlain,
                    std::abs(std::min(std::sqrt(double(plainAlpha->image.pixels[i])), 1.0) -
                             (unsigned char)own[4 * i + 1] / 255.0));
                // Metallic (B) and occlusion (R): the mean of the 8-bit texels under the footprint.
                const Footprint fp = footprintOf(f.width, f.height, k, x, y);
                double metallic = 0.0, occlusion = 0.0;
                for (int v = fp.y0; v < fp.y1; ++v)
                    for (int u = fp.x0; u < fp.x1; ++u) {
                        metallic += std::round(reference.at(u, v)[2] * 255.0) / 255.0;
                        occlusion += std::round(reference.at(u, v)[0] * 255.0) / 255.0;
                    }
                worstMetallic =
                    std::max(worstMetallic, std::abs(metallic / double(fp.count()) -
                                                     (unsigned char)wall[4 * i + 2] / 255.0));
                worstOcclusion =
                    std::max(worstOcclusion, std::abs(occlusion / double(fp.count()) -
                                                      (unsigned char)wall[4 * i] / 255.0));
                // 'Plain' had no map: R, B and A are 1.
                EXPECT_EQ((unsigned char)own[4 * i], 255);
                EXPECT_EQ((unsigned char)own[4 * i + 2], 255);
            }
    }
    std::printf("%dx%d, %d levels: roughness max error %.5f (Wall, factor 0.9; %zu texels "
                "clamped), %.5f (Plain); "
                "metallic %.5f, occlusion %.5f\n",
                f.width, f.height, levels, worstWall, clamped, worstPlain, worstMetallic,
                worstOcclusion);
    EXPECT_LE(worstWall, 1.0 / 255.0);
    EXPECT_LE(worstPlain, 1.0 / 255.0);
    EXPECT_LE(worstMetallic, 1.0 / 255.0);
    EXPECT_LE(worstOcclusion, 1.0 / 255.0);
    // The made map's core PNG is its level 0: what loaders without the extension draw (G = 0.5
    // with the factor now 1: the material as before).
    Result<SourceImage> core = decodeImage(
        test::glbImage(glb, glb.json["textures"][made]["source"].get<size_t>()), "made");
    ASSERT_TRUE(core) << core.error().message;
    EXPECT_NEAR(core->image.at(0, 0)[1], 0.5f, 0.5f / 255.f + 1e-6f);
}

TEST(GltfCli, GgxFitWritesTheFittedRoughnessOfEachMaterial) {
    // Each material's G levels are the ggx-fit bake's alpha with the material's roughness per
    // texel: 'Wall' its map (G times the factor 0.9), 'Plain' its factor 0.5 (alpha 0.25).
    Fixture f;
    const std::string fit = f.dir.file("fit.glb"), toksvig = f.dir.file("toksvig.glb");
    std::string output;
    ASSERT_EQ(test::runCli("gltf " + test::shellArg(f.gltf) + " -o " + test::shellArg(fit) +
                               " -q --method ggx-fit" + kDds,
                           &output),
              0)
        << output;
    ASSERT_EQ(test::runCli("gltf " + test::shellArg(f.gltf) + " -o " + test::shellArg(toksvig) +
                               " -q" + kDds,
                           &output),
              0)
        << output;
    const test::Glb glb = test::parseGlb(test::fileBytes(fit));
    const test::Glb reference = test::parseGlb(test::fileBytes(toksvig));
    ASSERT_TRUE(glb.ok && reference.ok);

    const float factor = 0.9f;
    Image material = materialMap(f.width, f.height);
    Image scaled(f.width, f.height, 1);
    for (size_t i = 0; i < scaled.texelCount(); ++i)
        scaled.pixels[i] = std::round(material.pixels[3 * i + 1] * 255.f) / 255.f * factor;
    ASSERT_TRUE(savePng(f.dir.file("roughness16.png"), scaled, 16));
    test::writeBytes(f.dir.path / "normal_copy.png", f.normalPng);
    const std::string wallBake = f.dir.file("wall.bake"), plainBake = f.dir.file("plain.bake");
    const std::string normal = test::shellArg(f.dir.file("normal_copy.png"));
    ASSERT_EQ(test::runCli("bake " + normal + " --method ggx-fit -q --roughness-map " +
                               test::shellArg(f.dir.file("roughness16.png")) + " -o " +
                               test::shellArg(wallBake),
                           &output),
              0)
        << output;
    ASSERT_EQ(test::runCli("bake " + normal + " --method ggx-fit -q --base-roughness 0.25 -o " +
                               test::shellArg(plainBake),
                           &output),
              0)
        << output;
    const size_t made =
        glb.json["materials"][2]["pbrMetallicRoughness"]["metallicRoughnessTexture"]["index"]
            .get<size_t>();
    struct Check {
        size_t texture;
        std::string bake;
        float factor;
    };
    for (const Check& c : {Check{1, wallBake, factor}, Check{made, plainBake, 1.f}}) {
        SCOPED_TRACE(c.bake);
        const Dds mine = textureDds(glb, c.texture), toksvigs = textureDds(reference, c.texture);
        double worst = 0.0;
        size_t off = 0, texels = 0;
        bool differs = false;
        for (size_t k = 0; k < mine.levels.size(); ++k) {
            Result<SourceImage> alpha =
                loadImage(c.bake + "/roughness_ggx_L" + std::to_string(k) + ".exr");
            ASSERT_TRUE(alpha);
            const Image& a = alpha->image;
            ASSERT_EQ(mine.levels[k].size(), a.texelCount() * 4);
            for (size_t i = 0; i < a.texelCount(); ++i) {
                const double g = (unsigned char)mine.levels[k][4 * i + 1] / 255.0;
                const double expected = std::min(std::sqrt(double(a.pixels[i])) / c.factor, 1.0);
                worst = std::max(worst, std::abs(expected - g));
                off += std::abs(expected - g) > 1.0 / 255.0 + 1e-6;
                ++texels;
                differs |= mine.levels[k][4 * i + 1] != toksvigs.levels[k][4 * i + 1];
            }
        }
        std::printf("%s: %zu of %zu texels more than 1/255 off (worst %.4f)\n", c.bake.c_str(), off,
                    texels, worst);
        // The reference reads the roughness from a 16-bit PNG, the filter from the 8-bit map
        // times the factor: measured 1 texel of 739450 off (0.18) where the map nears alpha 0.01
        // and the fit has two minima, a narrow and a wide lobe, that the difference tips.
        EXPECT_LE(off, texels / 100000) << "worst " << worst;
        EXPECT_TRUE(differs) << "the fit should differ from Toksvig's rule somewhere";
    }
}

TEST(GltfCli, GlbInputPassesTheKhronosValidator) {
    Fixture f;
    const std::string input = test::writeGlb(
        f.dir.path / "in.glb", f.asset, {{"image/png", f.normalPng}, {"image/png", f.materialPng}});
    const std::string out = f.dir.file("out.glb");
    std::string output;
    ASSERT_EQ(
        test::runCli("gltf " + test::shellArg(input) + " -o " + test::shellArg(out) + " -q" + kDds,
                     &output),
        0)
        << output;
    EXPECT_EQ(output, "");
    const test::Glb glb = test::parseGlb(test::fileBytes(out));
    ASSERT_TRUE(glb.ok);
    EXPECT_EQ(test::glbImage(glb, 0), f.normalPng);
    EXPECT_EQ(test::glbImage(glb, 1), f.materialPng);
    EXPECT_EQ(int(textureDds(glb, 0).levels.size()), levelCount(f.width, f.height));

    const std::string before = validatorReport(f.dir, input);
    if (before.empty())
        GTEST_SKIP() << "node and the npm package gltf-validator (scripts/setup installs it into "
                        ".npm) not found";
    const std::string after = validatorReport(f.dir, out);
    std::printf("validator, input: %s\nvalidator, output: %s\n", before.c_str(), after.c_str());
    const OrderedJson report = OrderedJson::parse(after), original = OrderedJson::parse(before);
    EXPECT_EQ(report["errors"], 0) << after;
    EXPECT_EQ(original["errors"], 0) << before;
    // Beyond the test asset's own notes (an unused node, non-power-of-two images), only what the
    // validator does not know: the vendor extension, the DDS mimeType and format, and so the DDS
    // images as unused.
    std::set<std::string> known{"UNSUPPORTED_EXTENSION", "VALUE_NOT_IN_LIST",
                                "IMAGE_UNRECOGNIZED_FORMAT", "UNUSED_OBJECT"};
    for (const OrderedJson& code : original["codes"])
        known.insert(code.get<std::string>().substr(0, code.get<std::string>().find(' ')));
    for (const OrderedJson& code : report["codes"]) {
        const std::string c = code.get<std::string>();
        EXPECT_TRUE(known.count(c.substr(0, c.find(' ')))) << c;
    }
}

TEST(GltfCli, BadInputIsRefusedWithOneLineAndNoOutput) {
    Fixture f;
    const std::string out = f.dir.file("out.glb");
    auto refuses = [&](const std::string& input, std::initializer_list<std::string> mentions,
                       const std::string& extra = "") {
        test::expectCliRefuses(
            "gltf " + test::shellArg(input) + " -o " + test::shellArg(out) + extra, mentions);
        EXPECT_FALSE(fs::exists(out)) << input;
        EXPECT_TRUE(test::leftovers(f.dir.path).empty()) << input;
    };
    auto variant = [&](const std::string& name, const std::function<void(test::TestAsset&)>& change,
                       const std::string& normal, const std::string& material) {
        const fs::path folder = f.dir.path / name;
        fs::create_directories(folder);
        test::TestAsset a = f.asset;
        change(a);
        return test::writeGltf(folder, a, {{"normal.png", normal}, {"orm.png", material}});
    };
    const auto same = [](test::TestAsset&) {};

    // Not glTF at all.
    test::writeBytes(f.dir.path / "garbage.gltf", "{\"asset\": [");
    refuses(f.dir.file("garbage.gltf"), {"garbage.gltf"});
    // The normal image missing, undecodable, one channel, or colours rather than normals.
    const std::string missing = variant("missing", same, f.normalPng, f.materialPng);
    fs::remove(fs::path(missing).parent_path() / "normal.png");
    refuses(missing, {"quad.gltf", "normal.png"});
    refuses(variant("undecodable", same, "\x89PNG\r\n\x1a\n but nothing after", f.materialPng),
            {"quad.gltf", "normalTexture", "normal.png"});
    refuses(variant("grey", same, encodePng(Image(f.width, f.height, 1), 8).value(), f.materialPng),
            {"quad.gltf", "normalTexture", "1 channel(s)"});
    // Colours: (0.9, 0.2, 0.4) decodes to unit vectors facing into the surface, (0.6, 0.5, 0.55)
    // to vectors of length 0.22.
    for (const auto& [name, rgb, problem] :
         {std::tuple{"into", glm::vec3(0.9f, 0.2f, 0.4f), "into the surface"},
          std::tuple{"short", glm::vec3(0.6f, 0.5f, 0.55f), "off unit length"}}) {
        Image colour(f.width, f.height, 3);
        for (size_t i = 0; i < colour.texelCount(); ++i)
            for (int c = 0; c < 3; ++c) colour.pixels[3 * i + size_t(c)] = rgb[c];
        refuses(variant(name, same, encodePng(colour, 8).value(), f.materialPng),
                {"quad.gltf", "Wall", problem, "normal map"});
    }
    // A metallic-roughness image of another size: both sizes named.
    const std::string small = encodePng(materialMap(64, 32), 8).value();
    refuses(variant("size", same, f.normalPng, small),
            {"quad.gltf", "orm.png", "64x32",
             std::to_string(f.width) + "x" + std::to_string(f.height)});
    // Texture coordinates that do not line up.
    refuses(variant(
                "texcoord",
                [](test::TestAsset& a) { a.json["materials"][0]["normalTexture"]["texCoord"] = 1; },
                f.normalPng, f.materialPng),
            {"quad.gltf", "TEXCOORD_1"});
    // Nothing to correct.
    refuses(variant(
                "plain",
                [](test::TestAsset& a) {
                    a.json["materials"][0].erase("normalTexture");
                    a.json["materials"][2].erase("normalTexture");
                },
                f.normalPng, f.materialPng),
            {"quad.gltf", "nothing to correct"});
    // An engine other than glTF, an output that is no .glb, an output folder that is missing.
    refuses(f.gltf, {"--engine", "unity"}, " --engine unity");
    test::expectCliRefuses("gltf " + test::shellArg(f.gltf) + " -o " +
                               test::shellArg(f.dir.file("out.gltf")),
                           {"out.gltf", ".glb"});
    EXPECT_FALSE(fs::exists(f.dir.file("out.gltf")));
    const std::string nowhere = f.dir.file("no/such/folder/out.glb");
    test::expectCliRefuses("gltf " + test::shellArg(f.gltf) + " -o " + test::shellArg(nowhere),
                           {"out.glb"});
    EXPECT_FALSE(fs::exists(nowhere));
    EXPECT_TRUE(test::leftovers(f.dir.path).empty());
}

// Buffer and image uris outside the asset's folder are refused, naming the asset and the uri,
// unless --allow-outside is given.
TEST(GltfCli, UrisOutsideTheFolderNeedAllowOutside) {
    Fixture f;
    const fs::path folder = f.dir.path / "asset";
    fs::create_directories(folder);
    test::TestAsset a = f.asset;
    a.json["buffers"][0]["uri"] = "../quad.bin";
    a.json["images"][0]["uri"] = "../normal.png";
    a.json["images"][1]["uri"] = "../orm.png";
    const std::string input = (folder / "outside.gltf").string();
    test::writeBytes(input, a.json.dump());
    const std::string out = f.dir.file("out.glb");
    test::expectCliRefuses("gltf " + test::shellArg(input) + " -o " + test::shellArg(out),
                           {"outside.gltf", "buffer 0 '../quad.bin'", "--allow-outside"});
    EXPECT_FALSE(fs::exists(out));
    std::string output;
    ASSERT_EQ(test::runCli("gltf " + test::shellArg(input) + " -o " + test::shellArg(out) +
                               " --allow-outside -q" + kDds,
                           &output),
              0)
        << output;
    const test::Glb glb = test::parseGlb(test::fileBytes(out));
    ASSERT_TRUE(glb.ok);
    EXPECT_EQ(test::glbImage(glb, 0), f.normalPng);
}

// ndfmip gltf on its own output replaces its images: the same size, the same image count.
TEST(GltfCli, RerunOnItsOwnOutputKeepsItsSize) {
    Fixture f;
    const std::string first = f.dir.file("first.glb"), second = f.dir.file("second.glb");
    std::string output;
    ASSERT_EQ(test::runCli("gltf " + test::shellArg(f.gltf) + " -o " + test::shellArg(first) +
                               " -q" + kDds,
                           &output),
              0)
        << output;
    ASSERT_EQ(test::runCli("gltf " + test::shellArg(first) + " -o " + test::shellArg(second) + kDds,
                           &output),
              0)
        << output;
    EXPECT_NE(output.find("4 images of an earlier ndfmip gltf replaced"), std::string::npos)
        << output;
    const std::string a = test::fileBytes(first), b = test::fileBytes(second);
    EXPECT_LE(std::abs(double(b.size()) - double(a.size())), 0.01 * double(a.size()));
    const test::Glb ga = test::parseGlb(a), gb = test::parseGlb(b);
    ASSERT_TRUE(ga.ok && gb.ok);
    EXPECT_EQ(gb.json["images"].size(), ga.json["images"].size());
    EXPECT_EQ(gb.json["bufferViews"].size(), ga.json["bufferViews"].size());
    EXPECT_EQ(gb.json["materials"], ga.json["materials"]);
}

// The quad asset with stripes whose normals alternate column by column between +-20 degrees about
// y (tilted along x) as its normal map, 64 x 64 8-bit, and an ORM map of roughness G 77/255.
struct StripesQuad {
    static constexpr int kSize = 64;
    std::string gltf;
    Image decoded; // the normals as the 8-bit file holds them
};

// The quad with its normal map's normals `normalAt(x, y)` (unit, as the 8-bit file holds them).
StripesQuad quadWithNormals(const test::TempDir& dir,
                            const std::function<glm::vec3(int, int)>& normalAt) {
    const int size = StripesQuad::kSize;
    Image normals(size, size, 3);
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x)
            for (int c = 0; c < 3; ++c) // as a file holds it: (n + 1)/2
                normals.at(x, y)[c] = 0.5f * (normalAt(x, y)[c] + 1.f);
    Image orm(size, size, 3);
    for (size_t i = 0; i < orm.texelCount(); ++i)
        orm.pixels[3 * i] = 1.f, orm.pixels[3 * i + 1] = 77.f / 255.f, orm.pixels[3 * i + 2] = 0.f;
    StripesQuad out;
    const std::string normalPng = encodePng(normals, 8).value();
    Result<SourceImage> source = decodeImage(normalPng, "stripes");
    out.decoded = decodeNormalMap(source.value(), DecodeOptions{}, "stripes", nullptr).value();
    out.gltf = test::writeGltf(dir.path, test::quadAsset(),
                               {{"normal.png", normalPng}, {"orm.png", encodePng(orm, 8).value()}});
    return out;
}

// Columns alternating between +-20 degrees about y (tilted along x).
StripesQuad stripesQuad(const test::TempDir& dir) {
    const float tilt = glm::radians(20.f);
    return quadWithNormals(dir, [tilt](int x, int) {
        return glm::vec3((x % 2 ? -1.f : 1.f) * std::sin(tilt), 0.f, std::cos(tilt));
    });
}

// --method sggx on stripes whose normals alternate column by column between +-20 degrees about
// y (tilted along x): from level 1 every texel's footprint holds both, so the slopes' variance
// along x is tan^2(20 degrees) and the lobe is KHR_materials_anisotropy's with its axis on x:
// alpha_t^2 = alpha^2 + 2 tan^2, alpha_b = alpha, strength s^2 = (alpha_t - alpha_b) / (1 -
// alpha_b). Level 0 has no spread: strength 0. The asset passes the Khronos validator and a
// rerun replaces ndfmip's images and extension.
TEST(GltfCli, SggxWritesKhrMaterialsAnisotropyWithTheStripesAxis) {
    test::TempDir dir{"gltf_sggx"};
    const int size = StripesQuad::kSize;
    const StripesQuad quad = stripesQuad(dir);
    const std::string& gltf = quad.gltf;
    // The slope as the 8-bit file holds it.
    const float slope = quad.decoded.at(0, 0)[0] / quad.decoded.at(0, 0)[2];
    const std::string out = dir.file("out.glb");
    std::string output;
    ASSERT_EQ(test::runCli("gltf " + test::shellArg(gltf) + " -o " + test::shellArg(out) +
                               " -q --method sggx" + kDds,
                           &output),
              0)
        << output;
    const test::Glb glb = test::parseGlb(test::fileBytes(out));
    ASSERT_TRUE(glb.ok);
    EXPECT_NE(std::find(glb.json["extensionsUsed"].begin(), glb.json["extensionsUsed"].end(),
                        "KHR_materials_anisotropy"),
              glb.json["extensionsUsed"].end());
    // Wall: G 77/255 times roughnessFactor 0.9; Plain: no map, roughnessFactor 0.5.
    const std::vector<std::pair<size_t, float>> materials = {{0, 77.f / 255.f * 0.9f}, {2, 0.5f}};
    for (const auto& [m, perceptual] : materials) {
        const OrderedJson& material = glb.json["materials"][m];
        SCOPED_TRACE(material["name"].get<std::string>());
        ASSERT_TRUE(material["extensions"].contains("KHR_materials_anisotropy")) << material;
        const OrderedJson& extension = material["extensions"]["KHR_materials_anisotropy"];
        EXPECT_EQ(extension["anisotropyStrength"], 1.0);
        const Dds anisotropy =
            textureDds(glb, extension["anisotropyTexture"]["index"].get<size_t>());
        ASSERT_EQ(anisotropy.dxgi, kDxgiRgba8);
        ASSERT_EQ(int(anisotropy.levels.size()), levelCount(size, size));
        const Dds roughness = textureDds(
            glb,
            material["pbrMetallicRoughness"]["metallicRoughnessTexture"]["index"].get<size_t>());
        const double alpha = double(perceptual) * double(perceptual);
        const double alphaT = std::sqrt(alpha * alpha + 2.0 * double(slope) * double(slope));
        const double strength = std::sqrt((alphaT - alpha) / (1.0 - alpha));
        // G holds sqrt(alpha_b) over the factor: the map's own value for Wall, 1 for Plain's
        // made map (roughnessFactor becomes 1 and G carries 0.5).
        const double g = m == 0 ? 77.0 : 0.5 * 255.0;
        for (size_t k = 0; k < 3; ++k) {
            const auto* a = reinterpret_cast<const unsigned char*>(anisotropy.levels[k].data());
            const auto* r = reinterpret_cast<const unsigned char*>(roughness.levels[k].data());
            EXPECT_EQ(int(a[0]), 255) << "level " << k; // direction x: (1 + 1)/2
            EXPECT_NEAR(double(a[1]), 127.5, 0.6) << "level " << k;
            EXPECT_NEAR(double(a[2]), k == 0 ? 0.0 : 255.0 * strength, 1.01) << "level " << k;
            EXPECT_NEAR(double(r[1]), g, 1.01) << "level " << k;
        }
    }

    const std::string report = validatorReport(dir, out);
    if (!report.empty()) {
        const OrderedJson counts = OrderedJson::parse(report);
        EXPECT_EQ(counts["errors"], 0) << report;
        for (const OrderedJson& code : counts["codes"])
            EXPECT_EQ(code.get<std::string>().find("KHR_materials_anisotropy"), std::string::npos)
                << code;
    }

    const std::string again = dir.file("again.glb");
    ASSERT_EQ(test::runCli("gltf " + test::shellArg(out) + " -o " + test::shellArg(again) +
                               " -q --method sggx" + kDds,
                           &output),
              0)
        << output;
    const test::Glb second = test::parseGlb(test::fileBytes(again));
    ASSERT_TRUE(second.ok);
    EXPECT_EQ(second.json["images"].size(), glb.json["images"].size());
    EXPECT_EQ(second.json["materials"], glb.json["materials"]);
    // Back to toksvig: the extension leaves with ndfmip's images.
    ASSERT_EQ(
        test::runCli("gltf " + test::shellArg(out) + " -o " + test::shellArg(again) + " -q" + kDds,
                     &output),
        0)
        << output;
    const test::Glb plain = test::parseGlb(test::fileBytes(again));
    ASSERT_TRUE(plain.ok);
    for (const OrderedJson& material : plain.json["materials"])
        EXPECT_FALSE(material.contains("extensions") &&
                     material["extensions"].contains("KHR_materials_anisotropy"));
    const OrderedJson& used = plain.json["extensionsUsed"];
    EXPECT_EQ(std::find(used.begin(), used.end(), "KHR_materials_anisotropy"), used.end());
}

// --method ggx-aniso on the same stripes: each level's KHR_materials_anisotropy holds the lobe
// bake --method ggx-aniso fits (the material's alpha, level by level), its axis on x; level 0 is
// the material's own lobe (strength 0). The asset passes the Khronos validator.
TEST(GltfCli, GgxAnisoWritesItsFittedLobeAsKhrMaterialsAnisotropy) {
    test::TempDir dir{"gltf_ggx_aniso"};
    const int size = StripesQuad::kSize;
    const StripesQuad quad = stripesQuad(dir);
    const std::string& gltf = quad.gltf;
    const Image& decoded = quad.decoded;
    const std::string out = dir.file("out.glb");
    std::string output;
    ASSERT_EQ(test::runCli("gltf " + test::shellArg(gltf) + " -o " + test::shellArg(out) +
                               " -q --method ggx-aniso" + kDds,
                           &output),
              0)
        << output;
    const test::Glb glb = test::parseGlb(test::fileBytes(out));
    ASSERT_TRUE(glb.ok);
    const Pyramid pyramid = buildPyramid(decoded);
    // Wall: G 77/255 times roughnessFactor 0.9; Plain: no map, roughnessFactor 0.5.
    const std::vector<std::pair<size_t, float>> materials = {{0, 77.f / 255.f * 0.9f}, {2, 0.5f}};
    for (const auto& [m, perceptual] : materials) {
        const OrderedJson& material = glb.json["materials"][m];
        SCOPED_TRACE(material["name"].get<std::string>());
        ASSERT_TRUE(material["extensions"].contains("KHR_materials_anisotropy")) << material;
        const OrderedJson& extension = material["extensions"]["KHR_materials_anisotropy"];
        const Dds anisotropy =
            textureDds(glb, extension["anisotropyTexture"]["index"].get<size_t>());
        ASSERT_EQ(int(anisotropy.levels.size()), levelCount(size, size));
        const Dds roughness = textureDds(
            glb,
            material["pbrMetallicRoughness"]["metallicRoughnessTexture"]["index"].get<size_t>());
        BakeOptions options;
        options.baseRoughness = perceptual * perceptual;
        const Bake bake = bakeGgxAniso(pyramid, options);
        // G over the factor: Wall's 0.9, 1 for Plain's made map.
        const double factor = m == 0 ? 0.9 : 1.0;
        for (size_t k = 0; k < 3; ++k) {
            const KhrAnisotropy lobe = khrAnisotropy(anisotropicLobeOfGgxAniso(
                bake.levels[k][1]->at(0, 0), bake.levels[k][0]->at(0, 0)));
            const auto* a = reinterpret_cast<const unsigned char*>(anisotropy.levels[k].data());
            const auto* r = reinterpret_cast<const unsigned char*>(roughness.levels[k].data());
            if (k > 0) {
                EXPECT_EQ(int(a[0]), 255) << "level " << k; // direction x: (1 + 1)/2
                EXPECT_NEAR(double(a[1]), 127.5, 0.6) << "level " << k;
                EXPECT_GT(double(a[2]), 100.0) << "level " << k; // the stripes' spread
            }
            EXPECT_NEAR(double(a[2]), 255.0 * lobe.strength, 1.01) << "level " << k;
            EXPECT_NEAR(double(r[1]), 255.0 * lobe.roughness / factor, 1.01) << "level " << k;
        }
    }
    const std::string report = validatorReport(dir, out);
    if (!report.empty()) {
        const OrderedJson counts = OrderedJson::parse(report);
        EXPECT_EQ(counts["errors"], 0) << report;
    }
}

// test::blocksAcrossTheVertical: level 1's lobes lie near the y axis, each neighbour on the other
// side of it. The anisotropyTexture signs their directions alike (coherentDirections), so a
// sampler's blend of two neighbours turns between them instead of reading along x.
TEST(GltfCli, AnisotropyDirectionsAgreeBetweenNeighboursAcrossTheVertical) {
    test::TempDir dir{"gltf_aniso_signs"};
    const Image blocks = test::blocksAcrossTheVertical(StripesQuad::kSize);
    const StripesQuad quad = quadWithNormals(dir, [&](int x, int y) {
        const float* n = blocks.at(x, y);
        return glm::vec3(n[0], n[1], n[2]);
    });
    for (const std::string method : {"ggx-aniso", "sggx"}) {
        const std::string out = dir.file(method + ".glb");
        std::string output;
        ASSERT_EQ(test::runCli("gltf " + test::shellArg(quad.gltf) + " -o " + test::shellArg(out) +
                                   " -q --method " + method + kDds,
                               &output),
                  0)
            << output;
        const test::Glb glb = test::parseGlb(test::fileBytes(out));
        ASSERT_TRUE(glb.ok);
        const OrderedJson& extension =
            glb.json["materials"][0]["extensions"]["KHR_materials_anisotropy"];
        const Dds anisotropy =
            textureDds(glb, extension["anisotropyTexture"]["index"].get<size_t>());
        ASSERT_GT(anisotropy.levels.size(), 1u);
        const int side = StripesQuad::kSize / 2;
        const auto* a = reinterpret_cast<const unsigned char*>(anisotropy.levels[1].data());
        ASSERT_EQ(anisotropy.levels[1].size(), size_t(4 * side * side));
        auto direction = [&](int x, int y) {
            const size_t i = 4 * size_t(y * side + x);
            return glm::normalize(
                glm::vec2(2.f * float(a[i]) / 255.f - 1.f, 2.f * float(a[i + 1]) / 255.f - 1.f));
        };
        for (int y = 0; y < side; ++y)
            for (int x = 0; x + 1 < side; ++x) {
                EXPECT_GT(std::abs(direction(x, y).y), 0.99f) << method << " " << x << "," << y;
                EXPECT_GT(glm::dot(direction(x, y), direction(x + 1, y)), 0.95f)
                    << method << " " << x << "," << y;
                EXPECT_GT(glm::dot(direction(y, x), direction(y, x + 1)), 0.95f)
                    << method << " " << y << "," << x;
            }
    }
}

} // namespace
} // namespace ndfmip
