// UASTC KTX2 made of ndfmip's own levels by npm's Basis Universal encoder: read back by
// ndfmip's reader and by ktx-parse, every level decoded back by the encoder's own transcoder
// and compared with ndfmip's; bake --normal-format uastc and ndfmip gltf's KHR_texture_basisu
// (checked by the Khronos validator); a missing or failing encoder refused in one line. What
// needs the encoder, node or the npm packages skips where scripts/setup did not install them.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <sys/wait.h>

#include <gtest/gtest.h>

#include "gltf_test_asset.h"
#include "ndfmip/io.h"
#include "ndfmip/pyramid.h"
#include "ndfmip/texture_container.h"
#include "test_support.h"

namespace ndfmip {
namespace {

namespace fs = std::filesystem;
using test::OrderedJson;

const std::string kMap = std::string(NDFMIP_SOURCE_DIR) + "/data/normalmaps/pyramidwall_256.png";

#define SKIP_WITHOUT_ENCODER()                                                                     \
    if (!basisuEncoder()) GTEST_SKIP() << basisuEncoder().error().message

// Sets an environment variable for one test, restoring it after.
struct ScopedEnv {
    std::string name;
    std::string old;
    bool had = false;
    ScopedEnv(const std::string& n, const std::string& value) : name(n) {
        if (const char* v = std::getenv(n.c_str())) had = true, old = v;
        setenv(n.c_str(), value.c_str(), 1);
    }
    ~ScopedEnv() {
        if (had)
            setenv(name.c_str(), old.c_str(), 1);
        else
            unsetenv(name.c_str());
    }
};

uint32_t u32(const std::string& bytes, size_t at) {
    uint32_t v = 0;
    std::memcpy(&v, bytes.data() + at, 4);
    return v;
}

// Smooth RGB levels of a non-square, odd-sized texture, each its own pattern (so a level taken
// from the wrong place shows).
std::vector<Image> patternLevels(int width, int height) {
    std::vector<Image> levels;
    for (int k = 0; k < levelCount(width, height); ++k) {
        Image level(std::max(width >> k, 1), std::max(height >> k, 1), 3);
        for (int y = 0; y < level.height; ++y)
            for (int x = 0; x < level.width; ++x) {
                float* p = level.at(x, y);
                p[0] = 0.5f + 0.3f * std::sin(0.11f * float(x) + float(k));
                p[1] = 0.5f + 0.3f * std::cos(0.07f * float(y) - float(k));
                p[2] = 0.2f + 0.06f * float(k);
            }
        levels.push_back(std::move(level));
    }
    return levels;
}

std::vector<const Image*> pointers(const std::vector<Image>& levels) {
    std::vector<const Image*> out;
    for (const Image& l : levels) out.push_back(&l);
    return out;
}

uint64_t uastcBytes(int w, int h) {
    return uint64_t((w + 3) / 4) * uint64_t((h + 3) / 4) * 16;
}

// The npm package ktx-parse's ES module, or "" where node or the package is missing.
std::string ktxParseModule() {
    const char* modules = std::getenv("NDFMIP_NODE_MODULES");
    const std::string path =
        modules ? modules : std::string(NDFMIP_SOURCE_DIR) + "/.npm/node_modules";
    if (!fs::exists("/usr/bin/node")) return "";
    for (const char* candidate :
         {"/ktx-parse/dist/ktx-parse.modern.js", "/ktx-parse/dist/index.mjs"})
        if (fs::exists(path + candidate)) return path + candidate;
    return "";
}

// What ktx-parse reads of a KTX2 file: format, size, levels, scheme, colour model, transfer.
std::string ktxParse(const test::TempDir& dir, const std::string& module, const std::string& file) {
    const std::string script = dir.file("read.mjs"), out = dir.file("ktx_parse.json");
    test::writeBytes(
        script,
        "import { read } from '" + module +
            "';\nimport { readFileSync } from 'fs';\n"
            "const c = read(new Uint8Array(readFileSync(process.argv[2])));\n"
            "const d = c.dataFormatDescriptor[0];\n"
            "console.log(JSON.stringify({format: c.vkFormat, w: c.pixelWidth, h: c.pixelHeight, "
            "levels: c.levels.map(l => l.uncompressedByteLength), scheme: "
            "c.supercompressionScheme, "
            "model: d.colorModel, transfer: d.transferFunction, writer: "
            "c.keyValue.KTXwriter}));\n");
    const int status = std::system(("node " + test::shellArg(script) + " " + test::shellArg(file) +
                                    " > " + test::shellArg(out) + " 2>&1")
                                       .c_str());
    return status == 0 ? test::fileBytes(out) : "node failed: " + test::fileBytes(out);
}

// The encoder's transcoder (basisu -unpack) decodes every level of `file` to PNGs (via BC7,
// which UASTC transcodes to nearly losslessly); each is compared with the level it was made of.
void expectLevelsDecodeBack(const test::TempDir& dir, const std::string& file,
                            const std::vector<Image>& levels) {
    const std::string encoder = basisuEncoder().value();
    const fs::path unpacked = dir.path / "unpacked";
    fs::create_directories(unpacked);
    const std::string command = "cd " + test::shellArg(unpacked.string()) + " && " +
                                test::shellArg(encoder) + " -unpack -no_ktx -file " +
                                test::shellArg(file) + " > unpack.log 2>&1";
    ASSERT_EQ(std::system(command.c_str()), 0) << test::fileBytes(unpacked / "unpack.log");
    const std::string stem = fs::path(file).stem().string();
    for (size_t k = 0; k < levels.size(); ++k) {
        const fs::path png =
            unpacked / (stem + "_unpacked_rgb_BC7_RGBA_" + std::to_string(k) + "_0_0000.png");
        Result<SourceImage> decoded = loadImage(png.string());
        ASSERT_TRUE(decoded) << decoded.error().message;
        const Image& d = decoded->image;
        const Image& l = levels[k];
        ASSERT_EQ(d.width, l.width) << "level " << k;
        ASSERT_EQ(d.height, l.height) << "level " << k;
        double error = 0.0;
        for (int y = 0; y < l.height; ++y)
            for (int x = 0; x < l.width; ++x)
                for (int c = 0; c < 3; ++c)
                    error += std::abs(double(d.at(x, y)[c]) - double(l.at(x, y)[c]));
        error /= 3.0 * double(l.texelCount());
        EXPECT_LE(error, 3.0 / 255.0) << "level " << k << " (" << l.width << "x" << l.height << ")";
    }
}

TEST(Ktx2Uastc, EveryLevelIsNdfmipsReadBackAndDecoded) {
    SKIP_WITHOUT_ENCODER();
    test::TempDir dir("uastc");
    const std::vector<Image> levels = patternLevels(70, 36);
    ASSERT_EQ(levels.size(), 7u);
    Result<EncodedTexture> t = encodeTexture(pointers(levels), TextureFormat::Uastc);
    ASSERT_TRUE(t) << t.error().message;
    ASSERT_EQ(t->levels.size(), levels.size());
    for (size_t k = 0; k < levels.size(); ++k)
        EXPECT_EQ(t->levels[k].size(), uastcBytes(levels[k].width, levels[k].height))
            << "level " << k;
    Result<std::string> bytes = ktx2File(t.value(), 6, {{"ndfmip", "{\"content\":\"test\"}"}});
    ASSERT_TRUE(bytes) << bytes.error().message;
    const std::string file = dir.file("pattern.ktx2");
    test::writeBytes(file, bytes.value());

    // The header: VK_FORMAT_UNDEFINED, 7 levels, Zstandard; the encoder's UASTC descriptor with
    // linear transfer and bytesPlane0 0 (supercompressed).
    const std::string& b = bytes.value();
    EXPECT_EQ(u32(b, 12), 0u);  // vkFormat
    EXPECT_EQ(u32(b, 16), 1u);  // typeSize
    EXPECT_EQ(u32(b, 20), 70u); // width
    EXPECT_EQ(u32(b, 24), 36u); // height
    EXPECT_EQ(u32(b, 40), 7u);  // levelCount
    EXPECT_EQ(u32(b, 44), 2u);  // Zstandard
    const size_t dfd = u32(b, 48);
    EXPECT_EQ(uint8_t(b[dfd + 12]), 166); // KHR_DF_MODEL_UASTC
    EXPECT_EQ(uint8_t(b[dfd + 14]), 1);   // KHR_DF_TRANSFER_LINEAR
    EXPECT_EQ(uint8_t(b[dfd + 20]), 0);   // bytesPlane0

    // ndfmip's reader: the same levels, inflated.
    Result<EncodedTexture> back = readKtx2(b);
    ASSERT_TRUE(back) << back.error().message;
    EXPECT_EQ(back->format, TextureFormat::Uastc);
    EXPECT_EQ(back->width, 70);
    EXPECT_EQ(back->height, 36);
    EXPECT_EQ(back->levels, t->levels);
    Result<Ktx2KeyValues> keys = readKtx2KeyValues(b);
    ASSERT_TRUE(keys) << keys.error().message;
    EXPECT_EQ(keys->at("KTXwriter").rfind("ndfmip ", 0), 0u);
    EXPECT_EQ(keys->at("ndfmip"), "{\"content\":\"test\"}");

    // ktx-parse, a reader ndfmip did not write.
    if (const std::string module = ktxParseModule(); !module.empty()) {
        const std::string json = ktxParse(dir, module, file);
        std::string lengths;
        for (size_t k = 0; k < levels.size(); ++k)
            lengths +=
                (k ? "," : "") + std::to_string(uastcBytes(levels[k].width, levels[k].height));
        EXPECT_NE(json.find("\"format\":0,\"w\":70,\"h\":36,\"levels\":[" + lengths +
                            "],\"scheme\":2,\"model\":166,"
                            "\"transfer\":1"),
                  std::string::npos)
            << json;
        EXPECT_NE(json.find("\"writer\":\"ndfmip "), std::string::npos) << json;
    }
    expectLevelsDecodeBack(dir, file, levels);
}

TEST(Ktx2Uastc, MissingOrFailingEncoderIsOneLine) {
    const std::vector<Image> levels = patternLevels(8, 8);
    {
        const ScopedEnv env("NDFMIP_BASISU", "/nonexistent/basisu");
        Result<EncodedTexture> t = encodeTexture(pointers(levels), TextureFormat::Uastc);
        ASSERT_FALSE(t);
        EXPECT_NE(t.error().message.find("NDFMIP_BASISU=/nonexistent/basisu"), std::string::npos)
            << t.error().message;
        EXPECT_EQ(t.error().message.find('\n'), std::string::npos);
    }
    {
        const ScopedEnv env("NDFMIP_BASISU", "/bin/false");
        Result<EncodedTexture> t = encodeTexture(pointers(levels), TextureFormat::Uastc);
        ASSERT_FALSE(t);
        EXPECT_NE(t.error().message.find("/bin/false failed on the 8x8 level (exit 1)"),
                  std::string::npos)
            << t.error().message;
    }
    // An encoder that stalls (its job pool deadlocked: asleep, no CPU used) is stopped, tried
    // once more, and named in one line; one that works, however long, is left alone.
    {
        test::TempDir scripts("uastc_stall");
        auto script = [&](const std::string& name, const std::string& body) {
            const std::string path = scripts.file(name);
            std::ofstream(path) << "#!/bin/sh\n" << body << "\n";
            fs::permissions(path, fs::perms::owner_all);
            return path;
        };
        const std::string asleep = script("asleep", "exec sleep 600");
        const ScopedEnv stall("NDFMIP_BASISU_STALL_SECONDS", "1");
        {
            const ScopedEnv env("NDFMIP_BASISU", asleep);
            const auto start = std::chrono::steady_clock::now();
            Result<EncodedTexture> t = encodeTexture(pointers(levels), TextureFormat::Uastc);
            const double seconds =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            ASSERT_FALSE(t);
            EXPECT_NE(t.error().message.find(
                          "failed on the 8x8 level (it stalled twice, using no CPU for 1 s"),
                      std::string::npos)
                << t.error().message;
            EXPECT_EQ(t.error().message.find('\n'), std::string::npos);
            EXPECT_LT(seconds, 60) << "a stalled encoder is stopped, not waited for";
        }
        {
            // About 1.7 s of CPU in the shell's own loop per level, over the stall limit.
            const ScopedEnv env(
                "NDFMIP_BASISU",
                script("busy", "i=0; while [ $i -lt 2000000 ]; do i=$((i+1)); done; exit 3"));
            Result<EncodedTexture> t = encodeTexture(pointers(levels), TextureFormat::Uastc);
            ASSERT_FALSE(t);
            EXPECT_NE(t.error().message.find("failed on the 8x8 level (exit 3)"), std::string::npos)
                << t.error().message;
        }
    }
    // Through the CLI: one line, non-zero, no bake folder.
    test::TempDir dir("uastc_missing");
    const std::string out = dir.file("wall.bake");
    const ScopedEnv env("NDFMIP_BASISU", "/nonexistent/basisu");
    test::expectCliRefuses("bake " + test::shellArg(kMap) +
                               " --export ktx2 --normal-format uastc -q -o " + test::shellArg(out),
                           {"NDFMIP_BASISU", "Basis Universal encoder"});
    EXPECT_FALSE(fs::exists(out));
    // DDS holds no UASTC.
    test::expectCliRefuses("bake " + test::shellArg(kMap) +
                               " --export dds --roughness-format uastc -q -o " +
                               test::shellArg(out),
                           {"--roughness-format uastc is a KTX2 format"});
}

TEST(Ktx2Uastc, BakeWritesUastcNormalAndRoughness) {
    SKIP_WITHOUT_ENCODER();
    test::TempDir dir("uastc_bake");
    const std::string out = dir.file("wall.bake");
    std::string output;
    ASSERT_EQ(test::runCli("bake " + test::shellArg(kMap) +
                               " --method toksvig --export ktx2 --export-textures normal,roughness "
                               "--normal-format uastc --roughness-format uastc -q -o " +
                               test::shellArg(out),
                           &output),
              0)
        << output;
    for (const char* name : {"normal_uastc", "roughness_uastc"}) {
        const std::string file = out + "/ktx2/" + name + ".ktx2";
        ASSERT_TRUE(fs::exists(file)) << file;
        const std::string bytes = test::fileBytes(file);
        Result<EncodedTexture> t = readKtx2(bytes);
        ASSERT_TRUE(t) << name << ": " << t.error().message;
        EXPECT_EQ(t->format, TextureFormat::Uastc);
        ASSERT_EQ(int(t->levels.size()), levelCount(256, 256)) << name;
        for (size_t k = 0; k < t->levels.size(); ++k)
            EXPECT_EQ(t->levels[k].size(), uastcBytes(256 >> k, 256 >> k))
                << name << " level " << k;
        EXPECT_EQ(u32(bytes, 44), 2u) << name << ": Zstandard";
        Result<Ktx2KeyValues> keys = readKtx2KeyValues(bytes);
        ASSERT_TRUE(keys);
        EXPECT_NE(keys->at("ndfmip").find("UASTC"), std::string::npos) << keys->at("ndfmip");
        EXPECT_EQ(keys->at("KTXswizzle"), std::string(name) == "normal_uastc" ? "rgb1" : "rrr1");
    }
}

// The Khronos glTF validator's report of a GLB, or "" where node or gltf-validator is missing.
std::string validatorReport(const test::TempDir& dir, const std::string& glb) {
    const char* modules = std::getenv("NDFMIP_NODE_MODULES");
    const std::string path =
        (modules ? modules : std::string(NDFMIP_SOURCE_DIR) + "/.npm/node_modules") +
        "/gltf-validator";
    if (!fs::exists("/usr/bin/node") || !fs::exists(path + "/index.js")) return "";
    const std::string script = dir.file("validate.js"), out = dir.file("validator.json");
    test::writeBytes(
        script,
        "const v = require(process.argv[2]);\n"
        "const bytes = new Uint8Array(require('fs').readFileSync(process.argv[3]));\n"
        "v.validateBytes(bytes, {maxIssues: 0}).then(r => console.log(JSON.stringify({errors: "
        "r.issues.numErrors, codes: r.issues.messages.map(m => m.code + ' ' + (m.pointer || "
        "''))})))\n"
        "  .catch(e => { console.log(JSON.stringify({failed: String(e)})); process.exit(1); });\n");
    EXPECT_EQ(std::system(("node " + test::shellArg(script) + " " + test::shellArg(path) + " " +
                           test::shellArg(glb) + " > " + test::shellArg(out) + " 2>&1")
                              .c_str()),
              0)
        << test::fileBytes(out);
    return test::fileBytes(out);
}

// The quad asset around the bundled normal map and a material map of its size.
std::string quadGltf(const test::TempDir& dir) {
    const std::string normal = test::fileBytes(kMap);
    Image orm(256, 256, 3);
    for (int y = 0; y < 256; ++y)
        for (int x = 0; x < 256; ++x) {
            float* p = orm.at(x, y);
            p[0] = 1.f, p[1] = 0.2f + 0.6f * float(x) / 255.f, p[2] = float((x / 32 + y / 32) % 2);
        }
    return test::writeGltf(dir.path, test::quadAsset(),
                           {{"normal.png", normal}, {"orm.png", encodePng(orm, 8).value()}});
}

TEST(GltfBasisu, DefaultWritesKhrTextureBasisuWithNdfmipsLevels) {
    SKIP_WITHOUT_ENCODER();
    test::TempDir dir("gltf_basisu");
    const std::string input = quadGltf(dir), out = dir.file("out.glb"),
                      again = dir.file("again.glb");
    std::string output;
    ASSERT_EQ(test::runCli("gltf " + test::shellArg(input) + " -o " + test::shellArg(out) + " -q",
                           &output),
              0)
        << output;
    const test::Glb glb = test::parseGlb(test::fileBytes(out));
    ASSERT_TRUE(glb.ok);
    const OrderedJson& used = glb.json["extensionsUsed"];
    EXPECT_NE(std::find(used.begin(), used.end(), "KHR_texture_basisu"), used.end()) << used.dump();
    EXPECT_EQ(std::find(used.begin(), used.end(), "MSFT_texture_dds"), used.end()) << used.dump();
    EXPECT_FALSE(glb.json.contains("extensionsRequired"));
    // The normal texture (0) and the material map's (1): the original PNG stays the source, the
    // KTX2 of every level is the extension's.
    for (size_t t : {0u, 1u}) {
        const OrderedJson& texture = glb.json["textures"][t];
        ASSERT_TRUE(texture["extensions"].contains("KHR_texture_basisu")) << texture.dump();
        EXPECT_EQ(glb.json["images"][texture["source"].get<size_t>()]["mimeType"], "image/png");
        const size_t image = texture["extensions"]["KHR_texture_basisu"]["source"].get<size_t>();
        EXPECT_EQ(glb.json["images"][image]["mimeType"], "image/ktx2");
        Result<EncodedTexture> k = readKtx2(test::glbImage(glb, image));
        ASSERT_TRUE(k) << k.error().message;
        EXPECT_EQ(k->format, TextureFormat::Uastc);
        EXPECT_EQ(k->width, 256);
        EXPECT_EQ(int(k->levels.size()), levelCount(256, 256));
    }
    const std::string report = validatorReport(dir, out);
    if (!report.empty()) {
        std::printf("validator: %s\n", report.c_str());
        EXPECT_EQ(OrderedJson::parse(report)["errors"], 0) << report;
    }
    // A rerun on its own output replaces its own images: the same size, within 1 %.
    ASSERT_EQ(test::runCli("gltf " + test::shellArg(out) + " -o " + test::shellArg(again), &output),
              0)
        << output;
    EXPECT_NE(output.find("images of an earlier ndfmip gltf replaced"), std::string::npos)
        << output;
    const std::string a = test::fileBytes(out), b = test::fileBytes(again);
    EXPECT_LE(std::abs(double(b.size()) - double(a.size())), 0.01 * double(a.size()));
    EXPECT_EQ(test::parseGlb(b).json["images"].size(), glb.json["images"].size());
    // Rerun as DDS: the KHR_texture_basisu images and the extension's name go.
    const std::string dds = dir.file("dds.glb");
    ASSERT_EQ(test::runCli("gltf " + test::shellArg(out) + " -o " + test::shellArg(dds) +
                               " -q --texture-format dds",
                           &output),
              0)
        << output;
    const test::Glb d = test::parseGlb(test::fileBytes(dds));
    ASSERT_TRUE(d.ok);
    EXPECT_EQ(d.json["extensionsUsed"].dump().find("KHR_texture_basisu"), std::string::npos)
        << d.json.dump();
    EXPECT_TRUE(d.json["textures"][0]["extensions"].contains("MSFT_texture_dds"));
    EXPECT_FALSE(d.json["textures"][0]["extensions"].contains("KHR_texture_basisu"));
}

// glTF-Transform (npm @gltf-transform/cli, which scripts/setup installs) run after ndfmip gltf:
// `copy` and `dedup` keep KHR_texture_basisu and every KTX2 byte for byte (ndfmip's levels and
// marks), but write the textures without their core source (the PNG fallback left as an unused
// image), and `prune` then deletes those PNGs. A later ndfmip gltf refuses such a file in one line.
TEST(GltfBasisu, GltfTransformStepsKeepTheLevelsButDropTheFallback) {
    SKIP_WITHOUT_ENCODER();
    const std::string cli =
        std::string(NDFMIP_SOURCE_DIR) + "/.npm/node_modules/@gltf-transform/cli/bin/cli.js";
    if (!std::filesystem::exists(cli) || !std::filesystem::exists("/usr/bin/node"))
        GTEST_SKIP() << "node and npm @gltf-transform/cli (scripts/setup installs it) not found";
    test::TempDir dir("gltf_transform");
    const std::string input = quadGltf(dir), out = dir.file("out.glb");
    std::string output;
    ASSERT_EQ(
        test::runCliWithin(
            180, "gltf " + test::shellArg(input) + " -o " + test::shellArg(out) + " -q", &output),
        0)
        << output;
    const test::Glb ours = test::parseGlb(test::fileBytes(out));
    ASSERT_TRUE(ours.ok);
    auto ktx2Of = [](const test::Glb& glb, size_t t) {
        const OrderedJson& texture = glb.json["textures"][t];
        return test::glbImage(glb,
                              texture["extensions"]["KHR_texture_basisu"]["source"].get<size_t>());
    };
    for (const char* step : {"copy", "dedup", "prune"}) {
        SCOPED_TRACE(step);
        const std::string after = dir.file(std::string(step) + ".glb"), log = dir.file("gt.log");
        // Bounded: a node process that does not exit fails this step in two minutes, not the
        // whole test at ctest's timeout; one such stall is retried, and the log says which.
        const std::string command = "timeout -k 10 120 node " + test::shellArg(cli) + " " + step +
                                    " " + test::shellArg(out) + " " + test::shellArg(after) +
                                    " > " + test::shellArg(log) + " 2>&1";
        int status = std::system(command.c_str());
        if (WIFEXITED(status) && WEXITSTATUS(status) == 124) {
            std::printf("glTF-Transform %s did not finish in 120 s; retried once\n", step);
            status = std::system(command.c_str());
        }
        ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0)
            << "status " << status << ": " << test::fileBytes(log);
        const test::Glb glb = test::parseGlb(test::fileBytes(after));
        ASSERT_TRUE(glb.ok);
        const OrderedJson& used = glb.json["extensionsUsed"];
        EXPECT_NE(std::find(used.begin(), used.end(), "KHR_texture_basisu"), used.end());
        for (size_t t : {0u, 1u}) {
            EXPECT_EQ(ktx2Of(glb, t), ktx2Of(ours, t)) << "texture " << t;
            EXPECT_FALSE(glb.json["textures"][t].contains("source")) << "texture " << t;
        }
        auto pngsOf = [](const test::Glb& g) {
            size_t n = 0;
            for (const OrderedJson& image : g.json["images"]) n += image["mimeType"] == "image/png";
            return n;
        };
        EXPECT_EQ(pngsOf(glb), std::string(step) == "prune" ? 0u : pngsOf(ours));
        test::expectCliRefuses("gltf " + test::shellArg(after) + " -o " +
                                   test::shellArg(dir.file("x.glb")),
                               {"has no core source image"});
    }
}

TEST(GltfBasisu, ForeignBasisuTextureAndMissingEncoderAreOneLine) {
    test::TempDir dir("gltf_basisu_bad");
    const std::string input = quadGltf(dir), out = dir.file("out.glb");
    {
        const ScopedEnv env("NDFMIP_BASISU", "/nonexistent/basisu");
        test::expectCliRefuses("gltf " + test::shellArg(input) + " -o " + test::shellArg(out),
                               {"NDFMIP_BASISU", "Basis Universal encoder"});
        EXPECT_FALSE(fs::exists(out));
    }
    // The normal texture already carries a KTX2 of the asset's own.
    OrderedJson gltf = OrderedJson::parse(test::fileBytes(input));
    gltf["images"].push_back({{"uri", "normal.png"}, {"mimeType", "image/png"}});
    gltf["textures"][0]["extensions"]["KHR_texture_basisu"] = {
        {"source", gltf["images"].size() - 1}};
    gltf["extensionsUsed"] = {"KHR_texture_basisu"};
    const std::string foreign = dir.file("foreign.gltf");
    test::writeBytes(foreign, gltf.dump());
    test::expectCliRefuses("gltf " + test::shellArg(foreign) + " -o " + test::shellArg(out),
                           {"foreign.gltf", "texture 0 already has a KHR_texture_basisu"});
    EXPECT_FALSE(fs::exists(out));
}

} // namespace
} // namespace ndfmip
