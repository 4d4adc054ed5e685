// glTF in, GLB out: every image and buffer byte kept, every property kept, and the texture
// sharing rule of filterGltf.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "gltf_test_asset.h"
#include "io/gltf_asset.h"
#include "ndfmip/gltf.h"
#include "ndfmip/io.h"
#include "ndfmip/limits.h"
#include "test_support.h"

namespace ndfmip {
namespace {

// The DDS output (MSFT_texture_dds), which these tests check: it needs no Basis encoder.
GltfOptions ddsOnly() {
    GltfOptions options;
    options.textureFormat = GltfTextureFormat::Dds;
    return options;
}

namespace fs = std::filesystem;

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

// The input limits in force for one test.
struct ScopedLimits {
    InputLimits saved = inputLimits();
    explicit ScopedLimits(const InputLimits& limits) { setInputLimits(limits); }
    ~ScopedLimits() { setInputLimits(saved); }
};

// A GLB of the given chunks (type, bytes) as they are, with header version `version` and a
// header length of the bytes written plus `lengthSlack`.
std::string glbOfChunks(const std::vector<std::pair<uint32_t, std::string>>& chunks,
                        uint32_t version = 2) {
    std::string body;
    for (const auto& [type, bytes] : chunks) {
        test::appendU32(body, uint32_t(bytes.size()));
        test::appendU32(body, type);
        body += bytes;
    }
    std::string out;
    test::appendU32(out, 0x46546C67);
    test::appendU32(out, version);
    test::appendU32(out, uint32_t(12 + body.size()));
    return out + body;
}

constexpr uint32_t kJson = 0x4E4F534A, kBin = 0x004E4942;

std::string padded(std::string text, char with) {
    text.resize((text.size() + 3) / 4 * 4, with);
    return text;
}

void expectRefusal(const Result<GltfAsset>& r, const std::string& path, const std::string& says) {
    ASSERT_FALSE(r) << path << " read, expected: " << says;
    EXPECT_EQ(r.error().message.rfind(path + ": ", 0), 0u) << r.error().message;
    EXPECT_EQ(r.error().message.find('\n'), std::string::npos) << r.error().message;
    EXPECT_NE(r.error().message.find(says), std::string::npos) << r.error().message;
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

// The GLB container is read strictly: version 2, the header's length, JSON first, at most one
// BIN chunk right after it, chunks 4-byte aligned; the asset's glTF version 2.x.
TEST(GltfAsset, GlbContainerIsReadStrictly) {
    test::TempDir dir("gltf_strict");
    const test::TestAsset asset = test::quadAsset();
    const std::string json = padded(asset.json.dump(), ' '), bin = padded(asset.bin, '\0');
    auto check = [&](const std::string& name, const std::string& bytes, const std::string& says) {
        const std::string path = dir.file(name);
        test::writeBytes(path, bytes);
        Result<GltfAsset> r = readGltf(path);
        if (says.empty()) {
            ASSERT_TRUE(r) << name << ": " << r.error().message;
            EXPECT_EQ(r->buffers.at(0), asset.bin);
        } else {
            expectRefusal(r, path, says);
        }
    };
    check("good.glb", glbOfChunks({{kJson, json}, {kBin, bin}}), "");
    // Chunks of unknown types after BIN are skipped, as the format says.
    check("extra.glb", glbOfChunks({{kJson, json}, {kBin, bin}, {0x12345678, "abcd"}}), "");
    check("v1.glb", glbOfChunks({{kJson, json}, {kBin, bin}}, 1), "GLB version 1");
    check("v99.glb", glbOfChunks({{kJson, json}, {kBin, bin}}, 99), "GLB version 99");
    check("trailing.glb", glbOfChunks({{kJson, json}, {kBin, bin}}) + std::string(8, '\0'),
          "8 bytes after the end of the GLB");
    std::string longer = glbOfChunks({{kJson, json}, {kBin, bin}});
    const uint32_t claimed = uint32_t(longer.size() + 4); // 4 bytes more than the file has
    std::memcpy(&longer[8], &claimed, 4);
    check("short.glb", longer, "the GLB header declares");
    check("twobins.glb", glbOfChunks({{kJson, json}, {kBin, bin}, {kBin, bin}}),
          "a second BIN chunk");
    check("binfirst.glb", glbOfChunks({{kBin, bin}, {kJson, json}}), "first chunk is not JSON");
    check("twojson.glb", glbOfChunks({{kJson, json}, {kJson, json}, {kBin, bin}}),
          "a second JSON chunk");
    check("unaligned.glb", glbOfChunks({{kJson, json + "  "}, {kBin, bin}}), "not a multiple of 4");
    // The glTF version, in a GLB and in a .gltf.
    test::TestAsset three = asset;
    three.json["asset"]["version"] = "3.0";
    check("three.glb", glbOfChunks({{kJson, padded(three.json.dump(), ' ')}, {kBin, bin}}),
          "asset.version '3.0'");
    three.json.erase("asset");
    check("noversion.glb", glbOfChunks({{kJson, padded(three.json.dump(), ' ')}, {kBin, bin}}),
          "no asset.version");
    test::TestAsset one = asset;
    one.json["asset"]["version"] = "1.0";
    const std::string gltf = test::writeGltf(dir.path, one, {});
    expectRefusal(readGltf(gltf), gltf, "asset.version '1.0'");
}

// A .gltf's JSON, data URIs aside, is held to the text limit before it is parsed.
TEST(GltfAsset, GltfJsonIsHeldToTheTextLimit) {
    test::TempDir dir("gltf_text");
    InputLimits limits = inputLimits();
    limits.maxTextFileBytes = 64 << 10;
    ScopedLimits scoped(limits);
    test::TestAsset asset = test::quadAsset();
    for (int k = 0; k < 30000; ++k) asset.json["nodes"].push_back(test::OrderedJson::object());
    const std::string nodes = test::writeGltf(dir.path, asset, {});
    expectRefusal(readGltf(nodes), nodes, "above the limit of 64.0 KiB");
    // An embedded image larger than the limit is no structure: it reads.
    test::TestAsset embedded = test::quadAsset();
    Image noise(160, 160, 3);
    uint32_t state = 12345;
    for (float& v : noise.pixels) {
        state = state * 1664525u + 1013904223u; // an LCG's high byte: incompressible enough
        v = float(state >> 24) / 255.f;
    }
    const std::string png = encodePng(noise, 8).value();
    ASSERT_GT(png.size(), size_t(64 << 10));
    embedded.json["images"][0]["uri"] = "data:image/png;base64," + test::base64(png);
    embedded.json["images"].erase(1);
    const std::string path = test::writeGltf(dir.path, embedded, {});
    Result<GltfAsset> read = readGltf(path);
    ASSERT_TRUE(read) << read.error().message;
    EXPECT_EQ(gltfImageBytes(read.value(), 0).value(), png);
}

// Buffer and image uris name files inside the asset's folder; anything else needs allowOutside,
// and NUL or control characters are refused always.
TEST(GltfAsset, UrisStayInsideTheAssetFolder) {
    test::TempDir dir("gltf_uris");
    const fs::path folder = dir.path / "asset";
    fs::create_directories(folder / "sub");
    const test::TestAsset asset = test::quadAsset();
    test::writeBytes(dir.path / "outside.bin", asset.bin);
    test::writeBytes(folder / "quad.bin", asset.bin);
    fs::create_symlink("../outside.bin", folder / "link.bin");
    const std::string absolute = (dir.path / "outside.bin").string();
    auto withBufferUri = [&](const std::string& uri) {
        test::TestAsset a = asset;
        a.json["images"] = test::OrderedJson::array();
        a.json["buffers"][0]["uri"] = uri;
        const std::string path = (folder / "asset.gltf").string();
        test::writeBytes(path, a.json.dump());
        return path;
    };
    struct Case {
        std::string uri, says;
        bool allowed; // read with allowOutside
    };
    const std::vector<Case> refused = {
        {absolute, "an absolute path", true},
        {"file://" + absolute, "file: uri", true},
        {"../outside.bin", "'..' climbs", true},
        {"sub/../../outside.bin", "'..' climbs", true},
        {"%2e%2e/outside.bin", "'..' climbs", true},
        {"sub%2F..%2F..%2Foutside.bin", "percent-encoded separator", true},
        {"link.bin", "real path", true},
        {"quad.bin%00.png", "NUL or control character", false},
        {"quad.bin\x01", "NUL or control character", false},
        {"http://example.com/quad.bin", "ndfmip reads files only", false},
    };
    for (const Case& c : refused) {
        const std::string path = withBufferUri(c.uri);
        Result<GltfAsset> r = readGltf(path);
        expectRefusal(r, path, c.says);
        if (!r) {
            EXPECT_NE(r.error().message.find(quote(c.uri)), std::string::npos) << r.error().message;
        }
        Result<GltfAsset> allowed = readGltf(path, true);
        EXPECT_EQ(bool(allowed), c.allowed) << c.uri;
        if (allowed) {
            EXPECT_EQ(allowed->buffers.at(0), asset.bin) << c.uri;
        }
    }
    // Inside the folder, by any spelling.
    for (const std::string uri : {"quad.bin", "sub/../quad.bin", "./quad.bin", "qu%61d.bin"}) {
        Result<GltfAsset> r = readGltf(withBufferUri(uri));
        ASSERT_TRUE(r) << uri << ": " << r.error().message;
        EXPECT_EQ(r->buffers.at(0), asset.bin);
    }
    // Images too.
    test::writeBytes(dir.path / "outside.png", bundledNormalMap());
    test::TestAsset a = asset;
    a.json["buffers"][0]["uri"] = "quad.bin";
    a.json["images"][0]["uri"] = "../outside.png";
    a.json["images"].erase(1);
    const std::string path = (folder / "image.gltf").string();
    test::writeBytes(path, a.json.dump());
    expectRefusal(readGltf(path), path, "image 0 '../outside.png': '..' climbs");
    EXPECT_TRUE(readGltf(path, true));
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
    Result<GltfFiltered> filtered = filterGltf(path, ddsOnly());
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

// Every image of a GLB is read by a texture (as its source or through an extension) and every
// bufferView by an accessor or an image: nothing orphaned.
void expectNothingOrphaned(const test::Glb& glb) {
    std::set<size_t> images, views;
    for (const auto& texture : glb.json["textures"]) {
        if (texture.contains("source")) images.insert(texture["source"].get<size_t>());
        if (texture.contains("extensions"))
            for (const auto& [name, extension] : texture["extensions"].items())
                if (extension.contains("source")) images.insert(extension["source"].get<size_t>());
    }
    for (size_t i = 0; i < glb.json["images"].size(); ++i) {
        EXPECT_TRUE(images.count(i)) << "image " << i << " is read by no texture";
        views.insert(glb.json["images"][i]["bufferView"].get<size_t>());
    }
    for (const auto& accessor : glb.json["accessors"])
        views.insert(accessor["bufferView"].get<size_t>());
    for (size_t v = 0; v < glb.json["bufferViews"].size(); ++v)
        EXPECT_TRUE(views.count(v)) << "bufferView " << v << " is read by nothing";
    // And the binary chunk holds nothing past the last bufferView (save alignment).
    size_t end = 0;
    for (const auto& view : glb.json["bufferViews"])
        end = std::max(end, view.value("byteOffset", size_t(0)) + view["byteLength"].get<size_t>());
    EXPECT_LE(glb.bin.size(), (end + 3) / 4 * 4);
}

// Materials that read the same images with the same options share one decode, one bake and one
// set of images: the output grows by the materials' JSON alone.
TEST(GltfFilter, SharedImagesAreDecodedAndBakedOnce) {
    test::TempDir dir("gltf_lean");
    auto filtered = [&](int clones, bool otherFactor) {
        test::TestAsset asset = test::quadAsset();
        for (int k = 0; k < clones; ++k) {
            auto wall = asset.json["materials"][0];
            wall["name"] = "Wall " + std::to_string(k);
            asset.json["materials"].push_back(wall);
        }
        if (otherFactor) {
            auto wall = asset.json["materials"][0];
            wall["pbrMetallicRoughness"]["roughnessFactor"] = 0.7;
            asset.json["materials"].push_back(wall);
        }
        const fs::path folder = dir.path / (std::to_string(clones) + (otherFactor ? "f" : ""));
        fs::create_directories(folder);
        const std::string path =
            test::writeGlb(folder / "in.glb", asset,
                           {{"image/png", bundledNormalMap()}, {"image/png", materialMapPng()}});
        Result<GltfFiltered> r = filterGltf(path, ddsOnly());
        EXPECT_TRUE(r) << r.error().message;
        return r ? std::move(r.value()) : GltfFiltered{};
    };
    const GltfFiltered base = filtered(0, false), many = filtered(60, false);
    // Two images (normal, material map); two bakes: 'Wall' (its map, factor 0.9) and 'Plain'
    // (no map, factor 0.5), however many materials read them.
    for (const GltfFiltered* f : {&base, &many}) {
        EXPECT_EQ(f->decodedImages, 2);
        EXPECT_EQ(f->bakes, 2);
    }
    ASSERT_EQ(many.materials.size(), base.materials.size() + 60);
    const test::Glb a = test::parseGlb(base.glb), b = test::parseGlb(many.glb);
    ASSERT_TRUE(a.ok && b.ok);
    EXPECT_EQ(b.json["images"].size(), a.json["images"].size());
    EXPECT_EQ(b.json["textures"].size(), a.json["textures"].size());
    EXPECT_EQ(b.bin, a.bin);
    // Each clone reads what 'Wall' reads.
    const size_t wallJson = b.json["materials"][0].dump().size();
    for (size_t m = 3; m < b.json["materials"].size(); ++m) {
        auto clone = b.json["materials"][m];
        clone["name"] = "Wall";
        EXPECT_EQ(clone, b.json["materials"][0]) << "material " << m;
    }
    // 60 materials of ("Wall k": 2 or 3 more name bytes) and a comma each, JSON padding aside.
    EXPECT_LE(many.glb.size(), base.glb.size() + 60 * (wallJson + 1 + 3) + 3);
    expectNothingOrphaned(b);
    // Another roughnessFactor is another bake, of the same decoded images.
    const GltfFiltered other = filtered(0, true);
    EXPECT_EQ(other.decodedImages, 2);
    EXPECT_EQ(other.bakes, 3);
}

// --max-memory is checked against the size the normal image's header declares, before it is
// decoded: a PNG header of 16000x16000 with nothing after it is refused for memory.
TEST(GltfFilter, MemoryLimitIsCheckedBeforeDecoding) {
    test::TempDir dir("gltf_memory");
    InputLimits limits = inputLimits();
    limits.maxMemoryBytes = int64_t(1) << 30;
    ScopedLimits scoped(limits);
    std::string png = "\x89PNG\r\n\x1a\n";
    test::appendU32(png, 0x0D000000); // length 13, big-endian
    png += "IHDR";
    for (uint32_t side : {16000u, 16000u})
        for (int shift : {24, 16, 8, 0}) png += char((side >> shift) & 0xFF);
    png += std::string("\x08\x02\x00\x00\x00", 5);
    test::appendU32(png, 0); // CRC, not checked before the size
    const std::string path = test::writeGlb(dir.path / "in.glb", test::quadAsset(),
                                            {{"image/png", png}, {"image/png", materialMapPng()}});
    Result<GltfFiltered> r = filterGltf(path, ddsOnly());
    ASSERT_FALSE(r);
    const std::string& m = r.error().message;
    EXPECT_EQ(m.rfind(path + ": material 0 'Wall'", 0), 0u) << m;
    EXPECT_NE(m.find("16000x16000 normal map needs about"), std::string::npos) << m;
    EXPECT_NE(m.find("above the limit of 1.0 GiB; --max-memory"), std::string::npos) << m;
}

// ndfmip gltf on its own output replaces its own images: nothing orphaned, the same materials
// and textures, the same size; a third pass gives the second's bytes.
TEST(GltfFilter, RerunOnItsOwnOutputReplacesItsImages) {
    for (bool shared : {false, true}) {
        test::TempDir dir("gltf_rerun");
        test::TestAsset asset = test::quadAsset();
        // Material 1 reads the ORM texture without a normal map: 'Wall' gets a copy of it.
        if (shared)
            asset.json["materials"][1]["pbrMetallicRoughness"]["metallicRoughnessTexture"] = {
                {"index", 1}};
        const std::string input = test::writeGltf(
            dir.path, asset, {{"normal.png", bundledNormalMap()}, {"orm.png", materialMapPng()}});
        std::vector<std::string> passes;
        std::string from = input;
        for (int pass = 0; pass < 3; ++pass) {
            Result<GltfFiltered> r = filterGltf(from, ddsOnly());
            ASSERT_TRUE(r) << r.error().message;
            EXPECT_EQ(r->replacedImages, pass == 0 ? 0 : 4)
                << "pass " << pass; // BC5, RGBA8 x2, PNG
            passes.push_back(r->glb);
            from = dir.file("pass" + std::to_string(pass) + ".glb");
            test::writeBytes(from, r->glb);
        }
        const test::Glb first = test::parseGlb(passes[0]), second = test::parseGlb(passes[1]);
        ASSERT_TRUE(first.ok && second.ok);
        for (const char* key : {"materials", "textures", "bufferViews", "accessors"})
            EXPECT_EQ(second.json[key], first.json[key]) << key << (shared ? ", shared" : "");
        // The images' names aside: the first pass named its DDS after the original's uri.
        ASSERT_EQ(second.json["images"].size(), first.json["images"].size());
        for (size_t i = 0; i < first.json["images"].size(); ++i) {
            auto a = first.json["images"][i], b = second.json["images"][i];
            a.erase("name"), b.erase("name");
            EXPECT_EQ(b, a) << "image " << i;
        }
        EXPECT_EQ(second.bin, first.bin);
        EXPECT_LE(std::abs(double(passes[1].size()) - double(passes[0].size())),
                  0.01 * double(passes[0].size()));
        EXPECT_EQ(passes[2], passes[1]);
        expectNothingOrphaned(second);
    }
}

} // namespace
} // namespace ndfmip
