// Image files as a hostile user would craft them: truncated, lying about their size, or not
// files at all. Each must fail with one line naming the file and the problem, quickly, without
// allocating what the header claims.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <sys/stat.h>

#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image_write.h>

#include "ndfmip/io.h"
#include "ndfmip/limits.h"
#include "test_support.h"

namespace fs = std::filesystem;

namespace ndfmip::test {
namespace {

std::string readFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

void writeRaw(const std::string& path, const std::string& bytes) {
    std::ofstream(path, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
}

bool has(const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
}

// A refusal: an error that starts with `name`, is one line and mentions each of `parts`.
void expectRefused(const Result<SourceImage>& loaded, const std::string& name,
                   std::initializer_list<std::string> parts) {
    ASSERT_FALSE(loaded) << name << " loaded";
    const std::string& m = loaded.error().message;
    EXPECT_EQ(m.rfind(name + ": ", 0), 0u) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    for (const std::string& part : parts)
        EXPECT_TRUE(has(m, part)) << "'" << part << "' not in: " << m;
}

void put32le(std::string& s, uint32_t v) {
    for (int i = 0; i < 4; ++i) s += char((v >> (8 * i)) & 0xFF);
}
void put32be(std::string& s, uint32_t v) {
    for (int i = 3; i >= 0; --i) s += char((v >> (8 * i)) & 0xFF);
}

uint32_t crc32(const std::string& bytes) {
    uint32_t crc = 0xFFFFFFFFu;
    for (unsigned char b : bytes) {
        crc ^= b;
        for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
    }
    return ~crc;
}

void pngChunk(std::string& s, const std::string& type, const std::string& data) {
    put32be(s, uint32_t(data.size()));
    s += type + data;
    put32be(s, crc32(type + data));
}

// A PNG signature and an IHDR declaring width x height 8-bit RGB, then `tail` (an IDAT, or
// nothing at all).
std::string pngHeader(uint32_t width, uint32_t height, const std::string& tail = "") {
    std::string s = "\x89PNG\r\n\x1A\n", ihdr;
    put32be(ihdr, width);
    put32be(ihdr, height);
    ihdr += std::string("\x08\x02\x00\x00\x00", 5);
    pngChunk(s, "IHDR", ihdr);
    return s + tail;
}

void putAttribute(std::string& s, const char* name, const char* type, const std::string& value) {
    s += name;
    s += '\0';
    s += type;
    s += '\0';
    put32le(s, uint32_t(value.size()));
    s += value;
}

// An uncompressed scanline OpenEXR header with one HALF channel R and the data window
// [0, width-1] x [0, height-1], an offset table of zeros (one per line) and no pixel data.
std::string exrHeader(int width, int height) {
    std::string channels = std::string("R") + '\0';
    put32le(channels, 1);
    put32le(channels, 0);
    put32le(channels, 1);
    put32le(channels, 1);
    channels += '\0';
    std::string box, one(1, '\0'), v2f(8, '\0'), unitFloat;
    for (uint32_t v : {0u, 0u, uint32_t(width - 1), uint32_t(height - 1)}) put32le(box, v);
    put32le(unitFloat, 0x3F800000);
    std::string s = "\x76\x2F\x31\x01";
    put32le(s, 2);
    putAttribute(s, "channels", "chlist", channels);
    putAttribute(s, "compression", "compression", one);
    putAttribute(s, "dataWindow", "box2i", box);
    putAttribute(s, "displayWindow", "box2i", box);
    putAttribute(s, "lineOrder", "lineOrder", one);
    putAttribute(s, "pixelAspectRatio", "float", unitFloat);
    putAttribute(s, "screenWindowCenter", "v2f", v2f);
    putAttribute(s, "screenWindowWidth", "float", unitFloat);
    s += '\0';
    return s + std::string(size_t(height) * 8, '\0');
}

// Pixels k/255 varied enough that no run-length packet spans a whole row.
std::vector<unsigned char> patternPixels(int w, int h, int c) {
    std::vector<unsigned char> p(size_t(w * h * c));
    for (size_t i = 0; i < p.size(); ++i) p[i] = static_cast<unsigned char>((i * 37 + i / 7) % 256);
    return p;
}

struct ScopedLimits {
    InputLimits saved = inputLimits();
    explicit ScopedLimits(const InputLimits& limits) { setInputLimits(limits); }
    ~ScopedLimits() { setInputLimits(saved); }
};

// ---- size limits before allocation -----------------------------------------------------------

TEST(UntrustedImage, PngHeaderClaimingHugeSizeIsRefusedBeforeAllocating) {
    TempDir dir("png-huge");
    const std::string path = dir.file("huge.png");
    writeRaw(path, pngHeader(30000, 30000));
    expectRefused(loadImage(path), path, {"30000x30000", "limit", "--max-pixels"});
    // Within the limits but far more than its bytes can inflate to (deflate: at most 1032:1).
    writeRaw(path, pngHeader(16000, 16000, std::string(64, '\0')));
    expectRefused(loadImage(path), path, {"truncated PNG", "16000x16000"});
}

TEST(UntrustedImage, ExrHeaderClaimingHugeSizeIsRefused) {
    TempDir dir("exr-huge");
    const std::string path = dir.file("huge.exr");
    writeRaw(path, exrHeader(20000, 20000));
    expectRefused(loadImage(path), path, {"20000x20000", "limit"});
    // Inside the limits, but the chunks are missing: refused before the pixels are allocated.
    writeRaw(path, exrHeader(16000, 16000));
    const auto start = std::chrono::steady_clock::now();
    expectRefused(loadImage(path), path, {"incomplete"});
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(5));
}

TEST(UntrustedImage, TgaHeaderClaimingHugeSizeIsRefused) {
    TempDir dir("tga-huge");
    const std::string path = dir.file("huge.tga");
    std::string tga(18, '\0');
    tga[2] = 10;                                        // run-length true colour
    tga[12] = tga[13] = tga[14] = tga[15] = char(0xFF); // 65535 x 65535
    tga[16] = 32;
    writeRaw(path, tga + std::string(7000, '\x80'));
    expectRefused(loadImage(path), path, {"65535x65535", "limit"});
}

TEST(UntrustedImage, LimitsCanBeLoweredAndRaised) {
    TempDir dir("limits");
    const std::string path = dir.file("a.png");
    ASSERT_TRUE(savePng(path, Image(64, 32, 3), 8));
    InputLimits low;
    low.maxPixels = 1000;
    {
        ScopedLimits scoped(low);
        expectRefused(loadImage(path), path, {"64x32", "1000 pixels"});
    }
    EXPECT_TRUE(loadImage(path)) << "the default limits allow 64x32";
    low.maxPixels = int64_t(1) << 40;
    low.maxSide = 40;
    ScopedLimits scoped(low);
    expectRefused(loadImage(path), path, {"64x32", "40 texels per side"});
}

// ---- Radiance HDR: our own bounded decoder ---------------------------------------------------

std::vector<float> hdrPattern(int w, int h) {
    std::vector<float> v(size_t(w * h * 3));
    for (size_t i = 0; i < v.size(); ++i) v[i] = 0.01f + float((i * 13) % 97) * 0.37f;
    return v;
}

TEST(UntrustedImage, RadianceRoundTripsFlatAndRunLengthScanlines) {
    TempDir dir("hdr");
    // Width 5 is stored flat, width 40 run-length encoded (stb_image_write picks by width).
    for (int w : {5, 40}) {
        SCOPED_TRACE(w);
        const int h = 3;
        const std::vector<float> values = hdrPattern(w, h);
        const std::string path = dir.file("a.hdr");
        ASSERT_TRUE(stbi_write_hdr(path.c_str(), w, h, 3, values.data()));
        auto loaded = loadImage(path);
        ASSERT_TRUE(loaded) << loaded.error().message;
        EXPECT_EQ(loaded->format, "hdr");
        EXPECT_TRUE(loaded->isFloat);
        ASSERT_EQ(loaded->image.width, w);
        ASSERT_EQ(loaded->image.height, h);
        ASSERT_EQ(loaded->image.channels, 3);
        // RGBE keeps 8 bits of mantissa against the largest component of the pixel.
        for (size_t i = 0; i < values.size(); ++i) {
            const size_t p = i / 3 * 3;
            const float peak = std::max({values[p], values[p + 1], values[p + 2]});
            EXPECT_NEAR(loaded->image.pixels[i], values[i], peak / 128.f) << "sample " << i;
        }
    }
}

TEST(UntrustedImage, RadianceCutAnywhereFailsQuickly) {
    TempDir dir("hdr-cut");
    const int w = 40, h = 6;
    const std::vector<float> values = hdrPattern(w, h);
    const std::string full = dir.file("full.hdr"), cut = dir.file("cut.hdr");
    ASSERT_TRUE(stbi_write_hdr(full.c_str(), w, h, 3, values.data()));
    const std::string bytes = readFile(full);
    const auto start = std::chrono::steady_clock::now();
    for (size_t n = 0; n < bytes.size(); n += 7) {
        writeRaw(cut, bytes.substr(0, n));
        SCOPED_TRACE(n);
        auto loaded = loadImage(cut);
        ASSERT_FALSE(loaded);
        EXPECT_EQ(loaded.error().message.rfind(cut + ": ", 0), 0u) << loaded.error().message;
    }
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(10));
}

TEST(UntrustedImage, RadianceHeadersOutsideTheFormatAreRefused) {
    TempDir dir("hdr-head");
    const std::string path = dir.file("a.hdr");
    const std::string pixel = std::string("\x80\x80\x80\x81", 4);
    writeRaw(path, "#?RADIANCE\nFORMAT=32-bit_rle_xyze\n\n-Y 1 +X 1\n" + pixel);
    expectRefused(loadImage(path), path, {"32-bit_rle_xyze"});
    writeRaw(path, "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n+Y 1 +X 1\n" + pixel);
    expectRefused(loadImage(path), path, {"+Y 1 +X 1"});
    writeRaw(path, "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 30000 +X 30000\n" + pixel);
    expectRefused(loadImage(path), path, {"30000x30000", "limit"});
    writeRaw(path, "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 2000 +X 2000\n" + pixel);
    expectRefused(loadImage(path), path, {"truncated"});
    writeRaw(path, "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 1\n" + pixel);
    auto one = loadImage(path);
    ASSERT_TRUE(one) << one.error().message;
    EXPECT_FLOAT_EQ(one->image.pixels[0], 128.f * std::ldexp(1.f, 129 - 136));
}

TEST(UntrustedImage, SharedRadianceMapsLoad) {
    const fs::path maps = sharedNormalMaps();
    if (maps.empty() || !fs::is_directory(maps.parent_path() / "envmaps")) GTEST_SKIP();
    for (const auto& entry : fs::directory_iterator(maps.parent_path() / "envmaps")) {
        if (entry.path().extension() != ".hdr") continue;
        auto loaded = loadImage(entry.path().string());
        ASSERT_TRUE(loaded) << loaded.error().message;
        EXPECT_EQ(loaded->image.width, 2 * loaded->image.height) << entry.path();
        float peak = 0.f;
        for (float v : loaded->image.pixels) peak = std::max(peak, v);
        EXPECT_GT(peak, 1.f) << entry.path() << ": an HDR environment has values above 1";
    }
}

// ---- files cut short: stb would fill the rest with zeros --------------------------------------

TEST(UntrustedImage, TruncatedTgaIsAnError) {
    TempDir dir("tga-cut");
    const int w = 64, h = 64;
    const std::vector<unsigned char> pixels = patternPixels(w, h, 4);
    for (int rle : {0, 1}) {
        SCOPED_TRACE(rle);
        stbi_write_tga_with_rle = rle;
        const std::string full = dir.file("full.tga"), cut = dir.file("cut.tga");
        ASSERT_TRUE(stbi_write_tga(full.c_str(), w, h, 4, pixels.data()));
        auto whole = loadImage(full);
        ASSERT_TRUE(whole) << whole.error().message;
        EXPECT_EQ(whole->image.pixels[5], pixels[5] / 255.f);
        const std::string bytes = readFile(full);
        for (size_t n : {bytes.size() / 20, bytes.size() / 2, bytes.size() - 1}) {
            writeRaw(cut, bytes.substr(0, n));
            expectRefused(loadImage(cut), cut, {"truncated TGA"});
        }
    }
    stbi_write_tga_with_rle = 1;
}

TEST(UntrustedImage, TruncatedBmpAndJpegAreErrors) {
    TempDir dir("bmp-jpeg-cut");
    const int w = 33, h = 17;
    const std::vector<unsigned char> pixels = patternPixels(w, h, 3);
    const std::string bmp = dir.file("a.bmp"), jpeg = dir.file("a.jpg"), cut = dir.file("cut");
    ASSERT_TRUE(stbi_write_bmp(bmp.c_str(), w, h, 3, pixels.data()));
    ASSERT_TRUE(stbi_write_jpg(jpeg.c_str(), w, h, 3, pixels.data(), 90));
    for (const std::string& file : {bmp, jpeg}) {
        SCOPED_TRACE(file);
        auto whole = loadImage(file);
        ASSERT_TRUE(whole) << whole.error().message;
        EXPECT_EQ(whole->image.width, w);
        const std::string bytes = readFile(file);
        for (size_t n : {bytes.size() / 20, bytes.size() / 2, bytes.size() - 2}) {
            writeRaw(cut, bytes.substr(0, n));
            expectRefused(loadImage(cut), cut, {"truncated"});
        }
    }
}

TEST(UntrustedImage, FormatsNobodyStoresNormalMapsInAreRefused) {
    TempDir dir("gif");
    const std::string path = dir.file("a.gif");
    writeRaw(path, "GIF89a\x01\x00\x01\x00\x00\x00\x00;");
    expectRefused(loadImage(path), path, {"unsupported image format (gif"});
    writeRaw(path, "P6\n1 1\n255\n\x01\x02\x03");
    expectRefused(loadImage(path), path, {"unsupported image format (pnm"});
}

// ---- only regular files -----------------------------------------------------------------------

TEST(UntrustedImage, OnlyRegularFilesAreRead) {
    TempDir dir("special");
    const std::string fifo = dir.file("fifo.png");
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    // Opening a FIFO for reading would wait for a writer: it must be refused at once.
    expectRefused(loadImage(fifo), fifo, {"not a regular file (a FIFO)"});
    expectRefused(loadImage("/dev/zero"), "/dev/zero", {"not a regular file (a character device)"});
    expectRefused(loadImage(dir.path.string()), dir.path.string(), {"is a directory"});
    auto hash = sha256File(fifo);
    ASSERT_FALSE(hash);
    EXPECT_TRUE(has(hash.error().message, "FIFO")) << hash.error().message;
}

TEST(UntrustedImage, DecodeFromMemoryMatchesTheFile) {
    TempDir dir("memory");
    Image image(3, 2, 3);
    for (size_t i = 0; i < image.pixels.size(); ++i) image.pixels[i] = float(i) / 8.f;
    for (const std::string name : {"a.exr", "a.png"}) {
        const std::string path = dir.file(name);
        ASSERT_TRUE(name == "a.exr" ? saveExr(path, image) : savePng(path, image, 16));
        auto fromFile = loadImage(path);
        auto fromMemory = decodeImage(readFile(path), "memory");
        ASSERT_TRUE(fromFile && fromMemory);
        EXPECT_EQ(fromFile->image.pixels, fromMemory->image.pixels);
    }
    expectRefused(decodeImage("", "memory"), "memory", {"empty"});
}

} // namespace
} // namespace ndfmip::test
