// `ndfmip render --gpu` from the command line: the same files as the CPU path, the same image,
// one-line errors.
#include <cstdlib>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "gpu_test_support.h"
#include "ndfmip/compare.h"
#include "ndfmip/io.h"
#include "test_support.h"

namespace ndfmip {
namespace {

const std::string kScene = std::string(NDFMIP_SOURCE_DIR) + "/scenes/sphere.json";

TEST(RenderGpuCli, WritesTheCpusImageAndTimesFrames) {
    NDFMIP_GL_OR_SKIP(gl);
    test::TempDir dir("ndfmip_render_gpu");
    const std::string cpu = (dir.path / "cpu.exr").string(), gpu = (dir.path / "gpu.exr").string();
    std::string output;
    ASSERT_EQ(test::runCli("render " + test::shellArg(kScene) + " --method vmf --lobes 3 -q -o " + test::shellArg(cpu), &output), 0)
        << output;
    ASSERT_EQ(test::runCli("render " + test::shellArg(kScene) + " --method vmf --lobes 3 -q --gpu --gpu-frames 2 -o " +
                               test::shellArg(gpu),
                           &output),
              0)
        << output;
    EXPECT_NE(output.find("gpu: "), std::string::npos) << output;
    EXPECT_NE(output.find("medians of 2"), std::string::npos) << output;
    EXPECT_TRUE(std::filesystem::exists(dir.path / "gpu.png"));
    Result<SourceImage> a = loadImage(cpu), b = loadImage(gpu);
    ASSERT_TRUE(a && b);
    Result<ImageComparison> c = compareImages(b->image, a->image);
    ASSERT_TRUE(c);
    EXPECT_LT(c->relativeRmse, 1e-3);
}

TEST(RenderGpuCli, CpuOnlyMethodsAndMissingDriversAreOneLineErrors) {
    test::TempDir dir("ndfmip_render_gpu_errors");
    const std::string out = (dir.path / "x.exr").string();
    {
        NDFMIP_GL_OR_SKIP(gl);
        test::expectCliRefuses("render " + test::shellArg(kScene) + " --method groundtruth --gpu -q -o " + test::shellArg(out),
                               {"CPU only"});
    }
    // No EGL vendor library: libglvnd finds no driver.
    std::string output;
    setenv("__EGL_VENDOR_LIBRARY_FILENAMES", "/nonexistent/vendor.json", 1);
    const int refused = test::runCli("render " + test::shellArg(kScene) + " --gpu -q -o " + test::shellArg(out), &output);
    unsetenv("__EGL_VENDOR_LIBRARY_FILENAMES");
    test::expectOneLineError(refused, output, {"GPU: ", "EGL"});
    EXPECT_FALSE(std::filesystem::exists(out));
}

} // namespace
} // namespace ndfmip
