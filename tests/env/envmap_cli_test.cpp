// ndfmip envmap: the folder it writes, and bad input (missing, corrupt, NaN, wrong shape, absurd
// options) refused with one line, a non-zero status and nothing written.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>

#include <glm/glm.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "ndfmip/environment.h"
#include "ndfmip/io.h"
#include "ndfmip/spherical_harmonics.h"
#include "ndfmip/texture_container.h"
#include "test_support.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace ndfmip::test {
namespace {

class EnvmapCli : public ::testing::Test {
  protected:
    TempDir tmp{"envmap_cli"};
    std::string map = tmp.file("sky.exr");
    fs::path out = tmp.path / "env";
    // Small and quick: few samples, an 8 x 8 table and, unless `extra` says otherwise, GGX levels
    // 32 and 16 wide.
    std::string quick = " -q --samples 16 --dfg-size 8 --dfg-samples 16";

    void SetUp() override {
        Image sky(64, 32, 3);
        for (int y = 0; y < 32; ++y)
            for (int x = 0; x < 64; ++x)
                for (int c = 0; c < 3; ++c)
                    sky.at(x, y)[c] = 0.1f * float(c + 1) + (x == 16 && y == 10 ? 50.f : 0.f);
        ASSERT_TRUE(saveExr(map, sky));
    }

    std::string envmapArgs(const std::string& input, const std::string& extra = "") const {
        std::string sizes;
        if (extra.find("--size") == std::string::npos) sizes += " --size 32";
        if (extra.find("--levels") == std::string::npos) sizes += " --levels 2";
        return "envmap " + shellArg(input) + quick + sizes + " " + extra + " -o " +
               shellArg(out.string());
    }

    void expectNothingWritten() {
        EXPECT_FALSE(fs::exists(out));
        EXPECT_TRUE(leftovers(tmp.path).empty());
    }
};

TEST_F(EnvmapCli, WritesShLevelsTableAndManifest) {
    std::string output;
    ASSERT_EQ(runCli(envmapArgs(map, "--sh-order 3 --rotation 90 --intensity 2"), &output), 0)
        << output;
    for (const char* file : {"environment.json", "sh.json", "ggx_L0.exr", "ggx_L1.exr", "dfg.exr"})
        EXPECT_TRUE(fs::is_regular_file(out / file)) << file;
    const json manifest = json::parse(fileBytes(out / "environment.json"));
    EXPECT_EQ(manifest["kind"], "environment");
    EXPECT_EQ(manifest["source"]["rotation_degrees"], 90.);
    ASSERT_EQ(manifest["ggx"]["levels"].size(), 2u);
    EXPECT_EQ(manifest["ggx"]["levels"][1]["perceptual_roughness"], 1.);
    EXPECT_EQ(manifest["ggx"]["levels"][1]["width"], 16);
    EXPECT_EQ(manifest["ggx"]["lod_mapping"], "filament");
    const json sh = json::parse(fileBytes(out / "sh.json"));
    ASSERT_EQ(sh["order"], 3);
    ASSERT_EQ(sh["radiance"].size(), 4u);
    EXPECT_EQ(sh["radiance"][3].size(), 7u);
    // The file's numbers are the library's, scaled by --intensity.
    EnvironmentOptions options{2.f, 90.f};
    const EnvironmentSh want = projectEnvironmentSh(loadEnvironment(map, options).value(), 3);
    for (int c = 0; c < 3; ++c) {
        EXPECT_DOUBLE_EQ(sh["radiance"][2][1][c].get<double>(),
                         want.radiance[size_t(shIndex(2, -1))][c]);
        EXPECT_DOUBLE_EQ(sh["irradiance"][1][2][c].get<double>(),
                         want.irradiance[size_t(shIndex(1, 1))][c]);
    }
    Result<SourceImage> dfg = loadImage((out / "dfg.exr").string());
    ASSERT_TRUE(dfg.ok());
    EXPECT_EQ(dfg->image.width, 8);
    EXPECT_EQ(dfg->image.channels, 3);
    // Run again: an earlier environment folder is replaced.
    ASSERT_EQ(runCli(envmapArgs(map, "--levels 1"), &output), 0) << output;
    EXPECT_FALSE(fs::exists(out / "ggx_L1.exr"));
    EXPECT_TRUE(leftovers(tmp.path).empty());
}

TEST_F(EnvmapCli, CubeLayoutWritesSixFacesPerLevel) {
    std::string output;
    ASSERT_EQ(runCli(envmapArgs(map, "--layout cube"), &output), 0) << output;
    const json manifest = json::parse(fileBytes(out / "environment.json"));
    const json& levels = manifest["ggx"]["levels"];
    ASSERT_EQ(levels.size(), 2u);
    for (size_t k = 0; k < 2; ++k) {
        EXPECT_FALSE(levels[k].contains("file"));
        EXPECT_FALSE(fs::exists(out / ("ggx_L" + std::to_string(k) + ".exr")));
        EXPECT_EQ(levels[k]["face_size"], (32 >> k) / 4);
        for (int face = 0; face < kCubeFaces; ++face) {
            const std::string file = levels[k]["faces"][cubeFaceName(face)];
            Result<SourceImage> image = loadImage((out / file).string());
            ASSERT_TRUE(image.ok()) << file;
            EXPECT_EQ(image->image.width, (32 >> k) / 4);
        }
    }
    // The folder holds only what its manifest lists, so a rerun may replace it.
    ASSERT_EQ(runCli(envmapArgs(map, "--layout both"), &output), 0) << output;
    EXPECT_TRUE(fs::is_regular_file(out / "ggx_L0.exr"));
    EXPECT_TRUE(fs::is_regular_file(out / "ggx_L0_nz.exr"));
    EXPECT_NE(runCli(envmapArgs(map, "--layout sphere"), &output), 0);
    EXPECT_NE(output.find("--layout"), std::string::npos) << output;
}

// IEEE binary16 to float (normal numbers and zero: what radiance and the DFG table hold).
float halfToFloat(uint16_t bits) {
    const int exponent = (bits >> 10) & 31, mantissa = bits & 1023;
    const float magnitude = exponent == 0
                                ? std::ldexp(float(mantissa), -24)
                                : std::ldexp(1.f + float(mantissa) / 1024.f, exponent - 15);
    return bits & 0x8000 ? -magnitude : magnitude;
}

// Texel (x, y) of face `face` (0 for a 2D texture) of level k of an RGBA16F KTX2 file, read
// through its level index.
glm::vec4 ktx2Texel(const std::string& file, uint32_t k, int face, int faces, int width, int x,
                    int y) {
    uint64_t offset = 0;
    std::memcpy(&offset, file.data() + 80 + 24 * k, 8);
    const int w = std::max(width >> k, 1);
    const size_t faceBytes = size_t(w) * size_t(faces == 6 ? w : std::max((width / 2) >> k, 1)) * 8;
    glm::vec4 v;
    for (int c = 0; c < 4; ++c) {
        uint16_t bits;
        std::memcpy(&bits,
                    file.data() + offset + size_t(face) * faceBytes +
                        (size_t(y) * size_t(w) + size_t(x)) * 8 + 2 * size_t(c),
                    2);
        v[c] = halfToFloat(bits);
    }
    return v;
}

TEST_F(EnvmapCli, Ktx2HoldsEveryLevelOfBothLayouts) {
    std::string output;
    ASSERT_EQ(runCli(envmapArgs(map, "--layout both --ktx2"), &output), 0) << output;
    const json manifest = json::parse(fileBytes(out / "environment.json"));
    EXPECT_EQ(manifest["ktx2"]["ggx_cube"], "ggx_cube.ktx2");
    const std::string cube = fileBytes(out / "ggx_cube.ktx2"),
                      flat = fileBytes(out / "ggx_equirect.ktx2");
    uint32_t header[9];
    std::memcpy(header, cube.data() + 12, sizeof header); // vkFormat ... levelCount
    EXPECT_EQ(header[0], 97u);                            // VK_FORMAT_R16G16B16A16_SFLOAT
    EXPECT_EQ(header[2], 8u);                             // face size: 32 / 4
    EXPECT_EQ(header[6], 6u);                             // faceCount
    EXPECT_EQ(header[7], 2u);                             // levelCount
    // Every face's corner texels are the EXR faces' (to half precision); the equirect file's the
    // EXR levels'.
    for (uint32_t k = 0; k < 2; ++k) {
        for (int face = 0; face < kCubeFaces; ++face) {
            const std::string name = manifest["ggx"]["levels"][k]["faces"][cubeFaceName(face)];
            const Image faceImage = loadImage((out / name).string())->image;
            for (auto [x, y] : {std::pair{0, 0}, {faceImage.width - 1, faceImage.height - 1}}) {
                const glm::vec4 got = ktx2Texel(cube, k, face, 6, 8, x, y);
                for (int c = 0; c < 3; ++c)
                    EXPECT_NEAR(got[c], faceImage.at(x, y)[c],
                                1e-3f * (1.f + faceImage.at(x, y)[c]));
                EXPECT_EQ(got[3], 1.f);
            }
        }
        const Image level =
            loadImage((out / ("ggx_L" + std::to_string(k) + ".exr")).string())->image;
        const glm::vec4 got = ktx2Texel(flat, k, 0, 1, 32, level.width - 1, 1);
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(got[c], level.at(level.width - 1, 1)[c],
                        1e-3f * (1.f + level.at(level.width - 1, 1)[c]));
    }
    EXPECT_TRUE(fs::is_regular_file(out / "dfg.ktx2"));
    // Each file says what it holds: radiance at each level's roughness, as the manifest has it; the
    // DFG table.
    for (const std::string& file : {cube, flat}) {
        Result<Ktx2KeyValues> kv = readKtx2KeyValues(file);
        ASSERT_TRUE(kv) << kv.error().message;
        EXPECT_EQ(kv->at("KTXwriter").rfind("ndfmip ", 0), 0u);
        const json about = json::parse(kv->at("ndfmip"));
        EXPECT_EQ(about["content"], "radiance");
        ASSERT_EQ(about["perceptual_roughness"].size(), 2u);
        for (size_t k = 0; k < 2; ++k)
            EXPECT_EQ(about["perceptual_roughness"][k],
                      manifest["ggx"]["levels"][k]["perceptual_roughness"]);
    }
    EXPECT_EQ(json::parse(readKtx2KeyValues(fileBytes(out / "dfg.ktx2"))->at("ndfmip"))["content"],
              "dfg");
    // The folder holds only what its manifest lists, so a rerun may replace it.
    ASSERT_EQ(runCli(envmapArgs(map, "--layout cube"), &output), 0) << output;
    EXPECT_FALSE(fs::exists(out / "ggx_cube.ktx2"));
}

// --dds writes the textures --ktx2 does as DDS (DX10 header): the same half texels, a cube map's
// faces each with its levels together where KTX2 keeps each level's faces together.
TEST_F(EnvmapCli, DdsHoldsTheKtx2TexturesInDdsOrder) {
    std::string output;
    ASSERT_EQ(runCli(envmapArgs(map, "--layout both --ktx2 --dds"), &output), 0) << output;
    const json manifest = json::parse(fileBytes(out / "environment.json"));
    EXPECT_EQ(manifest["dds"]["ggx_cube"], "ggx_cube.dds");
    EXPECT_EQ(manifest["dds"]["dfg"], "dfg.dds");
    const std::string ktx2 = fileBytes(out / "ggx_cube.ktx2"),
                      dds = fileBytes(out / "ggx_cube.dds");
    auto u32 = [](const std::string& bytes, size_t at) {
        uint32_t v = 0;
        std::memcpy(&v, bytes.data() + at, 4);
        return v;
    };
    ASSERT_GE(dds.size(), 148u);
    EXPECT_EQ(dds.substr(0, 4), "DDS ");
    EXPECT_EQ(u32(dds, 4 + 24), 2u);                // dwMipMapCount
    EXPECT_EQ(u32(dds, 4 + 108), 0x200u | 0xFC00u); // DDSCAPS2_CUBEMAP and all six faces
    EXPECT_EQ(u32(dds, 128), 10u);                  // DXGI_FORMAT_R16G16B16A16_FLOAT
    EXPECT_EQ(u32(dds, 128 + 8), 0x4u);             // D3D11_RESOURCE_MISC_TEXTURECUBE
    size_t at = 148;
    for (int face = 0; face < kCubeFaces; ++face)
        for (uint32_t k = 0; k < 2; ++k) {
            uint64_t offset = 0;
            std::memcpy(&offset, ktx2.data() + 80 + 24 * k, 8);
            const size_t faceBytes = size_t(8 >> k) * size_t(8 >> k) * 8;
            EXPECT_EQ(
                dds.compare(at, faceBytes, ktx2, offset + size_t(face) * faceBytes, faceBytes), 0)
                << "face " << face << " level " << k;
            at += faceBytes;
        }
    EXPECT_EQ(at, dds.size());
    const std::string flatKtx2 = fileBytes(out / "ggx_equirect.ktx2"),
                      flat = fileBytes(out / "ggx_equirect.dds");
    at = 148;
    for (uint32_t k = 0; k < 2; ++k) {
        uint64_t offset = 0, length = 0;
        std::memcpy(&offset, flatKtx2.data() + 80 + 24 * k, 8);
        std::memcpy(&length, flatKtx2.data() + 80 + 24 * k + 8, 8);
        EXPECT_EQ(flat.compare(at, length, flatKtx2, offset, length), 0) << "level " << k;
        at += length;
    }
    EXPECT_EQ(at, flat.size());
    // DDS alone, and a rerun without it replaces the folder (its manifest listed the DDS files).
    ASSERT_EQ(runCli(envmapArgs(map, "--layout cube --dds"), &output), 0) << output;
    EXPECT_TRUE(fs::is_regular_file(out / "ggx_cube.dds"));
    EXPECT_FALSE(fs::exists(out / "ggx_cube.ktx2"));
    ASSERT_EQ(runCli(envmapArgs(map, "--layout cube"), &output), 0) << output;
    EXPECT_FALSE(fs::exists(out / "ggx_cube.dds"));
}

TEST_F(EnvmapCli, RefusesBadInputWithOneLine) {
    expectCliRefuses(envmapArgs(tmp.file("missing.hdr")), {"missing.hdr"});
    expectNothingWritten();

    // A Radiance header whose scanlines stop early.
    const std::string corrupt = tmp.file("corrupt.hdr");
    writeBytes(corrupt, "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 32 +X 64\n\x02\x02\x00\x40\x80");
    expectCliRefuses(envmapArgs(corrupt), {"corrupt.hdr"});
    expectNothingWritten();

    Image nan(64, 32, 3);
    nan.at(7, 3)[2] = std::nanf("");
    const std::string nanMap = tmp.file("nan.exr");
    ASSERT_TRUE(saveExr(nanMap, nan));
    expectCliRefuses(envmapArgs(nanMap), {"nan.exr", "texel (7, 3)", "not a finite number"});
    expectNothingWritten();

    const std::string square = tmp.file("square.exr");
    ASSERT_TRUE(saveExr(square, Image(32, 32, 3)));
    expectCliRefuses(envmapArgs(square), {"square.exr", "32x32", "twice its height"});
    expectNothingWritten();
}

TEST_F(EnvmapCli, RefusesAbsurdOptions) {
    const std::pair<std::string, std::string> cases[] = {
        {"--intensity -1", "--intensity"},    {"--intensity 0", "--intensity"},
        {"--intensity nan", "--intensity"},   {"--rotation 1000", "--rotation"},
        {"--sh-order 99", "--sh-order"},      {"--sh-order -1", "--sh-order"},
        {"--size 100", "power of two"},       {"--size 2", "--size"},
        {"--levels 9", "--levels"},           {"--samples 0", "--samples"},
        {"--lod-mapping unreal", "unreal"},   {"--dfg-size 3", "--dfg-size"},
        {"--dfg-samples 0", "--dfg-samples"},
    };
    for (const auto& [options, mention] : cases) {
        expectCliRefuses(envmapArgs(map, options), {mention});
        expectNothingWritten();
    }
}

TEST_F(EnvmapCli, SmallestMapGetsAnEightWideLevel) {
    Image tiny(4, 2, 3);
    for (float& v : tiny.pixels) v = 1.f;
    const std::string small = tmp.file("tiny.exr");
    ASSERT_TRUE(saveExr(small, tiny));
    std::string output;
    ASSERT_EQ(
        runCli("envmap " + shellArg(small) + quick + " -o " + shellArg(out.string()), &output), 0)
        << output;
    const json manifest = json::parse(fileBytes(out / "environment.json"));
    EXPECT_EQ(manifest["ggx"]["levels"][0]["width"], 8);
}

TEST_F(EnvmapCli, NeverReplacesAFolderItDidNotWrite) {
    fs::create_directories(out);
    writeBytes(out / "notes.txt", "mine");
    expectCliRefuses(envmapArgs(map), {"not an ndfmip environment folder"});
    EXPECT_EQ(fileBytes(out / "notes.txt"), "mine");
    EXPECT_TRUE(leftovers(tmp.path).empty());
}

} // namespace
} // namespace ndfmip::test
