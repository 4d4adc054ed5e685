// `ndfmip render --gpu` from the command line: the same files as the CPU path, the same image,
// one-line errors.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

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
    ASSERT_EQ(test::runCli("render " + test::shellArg(kScene) + " --method vmf --lobes 3 -q -o " +
                               test::shellArg(cpu),
                           &output),
              0)
        << output;
    ASSERT_EQ(test::runCli("render " + test::shellArg(kScene) +
                               " --method vmf --lobes 3 -q --gpu --gpu-frames 2 -o " +
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

// A 32x32 sphere under one of the shared maps (visible around it), toksvig the split-sum way and
// vmf and sh the SH-lighting way: the GPU writes the CPU's image; lean (no environment shading)
// is refused by name.
TEST(RenderGpuCli, EnvironmentScenesMatchTheCpu) {
    NDFMIP_GL_OR_SKIP(gl);
    const std::filesystem::path maps = test::sharedEnvMaps();
    if (maps.empty() || !std::filesystem::exists(maps / "venice_sunset_1k.hdr"))
        GTEST_SKIP() << "no shared environment maps beside the checkout";
    test::TempDir dir("ndfmip_render_gpu_environment");
    const std::filesystem::path scene = dir.path / "sphere.json";
    {
        std::ofstream out(scene);
        out << R"({"camera": {"eye": [0, -4, 1.5], "target": [0, 0, 0], "up": [0, 0, 1], "fov": 35, "width": 32, "height": 32},
 "object": {"type": "sphere", "radius": 1, "tiling": [4, 2]},
 "environment": {"path": )"
            << nlohmann::json((maps / "venice_sunset_1k.hdr").string()).dump()
            << R"(, "rotation": 40, "visible": true},
 "material": {"brdf": "ggx", "roughness": 0.2, "albedo": 0.15, "specular": 1},
 "normal_map": {"path": )"
            << nlohmann::json(std::string(NDFMIP_SOURCE_DIR) +
                              "/data/normalmaps/pyramidwall_256.png")
                   .dump()
            << R"(, "green_down": true}})";
    }
    for (const char* args :
         {"--method toksvig --env-lod unreal", "--method toksvig --env-lod log2sigma",
          "--method vmf --lobes 2 --vmf-environment sh", "--method sh"}) {
        const std::string cpu = (dir.path / "cpu.exr").string(),
                          gpu = (dir.path / "gpu.exr").string();
        std::string output;
        const std::string common = "render " + test::shellArg(scene.string()) + " " + args + " -q";
        ASSERT_EQ(test::runCli(common + " -o " + test::shellArg(cpu), &output), 0) << output;
        ASSERT_EQ(test::runCli(common + " --gpu -o " + test::shellArg(gpu), &output), 0) << output;
        Result<SourceImage> a = loadImage(cpu), b = loadImage(gpu);
        ASSERT_TRUE(a && b);
        Result<ImageComparison> c = compareImages(b->image, a->image);
        ASSERT_TRUE(c);
        EXPECT_LT(c->relativeRmse, 3e-3) << args;
    }
    test::expectCliRefuses("render " + test::shellArg(scene.string()) +
                               " --method lean --gpu -q -o " +
                               test::shellArg((dir.path / "lean.exr").string()),
                           {"'lean'", "cannot shade under an environment"});
}

// A faceted-sphere scene (interpolated normals): cubemap-toksvig on the GPU writes the CPU's
// image, also over shifted frames; its ground truth is refused by name.
TEST(RenderGpuCli, FacetedSphereScenesMatchTheCpu) {
    NDFMIP_GL_OR_SKIP(gl);
    test::TempDir dir("ndfmip_render_gpu_faceted");
    const std::filesystem::path scene = dir.path / "faceted.json";
    {
        std::ofstream out(scene);
        out << R"({"camera": {"eye": [0, -20, 4], "target": [0, 0, 0], "fov": 8, "width": 24, "height": 24},
 "object": {"type": "faceted-sphere", "segments": 12, "rings": 6, "radius": 1},
 "lights": [{"type": "point", "position": [6, -18, 10], "intensity": 400}],
 "material": {"brdf": "blinnphong", "exponent": 256, "albedo": [0.05, 0.05, 0.05]}})";
    }
    const std::string cpu = (dir.path / "cpu.exr").string(), gpu = (dir.path / "gpu.exr").string();
    std::string output;
    const std::string common =
        "render " + test::shellArg(scene.string()) + " --method cubemap-toksvig -q ";
    ASSERT_EQ(test::runCli(common + "-o " + test::shellArg(cpu), &output), 0) << output;
    ASSERT_EQ(
        test::runCli(common + "--gpu --frames 2 --truth-spp 4 -o " + test::shellArg(gpu), &output),
        0)
        << output;
    EXPECT_NE(output.find("error flicker"), std::string::npos) << output;
    Result<SourceImage> a = loadImage(cpu), b = loadImage(gpu);
    ASSERT_TRUE(a && b);
    Result<ImageComparison> c = compareImages(b->image, a->image);
    ASSERT_TRUE(c);
    EXPECT_LT(c->relativeRmse, 1e-3);
    test::expectCliRefuses("render " + test::shellArg(scene.string()) +
                               " --method groundtruth --gpu -q -o " +
                               test::shellArg((dir.path / "truth.exr").string()),
                           {"'groundtruth'", "faceted-sphere", "CPU only"});
}

TEST(RenderGpuCli, CpuOnlyMethodsAndMissingDriversAreOneLineErrors) {
    test::TempDir dir("ndfmip_render_gpu_errors");
    const std::string out = (dir.path / "x.exr").string();
    {
        NDFMIP_GL_OR_SKIP(gl);
        test::expectCliRefuses("render " + test::shellArg(kScene) +
                                   " --method groundtruth --gpu -q -o " + test::shellArg(out),
                               {"CPU only"});
    }
    // No EGL vendor library: libglvnd finds no driver.
    std::string output;
    setenv("__EGL_VENDOR_LIBRARY_FILENAMES", "/nonexistent/vendor.json", 1);
    const int refused = test::runCli(
        "render " + test::shellArg(kScene) + " --gpu -q -o " + test::shellArg(out), &output);
    unsetenv("__EGL_VENDOR_LIBRARY_FILENAMES");
    test::expectOneLineError(refused, output, {"GPU: ", "EGL"});
    EXPECT_FALSE(std::filesystem::exists(out));
}

} // namespace
} // namespace ndfmip
