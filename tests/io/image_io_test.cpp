// Image file round trips, format detection, error messages and atomic writes.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>

#include <sys/stat.h>
#include <unistd.h>

// Private, static copy of the writer: Debian's libstb.so is not linked into the tests.
#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image_write.h>

#include "ndfmip/io.h"
#include "test_support.h"

namespace fs = std::filesystem;
using ndfmip::Image;
using ndfmip::test::TempDir;

namespace {

std::string readFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

void writeRaw(const std::string& path, const std::string& bytes) {
    std::ofstream(path, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
}

std::set<std::string> listing(const fs::path& dir) {
    std::set<std::string> names;
    for (const auto& entry : fs::directory_iterator(dir)) names.insert(entry.path().filename());
    return names;
}

// An image whose values are k/levels for varied k (all levels hit for small ones).
Image quantisedImage(int w, int h, int c, int levels) {
    Image image(w, h, c);
    for (size_t i = 0; i < image.pixels.size(); ++i)
        image.pixels[i] = float((i * 7919 + 13) % size_t(levels + 1)) / float(levels);
    return image;
}

bool startsWith(const std::string& text, const std::string& prefix) {
    return text.compare(0, prefix.size(), prefix) == 0;
}

// Little-endian field appenders for the hand-made OpenEXR file below.
void put32(std::string& s, uint32_t v) {
    for (int i = 0; i < 4; ++i) s += char((v >> (8 * i)) & 0xFF);
}
void put16(std::string& s, uint16_t v) {
    s += char(v & 0xFF);
    s += char(v >> 8);
}
void putAttribute(std::string& s, const char* name, const char* type, const std::string& value) {
    s += name;
    s += '\0';
    s += type;
    s += '\0';
    put32(s, uint32_t(value.size()));
    s += value;
}

// A 2x1 uncompressed OpenEXR file with HALF channels B,G,R (written by hand because the
// tests do not link OpenEXR): R = (1, -0.5), G = (0.25, 2), B = (0, -1).
std::string halfExrBytes() {
    const char* names[] = {"B", "G", "R"};
    const uint16_t values[3][2] = {{0x0000, 0xBC00}, {0x3400, 0x4000}, {0x3C00, 0xB800}};
    std::string channels;
    for (const char* name : names) {
        channels += name;
        channels += '\0';
        put32(channels, 1); // HALF
        put32(channels, 0); // pLinear + reserved
        put32(channels, 1);
        put32(channels, 1);
    }
    channels += '\0';
    std::string box, one(1, '\0'), v2f(8, '\0'), unitFloat;
    for (uint32_t v : {0u, 0u, 1u, 0u}) put32(box, v);
    put32(unitFloat, 0x3F800000);
    std::string s = "\x76\x2F\x31\x01";
    put32(s, 2);
    putAttribute(s, "channels", "chlist", channels);
    putAttribute(s, "compression", "compression", one);
    putAttribute(s, "dataWindow", "box2i", box);
    putAttribute(s, "displayWindow", "box2i", box);
    putAttribute(s, "lineOrder", "lineOrder", one);
    putAttribute(s, "pixelAspectRatio", "float", unitFloat);
    putAttribute(s, "screenWindowCenter", "v2f", v2f);
    putAttribute(s, "screenWindowWidth", "float", unitFloat);
    s += '\0';
    uint64_t offset = s.size() + 8;
    for (int i = 0; i < 8; ++i) s += char((offset >> (8 * i)) & 0xFF);
    put32(s, 0);     // y
    put32(s, 3 * 4); // bytes of pixel data
    for (const auto& channel : values)
        for (uint16_t v : channel) put16(s, v);
    return s;
}

} // namespace

TEST(ImageIo, Png8RoundTripIsExact) {
    TempDir dir("png8");
    for (int c = 1; c <= 4; ++c) {
        Image image = quantisedImage(37, 11, c, 255);
        std::string path = dir.file(std::to_string(c) + "_p8.png");
        ASSERT_TRUE(ndfmip::savePng(path, image, 8)) << c;
        auto loaded = ndfmip::loadImage(path);
        ASSERT_TRUE(loaded) << loaded.error().message;
        EXPECT_EQ(loaded->format, "png");
        EXPECT_EQ(loaded->bitsPerChannel, 8);
        EXPECT_FALSE(loaded->isFloat);
        EXPECT_EQ(loaded->image.width, 37);
        EXPECT_EQ(loaded->image.height, 11);
        EXPECT_EQ(loaded->image.channels, c);
        EXPECT_EQ(loaded->image.pixels, image.pixels) << c << " channels";
    }
}

TEST(ImageIo, Png16RoundTripIsExactWithAlpha) {
    TempDir dir("png16");
    for (int c = 1; c <= 4; ++c) {
        Image image = quantisedImage(29, 13, c, 65535);
        if (c == 2 || c == 4) image.pixels[size_t(c - 1)] = 0.f; // alpha 0: colour must survive
        image.pixels[0] = 12345.f / 65535.f;
        std::string path = dir.file(std::to_string(c) + "_p16.png");
        ASSERT_TRUE(ndfmip::savePng(path, image, 16)) << c;
        auto loaded = ndfmip::loadImage(path);
        ASSERT_TRUE(loaded) << loaded.error().message;
        EXPECT_EQ(loaded->bitsPerChannel, 16);
        EXPECT_EQ(loaded->image.channels, c);
        EXPECT_EQ(loaded->image.pixels, image.pixels) << c << " channels";
    }
}

TEST(ImageIo, PngClampsAndRoundsToNearest) {
    TempDir dir("pngclamp");
    Image image(6, 1, 1);
    image.pixels = {-0.5f,         1.5f,          std::numeric_limits<float>::quiet_NaN(),
                    10.4f / 255.f, 10.6f / 255.f, 0.5f};
    ASSERT_TRUE(ndfmip::savePng(dir.file("c.png"), image, 8));
    auto loaded = ndfmip::loadImage(dir.file("c.png"));
    ASSERT_TRUE(loaded) << loaded.error().message;
    ndfmip::PixelVector expected = {0.f, 1.f, 0.f, 10 / 255.f, 11 / 255.f, 128 / 255.f};
    EXPECT_EQ(loaded->image.pixels, expected);
}

TEST(ImageIo, PngRejectsBadParameters) {
    TempDir dir("pngbad");
    EXPECT_FALSE(ndfmip::savePng(dir.file("a.png"), Image(2, 2, 5), 8));
    EXPECT_FALSE(ndfmip::savePng(dir.file("b.png"), Image(2, 2, 3), 12));
    EXPECT_FALSE(ndfmip::savePng(dir.file("c.png"), Image(), 8));
    EXPECT_TRUE(listing(dir.path).empty());
}

TEST(ImageIo, ExrFloatRoundTripIsExact) {
    TempDir dir("exr");
    for (int c : {1, 2, 3, 4}) {
        Image image(9, 7, c);
        for (size_t i = 0; i < image.pixels.size(); ++i)
            image.pixels[i] = (float(i) - 100.f) * 0.0123456789f; // negative values too
        image.pixels[1] = 1e-30f;
        std::string path = dir.file(std::to_string(c) + "_channels.exr");
        ASSERT_TRUE(ndfmip::saveExr(path, image)) << c;
        auto loaded = ndfmip::loadImage(path);
        ASSERT_TRUE(loaded) << loaded.error().message;
        EXPECT_EQ(loaded->format, "exr");
        EXPECT_TRUE(loaded->isFloat);
        EXPECT_EQ(loaded->bitsPerChannel, 32);
        EXPECT_EQ(loaded->image.width, 9);
        EXPECT_EQ(loaded->image.height, 7);
        EXPECT_EQ(loaded->image.channels, c);
        EXPECT_EQ(loaded->image.pixels, image.pixels) << c << " channels";
    }
}

TEST(ImageIo, ExrChannelNames) {
    TempDir dir("exrnames");
    Image image(2, 2, 1);
    image.pixels = {0.f, -1.f, 2.f, 3.5f};
    ASSERT_TRUE(ndfmip::saveExr(dir.file("h.exr"), image, {"height"}));
    auto loaded = ndfmip::loadImage(dir.file("h.exr"));
    ASSERT_TRUE(loaded) << loaded.error().message;
    EXPECT_EQ(loaded->image.pixels, image.pixels); // the only channel is read whatever its name

    Image rgb(1, 1, 3);
    rgb.pixels = {0.1f, 0.2f, 0.3f};
    ASSERT_TRUE(ndfmip::saveExr(dir.file("bgr.exr"), rgb, {"B", "G", "R"}));
    loaded = ndfmip::loadImage(dir.file("bgr.exr"));
    ASSERT_TRUE(loaded) << loaded.error().message;
    EXPECT_EQ(loaded->image.pixels, (ndfmip::PixelVector{0.3f, 0.2f, 0.1f}));

    auto wrongCount = ndfmip::saveExr(dir.file("bad.exr"), rgb, {"R", "G"});
    EXPECT_FALSE(wrongCount);
    EXPECT_TRUE(startsWith(wrongCount.error, dir.file("bad.exr") + ": ")) << wrongCount.error;
    EXPECT_FALSE(ndfmip::saveExr(dir.file("dup.exr"), rgb, {"R", "R", "B"}));
    EXPECT_FALSE(fs::exists(dir.file("bad.exr")));
    EXPECT_FALSE(fs::exists(dir.file("dup.exr")));
}

TEST(ImageIo, ExrHalfIsReadAsHalf) {
    TempDir dir("exrhalf");
    writeRaw(dir.file("half.exr"), halfExrBytes());
    auto loaded = ndfmip::loadImage(dir.file("half.exr"));
    ASSERT_TRUE(loaded) << loaded.error().message;
    EXPECT_EQ(loaded->bitsPerChannel, 16);
    EXPECT_TRUE(loaded->isFloat);
    ASSERT_EQ(loaded->image.channels, 3);
    ASSERT_EQ(loaded->image.width, 2);
    EXPECT_EQ(loaded->image.pixels, (ndfmip::PixelVector{1.f, 0.25f, 0.f, -0.5f, 2.f, -1.f}));
}

TEST(ImageIo, TgaLoadsExactly) {
    TempDir dir("tga");
    const int w = 5, h = 3;
    unsigned char rgba[w * h * 4];
    for (int i = 0; i < w * h * 4; ++i) rgba[i] = static_cast<unsigned char>(i * 17 % 256);
    ASSERT_TRUE(stbi_write_tga(dir.file("a.tga").c_str(), w, h, 4, rgba));
    auto loaded = ndfmip::loadImage(dir.file("a.tga"));
    ASSERT_TRUE(loaded) << loaded.error().message;
    EXPECT_EQ(loaded->format, "tga");
    EXPECT_EQ(loaded->bitsPerChannel, 8);
    ASSERT_EQ(loaded->image.channels, 4);
    ASSERT_EQ(loaded->image.width, w);
    ASSERT_EQ(loaded->image.height, h);
    for (int i = 0; i < w * h * 4; ++i) EXPECT_EQ(loaded->image.pixels[size_t(i)], rgba[i] / 255.f);
}

TEST(ImageIo, JpegFlatColourLoads) {
    TempDir dir("jpeg");
    const int w = 16, h = 16;
    std::vector<unsigned char> rgb(w * h * 3);
    for (int i = 0; i < w * h; ++i) rgb[3 * i] = 200, rgb[3 * i + 1] = 100, rgb[3 * i + 2] = 50;
    ASSERT_TRUE(stbi_write_jpg(dir.file("a.jpg").c_str(), w, h, 3, rgb.data(), 100));
    auto loaded = ndfmip::loadImage(dir.file("a.jpg"));
    ASSERT_TRUE(loaded) << loaded.error().message;
    EXPECT_EQ(loaded->format, "jpeg");
    ASSERT_EQ(loaded->image.channels, 3);
    const float expected[3] = {200 / 255.f, 100 / 255.f, 50 / 255.f};
    for (size_t i = 0; i < loaded->image.pixels.size(); ++i)
        EXPECT_NEAR(loaded->image.pixels[i], expected[i % 3], 3.f / 255.f);
}

TEST(ImageIo, FormatComesFromContentNotExtension) {
    TempDir dir("magic");
    Image image = quantisedImage(3, 3, 3, 255);
    ASSERT_TRUE(ndfmip::savePng(dir.file("looks_like.exr"), image, 8));
    ASSERT_TRUE(ndfmip::saveExr(dir.file("looks_like.png"), image));
    auto png = ndfmip::loadImage(dir.file("looks_like.exr"));
    auto exr = ndfmip::loadImage(dir.file("looks_like.png"));
    ASSERT_TRUE(png) << png.error().message;
    ASSERT_TRUE(exr) << exr.error().message;
    EXPECT_EQ(png->format, "png");
    EXPECT_EQ(exr->format, "exr");
    EXPECT_EQ(png->image.pixels, image.pixels);
    EXPECT_EQ(exr->image.pixels, image.pixels);
}

TEST(ImageIo, TruncatedPngIsAnError) {
    TempDir dir("trunc");
    std::string path = dir.file("t.png");
    Image noise = quantisedImage(64, 64, 3, 255);
    ASSERT_TRUE(ndfmip::savePng(path, noise, 8));
    std::string bytes = readFile(path);
    writeRaw(path, bytes.substr(0, bytes.size() / 2));
    auto loaded = ndfmip::loadImage(path);
    ASSERT_FALSE(loaded);
    EXPECT_TRUE(startsWith(loaded.error().message, path + ": ")) << loaded.error().message;
    EXPECT_EQ(loaded.error().message.find('\n'), std::string::npos);
}

TEST(ImageIo, CorruptPngCrcIsAnError) {
    TempDir dir("crc");
    std::string path = dir.file("c.png");
    ASSERT_TRUE(ndfmip::savePng(path, quantisedImage(8, 8, 3, 255), 8));
    std::string bytes = readFile(path);
    bytes[bytes.size() / 2] = char(bytes[bytes.size() / 2] ^ 0x5A); // inside IDAT
    writeRaw(path, bytes);
    auto loaded = ndfmip::loadImage(path);
    ASSERT_FALSE(loaded);
    EXPECT_TRUE(startsWith(loaded.error().message, path + ": ")) << loaded.error().message;
}

TEST(ImageIo, TruncatedExrIsAnError) {
    TempDir dir("truncexr");
    std::string path = dir.file("t.exr");
    Image image(64, 64, 3);
    for (size_t i = 0; i < image.pixels.size(); ++i) image.pixels[i] = std::sin(float(i));
    ASSERT_TRUE(ndfmip::saveExr(path, image));
    std::string bytes = readFile(path);
    writeRaw(path, bytes.substr(0, bytes.size() / 2));
    auto loaded = ndfmip::loadImage(path);
    ASSERT_FALSE(loaded);
    EXPECT_TRUE(startsWith(loaded.error().message, path + ": ")) << loaded.error().message;
    EXPECT_EQ(loaded.error().message.find('\n'), std::string::npos);
}

TEST(ImageIo, GarbageEmptyAndMissingFilesAreErrors) {
    TempDir dir("garbage");
    writeRaw(dir.file("garbage.png"), std::string("this is not an image at all, just text\n"));
    writeRaw(dir.file("empty.png"), "");
    for (std::string name : {"garbage.png", "empty.png", "missing.png"}) {
        std::string path = dir.file(name);
        auto loaded = ndfmip::loadImage(path);
        ASSERT_FALSE(loaded) << name;
        EXPECT_TRUE(startsWith(loaded.error().message, path + ": ")) << loaded.error().message;
    }
    auto directory = ndfmip::loadImage(dir.path.string());
    EXPECT_FALSE(directory);
}

TEST(ImageIo, WritingIntoMissingDirectoryFails) {
    TempDir dir("nodir");
    std::string missing = dir.file("no_such_dir");
    Image image = quantisedImage(4, 4, 3, 255);
    std::string png = missing + "/a.png", exr = missing + "/a.exr", raw = missing + "/a.txt";
    ndfmip::Status results[] = {ndfmip::savePng(png, image, 8), ndfmip::saveExr(exr, image),
                                ndfmip::writeFileAtomic(raw, "hello")};
    std::string paths[] = {png, exr, raw};
    for (int i = 0; i < 3; ++i) {
        EXPECT_FALSE(results[i]);
        const std::string& error = results[i].error;
        EXPECT_TRUE(startsWith(error, paths[i] + ": cannot write (")) << error;
    }
    EXPECT_FALSE(fs::exists(missing));
    EXPECT_TRUE(listing(dir.path).empty());
}

TEST(ImageIo, WritingIntoReadOnlyDirectoryFails) {
    if (::geteuid() == 0) GTEST_SKIP() << "root can write anywhere";
    TempDir dir("readonly");
    ASSERT_EQ(::chmod(dir.path.c_str(), 0500), 0);
    auto status = ndfmip::writeFileAtomic(dir.file("a.txt"), "hello");
    ::chmod(dir.path.c_str(), 0700);
    EXPECT_FALSE(status);
    EXPECT_TRUE(startsWith(status.error, dir.file("a.txt") + ": cannot write (")) << status.error;
    EXPECT_TRUE(listing(dir.path).empty());
}

TEST(ImageIo, AtomicWritesLeaveNoTemporaryFiles) {
    TempDir dir("atomic");
    ASSERT_TRUE(ndfmip::writeFileAtomic(dir.file("a.txt"), "first"));
    ASSERT_TRUE(ndfmip::writeFileAtomic(dir.file("a.txt"), "second, longer")); // replaces
    ASSERT_TRUE(ndfmip::savePng(dir.file("b.png"), quantisedImage(3, 2, 2, 255), 16));
    ASSERT_TRUE(ndfmip::saveExr(dir.file("c.exr"), quantisedImage(3, 2, 4, 255)));
    EXPECT_FALSE(ndfmip::saveExr(dir.file("d.exr"), Image(3, 2, 2), {"only_one"}));
    EXPECT_EQ(readFile(dir.file("a.txt")), "second, longer");
    EXPECT_EQ(listing(dir.path), (std::set<std::string>{"a.txt", "b.png", "c.exr"}));
}

TEST(ImageIo, Sha256OfKnownContents) {
    TempDir dir("sha");
    writeRaw(dir.file("abc"), "abc");
    writeRaw(dir.file("empty"), "");
    auto abc = ndfmip::sha256File(dir.file("abc"));
    auto empty = ndfmip::sha256File(dir.file("empty"));
    ASSERT_TRUE(abc) << abc.error().message;
    ASSERT_TRUE(empty) << empty.error().message;
    EXPECT_EQ(abc.value(), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
    EXPECT_EQ(empty.value(), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
    auto missing = ndfmip::sha256File(dir.file("missing"));
    ASSERT_FALSE(missing);
    EXPECT_TRUE(startsWith(missing.error().message, dir.file("missing") + ": "));
}

TEST(ImageIo, Sha256StreamsLargeFiles) {
    TempDir dir("shabig");
    // 1,000,000 x 'a' is a standard test vector and spans several read chunks.
    writeRaw(dir.file("a"), std::string(1000000, 'a'));
    auto digest = ndfmip::sha256File(dir.file("a"));
    ASSERT_TRUE(digest) << digest.error().message;
    EXPECT_EQ(digest.value(), "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}
