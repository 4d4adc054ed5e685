// ndfmip compare: JSON statistics checked against a computation in the test, clean refusals,
// and the false-colour error image.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>

#include <nlohmann/json.hpp>

#include "ndfmip/io.h"
#include "test_support.h"

namespace ndfmip::test {
namespace {

using nlohmann::json;

void writeExr(const std::string& path, const Image& image) {
    Status s = saveExr(path, image);
    ASSERT_TRUE(s.ok()) << s.error;
}

// A smooth positive reference and a copy with a position-dependent error.
Image reference(int w, int h, int c) {
    Image image(w, h, c);
    for (size_t i = 0; i < image.pixels.size(); ++i)
        image.pixels[i] = 0.5f + 0.4f * std::sin(0.7f * float(i));
    return image;
}

Image perturbed(const Image& b) {
    Image a = b;
    for (size_t i = 0; i < a.pixels.size(); ++i) a.pixels[i] += 0.05f * float(i % 5) - 0.07f;
    return a;
}

// The statistics of compare.h computed directly over channels [first, last).
struct Expected {
    double rmse, relRmse, psnr, energyRatio, maxAbs;
};

Expected expected(const Image& a, const Image& b, int first, int last) {
    double se = 0, bb = 0, sa = 0, sb = 0, peak = 0, maxAbs = 0, n = 0;
    for (size_t t = 0; t < b.texelCount(); ++t)
        for (int c = first; c < last; ++c) {
            double va = a.pixels[t * size_t(b.channels) + size_t(c)];
            double vb = b.pixels[t * size_t(b.channels) + size_t(c)];
            se += (va - vb) * (va - vb);
            bb += vb * vb;
            sa += va;
            sb += vb;
            peak = std::max(peak, vb);
            maxAbs = std::max(maxAbs, std::abs(va - vb));
            n += 1;
        }
    return {std::sqrt(se / n), std::sqrt(se / bb), 10 * std::log10(peak * peak / (se / n)), sa / sb,
            maxAbs};
}

json runCompare(const std::string& args) {
    std::string output;
    int status = runCli("compare " + args, &output);
    EXPECT_EQ(status, 0) << output;
    json out = json::parse(output, nullptr, /*allow_exceptions=*/false);
    EXPECT_FALSE(out.is_discarded()) << "compare printed no JSON: " << output;
    return out;
}

void expectNumbers(const json& out, const Expected& e) {
    EXPECT_NEAR(out.at("rmse").get<double>(), e.rmse, 1e-9);
    EXPECT_NEAR(out.at("rel_rmse").get<double>(), e.relRmse, 1e-9);
    EXPECT_NEAR(out.at("psnr").get<double>(), e.psnr, 1e-7);
    EXPECT_NEAR(out.at("energy_ratio").get<double>(), e.energyRatio, 1e-9);
    EXPECT_NEAR(out.at("max_abs_error").get<double>(), e.maxAbs, 1e-9);
}

// Exit status 1 and one line of output that mentions each of `mentions`.
void expectOneLineFailure(const std::string& args, std::initializer_list<std::string> mentions) {
    std::string output;
    EXPECT_EQ(runCli("compare " + args, &output), 1) << output;
    EXPECT_EQ(std::count(output.begin(), output.end(), '\n'), 1) << output;
    for (const std::string& m : mentions)
        EXPECT_NE(output.find(m), std::string::npos) << "'" << m << "' not in: " << output;
}

TEST(CompareCli, PrintsStatisticsOfTheWholeImage) {
    TempDir tmp("compare_cli");
    const Image b = reference(7, 5, 3), a = perturbed(b);
    writeExr(tmp.file("a.exr"), a);
    writeExr(tmp.file("b.exr"), b);
    json out = runCompare(tmp.file("a.exr") + " " + tmp.file("b.exr"));
    std::set<std::string> keys;
    for (const auto& item : out.items()) keys.insert(item.key());
    EXPECT_EQ(keys, (std::set<std::string>{"a", "b", "width", "height", "channels", "rmse",
                                           "rel_rmse", "psnr", "energy_ratio", "max_abs_error"}));
    EXPECT_EQ(out.at("a"), tmp.file("a.exr"));
    EXPECT_EQ(out.at("b"), tmp.file("b.exr"));
    EXPECT_EQ(out.at("width"), 7);
    EXPECT_EQ(out.at("height"), 5);
    EXPECT_EQ(out.at("channels"), 3);
    expectNumbers(out, expected(a, b, 0, 3));
}

TEST(CompareCli, OneChannelAndIdenticalImages) {
    TempDir tmp("compare_cli");
    const Image b = reference(4, 6, 3), a = perturbed(b);
    writeExr(tmp.file("a.exr"), a);
    writeExr(tmp.file("b.exr"), b);
    json one = runCompare(tmp.file("a.exr") + " " + tmp.file("b.exr") + " --channel 2");
    EXPECT_EQ(one.at("channels"), 1);
    expectNumbers(one, expected(a, b, 2, 3));
    json same = runCompare(tmp.file("b.exr") + " " + tmp.file("b.exr"));
    EXPECT_TRUE(same.at("psnr").is_null()); // infinite
    EXPECT_EQ(same.at("rmse"), 0.0);
    EXPECT_EQ(same.at("energy_ratio"), 1.0);
}

TEST(CompareCli, RefusesMismatchedMissingAndOutOfRange) {
    TempDir tmp("compare_cli");
    writeExr(tmp.file("a.exr"), reference(4, 4, 3));
    writeExr(tmp.file("b.exr"), reference(5, 4, 3));
    const std::string a = tmp.file("a.exr"), b = tmp.file("b.exr");
    expectOneLineFailure(a + " " + b, {a, b, "4x4", "5x4"});
    expectOneLineFailure(a + " " + tmp.file("none.exr"), {tmp.file("none.exr")});
    expectOneLineFailure(a + " " + a + " --channel 3", {a, "--channel 3"});
    EXPECT_FALSE(std::filesystem::exists(tmp.file("e.png")));
    expectOneLineFailure(a + " " + b + " --error-image " + tmp.file("e.png"), {"4x4"});
    EXPECT_FALSE(std::filesystem::exists(tmp.file("e.png")));
}

TEST(CompareCli, WritesTheErrorImage) {
    TempDir tmp("compare_cli");
    const Image b = reference(9, 3, 1);
    Image a = b;
    a.at(4, 1)[0] += 0.5f; // the only error
    writeExr(tmp.file("a.exr"), a);
    writeExr(tmp.file("b.exr"), b);
    const std::string png = tmp.file("error.png");
    runCompare(tmp.file("a.exr") + " " + tmp.file("b.exr") + " --error-image " + png +
               " --error-scale 0.5");
    Result<SourceImage> loaded = loadImage(png);
    ASSERT_TRUE(loaded.ok()) << loaded.error().message;
    EXPECT_EQ(loaded->format, "png");
    EXPECT_EQ(loaded->bitsPerChannel, 8);
    const Image& e = loaded->image;
    ASSERT_EQ(e.width, 9);
    ASSERT_EQ(e.height, 3);
    ASSERT_EQ(e.channels, 3);
    EXPECT_EQ(e.at(0, 0)[0], 0.f);
    EXPECT_EQ(e.at(4, 1)[1], 1.f); // error = scale: the top colour, (252, 255, 164)
    EXPECT_EQ(e.at(4, 1)[2], 164.f / 255.f);
}

} // namespace
} // namespace ndfmip::test
