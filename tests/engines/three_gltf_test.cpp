// A real client loads ndfmip gltf's output: three.js (npm three, GLTFLoader + KTX2Loader with
// its Basis transcoder) in headless chromium, WebGL2 on SwiftShader. The GLB's
// KHR_texture_basisu textures must become the material's normalMap and roughnessMap with
// ndfmip's levels (no generated mips), and every level read back from the GPU must match the
// levels of an independent bake of the same map within 3/255 mean absolute error (through
// ASTC, BC7 or uncompressed; the lossy ETC1 and BC1 transcodes within 9 and 5). Registered
// as the ctest test three_gltf_levels; it skips, saying why, where chromium, node, npm's three
// or the Basis Universal encoder is missing (scripts/setup installs them all).
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "engines/engine_client.h"
#include "gltf_test_asset.h"
#include "ndfmip/io.h"
#include "ndfmip/pyramid.h"
#include "ndfmip/texture_container.h"
#include "test_support.h"

namespace ndfmip {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

const std::string kMap = std::string(NDFMIP_SOURCE_DIR) + "/data/normalmaps/pyramidwall_256.png";

// Mean absolute error, in units of 1/255, of the RGBA8 texels `read` against `expected`: for
// each pair (c, e) of `channels`, channel c of `read` against channel e of `expected` (e = -1:
// against 1.0).
double meanError255(const std::vector<unsigned char>& read, const Image& expected,
                    const std::vector<std::pair<int, int>>& channels, double* worst) {
    double sum = 0.0;
    *worst = 0.0;
    for (size_t i = 0; i < expected.texelCount(); ++i)
        for (const auto& [c, e] : channels) {
            const double want =
                e < 0 ? 1.0 : double(expected.pixels[i * size_t(expected.channels) + size_t(e)]);
            const double error = std::abs(double(read[4 * i + size_t(c)]) / 255.0 - want) * 255.0;
            sum += error;
            *worst = std::max(*worst, error);
        }
    return sum / double(expected.texelCount() * channels.size());
}

// The transcode targets the page loads the GLB with: what KTX2Loader picks here (`auto`: BC7 on
// desktop Linux, where three turns ASTC and ETC off as likely emulated), then each forced, as
// on a device that has only it (`rgba`: none, the uncompressed fallback), and the bound on the
// mean error of every level, in 1/255. UASTC transcodes to ASTC and RGBA losslessly and to BC7
// nearly so: 3/255, what the encoder's own decoder is held to (tests/cli/uastc_cli_test.cpp).
// ETC1 (three's RGB_ETC2_Format for opaque UASTC) and BC1 are lossy transcodes: measured up to
// 6.9/255 (ETC1: the roughness map's R and B, which should read 1; 5.8 on the normals) and
// 4.0/255 on this asset (basisu 1.16.3, three 0.187.0), bounded at 9 and 5.
struct Target {
    const char* name;
    const char* format; // three's format of the texture, nullptr: any
    double bound;
};
const std::vector<Target> kTargets = {{"auto", nullptr, 3.0},
                                      {"astc", "RGBA_ASTC_4x4_Format", 3.0},
                                      {"bptc", "RGBA_BPTC_Format", 3.0},
                                      {"etc2", "RGB_ETC2_Format", 9.0},
                                      {"dxt", "RGBA_S3TC_DXT1_Format", 5.0},
                                      {"rgba", "RGBAFormat", 3.0}};

TEST(EngineClients, ThreeGltfLevels) {
    std::string chromium, node;
    if (const std::string missing = test::missingGltfPage(&chromium, &node); !missing.empty()) {
        if (const char* v = std::getenv("NDFMIP_REQUIRE_BROWSER"); v && std::string(v) == "1")
            FAIL() << missing;
        GTEST_SKIP() << missing;
    }
    const auto start = std::chrono::steady_clock::now();
    double browserSeconds = 0.0;
    // The roughness of each method ndfmip gltf writes: Toksvig's rule, and the one fitted to each
    // texel's filtered NDF.
    for (const std::string method : {"toksvig", "ggx-fit"}) {
        SCOPED_TRACE("--method " + method);
        test::TempDir dir("ndfmip_three_gltf_" + method);

        // A plane whose one material has a normal map (the bundled 256² wall) and a base roughness
        // (roughnessFactor 0.5, no texture): ndfmip gltf gives it a UASTC KTX2 normal texture and a
        // made metallicRoughness texture (G = sqrt(alpha_k), R = B = 1), every level its own.
        test::TestAsset asset = test::quadAsset();
        asset.json["meshes"][0]["primitives"] =
            test::OrderedJson::array({asset.json["meshes"][0]["primitives"][0]});
        asset.json["materials"] = test::OrderedJson::parse(R"([{"name": "Wall",
            "normalTexture": {"index": 0},
            "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.7, 0.6, 1], "metallicFactor": 0,
                                     "roughnessFactor": 0.5}}])");
        asset.json["textures"] = test::OrderedJson::array({asset.json["textures"][0]});
        asset.json["images"] = test::OrderedJson::array({asset.json["images"][0]});
        const std::string input =
            test::writeGlb(dir.path / "plane.glb", asset, {{"image/png", test::fileBytes(kMap)}});
        const std::string glb = dir.file("plane_filtered.glb");
        std::string output;
        ASSERT_EQ(test::runGltfCli(test::shellArg(input) + " -o " + test::shellArg(glb) +
                                       " -q --method " + method,
                                   &output),
                  0)
            << output;

        // ndfmip's KTX2, as ndfmip reads it: the level count three must keep.
        const test::Glb parsed = test::parseGlb(test::fileBytes(glb));
        ASSERT_TRUE(parsed.ok);
        const auto& textures = parsed.json["textures"];
        const auto& material = parsed.json["materials"][0];
        std::vector<int> ktx2Levels;
        for (size_t t : {material["normalTexture"]["index"].get<size_t>(),
                         material["pbrMetallicRoughness"]["metallicRoughnessTexture"]["index"]
                             .get<size_t>()}) {
            ASSERT_TRUE(textures[t]["extensions"].contains("KHR_texture_basisu")) << textures[t];
            Result<EncodedTexture> k = readKtx2(test::glbImage(
                parsed, textures[t]["extensions"]["KHR_texture_basisu"]["source"].get<size_t>()));
            ASSERT_TRUE(k) << k.error().message;
            EXPECT_EQ(k->format, TextureFormat::Uastc);
            ktx2Levels.push_back(int(k->levels.size()));
        }
        const int levels = levelCount(256, 256);
        EXPECT_EQ(ktx2Levels, std::vector<int>({levels, levels}));

        // The independent levels: a bake of the same map with the same method and roughness (alpha
        // 0.25 = 0.5²), its normals and perceptual roughness as 16-bit PNGs.
        const std::string bake = dir.file("wall.bake");
        ASSERT_EQ(test::runCli("bake " + test::shellArg(kMap) + " --method " + method +
                                   " --base-roughness 0.25 --export png16 -q -o " +
                                   test::shellArg(bake),
                               &output),
                  0)
            << output;

        // three.js in headless chromium.
        const std::string result = dir.file("three.json"), log = dir.file("three.log");
        std::string targets;
        for (const Target& target : kTargets) {
            if (!targets.empty()) targets += ',';
            targets += target.name;
        }
        const auto browserStart = std::chrono::steady_clock::now();
        const int status = test::runThreePage(node, chromium, "three_gltf_levels.mjs",
                                              "glb=/asset/plane_filtered.glb&targets=" + targets,
                                              {{"/asset/", dir.path.string()}}, result, log);
        browserSeconds +=
            std::chrono::duration<double>(std::chrono::steady_clock::now() - browserStart).count();
        ASSERT_EQ(status, 0) << test::fileBytes(log);
        const json report = json::parse(test::fileBytes(result));
        std::printf("three r%s on %s\n", report["three"].get<std::string>().c_str(),
                    report["renderer"].get<std::string>().c_str());
        ASSERT_EQ(report["runs"].size(), kTargets.size()) << report.dump().substr(0, 400);
        for (const Target& target : kTargets) {
            const json& run = report["runs"][size_t(&target - kTargets.data())];
            SCOPED_TRACE(std::string("transcode target ") + target.name);
            ASSERT_EQ(run["target"], target.name);
            std::printf("%s: %s, GLB loaded in %.0f ms, levels read back in %.0f + %.0f ms\n",
                        target.name, run["normalMap"]["format"].get<std::string>().c_str(),
                        run["loadMs"].get<double>(), run["normalMap"].value("readMs", 0.0),
                        run["roughnessMap"].is_object() ? run["roughnessMap"].value("readMs", 0.0)
                                                        : 0.0);
            EXPECT_EQ(run["type"], "MeshStandardMaterial");
            EXPECT_EQ(run["glError"], 0);
            EXPECT_TRUE(run["metalnessIsRoughness"].get<bool>()) << "glTF's map is both";
            if (target.format) {
                EXPECT_EQ(run["normalMap"]["format"], target.format);
            }

            // Each map: three's texture from the KTX2 (not the PNG fallback), ndfmip's levels
            // uploaded as they are, each level back from the GPU against the bake's.
            struct Map {
                const char* name;
                const char* stem; // the bake's png16 files
                std::vector<std::pair<int, int>>
                    channels;                          // (texture's, PNG's): the levels compared
                std::vector<std::pair<int, int>> ones; // channels that must read 1
            };
            for (const Map& map :
                 {Map{"normalMap", "normal", {{0, 0}, {1, 1}, {2, 2}}, {}},
                  Map{"roughnessMap", "roughness", {{1, 0}}, {{0, -1}, {2, -1}}}}) {
                SCOPED_TRACE(map.name);
                const json& t = run[map.name];
                ASSERT_TRUE(t.is_object()) << run.dump().substr(0, 400);
                EXPECT_EQ(t["mimeType"], "image/ktx2");
                // KTX2Loader's CompressedTexture for every target (RGBA too), not a PNG's Texture.
                EXPECT_TRUE(t["compressed"].get<bool>());
                EXPECT_FALSE(t["generateMipmaps"].get<bool>());
                EXPECT_FALSE(t["flipY"].get<bool>());
                EXPECT_EQ(t["colorSpace"], "srgb-linear");
                ASSERT_EQ(int(t["mipmaps"].size()), levels);
                ASSERT_EQ(int(t["levels"].size()), levels);
                std::string line;
                double onesMean = 0.0;
                for (int k = 0; k < levels; ++k) {
                    Result<SourceImage> expected =
                        loadImage(bake + "/png16/" + map.stem + "_L" + std::to_string(k) + ".png");
                    ASSERT_TRUE(expected) << expected.error().message;
                    const Image& e = expected->image;
                    EXPECT_EQ(t["mipmaps"][size_t(k)], json::array({e.width, e.height}))
                        << "level " << k;
                    const std::vector<unsigned char> read =
                        test::fromBase64(t["levels"][size_t(k)].get<std::string>());
                    ASSERT_EQ(read.size(), 4 * e.texelCount()) << "level " << k;
                    double worst = 0.0;
                    const double mean = meanError255(read, e, map.channels, &worst);
                    char text[64];
                    std::snprintf(text, sizeof text, " %.2f", mean);
                    line += text;
                    EXPECT_LE(mean, target.bound) << "level " << k << " (" << e.width << "x"
                                                  << e.height << "), max error " << worst << "/255";
                    if (!map.ones.empty()) {
                        double worstOne = 0.0;
                        const double ones = meanError255(read, e, map.ones, &worstOne);
                        onesMean = std::max(onesMean, ones);
                        EXPECT_LE(ones, target.bound)
                            << "level " << k << ": R and B (occlusion, metallic) should read 1";
                    }
                }
                std::printf("  %s mean error per level (1/255):%s", map.name, line.c_str());
                if (!map.ones.empty()) std::printf("; R, B against 1: at most %.2f", onesMean);
                std::printf("\n");
            }
        }
    }
    const double total =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("three_gltf_levels: %.1f s (browser %.1f s)\n", total, browserSeconds);
}

} // namespace
} // namespace ndfmip
