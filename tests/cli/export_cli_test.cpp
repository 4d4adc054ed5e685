// bake --export ktx2,dds: the files every level in one container each, listed in the manifest,
// the bake still read back; DDS headers as an independent reader (nvddsinfo) sees them.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "ndfmip/io.h"
#include "ndfmip/texture_container.h"
#include "test_support.h"

namespace ndfmip {
namespace {

const std::string kMap = std::string(NDFMIP_SOURCE_DIR) + "/data/normalmaps/pyramidwall_256.png";

nlohmann::json manifestOf(const std::string& dir) {
    std::ifstream in(dir + "/manifest.json");
    return nlohmann::json::parse(in);
}

TEST(ExportCli, ToksvigWritesNormalRoughnessAndPlaneContainers) {
    test::TempDir dir("ndfmip_export");
    const std::string out = dir.file("wall.bake");
    std::string output;
    ASSERT_EQ(test::runCli("bake " + test::shellArg(kMap) +
                               " --green-down --method toksvig --export exr,ktx2,dds,png16 "
                               "--export-textures normal,roughness,planes -o " +
                               test::shellArg(out),
                           &output),
              0)
        << output;
    const nlohmann::json m = manifestOf(out);
    for (const char* container : {"ktx2", "dds"}) {
        ASSERT_TRUE(m["exports"].contains(container)) << m["exports"].dump();
        const auto names = m["exports"][container].get<std::vector<std::string>>();
        for (const char* stem : {"normal_bc5", "roughness_bc4", "mean"})
            EXPECT_NE(std::find(names.begin(), names.end(),
                                std::string(container) + "/" + stem + "." + container),
                      names.end())
                << stem;
        for (const std::string& name : names)
            EXPECT_TRUE(std::filesystem::exists(out + "/" + name)) << name;
    }
    EXPECT_TRUE(m["exports"].contains("png16"));
    // The bake is still a bake: inspect reads it, and a rebake replaces it.
    ASSERT_EQ(test::runCli("inspect " + test::shellArg(out) + " --level 3 --texel 1,1", &output), 0)
        << output;
    ASSERT_EQ(
        test::runCli(
            "bake " + test::shellArg(kMap) +
                " --green-down --method vmf --lobes 2 --export ktx2 --export-textures planes -o " +
                test::shellArg(out),
            &output),
        0)
        << output;
    const auto names = manifestOf(out)["exports"]["ktx2"].get<std::vector<std::string>>();
    EXPECT_EQ(names, (std::vector<std::string>{"ktx2/lobe0.ktx2", "ktx2/lobe1.ktx2"}));
    EXPECT_FALSE(std::filesystem::exists(out + "/dds"));
    // A plane's KTX2 names the plane and its channels.
    std::ifstream in(out + "/ktx2/lobe1.ktx2", std::ios::binary);
    Result<Ktx2KeyValues> kv =
        readKtx2KeyValues(std::string((std::istreambuf_iterator<char>(in)), {}));
    ASSERT_TRUE(kv) << kv.error().message;
    const nlohmann::json about = nlohmann::json::parse(kv->at("ndfmip"));
    EXPECT_EQ(about["content"], "plane");
    EXPECT_EQ(about["plane"], "lobe1");
    EXPECT_EQ(about["channels"].size(), 4u) << about.dump();
}

// --export ktx2 writes what --export-textures asks for, by default the normal and the roughness
// only: the float planes (22 MB for a 2048^2 map's mean) only with planes. A container that
// would hold nothing (vmf stores no normal or roughness) is refused, nothing written.
TEST(ExportCli, PlanesOnlyWhenAskedFor) {
    test::TempDir dir("ndfmip_export_planes");
    const std::string out = dir.file("wall.bake");
    std::string output;
    ASSERT_EQ(test::runCli("bake " + test::shellArg(kMap) + " --export ktx2,dds -q -o " +
                               test::shellArg(out),
                           &output),
              0)
        << output;
    std::vector<std::string> files;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(out))
        if (entry.is_regular_file()) files.push_back(entry.path().lexically_relative(out).string());
    std::sort(files.begin(), files.end());
    EXPECT_EQ(files, (std::vector<std::string>{"dds/normal_bc5.dds", "dds/roughness_bc4.dds",
                                               "ktx2/normal_bc5.ktx2", "ktx2/roughness_bc4.ktx2",
                                               "manifest.json"}));
    test::expectCliRefuses("bake " + test::shellArg(kMap) +
                               " --method vmf --lobes 2 --export ktx2 -o " +
                               test::shellArg(dir.file("v")),
                           {"--export ktx2", "planes", "--export-textures"});
    EXPECT_FALSE(std::filesystem::exists(dir.file("v")));
    EXPECT_TRUE(test::leftovers(dir.path).empty());
}

TEST(ExportCli, DdsHeaderAsNvddsinfoReadsIt) {
    if (!std::filesystem::exists("/usr/bin/nvddsinfo"))
        GTEST_SKIP() << "nvddsinfo (libnvtt-bin) not installed";
    test::TempDir dir("ndfmip_export_dds");
    const std::string out = dir.file("wall.bake");
    std::string output;
    ASSERT_EQ(test::runCli("bake " + test::shellArg(kMap) +
                               " --green-down --method toksvig --export dds -o " +
                               test::shellArg(out),
                           &output),
              0)
        << output;
    const std::string info = dir.file("info.txt");
    ASSERT_EQ(std::system(("nvddsinfo " + test::shellArg(out + "/dds/normal_bc5.dds") + " > " +
                           test::shellArg(info))
                              .c_str()),
              0);
    std::ifstream in(info);
    const std::string text((std::istreambuf_iterator<char>(in)), {});
    EXPECT_NE(text.find("Width: 256"), std::string::npos) << text;
    EXPECT_NE(text.find("Mipmap count: 9"), std::string::npos) << text;
    EXPECT_NE(text.find("DXGI Format: 83"), std::string::npos) << text; // BC5_UNORM
}

TEST(ExportCli, UnknownExportsAndForeignPathsAreRefused) {
    test::TempDir dir("ndfmip_export_bad");
    test::expectCliRefuses("bake " + test::shellArg(kMap) + " --export ktx3 -o " +
                               test::shellArg(dir.file("x")),
                           {"--export", "ktx3"});
    const std::string out = dir.file("wall.bake");
    std::string output;
    ASSERT_EQ(test::runCli("bake " + test::shellArg(kMap) + " --export exr,ktx2 -o " +
                               test::shellArg(out),
                           &output),
              0)
        << output;
    nlohmann::json m = manifestOf(out);
    m["exports"]["ktx2"][0] = "../../etc/passwd";
    std::ofstream(out + "/manifest.json") << m.dump(2);
    test::expectCliRefuses("inspect " + test::shellArg(out) + " --texel 0,0",
                           {"exports.ktx2", "not ktx2/"});
}

// --export lists exactly what is written: the roughness alone in one KTX2, no EXR planes; the
// folder is still a bake (a manifest, replaced by the next bake) but readers refuse it by name.
TEST(ExportCli, OnlyWhatIsAskedForIsWritten) {
    test::TempDir dir("ndfmip_export_only");
    const std::string out = dir.file("wall.bake");
    std::string output;
    ASSERT_EQ(test::runCli("bake " + test::shellArg(kMap) +
                               " --export ktx2 --export-textures roughness --zstd 3 -o " +
                               test::shellArg(out),
                           &output),
              0)
        << output;
    std::vector<std::string> files;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(out))
        if (entry.is_regular_file()) files.push_back(entry.path().lexically_relative(out).string());
    std::sort(files.begin(), files.end());
    EXPECT_EQ(files, (std::vector<std::string>{"ktx2/roughness_bc4.ktx2", "manifest.json"}));
    const nlohmann::json m = manifestOf(out);
    EXPECT_EQ(m["storage"], "none");
    EXPECT_TRUE(m["levels"][0]["files"].empty());
    test::expectCliRefuses("inspect " + test::shellArg(out) + " --texel 0,0",
                           {"only exported textures", "exr"});
    // Formats by name; the next bake replaces the folder.
    ASSERT_EQ(test::runCli("bake " + test::shellArg(kMap) +
                               " --export dds,ktx2 --export-textures normal,roughness "
                               "--normal-format rg16 --roughness-format r16f -o " +
                               test::shellArg(out),
                           &output),
              0)
        << output;
    const auto names = manifestOf(out)["exports"]["dds"].get<std::vector<std::string>>();
    EXPECT_EQ(names, (std::vector<std::string>{"dds/normal_rg16.dds", "dds/roughness_r16f.dds"}));
    test::expectCliRefuses("bake " + test::shellArg(kMap) +
                               " --export ktx2 --export-textures albedo -o " +
                               test::shellArg(dir.file("y")),
                           {"--export-textures", "albedo"});
    test::expectCliRefuses("bake " + test::shellArg(kMap) + " --export dds --zstd 3 -o " +
                               test::shellArg(dir.file("y")),
                           {"--zstd", "ktx2"});
    EXPECT_FALSE(std::filesystem::exists(dir.file("y")));
}

// The least squared error any 8-level BC4 block can reach on 16 values (8-bit endpoints,
// every pair tried): the bar for an encoder on content that BC4 cannot hold exactly.
double bestBc4SquaredError(const double values[16]) {
    double best = 1e30;
    for (int r0 = 1; r0 < 256; ++r0)
        for (int r1 = 0; r1 < r0; ++r1) {
            double palette[8] = {double(r0), double(r1)};
            for (int c = 2; c < 8; ++c) palette[c] = double(((8 - c) * r0 + (c - 1) * r1 + 3) / 7);
            double total = 0.0;
            for (int i = 0; i < 16 && total < best; ++i) {
                double nearest = 1e30;
                for (double p : palette)
                    nearest = std::min(nearest, (values[i] - p) * (values[i] - p));
                total += nearest;
            }
            best = std::min(best, total);
        }
    return best / (255.0 * 255.0);
}

// The roughness an engine reads back is the bake's float plane: the BC4 DDS decoded by
// nvdecompress (an independent decoder) against sqrt(alpha) of roughness_ggx, level by level.
// BC4 holds 8 levels per 4x4 block; where a level's roughness varies more than that within
// blocks (this map's levels 3-5: the best any BC4 block can do is 43.2-43.4 dB) the bar is
// that optimum, less 1.5 dB; everywhere at least 40 dB.
TEST(ExportCli, DecodedBc4RoughnessMatchesTheFloatPlane) {
    if (!std::filesystem::exists("/usr/bin/nvdecompress"))
        GTEST_SKIP() << "nvdecompress (libnvtt-bin) not installed";
    test::TempDir dir("ndfmip_export_rough");
    const std::string out = dir.file("wall.bake");
    std::string output;
    ASSERT_EQ(test::runCli("bake " + test::shellArg(kMap) +
                               " --green-down --base-roughness 0.2 --export exr,dds -o " +
                               test::shellArg(out),
                           &output),
              0)
        << output;
    std::ifstream in(out + "/dds/roughness_bc4.dds", std::ios::binary);
    const std::string dds((std::istreambuf_iterator<char>(in)), {});
    size_t at = 4 + 124 + 20; // magic, DDS_HEADER, DDS_HEADER_DXT10
    const nlohmann::json m = manifestOf(out);
    for (size_t k = 0; k < m["levels"].size(); ++k) {
        const int w = m["levels"][k]["width"], h = m["levels"][k]["height"];
        const size_t bytes = size_t((w + 3) / 4) * size_t((h + 3) / 4) * 8;
        ASSERT_LE(at + bytes, dds.size());
        EncodedTexture one;
        one.format = TextureFormat::Bc4Unorm;
        one.width = w, one.height = h;
        one.levels = {dds.substr(at, bytes)};
        at += bytes;
        const std::string level = dir.file("r" + std::to_string(k) + ".dds");
        std::ofstream(level, std::ios::binary) << ddsFileLegacy(one).value();
        ASSERT_EQ(std::system(("cd " + test::shellArg(dir.path.string()) + " && nvdecompress " +
                               test::shellArg(level) + " > /dev/null 2>&1")
                                  .c_str()),
                  0);
        Result<SourceImage> decoded = loadImage(dir.file("r" + std::to_string(k) + ".tga"));
        ASSERT_TRUE(decoded) << decoded.error().message;
        Result<SourceImage> plane =
            loadImage(out + "/" + m["levels"][k]["files"]["roughness_ggx"].get<std::string>());
        ASSERT_TRUE(plane) << plane.error().message;
        double squared = 0.0;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const double e = double(decoded->image.at(x, y)[0]) -
                                 std::sqrt(double(plane->image.at(x, y)[0]));
                squared += e * e;
            }
        auto psnr = [&](double total) {
            return 10.0 * std::log10(1.0 / std::max(total / double(w * h), 1e-12));
        };
        EXPECT_GE(psnr(squared), 40.0) << "level " << k;
        if (w % 4 == 0 && h % 4 == 0 && w <= 32 && h <= 32) {
            double optimum = 0.0;
            for (int by = 0; by < h; by += 4)
                for (int bx = 0; bx < w; bx += 4) {
                    double values[16];
                    for (int i = 0; i < 16; ++i)
                        values[i] =
                            255.0 * std::sqrt(double(plane->image.at(bx + i % 4, by + i / 4)[0]));
                    optimum += bestBc4SquaredError(values);
                }
            EXPECT_GE(psnr(squared), psnr(optimum) - 1.5) << "level " << k;
            std::printf("level %zu (%dx%d): %.1f dB, best 8-level BC4 %.1f dB\n", k, w, h,
                        psnr(squared), psnr(optimum));
        } else {
            std::printf("level %zu (%dx%d): %.1f dB\n", k, w, h, psnr(squared));
        }
    }
    EXPECT_EQ(at, dds.size());
}

} // namespace
} // namespace ndfmip
