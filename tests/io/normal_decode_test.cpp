// Decoding conventions, input checks and height-map normals.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "ndfmip/io.h"
#include "ndfmip/normal_map.h"
#include "test_support.h"

using ndfmip::AddressMode;
using ndfmip::DecodeOptions;
using ndfmip::DecodeReport;
using ndfmip::Image;
using ndfmip::SourceImage;

namespace {

constexpr double kPi = 3.14159265358979323846;

SourceImage source(Image image, bool isFloat = false) {
    SourceImage s;
    s.image = std::move(image);
    s.isFloat = isFloat;
    s.bitsPerChannel = isFloat ? 32 : 8;
    s.format = isFloat ? "exr" : "png";
    return s;
}

// A w x h image with every texel set to `texel` (c values).
Image filled(int w, int h, std::initializer_list<float> texel) {
    Image image(w, h, int(texel.size()));
    for (size_t i = 0; i < image.pixels.size(); ++i)
        image.pixels[i] = texel.begin()[i % texel.size()];
    return image;
}

void expectNormal(const float* n, double x, double y, double z, double tolerance = 1e-6) {
    double length = std::sqrt(x * x + y * y + z * z);
    EXPECT_NEAR(n[0], x / length, tolerance);
    EXPECT_NEAR(n[1], y / length, tolerance);
    EXPECT_NEAR(n[2], z / length, tolerance);
}

bool startsWith(const std::string& text, const std::string& prefix) {
    return text.compare(0, prefix.size(), prefix) == 0;
}

} // namespace

TEST(NormalDecode, IntegerMapIsTwoCMinusOne) {
    DecodeReport report;
    auto n = ndfmip::decodeNormalMap(source(filled(2, 2, {0.75f, 0.75f, 1.f})), {}, "m", &report);
    ASSERT_TRUE(n) << n.error().message;
    ASSERT_EQ(n->channels, 3);
    expectNormal(n->at(1, 1), 0.5, 0.5, 1.0);
    EXPECT_EQ(report.texels, 4u);
    EXPECT_EQ(report.offUnitLength, 4u); // |(0.5, 0.5, 1)| = 1.22
    EXPECT_EQ(report.degenerate, 0u);
    EXPECT_EQ(report.facingDown, 0u);
}

TEST(NormalDecode, GreenDownFlipsY) {
    DecodeOptions options;
    options.greenDown = true;
    auto n =
        ndfmip::decodeNormalMap(source(filled(1, 1, {0.75f, 0.75f, 1.f})), options, "m", nullptr);
    ASSERT_TRUE(n) << n.error().message;
    expectNormal(n->at(0, 0), 0.5, -0.5, 1.0);
}

TEST(NormalDecode, AlphaIsIgnored) {
    auto n =
        ndfmip::decodeNormalMap(source(filled(1, 1, {0.5f, 1.f, 0.5f, 0.f})), {}, "m", nullptr);
    ASSERT_TRUE(n) << n.error().message;
    ASSERT_EQ(n->channels, 3);
    expectNormal(n->at(0, 0), 0.0, 1.0, 0.0);
}

TEST(NormalDecode, TwoChannelRebuildsZ) {
    DecodeOptions options;
    options.twoChannel = true;
    // Works for 2-channel images and ignores B of wider ones.
    for (Image image : {filled(2, 1, {0.8f, 0.3f}), filled(2, 1, {0.8f, 0.3f, 0.f, 1.f})}) {
        DecodeReport report;
        auto n = ndfmip::decodeNormalMap(source(image), options, "rg", &report);
        ASSERT_TRUE(n) << n.error().message;
        const float* t = n->at(1, 0);
        EXPECT_NEAR(t[0], 0.6, 1e-6);
        EXPECT_NEAR(t[1], -0.4, 1e-6);
        EXPECT_NEAR(t[2], std::sqrt(1.0 - 0.36 - 0.16), 1e-6);
        EXPECT_EQ(report.offUnitLength, 0u);
    }
}

TEST(NormalDecode, TwoChannelOutsideDiscClampsZ) {
    DecodeOptions options;
    options.twoChannel = true;
    auto n = ndfmip::decodeNormalMap(source(filled(1, 1, {1.f, 1.f})), options, "rg", nullptr);
    ASSERT_TRUE(n) << n.error().message;
    expectNormal(n->at(0, 0), 1.0, 1.0, 0.0);
}

TEST(NormalDecode, TooFewChannelsIsAnError) {
    for (int channels : {1, 2}) {
        auto n = ndfmip::decodeNormalMap(source(Image(2, 2, channels)), {}, "map.png", nullptr);
        ASSERT_FALSE(n);
        const std::string& message = n.error().message;
        EXPECT_TRUE(startsWith(message, "map.png: has " + std::to_string(channels) +
                                            " channel(s); a normal map needs 3"))
            << message;
        EXPECT_NE(message.find("--two-channel"), std::string::npos);
    }
    DecodeOptions options;
    options.twoChannel = true;
    auto grey = ndfmip::decodeNormalMap(source(Image(2, 2, 1)), options, "g.png", nullptr);
    ASSERT_FALSE(grey);
    EXPECT_NE(grey.error().message.find("channel"), std::string::npos);
}

TEST(NormalDecode, EmptyImageIsAnError) {
    auto n = ndfmip::decodeNormalMap(source(Image()), {}, "e", nullptr);
    ASSERT_FALSE(n);
    EXPECT_TRUE(startsWith(n.error().message, "e: "));
}

TEST(NormalDecode, NanInExrIsAnError) {
    ndfmip::test::TempDir dir("nan");
    Image image = filled(3, 2, {0.f, 0.f, 1.f});
    image.at(1, 1)[2] = std::numeric_limits<float>::infinity();
    image.at(2, 0)[1] = std::numeric_limits<float>::quiet_NaN(); // first in reading order
    std::string path = dir.file("nan.exr");
    ASSERT_TRUE(ndfmip::saveExr(path, image));
    DecodeOptions options;
    options.signedValues = true;
    auto n = ndfmip::loadNormalMap(path, options, nullptr);
    ASSERT_FALSE(n);
    EXPECT_TRUE(startsWith(n.error().message, path + ": ")) << n.error().message;
    EXPECT_NE(n.error().message.find("(2, 0)"), std::string::npos) << n.error().message;
}

TEST(NormalDecode, NanInUnusedChannelIsIgnored) {
    Image image = filled(1, 1, {0.5f, 0.5f, 1.f, 0.f});
    image.pixels[3] = std::numeric_limits<float>::quiet_NaN(); // alpha
    EXPECT_TRUE(ndfmip::decodeNormalMap(source(image, true), {}, "a", nullptr));
}

TEST(NormalDecode, AllZeroIsAnError) {
    auto n =
        ndfmip::decodeNormalMap(source(filled(4, 4, {0.5f, 0.5f, 0.5f})), {}, "flat.png", nullptr);
    ASSERT_FALSE(n);
    EXPECT_EQ(n.error().message, "flat.png: every normal is zero-length (not a normal map?)");
}

TEST(NormalDecode, CountsDegenerateOffUnitAndFacingDown) {
    Image image(4, 1, 3);
    const float texels[4][3] = {
        {0.f, 0.f, 1.f}, {0.f, 0.f, 0.f}, {0.f, 2.f, 0.f}, {0.6f, 0.f, -0.8f}};
    for (int x = 0; x < 4; ++x)
        for (int c = 0; c < 3; ++c) image.at(x, 0)[c] = texels[x][c];
    DecodeOptions options;
    options.signedValues = true;
    DecodeReport report;
    auto n = ndfmip::decodeNormalMap(source(image, true), options, "s.exr", &report);
    ASSERT_TRUE(n) << n.error().message;
    EXPECT_EQ(report.texels, 4u);
    EXPECT_EQ(report.degenerate, 1u);
    EXPECT_EQ(report.offUnitLength, 2u); // the zero one and the long one
    EXPECT_EQ(report.facingDown, 1u);
    expectNormal(n->at(0, 0), 0, 0, 1);
    expectNormal(n->at(1, 0), 0, 0, 1); // degenerate replaced
    expectNormal(n->at(2, 0), 0, 1, 0);
    expectNormal(n->at(3, 0), 0.6, 0, -0.8);
}

TEST(NormalDecode, FloatMapsDecodeSignedOnlyWhenAsked) {
    Image image = filled(1, 1, {0.6f, -0.8f, 0.f});
    DecodeOptions options;
    options.signedValues = true;
    auto stored = ndfmip::decodeNormalMap(source(image, true), options, "f", nullptr);
    ASSERT_TRUE(stored) << stored.error().message;
    expectNormal(stored->at(0, 0), 0.6, -0.8, 0.0);
    auto scaled = ndfmip::decodeNormalMap(source(image, true), {}, "f", nullptr);
    ASSERT_TRUE(scaled) << scaled.error().message;
    expectNormal(scaled->at(0, 0), 0.2, -2.6, -1.0);
}

TEST(NormalDecode, OutputIsUnitLength) {
    Image image(8, 8, 3);
    for (size_t i = 0; i < image.pixels.size(); ++i)
        image.pixels[i] = 0.5f + 0.45f * std::sin(float(i) * 1.7f);
    auto n = ndfmip::decodeNormalMap(source(image), {}, "u", nullptr);
    ASSERT_TRUE(n) << n.error().message;
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) {
            const float* t = n->at(x, y);
            EXPECT_NEAR(std::sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]), 1.0, 1e-6);
        }
}

TEST(NormalDecode, LoadNormalMapFromPng) {
    ndfmip::test::TempDir dir("loadpng");
    std::string path = dir.file("n.png");
    ASSERT_TRUE(ndfmip::savePng(path, filled(2, 2, {0.5f, 1.f, 0.5f}), 16));
    DecodeOptions options;
    options.greenDown = true;
    auto n = ndfmip::loadNormalMap(path, options, nullptr);
    ASSERT_TRUE(n) << n.error().message;
    expectNormal(n->at(0, 1), 0, -1, 0, 1e-4); // 0.5 is not exact in 16 bits
    auto missing = ndfmip::loadNormalMap(dir.file("none.png"), {}, nullptr);
    ASSERT_FALSE(missing);
    EXPECT_TRUE(startsWith(missing.error().message, dir.file("none.png") + ": "));
}

// h(x) = A sin(2 pi x / P) on a P-periodic map: the wrapped central difference is exactly
// A cos(2 pi x / P) sin(2 pi / P).
TEST(NormalDecode, HeightSineWrapsExactly) {
    const int P = 16;
    const double A = 0.7, s = 1.5;
    Image h(P, 3, 1);
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < P; ++x) h.at(x, y)[0] = float(A * std::sin(2 * kPi * x / P));
    Image n = ndfmip::heightToNormals(h, float(s), AddressMode::Wrap);
    ASSERT_EQ(n.channels, 3);
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < P; ++x) {
            double d = A * std::cos(2 * kPi * x / P) * std::sin(2 * kPi / P);
            expectNormal(n.at(x, y), -s * d, 0.0, 1.0, 2e-6);
        }
}

// The same along y, rows counted downwards, y up: dh/dy_up = (h[row-1] - h[row+1]) / 2.
TEST(NormalDecode, HeightSineAlongYIsUp) {
    const int P = 12;
    const double A = 0.4, s = 2.0;
    Image h(2, P, 1);
    for (int row = 0; row < P; ++row)
        for (int x = 0; x < 2; ++x) h.at(x, row)[0] = float(A * std::sin(2 * kPi * row / P));
    Image n = ndfmip::heightToNormals(h, float(s), AddressMode::Wrap);
    for (int row = 0; row < P; ++row) {
        double dRow = A * std::cos(2 * kPi * row / P) * std::sin(2 * kPi / P);
        expectNormal(n.at(1, row), 0.0, s * dRow, 1.0, 2e-6); // n.y = -s dh/dy_up = s dh/drow
    }
}

// Central differences are exact for quadratics; the edges use one-sided differences.
TEST(NormalDecode, HeightQuadraticClamp) {
    const int W = 9, H = 7;
    const double a = 0.01, b = -0.02, c = 0.005;
    auto height = [&](int x, int row) { return a * x * x + b * row * row + c * x * row; };
    Image h(W, H, 1);
    for (int row = 0; row < H; ++row)
        for (int x = 0; x < W; ++x) h.at(x, row)[0] = float(height(x, row));
    Image n = ndfmip::heightToNormals(h, 1.f, AddressMode::Clamp);
    for (int row = 1; row < H - 1; ++row)
        for (int x = 1; x < W - 1; ++x) {
            double dx = 2 * a * x + c * row, dRow = 2 * b * row + c * x;
            expectNormal(n.at(x, row), -dx, dRow, 1.0, 1e-5);
        }
    // Left edge: h(1) - h(0); top edge: dh/dy_up = h(row 0) - h(row 1).
    int row = 3;
    expectNormal(n.at(0, row), -(height(1, row) - height(0, row)), 2 * b * row, 1.0, 1e-5);
    int x = 4;
    expectNormal(n.at(x, 0), -(2 * a * x + c * 0), -(height(x, 0) - height(x, 1)), 1.0, 1e-5);
    expectNormal(n.at(x, H - 1), -(2 * a * x + c * (H - 1)), -(height(x, H - 2) - height(x, H - 1)),
                 1.0, 1e-5);
}

TEST(NormalDecode, HeightRampWrapsAcrossEdges) {
    const int W = 8;
    Image h(W, 1, 1);
    for (int x = 0; x < W; ++x) h.at(x, 0)[0] = float(x) / W;
    Image wrap = ndfmip::heightToNormals(h, 1.f, AddressMode::Wrap);
    Image clamp = ndfmip::heightToNormals(h, 1.f, AddressMode::Clamp);
    expectNormal(wrap.at(0, 0), -0.5 * (1.0 / W - (W - 1.0) / W), 0, 1);
    expectNormal(wrap.at(3, 0), -1.0 / W, 0, 1);
    expectNormal(clamp.at(0, 0), -1.0 / W, 0, 1);
    expectNormal(clamp.at(W - 1, 0), -1.0 / W, 0, 1);
}

TEST(NormalDecode, HeightRisingTowardsTopGivesNegativeY) {
    Image h(4, 4, 1);
    for (int row = 0; row < 4; ++row)
        for (int x = 0; x < 4; ++x) h.at(x, row)[0] = float(3 - row) * 0.1f + float(x) * 0.05f;
    Image n = ndfmip::heightToNormals(h, 1.f, AddressMode::Clamp);
    for (int row = 0; row < 4; ++row)
        for (int x = 0; x < 4; ++x) {
            EXPECT_LT(n.at(x, row)[1], 0.f); // surface tilts away from +y
            EXPECT_LT(n.at(x, row)[0], 0.f); // and from +x
            expectNormal(n.at(x, row), -0.05, -0.1, 1.0);
        }
}

TEST(NormalDecode, HeightOnePixelWide) {
    Image h(1, 3, 1);
    h.pixels = {0.f, 0.5f, 1.f};
    for (AddressMode mode : {AddressMode::Wrap, AddressMode::Clamp}) {
        Image n = ndfmip::heightToNormals(h, 1.f, mode);
        EXPECT_EQ(n.at(0, 1)[0], 0.f);
    }
    Image single(1, 1, 1);
    single.pixels = {3.f};
    expectNormal(ndfmip::heightToNormals(single, 1.f, AddressMode::Clamp).at(0, 0), 0, 0, 1);
}

TEST(NormalDecode, HeightOptionUsesFirstChannelAndScale) {
    Image image(4, 1, 3);
    for (int x = 0; x < 4; ++x) {
        image.at(x, 0)[0] = 0.25f * float(x);
        image.at(x, 0)[1] = std::numeric_limits<float>::quiet_NaN(); // unused
    }
    DecodeOptions options;
    options.height = true;
    options.heightScale = 4.f;
    options.address = AddressMode::Clamp;
    DecodeReport report;
    auto n = ndfmip::decodeNormalMap(source(image), options, "h.png", &report);
    ASSERT_TRUE(n) << n.error().message;
    for (int x = 0; x < 4; ++x) expectNormal(n->at(x, 0), -1.0, 0, 1); // 4 * 0.25 per texel
    EXPECT_EQ(report.texels, 4u);
    EXPECT_EQ(report.offUnitLength, 0u);

    image.at(2, 0)[0] = std::numeric_limits<float>::infinity();
    auto bad = ndfmip::decodeNormalMap(source(image), options, "h.png", nullptr);
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.error().message.find("(2, 0)"), std::string::npos) << bad.error().message;
}

TEST(NormalDecode, ValuesWhoseLengthOverflowsAreAnErrorNotZeroNormals) {
    // 1e30 is finite, but its square is not: it must not become a silent (0, 0, 0) normal.
    for (bool isSigned : {false, true}) {
        Image image = filled(3, 2, {0.5f, 0.5f, 1.f});
        image.at(1, 1)[0] = 1e30f;
        DecodeOptions options;
        options.signedValues = isSigned;
        auto n = ndfmip::decodeNormalMap(source(image, true), options, "big.exr", nullptr);
        ASSERT_FALSE(n);
        const std::string& m = n.error().message;
        EXPECT_TRUE(startsWith(m, "big.exr: texel (1, 1) holds (1e+30, ")) << m;
        EXPECT_NE(m.find("too large for a normal"), std::string::npos) << m;
    }
    // Large but finite lengths still give the direction they mean, counted as off unit length.
    Image image = filled(2, 1, {0.f, 0.f, 1.f});
    image.at(0, 0)[0] = 1e15f;
    image.at(0, 0)[2] = 1e15f;
    DecodeOptions options;
    options.signedValues = true;
    DecodeReport report;
    auto n = ndfmip::decodeNormalMap(source(image, true), options, "big.exr", &report);
    ASSERT_TRUE(n) << n.error().message;
    expectNormal(n->at(0, 0), 1, 0, 1);
    EXPECT_EQ(report.offUnitLength, 1u);
}

TEST(NormalDecode, HugeHeightsGiveSteepNormalsNotZeroOnes) {
    Image h(3, 1, 1);
    h.pixels = {0.f, 1e30f, 2e30f};
    Image n = ndfmip::heightToNormals(h, 1.f, AddressMode::Clamp);
    for (int x = 0; x < 3; ++x) expectNormal(n.at(x, 0), -1, 0, 0, 1e-6);
    h.pixels = {-3e38f, 0.f, 3e38f}; // differences beyond float range
    n = ndfmip::heightToNormals(h, 1e6f, AddressMode::Wrap);
    expectNormal(n.at(1, 0), -1, 0, 0, 1e-6);
}
