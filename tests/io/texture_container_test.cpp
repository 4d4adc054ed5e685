// KTX2 and DDS files: their structure, and their blocks decoded by readers ndfmip did not
// write (libnvtt's nvdecompress for DDS; the npm package ktx-parse for KTX2, where installed).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

#include <glm/glm.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "ndfmip/io.h"
#include "ndfmip/normal_map.h"
#include "ndfmip/pyramid.h"
#include "ndfmip/texture_container.h"
#include "test_support.h"

namespace ndfmip {
namespace {

template <typename T> T read(const std::string& bytes, size_t at) {
    T v;
    std::memcpy(&v, bytes.data() + at, sizeof v);
    return v;
}

// Encoded normals (n + 1)/2 of every level: the bundled wall map's (real data, 256x256), or a
// 64x48 synthetic one.
std::vector<Image> encodedNormalLevels(bool real = false) {
    SharedImage normals;
    if (real) {
        DecodeOptions decode;
        decode.greenDown = true;
        Result<Image> map =
            loadNormalMap(std::string(NDFMIP_SOURCE_DIR) + "/data/normalmaps/pyramidwall_256.png",
                          decode, nullptr);
        if (map) normals = std::make_shared<const Image>(std::move(map.value()));
    }
    if (!normals) {
        auto synthetic = std::make_shared<Image>(64, 48, 3);
        for (int y = 0; y < 48; ++y)
            for (int x = 0; x < 64; ++x) {
                const glm::vec3 n = glm::normalize(glm::vec3(
                    0.6f * std::sin(0.3f * float(x)), 0.5f * std::cos(0.4f * float(y)), 1.f));
                float* p = synthetic->at(x, y);
                p[0] = n.x, p[1] = n.y, p[2] = n.z;
            }
        normals = synthetic;
    }
    const Pyramid pyramid = buildPyramid(normals);
    std::vector<Image> means{*normals}; // the pyramid's mean normals, level after level
    for (int k = 1; k < int(pyramid.levels.size()); ++k)
        means.push_back(averageToLevel(pyramid, means.back(), k));
    std::vector<Image> levels;
    for (Image mean : means) {
        for (size_t i = 0; i < mean.texelCount(); ++i) {
            float* p = &mean.pixels[3 * i];
            const float len = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
            for (int c = 0; c < 3; ++c) p[c] = 0.5f * (p[c] / len + 1.f);
        }
        levels.push_back(std::move(mean));
    }
    return levels;
}

std::vector<const Image*> pointers(const std::vector<Image>& levels) {
    std::vector<const Image*> out;
    for (const Image& image : levels) out.push_back(&image);
    return out;
}

// rowsOf hands an image over a row at a time: its own channels copied, more filled, fewer cut;
// the owning form keeps the image alive after the caller drops it.
TEST(TextureContainer, RowsOfAnImagePadCutAndOwn) {
    Image rgb(2, 2, 3);
    for (size_t i = 0; i < rgb.pixels.size(); ++i) rgb.pixels[i] = float(i) + 0.5f;
    std::vector<float> row(8);
    const LevelRows same = rowsOf(rgb);
    EXPECT_EQ(same.channels, 3);
    same.row(1, row.data());
    EXPECT_EQ(std::vector<float>(row.begin(), row.begin() + 6),
              std::vector<float>(rgb.at(0, 1), rgb.at(0, 1) + 6));
    const LevelRows opaque = rowsOf(rgb, 4, 1.f);
    EXPECT_EQ(opaque.channels, 4);
    opaque.row(1, row.data());
    EXPECT_EQ(row, (std::vector<float>{6.5f, 7.5f, 8.5f, 1.f, 9.5f, 10.5f, 11.5f, 1.f}));
    const LevelRows two = rowsOf(rgb, 2);
    two.row(0, row.data());
    EXPECT_EQ(std::vector<float>(row.begin(), row.begin() + 4),
              (std::vector<float>{0.5f, 1.5f, 3.5f, 4.5f}));
    auto shared = std::make_shared<const Image>(rgb);
    const std::weak_ptr<const Image> watch = shared;
    LevelRows owned = rowsOf(std::move(shared), 4, 0.f);
    EXPECT_FALSE(watch.expired());
    owned.row(0, row.data());
    EXPECT_EQ(row, (std::vector<float>{0.5f, 1.5f, 2.5f, 0.f, 3.5f, 4.5f, 5.5f, 0.f}));
    owned.row = nullptr;
    EXPECT_TRUE(watch.expired());
}

TEST(TextureContainer, Ktx2HeaderLevelIndexAndDescriptor) {
    const std::vector<Image> levels = encodedNormalLevels();
    Result<EncodedTexture> t = encodeTexture(pointers(levels), TextureFormat::Bc5Unorm);
    ASSERT_TRUE(t) << t.error().message;
    const std::string file = ktx2File(t.value()).value();
    ASSERT_EQ(file.compare(0, 12, std::string("\xABKTX 20\xBB\r\n\x1A\n", 12)), 0);
    EXPECT_EQ(read<uint32_t>(file, 12), 141u); // VK_FORMAT_BC5_UNORM_BLOCK
    EXPECT_EQ(read<uint32_t>(file, 20), 64u);
    EXPECT_EQ(read<uint32_t>(file, 24), 48u);
    const uint32_t levelCount = read<uint32_t>(file, 40);
    ASSERT_EQ(levelCount, levels.size());
    for (uint32_t k = 0; k < levelCount; ++k) {
        const uint64_t offset = read<uint64_t>(file, 80 + 24 * k),
                       length = read<uint64_t>(file, 88 + 24 * k);
        const int w = std::max(64 >> k, 1), h = std::max(48 >> k, 1);
        EXPECT_EQ(length, uint64_t(((w + 3) / 4) * ((h + 3) / 4) * 16)) << k;
        EXPECT_EQ(offset % 16, 0u) << k;
        ASSERT_LE(offset + length, file.size());
        EXPECT_EQ(file.compare(offset, length, t->levels[k]), 0);
    }
    const uint32_t dfdAt = read<uint32_t>(file, 48), dfdLength = read<uint32_t>(file, 52);
    EXPECT_EQ(read<uint32_t>(file, dfdAt), dfdLength);
    EXPECT_EQ(uint8_t(file[dfdAt + 12]), 132); // KHR_DF_MODEL_BC5
}

// The bar: BC5 normals >= 40 dB and BC4 roughness >= 45 dB PSNR on every level, on the bundled
// real map (stb_dxt's encoder; a synthetic map of 4-texel sines reaches only 37 dB at levels 1-2).
TEST(TextureContainer, Bc5AndBc4DecodedByNvdecompressKeepEveryLevel) {
    if (!std::filesystem::exists("/usr/bin/nvdecompress"))
        GTEST_SKIP() << "nvdecompress (libnvtt-bin) not installed";
    test::TempDir dir("ndfmip_dds");
    const std::vector<Image> levels = encodedNormalLevels(true);
    std::vector<Image>
        roughness; // one channel: the encoded normal's blue, a smooth field in [0.5, 1]
    for (const Image& level : levels) {
        Image r(level.width, level.height, 1);
        for (size_t i = 0; i < r.texelCount(); ++i) r.pixels[i] = level.pixels[3 * i + 2];
        roughness.push_back(std::move(r));
    }
    const std::pair<TextureFormat, const std::vector<Image>*> cases[] = {
        {TextureFormat::Bc5Unorm, &levels}, {TextureFormat::Bc4Unorm, &roughness}};
    for (const auto& [format, source] : cases) {
        Result<EncodedTexture> all = encodeTexture(pointers(*source), format);
        ASSERT_TRUE(all);
        // Every level as its own one-level file (nvdecompress decodes the top level only); the
        // blocks are the full file's.
        for (size_t k = 0; k < source->size(); ++k) {
            EncodedTexture one = all.value();
            one.width = (*source)[k].width;
            one.height = (*source)[k].height;
            one.levels = {all->levels[k]};
            const std::string dds =
                dir.file(std::string(textureFormatName(format)) + "_" + std::to_string(k) + ".dds");
            // The legacy FourCC header: NVIDIA Texture Tools 2 decodes BC4/BC5 only from it (the
            // blocks are the same as in the DX10 file; its header is checked by nvddsinfo below).
            Result<std::string> legacy = ddsFileLegacy(one);
            ASSERT_TRUE(legacy);
            std::ofstream(dds, std::ios::binary) << legacy.value();
            const std::string command = "cd " + test::shellArg(dir.path.string()) +
                                        " && nvdecompress " + test::shellArg(dds) +
                                        " > /dev/null 2>&1";
            ASSERT_EQ(std::system(command.c_str()), 0) << dds;
            Result<SourceImage> decoded =
                loadImage(std::filesystem::path(dds).replace_extension(".tga").string());
            ASSERT_TRUE(decoded) << decoded.error().message;
            const Image& d = decoded->image;
            ASSERT_EQ(d.width, one.width);
            ASSERT_EQ(d.height, one.height);
            // PSNR over the channels the format holds (nvdecompress writes BC4 red, BC5 red and
            // green).
            const int channels = format == TextureFormat::Bc5Unorm ? 2 : 1;
            double squared = 0.0;
            for (int y = 0; y < d.height; ++y)
                for (int x = 0; x < d.width; ++x)
                    for (int c = 0; c < channels; ++c) {
                        const double e = double(d.at(x, y)[c]) - double((*source)[k].at(x, y)[c]);
                        squared += e * e;
                    }
            const double psnr =
                10.0 *
                std::log10(1.0 /
                           std::max(squared / double(d.texelCount() * size_t(channels)), 1e-12));
            EXPECT_GE(psnr, format == TextureFormat::Bc5Unorm ? 40.0 : 45.0)
                << textureFormatName(format) << " level " << k;
            std::printf("%s level %zu (%dx%d): %.1f dB\n", textureFormatName(format), k, d.width,
                        d.height, psnr);
        }
    }
}

// The npm package ktx-parse's ES module, or "" where node or the package is missing.
std::string ktxParseModule() {
    const char* modules = std::getenv("NDFMIP_NODE_MODULES");
    const std::string path =
        modules ? modules : std::string(NDFMIP_SOURCE_DIR) + "/.npm/node_modules";
    if (!std::filesystem::exists("/usr/bin/node")) return "";
    // dist/ktx-parse.modern.js in 1.x, dist/index.mjs in 2.x.
    for (const char* candidate :
         {"/ktx-parse/dist/ktx-parse.modern.js", "/ktx-parse/dist/index.mjs"})
        if (std::filesystem::exists(path + candidate)) return path + candidate;
    return "";
}

// Runs `script` (an ES module reading the KTX2 file given as its argument) and returns what it
// printed.
std::string runNode(const test::TempDir& dir, const std::string& script, const std::string& file) {
    const std::string source = dir.file("read.mjs"), out = dir.file("out.json");
    std::ofstream(source) << script;
    const int status = std::system(("node " + test::shellArg(source) + " " + test::shellArg(file) +
                                    " > " + test::shellArg(out) + " 2>&1")
                                       .c_str());
    std::ifstream in(out);
    std::string printed((std::istreambuf_iterator<char>(in)), {});
    return status == 0 ? printed : "node failed: " + printed;
}

TEST(TextureContainer, Ktx2ReadBackByKtxParse) {
    const std::string module = ktxParseModule();
    if (module.empty())
        GTEST_SKIP()
            << "node and the npm package ktx-parse (scripts/setup installs it into .npm) not found";
    test::TempDir dir("ndfmip_ktx_parse");
    const std::vector<Image> levels = encodedNormalLevels();
    const std::pair<TextureFormat, int> cases[] = {
        {TextureFormat::Bc5Unorm, 0},  {TextureFormat::Rgba32F, 0},  {TextureFormat::Rgba16F, 0},
        {TextureFormat::Rg16Unorm, 0}, {TextureFormat::Bc5Unorm, 9}, {TextureFormat::Rgba16F, 3}};
    for (const auto& [format, zstd] : cases) {
        Result<EncodedTexture> t = encodeTexture(pointers(levels), format);
        ASSERT_TRUE(t);
        const std::string file =
            dir.file(std::string(textureFormatName(format)) + std::to_string(zstd) + ".ktx2");
        std::ofstream(file, std::ios::binary) << ktx2File(t.value(), zstd).value();
        const std::string json =
            runNode(dir,
                    "import { read } from '" + module +
                        "';\n"
                        "import { readFileSync } from 'fs';\n"
                        "const c = read(new Uint8Array(readFileSync(process.argv[2])));\n"
                        "console.log(JSON.stringify({format: c.vkFormat, w: c.pixelWidth, h: "
                        "c.pixelHeight, "
                        "levels: c.levels.map(l => l.uncompressedByteLength), scheme: "
                        "c.supercompressionScheme, "
                        "model: c.dataFormatDescriptor[0].colorModel}));\n",
                    file);
        EXPECT_NE(json.find("\"w\":64,\"h\":48"), std::string::npos) << json;
        std::string lengths = "[";
        for (size_t k = 0; k < t->levels.size(); ++k) {
            if (k) lengths += ',';
            lengths += std::to_string(t->levels[k].size());
        }
        EXPECT_NE(json.find("\"levels\":" + lengths + "]"), std::string::npos) << json;
        EXPECT_NE(json.find("\"scheme\":" + std::to_string(zstd > 0 ? 2 : 0)), std::string::npos)
            << json;
    }
}

// Zstandard supercompression: every level inflated by the zstd tool (an independent decoder)
// is the uncompressed level; the level index holds both lengths; levels are packed unaligned.
TEST(TextureContainer, Ktx2ZstdLevelsInflateToTheLevels) {
    if (std::system("zstd --version > /dev/null 2>&1") != 0)
        GTEST_SKIP() << "the zstd tool is not installed";
    test::TempDir dir("ndfmip_ktx_zstd");
    const std::vector<Image> levels = encodedNormalLevels();
    Result<EncodedTexture> t = encodeTexture(pointers(levels), TextureFormat::Rgba16F);
    ASSERT_TRUE(t);
    const std::string file = ktx2File(t.value(), 19).value();
    EXPECT_EQ(read<uint32_t>(file, 44), 2u); // supercompressionScheme: Zstandard
    EXPECT_LT(file.size(), ktx2File(t.value()).value().size());
    for (uint32_t k = 0; k < t->levels.size(); ++k) {
        const uint64_t offset = read<uint64_t>(file, 80 + 24 * k),
                       length = read<uint64_t>(file, 88 + 24 * k);
        EXPECT_EQ(read<uint64_t>(file, 96 + 24 * k), t->levels[k].size());
        ASSERT_LE(offset + length, file.size());
        const std::string packed = dir.file("level" + std::to_string(k) + ".zst");
        std::ofstream(packed, std::ios::binary) << file.substr(offset, length);
        ASSERT_EQ(std::system(("zstd -q -d -f " + test::shellArg(packed) + " -o " +
                               test::shellArg(packed + ".raw"))
                                  .c_str()),
                  0);
        std::ifstream in(packed + ".raw", std::ios::binary);
        const std::string raw((std::istreambuf_iterator<char>(in)), {});
        EXPECT_EQ(raw, t->levels[k]) << "level " << k;
    }
    EXPECT_FALSE(ktx2File(t.value(), 23));
}

// The key/value data as KTX 2.0 section 3.11 lays it out, byte for byte: each entry its length
// (key and value with their NULs), padded to 4 bytes, sorted by key ("KTXswizzle" < "KTXwriter"
// < "ndfmip", upper case first); its offset and length in the header, right after the DFD; the
// levels after it, where the level index says, supercompressed or not. Our reader gives the
// values back.
TEST(TextureContainer, Ktx2KeyValueDataLaidOutAsTheSpecificationSays) {
    const std::vector<Image> levels = encodedNormalLevels();
    Result<EncodedTexture> t = encodeTexture(pointers(levels), TextureFormat::Bc5Unorm);
    ASSERT_TRUE(t);
    const std::string about = "{\"content\":\"normal\"}"; // 20 bytes
    for (const int zstd : {0, 5}) {
        const std::string file =
            ktx2File(t.value(), zstd, {{"ndfmip", about}, {"KTXswizzle", "rg01"}}).value();
        Result<Ktx2KeyValues> kv = readKtx2KeyValues(file);
        ASSERT_TRUE(kv) << kv.error().message;
        ASSERT_EQ(kv->size(), 3u);
        EXPECT_EQ(kv->at("KTXswizzle"), "rg01");
        EXPECT_EQ(kv->at("ndfmip"), about);
        const std::string writer = kv->at("KTXwriter");
        EXPECT_EQ(writer.rfind("ndfmip ", 0), 0u) << writer;
        auto entry = [](const std::string& key, const std::string& value) {
            std::string e(4, '\0');
            const uint32_t n = uint32_t(key.size() + value.size() + 2);
            std::memcpy(&e[0], &n, 4);
            e += key + '\0' + value + '\0';
            e.resize((e.size() + 3) / 4 * 4, '\0');
            return e;
        };
        const std::string expected =
            entry("KTXswizzle", "rg01") + entry("KTXwriter", writer) + entry("ndfmip", about);
        EXPECT_EQ(expected.substr(0, 20),
                  std::string("\x10\0\0\0KTXswizzle\0rg01\0", 20)); // 16 bytes, no padding
        const uint32_t dfdAt = read<uint32_t>(file, 48), dfdLength = read<uint32_t>(file, 52);
        const uint32_t kvdAt = read<uint32_t>(file, 56), kvdLength = read<uint32_t>(file, 60);
        EXPECT_EQ(kvdAt, dfdAt + dfdLength);
        EXPECT_EQ(kvdAt % 4, 0u);
        ASSERT_EQ(kvdLength, expected.size());
        EXPECT_EQ(file.substr(kvdAt, kvdLength), expected);
        EXPECT_EQ(read<uint64_t>(file, 64), 0u); // no supercompression global data
        EXPECT_EQ(read<uint64_t>(file, 72), 0u);
        for (uint32_t k = 0; k < t->levels.size(); ++k) {
            const uint64_t offset = read<uint64_t>(file, 80 + 24 * k),
                           length = read<uint64_t>(file, 88 + 24 * k);
            EXPECT_GE(offset, kvdAt + kvdLength) << k;
            ASSERT_LE(offset + length, file.size());
            if (zstd == 0) {
                EXPECT_EQ(file.compare(offset, length, t->levels[k]), 0) << k;
            }
        }
    }
    // KTXwriter given is kept; a key that cannot be written is refused.
    EXPECT_EQ(
        readKtx2KeyValues(ktx2File(t.value(), 0, {{"KTXwriter", "x 1"}}).value())->at("KTXwriter"),
        "x 1");
    EXPECT_FALSE(ktx2File(t.value(), 0, {{"", "v"}}));
    EXPECT_FALSE(ktx2File(t.value(), 0, {{std::string("a\0b", 3), "v"}}));
}

// A damaged file is an error from the reader, never a read past its bytes.
TEST(TextureContainer, Ktx2KeyValueReaderRefusesDamagedData) {
    const std::vector<Image> levels = encodedNormalLevels();
    const std::string good =
        ktx2File(encodeTexture(pointers(levels), TextureFormat::Rgba8Unorm).value()).value();
    EXPECT_FALSE(readKtx2KeyValues("not a texture"));
    EXPECT_FALSE(readKtx2KeyValues(good.substr(0, 79)));
    const uint32_t kvdAt = read<uint32_t>(good, 56);
    std::string past = good;
    const uint32_t huge = uint32_t(good.size());
    std::memcpy(&past[60], &huge, 4); // the data's length past the end of the file
    EXPECT_FALSE(readKtx2KeyValues(past));
    std::string entry = good;
    const uint32_t tooLong = 1u << 30;
    std::memcpy(&entry[kvdAt], &tooLong, 4); // an entry longer than the data
    EXPECT_FALSE(readKtx2KeyValues(entry));
    std::string noNul = good;
    const uint32_t first = read<uint32_t>(good, kvdAt); // "KTXwriter\0ndfmip <version>\0"
    for (size_t i = kvdAt + 4; i < kvdAt + 4 + first; ++i) noNul[i] = 'K';
    EXPECT_FALSE(readKtx2KeyValues(noNul));
    EXPECT_TRUE(readKtx2KeyValues(good));
}

// ktx-parse, a reader ndfmip did not write, reads the same keys and values back, from a plain and
// a supercompressed file (it returns KTX* values as text, others as bytes).
TEST(TextureContainer, Ktx2KeyValuesReadBackByKtxParse) {
    const std::string module = ktxParseModule();
    if (module.empty())
        GTEST_SKIP()
            << "node and the npm package ktx-parse (scripts/setup installs it into .npm) not found";
    test::TempDir dir("ndfmip_ktx_kvd");
    const std::vector<Image> levels = encodedNormalLevels();
    Result<EncodedTexture> t = encodeTexture(pointers(levels), TextureFormat::Rg16Unorm);
    ASSERT_TRUE(t);
    const std::string about = "{\"content\":\"normal\",\"encoding\":\"(n+1)/2\",\"green\":\"up\"}";
    for (const int zstd : {0, 7}) {
        const std::string file = dir.file("kv" + std::to_string(zstd) + ".ktx2");
        const std::string bytes =
            ktx2File(t.value(), zstd, {{"KTXswizzle", "rg01"}, {"ndfmip", about}}).value();
        std::ofstream(file, std::ios::binary) << bytes;
        const std::string json =
            runNode(dir,
                    "import { read } from '" + module +
                        "';\n"
                        "import { readFileSync } from 'fs';\n"
                        "const c = read(new Uint8Array(readFileSync(process.argv[2])));\n"
                        "const kv = {};\n"
                        "for (const [k, v] of Object.entries(c.keyValue))\n"
                        "  kv[k] = typeof v === 'string' ? v : new "
                        "TextDecoder().decode(v).replace(/\\0$/, '');\n"
                        "console.log(JSON.stringify({keys: Object.keys(c.keyValue), kv, "
                        "levels: c.levels.length}));\n",
                    file);
        const nlohmann::json got = nlohmann::json::parse(json, nullptr, false);
        ASSERT_TRUE(got.is_object()) << json;
        EXPECT_EQ(got["keys"], nlohmann::json::array({"KTXswizzle", "KTXwriter", "ndfmip"}))
            << json;
        EXPECT_EQ(got["kv"]["KTXswizzle"], "rg01");
        EXPECT_EQ(got["kv"]["KTXwriter"], readKtx2KeyValues(bytes)->at("KTXwriter"));
        EXPECT_EQ(got["kv"]["ndfmip"], about);
        EXPECT_EQ(got["levels"], t->levels.size());
    }
}

// Six 8x8 faces, four levels; texel (x, y) of face f at level k holds f + 10 k + (x + 8 y) / 1000.
std::vector<std::vector<Image>> numberedCube() {
    std::vector<std::vector<Image>> cube;
    for (int k = 0; k < 4; ++k) {
        std::vector<Image> faces;
        for (int f = 0; f < 6; ++f) {
            Image face(8 >> k, 8 >> k, 4);
            for (int y = 0; y < face.height; ++y)
                for (int x = 0; x < face.width; ++x)
                    for (int c = 0; c < 4; ++c)
                        face.at(x, y)[c] = float(f + 10 * k) + float(x + 8 * y) / 1000.f + float(c);
            faces.push_back(std::move(face));
        }
        cube.push_back(std::move(faces));
    }
    return cube;
}

std::vector<std::vector<LevelRows>> rowsOf(const std::vector<std::vector<Image>>& cube) {
    std::vector<std::vector<LevelRows>> rows;
    for (const std::vector<Image>& faces : cube) {
        rows.emplace_back();
        for (const Image& face : faces)
            rows.back().push_back(
                {face.width, face.height, face.channels, [&face](int y, float* out) {
                     std::copy_n(face.at(0, y), size_t(face.width) * 4, out);
                 }});
    }
    return rows;
}

TEST(TextureContainer, CubeMapLevelsHoldTheirSixFaces) {
    const auto cube = numberedCube();
    Result<EncodedTexture> t = encodeCubeTexture(rowsOf(cube), TextureFormat::Rgba32F);
    ASSERT_TRUE(t) << t.error().message;
    EXPECT_EQ(t->faces, 6);
    ASSERT_EQ(t->levels.size(), 4u);
    for (size_t k = 0; k < 4; ++k) {
        const size_t faceBytes = size_t(8 >> k) * size_t(8 >> k) * 16;
        ASSERT_EQ(t->levels[k].size(), 6 * faceBytes);
        for (int f = 0; f < 6; ++f)
            EXPECT_EQ(read<float>(t->levels[k], size_t(f) * faceBytes), float(f + 10 * int(k)));
    }
    const std::string ktx2 = ktx2File(t.value()).value();
    EXPECT_EQ(read<uint32_t>(ktx2, 36), 6u); // faceCount
    EXPECT_EQ(read<uint32_t>(ktx2, 28), 0u); // pixelDepth
    // DDS: face by face, each with its four levels; the cube flags in caps2 and the DX10 misc
    // flags.
    const std::string dds = ddsFile(t.value());
    EXPECT_EQ(read<uint32_t>(dds, 4 + 108), 0x200u | 0xFC00u);
    EXPECT_EQ(read<uint32_t>(dds, 128 + 8), 0x4u);
    size_t at = 128 + 20;
    for (int f = 0; f < 6; ++f)
        for (int k = 0; k < 4; ++k) {
            EXPECT_EQ(read<float>(dds, at), float(f + 10 * k)) << "face " << f << " level " << k;
            at += size_t(8 >> k) * size_t(8 >> k) * 16;
        }
    EXPECT_EQ(at, dds.size());

    std::vector<std::vector<LevelRows>> five = rowsOf(cube);
    five[1].pop_back();
    EXPECT_FALSE(encodeCubeTexture(five, TextureFormat::Rgba32F));
}

TEST(TextureContainer, CubeMapReadBackByKtxParse) {
    const std::string module = ktxParseModule();
    if (module.empty())
        GTEST_SKIP()
            << "node and the npm package ktx-parse (scripts/setup installs it into .npm) not found";
    test::TempDir dir("ndfmip_ktx_cube");
    Result<EncodedTexture> t = encodeCubeTexture(rowsOf(numberedCube()), TextureFormat::Rgba32F);
    ASSERT_TRUE(t);
    const std::string file = dir.file("cube.ktx2");
    std::ofstream(file, std::ios::binary) << ktx2File(t.value()).value();
    // The first float of every face of every level, as the reader splits the level data.
    const std::string json =
        runNode(dir,
                "import { read } from '" + module +
                    "';\n"
                    "import { readFileSync } from 'fs';\n"
                    "const c = read(new Uint8Array(readFileSync(process.argv[2])));\n"
                    "const first = c.levels.map((l, k) => { const d = l.levelData; "
                    "const f = new Float32Array(d.buffer.slice(d.byteOffset, d.byteOffset + "
                    "d.byteLength)); "
                    "const n = f.length / c.faceCount; return [...Array(c.faceCount).keys()].map(i "
                    "=> f[i * n]); });\n"
                    "console.log(JSON.stringify({faces: c.faceCount, w: c.pixelWidth, h: "
                    "c.pixelHeight, first}));\n",
                file);
    EXPECT_NE(json.find("\"faces\":6,\"w\":8,\"h\":8"), std::string::npos) << json;
    EXPECT_NE(json.find("\"first\":[[0,1,2,3,4,5],[10,11,12,13,14,15],[20,21,22,23,24,25],[30,31,"
                        "32,33,34,35]]"),
              std::string::npos)
        << json;
}

} // namespace
} // namespace ndfmip
