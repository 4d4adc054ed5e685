// glTF in, GLB out: every image and buffer byte kept, every property kept, and the texture
// sharing rule of filterGltf.
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "gltf_test_asset.h"
#include "io/gltf_asset.h"
#include "ndfmip/gltf.h"
#include "ndfmip/io.h"
#include "test_support.h"

namespace ndfmip {
namespace {

std::string bundledNormalMap() {
    return test::fileBytes(std::string(NDFMIP_SOURCE_DIR) + "/data/normalmaps/pyramidwall_256.png");
}

// A 256x256 packed map: R occlusion, G roughness, B metallic (8-bit PNG).
std::string materialMapPng() {
    Image m(256, 256, 3);
    for (int y = 0; y < 256; ++y)
        for (int x = 0; x < 256; ++x) {
            float* p = m.at(x, y);
            p[0] = 0.5f + 0.002f * float(x), p[1] = 0.1f + 0.003f * float(y),
            p[2] = float((x / 16 + y / 16) % 2);
        }
    return encodePng(m, 8).value();
}

TEST(GltfAsset, GltfToGlbKeepsEveryImageAndBufferByteForByte) {
    test::TempDir dir("gltf_asset");
    test::TestAsset asset = test::quadAsset();
    // A third image as a data URI, read by a texture of its own.
    const std::string tiny = encodePng(Image(2, 2, 3), 8).value();
    asset.json["images"].push_back({{"uri", "data:image/png;base64," + test::base64(tiny)}});
    asset.json["textures"].push_back({{"source", 2}});
    const std::string normal = bundledNormalMap(), material = materialMapPng();
    const std::string path =
        test::writeGltf(dir.path, asset, {{"normal map.png", normal}, {"orm.png", material}});
    // A uri is percent-encoded.
    std::string text = test::fileBytes(path);
    text.replace(text.find("normal map.png"), 14, "normal%20map.png");
    test::writeBytes(path, text);

    Result<GltfAsset> read = readGltf(path);
    ASSERT_TRUE(read) << read.error().message;
    const std::string originals[] = {normal, material, tiny};
    for (int k = 0; k < 3; ++k) {
        Result<std::string> bytes = gltfImageBytes(read.value(), k);
        ASSERT_TRUE(bytes) << bytes.error().message;
        EXPECT_EQ(bytes.value(), originals[k]) << "image " << k;
        EXPECT_EQ(read->json["images"][size_t(k)]["mimeType"], "image/png");
        EXPECT_FALSE(read->json["images"][size_t(k)].contains("uri"));
    }
    EXPECT_EQ(read->imageLabels[0], "image 0 'normal%20map.png'");

    Result<std::string> glb = glbFile(read.value());
    ASSERT_TRUE(glb) << glb.error().message;
    test::writeBytes(dir.path / "out.glb", glb.value());
    const test::Glb out = test::parseGlb(glb.value());
    ASSERT_TRUE(out.ok);
    for (size_t k = 0; k < 3; ++k) EXPECT_EQ(test::glbImage(out, k), originals[k]) << "image " << k;
    // The quad's bufferViews point at the same bytes as before, in the one buffer.
    ASSERT_EQ(out.json["buffers"].size(), 1u);
    EXPECT_FALSE(out.json["buffers"][0].contains("uri"));
    for (size_t v = 0; v < asset.json["bufferViews"].size(); ++v) {
        const auto& before = asset.json["bufferViews"][v];
        const auto& after = out.json["bufferViews"][v];
        EXPECT_EQ(
            out.bin.substr(after["byteOffset"].get<size_t>(), after["byteLength"].get<size_t>()),
            asset.bin.substr(before["byteOffset"].get<size_t>(),
                             before["byteLength"].get<size_t>()));
        EXPECT_EQ(after["byteOffset"].get<size_t>() % 4, 0u);
        EXPECT_EQ(after["target"], before["target"]);
    }
    for (const char* key : {"asset", "scene", "scenes", "nodes", "meshes", "materials", "samplers",
                            "textures", "accessors", "extras"})
        EXPECT_EQ(out.json[key], read->json[key]) << key;
    EXPECT_EQ(out.json["materials"], asset.json["materials"]);
    EXPECT_EQ(out.json["nodes"], asset.json["nodes"]);

    // And back in: the GLB reads to the same images.
    Result<GltfAsset> again = readGltf((dir.path / "out.glb").string());
    ASSERT_TRUE(again) << again.error().message;
    for (int k = 0; k < 3; ++k) EXPECT_EQ(gltfImageBytes(again.value(), k).value(), originals[k]);
}

TEST(GltfAsset, BrokenContainersAreOneLineErrors) {
    test::TempDir dir("gltf_broken");
    const std::string garbage = dir.file("garbage.gltf");
    test::writeBytes(garbage, "{\"asset\": {\"version\": \"2.0\"}, \"nodes\": [");
    for (const std::string& path : {garbage, dir.file("absent.gltf")}) {
        Result<GltfAsset> r = readGltf(path);
        ASSERT_FALSE(r);
        EXPECT_EQ(r.error().message.rfind(path + ": ", 0), 0u) << r.error().message;
        EXPECT_EQ(r.error().message.find('\n'), std::string::npos) << r.error().message;
    }
    // A missing image file is named.
    test::TestAsset asset = test::quadAsset();
    const std::string path = test::writeGltf(
        dir.path, asset, {{"normal.png", bundledNormalMap()}, {"orm.png", materialMapPng()}});
    std::filesystem::remove(dir.path / "orm.png");
    Result<GltfAsset> missing = readGltf(path);
    ASSERT_FALSE(missing);
    EXPECT_NE(missing.error().message.find("image 1 'orm.png'"), std::string::npos)
        << missing.error().message;
    EXPECT_NE(missing.error().message.find("No such file"), std::string::npos)
        << missing.error().message;
    // A uri naming a file that is no image is not embedded, whatever mimeType the asset claims.
    test::TestAsset secret = test::quadAsset();
    secret.json["images"][1]["mimeType"] = "image/png";
    const std::string claims = test::writeGltf(
        dir.path, secret, {{"normal.png", bundledNormalMap()}, {"notes.txt", "private text"}});
    Result<GltfAsset> text = readGltf(claims);
    ASSERT_FALSE(text);
    EXPECT_NE(text.error().message.find("image 1 'notes.txt': not an image file"),
              std::string::npos)
        << text.error().message;
    // A GLB whose JSON chunk runs past the end of the file.
    std::string glb = test::glbBytes(asset.json, asset.bin);
    glb.resize(40);
    test::writeBytes(dir.path / "cut.glb", glb);
    Result<GltfAsset> cut = readGltf(dir.file("cut.glb"));
    ASSERT_FALSE(cut);
    EXPECT_NE(cut.error().message.find("JSON chunk"), std::string::npos) << cut.error().message;
}

// A texture that another material reads without a normal map keeps its plain form there; the
// filtered material reads a copy of it that carries the DDS.
TEST(GltfFilter, SharedTextureIsCopiedForTheFilteredMaterial) {
    test::TempDir dir("gltf_shared");
    test::TestAsset asset = test::quadAsset();
    asset.json["materials"][1]["pbrMetallicRoughness"]["metallicRoughnessTexture"] = {{"index", 1}};
    const std::string path =
        test::writeGlb(dir.path / "in.glb", asset,
                       {{"image/png", bundledNormalMap()}, {"image/png", materialMapPng()}});
    Result<GltfFiltered> filtered = filterGltf(path);
    ASSERT_TRUE(filtered) << filtered.error().message;
    const test::Glb out = test::parseGlb(filtered->glb);
    ASSERT_TRUE(out.ok);
    const auto& textures = out.json["textures"];
    const auto& wall = out.json["materials"][0];
    // Texture 1 as it was (material 1 reads it); material 0 reads a copy for both its
    // metallicRoughness and its occlusion (ORM), with the same sampler and core source.
    EXPECT_EQ(textures[1], asset.json["textures"][1]);
    EXPECT_EQ(out.json["materials"][1], asset.json["materials"][1]);
    const size_t copy =
        wall["pbrMetallicRoughness"]["metallicRoughnessTexture"]["index"].get<size_t>();
    EXPECT_GE(copy, 2u);
    EXPECT_EQ(wall["occlusionTexture"]["index"], copy);
    EXPECT_EQ(textures[copy]["source"], 1);
    EXPECT_EQ(textures[copy]["sampler"], 0);
    EXPECT_TRUE(textures[copy]["extensions"]["MSFT_texture_dds"].contains("source"));
    // The normal texture, read by two filtered materials as a normal map, is changed in place.
    EXPECT_EQ(wall["normalTexture"]["index"], 0);
    EXPECT_TRUE(textures[0]["extensions"]["MSFT_texture_dds"].contains("source"));
    ASSERT_EQ(filtered->materials.size(), 2u);
    EXPECT_FALSE(filtered->materials[0].madeRoughnessMap);
    EXPECT_TRUE(filtered->materials[1].madeRoughnessMap);
}

} // namespace
} // namespace ndfmip
