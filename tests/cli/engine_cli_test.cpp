// bake --engine: each engine's normal map convention and packed material map.
#include <array>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "ndfmip/io.h"
#include "test_support.h"

namespace ndfmip {
namespace {

std::string slurp(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), {});
}

// The first texel of level 0 of an uncompressed RGBA8 DDS with the DX10 header (4 + 124 + 20 bytes).
std::array<int, 4> firstTexel(const std::string& dds) {
    const std::string bytes = slurp(dds);
    std::array<int, 4> out{};
    for (int c = 0; c < 4; ++c) out[c] = (unsigned char)bytes.at(148 + c);
    return out;
}

TEST(EngineCli, PackedMapsFollowEachEnginesLayout) {
    test::TempDir dir("ndfmip_engine");
    // Normals tilted in y (so the green convention shows) and a packed map: R occlusion 0.5,
    // G perceptual roughness 0.6, B metallic 0.25.
    Image normal(8, 8, 3), packed(8, 8, 4);
    for (size_t i = 0; i < 64; ++i) {
        normal.pixels[3 * i] = 0.5f, normal.pixels[3 * i + 1] = 0.8f, normal.pixels[3 * i + 2] = 0.9f;
        packed.pixels[4 * i] = 0.5f, packed.pixels[4 * i + 1] = 0.6f, packed.pixels[4 * i + 2] = 0.25f;
    }
    ASSERT_TRUE(savePng(dir.file("n.png"), normal, 16));
    ASSERT_TRUE(savePng(dir.file("m.png"), packed, 16));
    const std::string common = " --roughness-map " + test::shellArg(dir.file("m.png")) +
                               " --roughness-channel g --metallic-channel b --occlusion-channel r --export dds -q -o ";
    std::string output;
    for (const char* engine : {"unity", "gltf", "unreal"}) {
        const std::string out = dir.file(engine);
        ASSERT_EQ(test::runCli("bake " + test::shellArg(dir.file("n.png")) + " --engine " + engine + common + test::shellArg(out), &output), 0)
            << output;
    }
    // Unity's mask map: metallic, occlusion, detail mask 1, smoothness 1 - 0.6 (flat: no widening).
    EXPECT_EQ(firstTexel(dir.file("unity") + "/dds/unity_mask_map.dds"), (std::array<int, 4>{64, 128, 255, 102}));
    // glTF's ORM: occlusion, roughness, metallic.
    EXPECT_EQ(firstTexel(dir.file("gltf") + "/dds/gltf_occlusion_roughness_metallic.dds"), (std::array<int, 4>{128, 153, 64, 255}));
    // Unreal flips green: its BC5 normal map differs from glTF's for normals tilted in y.
    EXPECT_NE(slurp(dir.file("unreal") + "/dds/unreal_normal.dds"), slurp(dir.file("gltf") + "/dds/gltf_normal.dds"));
    test::expectCliRefuses("bake " + test::shellArg(dir.file("n.png")) + " --engine cryengine -o " + test::shellArg(dir.file("x")),
                           {"--engine", "cryengine", "unity"});
    test::expectCliRefuses("bake " + test::shellArg(dir.file("n.png")) + " --engine gltf --metallic-channel b -o " +
                               test::shellArg(dir.file("x")),
                           {"--metallic-channel", "--roughness-map"});
}

} // namespace
} // namespace ndfmip
