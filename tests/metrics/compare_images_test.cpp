// Image comparison statistics, false-colour error images and tone mapping against closed forms.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "ndfmip/compare.h"
#include "ndfmip/tonemap.h"

namespace ndfmip {
namespace {

// Values k/8 (exact in float), so b + c is exact for c = 1/4 too.
Image eighths(int w, int h, int c) {
    Image image(w, h, c);
    for (size_t i = 0; i < image.pixels.size(); ++i)
        image.pixels[i] = float((i * 5 + 1) % 17) / 8.f;
    return image;
}

float srgb(float linear) {
    return 1.055f * std::pow(linear, 1.f / 2.4f) - 0.055f;
}

float rec709(const float* rgb) {
    return 0.2126f * rgb[0] + 0.7152f * rgb[1] + 0.0722f * rgb[2];
}

TEST(CompareImages, ConstantOffsetMatchesClosedForms) {
    const Image b = eighths(5, 3, 3);
    const float c = 0.25f;
    Image a = b;
    for (float& v : a.pixels) v += c;
    double norm = 0, sum = 0, peak = 0;
    for (float v : b.pixels) {
        norm += double(v) * v;
        sum += v;
        peak = std::max(peak, double(v));
    }
    const double n = double(b.pixels.size());
    auto r = compareImages(a, b);
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ(r->width, 5);
    EXPECT_EQ(r->height, 3);
    EXPECT_EQ(r->channels, 3);
    EXPECT_NEAR(r->rmse, c, 1e-12);
    EXPECT_NEAR(r->relativeRmse, c * std::sqrt(n) / std::sqrt(norm), 1e-12);
    EXPECT_NEAR(r->energyRatio, (sum + c * n) / sum, 1e-12);
    EXPECT_NEAR(r->maxAbsError, c, 1e-12);
    EXPECT_NEAR(r->psnr, 10 * std::log10(peak * peak / (c * c)), 1e-9);
}

TEST(CompareImages, IdenticalImagesHaveNoErrorAndInfinitePsnr) {
    const Image b = eighths(4, 4, 1);
    auto r = compareImages(b, b);
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ(r->rmse, 0);
    EXPECT_EQ(r->relativeRmse, 0);
    EXPECT_EQ(r->maxAbsError, 0);
    EXPECT_EQ(r->energyRatio, 1);
    EXPECT_TRUE(std::isinf(r->psnr) && r->psnr > 0);
}

TEST(CompareImages, AllZeroReference) {
    Image zero(3, 2, 1), half(3, 2, 1);
    for (float& v : half.pixels) v = 0.5f;
    auto both = compareImages(zero, zero);
    ASSERT_TRUE(both.ok());
    EXPECT_EQ(both->relativeRmse, 0);
    EXPECT_EQ(both->energyRatio, 1);
    auto only = compareImages(half, zero);
    ASSERT_TRUE(only.ok());
    EXPECT_TRUE(std::isinf(only->relativeRmse));
    // The peak falls back to 1: 10 log10(1 / 0.25).
    EXPECT_NEAR(only->psnr, 10 * std::log10(4.0), 1e-12);
}

TEST(CompareImages, SizeMismatchIsAnErrorNamingBothSizes) {
    auto wide = compareImages(Image(4, 2, 3), Image(3, 2, 3));
    ASSERT_FALSE(wide.ok());
    EXPECT_NE(wide.error().message.find("4x2"), std::string::npos) << wide.error().message;
    EXPECT_NE(wide.error().message.find("3x2"), std::string::npos) << wide.error().message;
    auto channels = compareImages(Image(2, 2, 1), Image(2, 2, 3));
    ASSERT_FALSE(channels.ok());
    EXPECT_NE(channels.error().message.find("1 channel "), std::string::npos);
    EXPECT_NE(channels.error().message.find("3 channels"), std::string::npos);
    EXPECT_FALSE(compareImages(Image(), Image()).ok());
}

TEST(CompareImages, NonFiniteValuesAreErrors) {
    Image a = eighths(3, 2, 2), b = a;
    a.at(2, 1)[1] = std::numeric_limits<float>::quiet_NaN();
    auto r = compareImages(a, b);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("under test"), std::string::npos) << r.error().message;
    EXPECT_NE(r.error().message.find("(2, 1), channel 1"), std::string::npos) << r.error().message;
    b.at(0, 0)[0] = std::numeric_limits<float>::infinity();
    auto s = compareImages(b, b);
    ASSERT_FALSE(s.ok());
    EXPECT_NE(s.error().message.find("under test"), std::string::npos) << s.error().message;
    auto t = compareImages(eighths(3, 2, 2), b);
    ASSERT_FALSE(t.ok());
    EXPECT_NE(t.error().message.find("reference"), std::string::npos) << t.error().message;
}

TEST(ErrorImage, BlackWhereEqualTopColourAtScale) {
    // Errors per pixel (mean over the 2 channels): 0, 0.5, 2, 0.25.
    Image b(4, 1, 2), a(4, 1, 2);
    const float diff[4][2] = {{0, 0}, {0.25f, 0.75f}, {-2, 2}, {0.5f, 0}};
    for (int x = 0; x < 4; ++x)
        for (int c = 0; c < 2; ++c) a.at(x, 0)[c] = b.at(x, 0)[c] + diff[x][c];
    Image e = errorImage(a, b, 0.5f);
    ASSERT_EQ(e.width, 4);
    ASSERT_EQ(e.channels, 3);
    const float top[3] = {0xfc / 255.f, 0xff / 255.f, 0xa4 / 255.f};
    const float middle[3] = {0xbc / 255.f, 0x37 / 255.f, 0x54 / 255.f}; // stop 3 of 0..6
    for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(e.at(0, 0)[c], 0.f);
        EXPECT_NEAR(e.at(1, 0)[c], top[c], 1e-6f);
        EXPECT_NEAR(e.at(2, 0)[c], top[c], 1e-6f); // beyond the scale: clamped
        EXPECT_NEAR(e.at(3, 0)[c], middle[c], 1e-6f);
    }
    EXPECT_TRUE(errorImage(Image(2, 2, 1), Image(3, 2, 1)).empty());
}

TEST(ErrorImage, AutomaticScaleAndOrderedColours) {
    // A uniform error of 0.3: its 99th percentile is 0.3, so every pixel is the top colour.
    Image b(3, 3, 1), a(3, 3, 1);
    for (float& v : a.pixels) v = 0.3f;
    Image uniform = errorImage(a, b);
    for (int y = 0; y < 3; ++y) EXPECT_NEAR(uniform.at(1, y)[1], 1.f, 1e-6f);
    // No error: the scale falls back to 1 and everything is black.
    for (float v : errorImage(b, b).pixels) EXPECT_EQ(v, 0.f);
    // Luminance rises with the error along a ramp, so the map reads in order.
    Image ramp(64, 1, 1), zero(64, 1, 1);
    for (int x = 0; x < 64; ++x) ramp.at(x, 0)[0] = float(x) / 63.f;
    Image e = errorImage(ramp, zero, 1.f);
    for (int x = 1; x < 64; ++x) EXPECT_GT(rec709(e.at(x, 0)), rec709(e.at(x - 1, 0))) << x;
}

TEST(ToneMap, ReinhardThenSrgb) {
    Image in(6, 1, 1);
    const float values[6] = {0.f,
                             1.f,
                             1e6f,
                             -2.f,
                             std::numeric_limits<float>::quiet_NaN(),
                             std::numeric_limits<float>::infinity()};
    for (int x = 0; x < 6; ++x) in.at(x, 0)[0] = values[x];
    Image out = toneMap(in);
    ASSERT_EQ(out.channels, 3);
    for (int c = 0; c < 3; ++c) { // grey is replicated
        EXPECT_EQ(out.at(0, 0)[c], 0.f);
        EXPECT_NEAR(out.at(1, 0)[c], srgb(0.5f), 1e-6f); // 1 / (1 + 1) = 0.5
        EXPECT_GT(out.at(2, 0)[c], 0.9999f);
        EXPECT_LE(out.at(2, 0)[c], 1.f);
        EXPECT_EQ(out.at(3, 0)[c], 0.f);
        EXPECT_EQ(out.at(4, 0)[c], 0.f);
        EXPECT_EQ(out.at(5, 0)[c], 1.f);
    }
    // One stop up: 0.5 becomes 1, which the curve maps to 0.5.
    Image half(1, 1, 1);
    half.pixels[0] = 0.5f;
    EXPECT_NEAR(toneMap(half, 1.f).pixels[0], srgb(0.5f), 1e-6f);
}

TEST(ToneMap, MonotonicPerChannelAndAlphaIgnored) {
    Image in(200, 1, 4);
    for (int x = 0; x < 200; ++x) {
        float* p = in.at(x, 0);
        p[0] = 0.01f * float(x) * float(x);
        p[1] = 0.5f; // constant channel stays constant
        p[2] = 0.f;
        p[3] = float(x % 2); // alpha: must not show up anywhere
    }
    Image out = toneMap(in, -1.f);
    ASSERT_EQ(out.channels, 3);
    for (int x = 1; x < 200; ++x) {
        EXPECT_GT(out.at(x, 0)[0], out.at(x - 1, 0)[0]) << x;
        EXPECT_EQ(out.at(x, 0)[1], out.at(0, 0)[1]) << x;
        EXPECT_EQ(out.at(x, 0)[2], 0.f);
    }
}

TEST(AutoExposure, NinetyNinthPercentileShowsAtPointEight) {
    EXPECT_EQ(autoExposure(Image(4, 4, 3)), 0.f);
    // 101 grey texels 0, 0.04, ..., 4: the 99th percentile is texel 99 (3.96).
    Image grey(101, 1, 3);
    for (int x = 0; x < 101; ++x)
        for (int c = 0; c < 3; ++c) grey.at(x, 0)[c] = 0.04f * float(x);
    Image shown = toneMap(grey, autoExposure(grey));
    EXPECT_NEAR(shown.at(99, 0)[0], 0.8f, 1e-4f);
    EXPECT_LT(shown.at(100, 0)[0], 1.f);
    // The same for one channel, and independent of the overall brightness.
    Image scaled(101, 1, 1);
    for (int x = 0; x < 101; ++x) scaled.at(x, 0)[0] = 1000.f * float(x);
    EXPECT_NEAR(toneMap(scaled, autoExposure(scaled)).at(99, 0)[1], 0.8f, 1e-4f);
}

} // namespace
} // namespace ndfmip
