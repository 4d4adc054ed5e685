// The three.js vMF module (integrations/three/ndfmip_vmf.js, built into
// build/integrations/three) against ndfmip's own GPU renderer: the bundled wall baked with vmf
// (4 lobes, half floats; the KTX2 lobe textures for three, the EXR planes for ndfmip), one plane
// scene (perspective camera, a directional and a point light, GGX), rendered by
// MeshStandardMaterial + the module in headless chromium (WebGL2 on SwiftShader) into a float
// target and by `ndfmip render --gpu` with one hardware-trilinear lookup per pixel (--taps 1
// --lod-bias 0 --lobe-filter parameter: what a texture() call in three does). The two images
// must agree within 2 % relative RMSE. Registered as the ctest test three_vmf_render; it skips,
// saying why, without chromium, node, npm's three, the built module or an OpenGL (EGL) context.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "engines/engine_client.h"
#include "ndfmip/compare.h"
#include "ndfmip/io.h"
#include "test_support.h"
#ifdef NDFMIP_HAS_GPU
#include "gpu/gl_context.h"
#endif

namespace ndfmip {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

const std::string kMap = std::string(NDFMIP_SOURCE_DIR) + "/data/normalmaps/pyramidwall_256.png";
const std::string kModule = std::string(NDFMIP_BINARY_DIR) + "/integrations/three";
constexpr int kLobes = 4;
constexpr int kFrames = 10; // timed frames per material

// Why the test cannot run here, or "" when everything it needs is installed.
std::string missingPrerequisite(std::string* chromium, std::string* node) {
    if (std::string missing = test::missingThreePage(
            {"/build/three.module.js", "/examples/jsm/loaders/KTX2Loader.js"}, chromium, node);
        !missing.empty())
        return missing;
    if (!fs::exists(kModule + "/ndfmip_vmf_glsl.js") || !fs::exists(kModule + "/ndfmip_vmf.js"))
        return "the three.js module was not built (" + kModule +
               "; glslangValidator or spirv-cross missing when configured)";
#ifdef NDFMIP_HAS_GPU
    if (Result<GlContext> gl = createHeadlessGl(); !gl) return gl.error().message;
#else
    return "this ndfmip was built without the OpenGL path (render --gpu)";
#endif
    return "";
}

// Float32 RGBA pixels, bottom row first (readPixels), from base64, as an RGB image top row first.
Image fromReadPixels(const std::string& base64, int width, int height) {
    const std::vector<unsigned char> bytes = test::fromBase64(base64);
    Image image(width, height, 3);
    if (bytes.size() != size_t(width) * size_t(height) * 16) return Image();
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            float rgba[4];
            std::memcpy(rgba,
                        bytes.data() + 16 * (size_t(height - 1 - y) * size_t(width) + size_t(x)),
                        sizeof rgba);
            float* p = image.at(x, y);
            p[0] = rgba[0], p[1] = rgba[1], p[2] = rgba[2];
        }
    return image;
}

double median(std::vector<double> values) {
    if (values.empty()) return 0.0;
    std::sort(values.begin(), values.end());
    return values[values.size() / 2];
}

TEST(EngineClients, ThreeVmfRender) {
    std::string chromium, node;
    if (const std::string missing = missingPrerequisite(&chromium, &node); !missing.empty()) {
        if (const char* v = std::getenv("NDFMIP_REQUIRE_BROWSER"); v && std::string(v) == "1")
            FAIL() << missing;
        GTEST_SKIP() << missing;
    }
    test::TempDir dir("ndfmip_three_vmf");

    // The bake: the wall (green down, as scenes/ read it) with 4 lobes in half floats, the EXR
    // planes for ndfmip's renderer and the same planes as KTX2 RGBA16F for three.
    const std::string bake = dir.file("wall.bake");
    std::string output;
    ASSERT_EQ(test::runCli("bake " + test::shellArg(kMap) + " --green-down --method vmf --lobes " +
                               std::to_string(kLobes) +
                               " --half --export exr,ktx2 --export-textures planes -q -o " +
                               test::shellArg(bake),
                           &output),
              0)
        << output;

    // The scene: a 10 x 10 plane (one repeat of the map per unit) filling a 256² perspective
    // view, a directional and a point light, GGX alpha 0.15.
    const json scene = json::parse(R"({
  "camera": {"type": "perspective", "eye": [0, -2.4, 1.8], "target": [0, 0.2, 0], "up": [0, 0, 1],
             "fov": 40, "width": 256, "height": 256},
  "object": {"type": "plane", "center": [0, 0, 0], "normal": [0, 0, 1], "tangent": [1, 0, 0],
             "size": [10, 10], "tiling": [10, 10]},
  "lights": [
    {"type": "directional", "direction": [0, 0.6, 0.8], "color": [1, 0.9, 0.8], "intensity": 1},
    {"type": "point", "position": [0.8, 0.6, 0.9], "color": [0.6, 0.7, 1], "intensity": 1.5}
  ],
  "material": {"brdf": "ggx", "roughness": 0.15, "albedo": [0.25, 0.2, 0.15], "specular": 1},
  "method": "vmf",
  "background": 0
})");
    json withMap = scene;
    withMap["normal_map"] = {{"path", kMap}, {"green_down", true}};
    const std::string scenePath = dir.file("scene.json");
    test::writeBytes(scenePath, withMap.dump(2));

    // ndfmip's GPU renderer: one trilinear lookup per pixel, parameters blended by the hardware.
    const std::string gpu = dir.file("gpu.exr");
    ASSERT_EQ(test::runCli("render " + test::shellArg(scenePath) + " --gpu --bake " +
                               test::shellArg(bake) +
                               " --taps 1 --lod-bias 0 --lobe-filter parameter --aniso 1 "
                               "--no-png -q -o " +
                               test::shellArg(gpu),
                           &output),
              0)
        << output;
    Result<SourceImage> reference = loadImage(gpu);
    ASSERT_TRUE(reference) << reference.error().message;

    // three.js in headless chromium.
    std::string lobes;
    for (int j = 0; j < kLobes; ++j)
        lobes += (j ? ",/bake/ktx2/lobe" : "/bake/ktx2/lobe") + std::to_string(j) + ".ktx2";
    const std::string result = dir.file("three.json"), log = dir.file("three.log");
    ASSERT_EQ(test::runThreePage(node, chromium, "three_vmf_render.mjs",
                                 "scene=/asset/scene.json&lobes=" + lobes + "&frames=" +
                                     std::to_string(kFrames) + "&normal=/data/pyramidwall_256.png",
                                 {{"/ndfmip/", kModule},
                                  {"/bake/", bake},
                                  {"/asset/", dir.path.string()},
                                  {"/data/", std::string(NDFMIP_SOURCE_DIR) + "/data/normalmaps"}},
                                 result, log),
              0)
        << test::fileBytes(log);
    const json report = json::parse(test::fileBytes(result));
    std::printf("three r%s on %s\n", report["three"].get<std::string>().c_str(),
                report["renderer"].get<std::string>().c_str());
    EXPECT_EQ(report["glError"], 0);
    const int width = report["width"].get<int>(), height = report["height"].get<int>();
    ASSERT_EQ(width, reference->image.width);
    ASSERT_EQ(height, reference->image.height);
    const Image three = fromReadPixels(report["pixels"].get<std::string>(), width, height);
    ASSERT_EQ(three.width, width) << "pixel data of the wrong size";

    Result<ImageComparison> c = compareImages(three, reference->image);
    ASSERT_TRUE(c) << c.error().message;
    std::printf("three.js vs render --gpu: relative RMSE %.4f, energy ratio %.4f, max |error| %.4f "
                "(RMSE %.4f)\n",
                c->relativeRmse, c->energyRatio, c->maxAbsError, c->rmse);
    EXPECT_LT(c->relativeRmse, 0.02);
    EXPECT_NEAR(c->energyRatio, 1.0, 0.02);

    // The environment path (PMREM, per lobe about its mean normal) compiles and adds light.
    const json& environment = report["environment"];
    std::printf("under RoomEnvironment: mean radiance %.4f (lights alone %.4f)\n",
                environment["meanWithEnvironment"].get<double>(),
                environment["meanDirect"].get<double>());
    EXPECT_TRUE(environment["programsRunnable"].get<bool>());
    EXPECT_EQ(environment["glError"], 0);
    EXPECT_GT(environment["meanWithEnvironment"].get<double>(),
              environment["meanDirect"].get<double>() * 1.01);
    EXPECT_TRUE(std::isfinite(environment["meanWithEnvironment"].get<double>()));

    const json& frames = report["frameMs"];
    for (const char* material : {"vmf", "standard"})
        if (frames.contains(material)) {
            const std::vector<double> ms = frames[material].get<std::vector<double>>();
            std::printf("frame time, %s: median %.1f ms over %zu frames (%dx%d)\n", material,
                        median(ms), ms.size(), width, height);
        }
}

} // namespace
} // namespace ndfmip
