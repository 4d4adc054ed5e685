// The allocation policy: the peak a pipeline plans from its options is checked against
// --max-memory with the size an image's header declares, before the image is decoded, and an
// allocation that fails anyway becomes a line naming the file.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>

#include "ndfmip/bake_file.h"
#include "ndfmip/io.h"
#include "ndfmip/limits.h"
#include "test_support.h"

namespace ndfmip::test {
namespace {

// A PNG whose IHDR declares width x height 8-bit RGB pixels, followed by `dataBytes` bytes that
// no decoder inflates: only its header can be read, so any error about its size comes from it.
std::string headerOnlyPng(uint32_t width, uint32_t height, size_t dataBytes) {
    std::string png("\x89PNG\r\n\x1a\n", 8);
    auto be32 = [&](uint32_t v) {
        for (int shift = 24; shift >= 0; shift -= 8) png += char((v >> shift) & 0xFF);
    };
    be32(13);
    png += "IHDR";
    be32(width);
    be32(height);
    png += std::string("\x08\x02\x00\x00\x00", 5); // 8 bits, RGB, deflate, no filter, no interlace
    be32(0);                                       // CRC (never reached)
    be32(uint32_t(dataBytes));
    png += "IDAT";
    png += std::string(dataBytes, '\x55');
    return png;
}

class AllocationPolicy : public ::testing::Test {
  protected:
    TempDir tmp{"allocation_policy"};
    InputLimits saved = inputLimits();
    void TearDown() override { setInputLimits(saved); }
    void setMaxMemory(int64_t bytes) {
        InputLimits limits = saved;
        limits.maxMemoryBytes = bytes;
        setInputLimits(limits);
    }
};

TEST_F(AllocationPolicy, APlannedPeakIsCheckedAgainstTheLimitAtTheHeadersSize) {
    setMaxMemory(int64_t(1) << 20);
    {
        const PlannedPeak peak("a test bake", 100.0, 1000);
        // 100 x 100 x 100 + 1000 = 1 001 000 bytes <= 1 048 576; 103 x 102 x 100 + 1000 > it.
        EXPECT_TRUE(checkDecodedSize("a.png", 100, 100));
        const Status refused = checkDecodedSize("a.png", 103, 102);
        ASSERT_FALSE(refused);
        EXPECT_EQ(
            refused.error,
            "a.png: a test bake of a 103x102 map needs about 1.0 MiB, above the limit of 1.0 MiB; "
            "--max-memory raises it");
        EXPECT_EQ(outOfMemoryMessage("a.png"), "a.png: out of memory (needs about 1.0 MiB)");
        EXPECT_EQ(outOfMemoryMessage(), "a.png: out of memory (needs about 1.0 MiB)");
        // Another file's figure is not this one's.
        EXPECT_EQ(outOfMemoryMessage("b.png"), "b.png: out of memory");
    }
    // Without a plan, the decoded image's own 16 bytes per texel: 256 x 256 is 1 MiB exactly.
    EXPECT_TRUE(checkDecodedSize("a.png", 256, 256));
    EXPECT_FALSE(checkDecodedSize("a.png", 256, 257));
    // checkImageSize is the size alone (a manifest's source size is not decoded).
    EXPECT_TRUE(checkImageSize("a.png", 4096, 4096));
}

TEST_F(AllocationPolicy, ABakeIsRefusedFromThePngHeaderBeforeDecoding) {
    const std::string input = tmp.file("big.png");
    // 2048 x 2048 RGB: 12.6 MB of rows, which 16 KB of deflate could hold (1:1032).
    writeBytes(input, headerOnlyPng(2048, 2048, 16384));
    setMaxMemory(int64_t(10) << 20);
    BakeFileOptions options;
    options.method = "toksvig";
    Result<BakeFileReport> baked = bakeFile(input, tmp.file("out.bake"), options);
    ASSERT_FALSE(baked);
    const std::string& message = baked.error().message;
    // The estimate, not a decoding error: the data was never inflated.
    EXPECT_EQ(message.rfind(input + ": a toksvig bake of a 2048x2048 map needs about ", 0), 0u)
        << message;
    EXPECT_NE(message.find("--max-memory"), std::string::npos) << message;
    // The peak counted is at least the bake's own estimate (the decoded file comes on top).
    const int64_t bake = bakeMemoryEstimate(Method::Toksvig, BakeOptions{}, 2048, 2048);
    setMaxMemory(bake);
    Result<BakeFileReport> again = bakeFile(input, tmp.file("out.bake"), options);
    ASSERT_FALSE(again);
    EXPECT_NE(again.error().message.find("needs about"), std::string::npos)
        << again.error().message;
    EXPECT_FALSE(std::filesystem::exists(tmp.file("out.bake")));
}

TEST_F(AllocationPolicy, AMapWithinTheLimitIsStillBaked) {
    const std::string input = tmp.file("small.png");
    Image map = randomNormals(16, 16, 0.5f, 3);
    for (float& v : map.pixels) v = 0.5f * (v + 1.f); // stored as (n + 1) / 2
    ASSERT_TRUE(savePng(input, map, 8));
    setMaxMemory(int64_t(1) << 20); // 16 x 16 texels need a few tens of KiB
    BakeFileOptions options;
    options.method = "toksvig";
    Result<BakeFileReport> baked = bakeFile(input, tmp.file("out.bake"), options);
    ASSERT_TRUE(baked) << baked.error().message;
    EXPECT_EQ(baked->width, 16);
}

} // namespace
} // namespace ndfmip::test
