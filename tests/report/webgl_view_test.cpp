// The report's live WebGL2 view: its GLSL ES compiles for every method, and a real browser
// (headless chromium, SwiftShader) draws the same frame as the CPU renderer.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "report/webgl_view.h"
#include "test_support.h"

namespace ndfmip {
namespace {

std::string findProgram(const char* name) {
    for (const char* dir : {"/usr/bin/", "/usr/local/bin/", "/bin/"}) {
        const std::string path = std::string(dir) + name;
        if (std::filesystem::exists(path)) return path;
    }
    return "";
}

SharedImage bumps() {
    auto image = std::make_shared<Image>(32, 32, 3);
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) {
            const glm::vec3 n = glm::normalize(
                glm::vec3(0.5f * std::sin(0.9f * float(x)), 0.4f * std::cos(1.3f * float(y)), 1.f));
            float* p = image->at(x, y);
            p[0] = n.x, p[1] = n.y, p[2] = n.z;
        }
    return image;
}

TEST(WebglView, FragmentShaderIsGlslEs300ForEveryMethod) {
    const std::string glslang = findProgram("glslangValidator");
    if (glslang.empty()) GTEST_SKIP() << "glslangValidator (glslang-tools) not installed";
    test::TempDir dir("ndfmip_webgl_es");
    const Pyramid pyramid = buildPyramid(bumps());
    Scene scene;
    scene.camera.width = scene.camera.height = 16;
    scene.lights.push_back(Light{});
    for (const MethodShader& shader : methodShaders()) {
        SCOPED_TRACE(shader.name);
        RenderTextures t;
        t.normals = pyramid.base;
        BakeOptions options;
        options.parameters["order"] = 5;
        options.parameters["lobes"] = 3;
        options.baseRoughness = 0.2f; // ggx-fit's fit is for the material's GGX alpha
        t.bake = bakeMethod(shader.bake, pyramid, options);
        if (std::string(shader.name) == kRoughnessMips) {
            for (const auto& level : t.bake.levels) t.roughness.push_back(level[0]);
            scene.material.brdf = Brdf::Ggx;
        } else if (bakeFitsMaterialRoughness(shader.bake)) {
            scene.material.brdf = Brdf::Ggx;
            scene.material.roughness = 0.2f;
        } else {
            scene.material.brdf = Brdf::BlinnPhong;
        }
        Result<RenderProgram> program = renderProgram(scene, t, shader.name, RenderOptions{});
        ASSERT_TRUE(program) << program.error().message;
        const std::string file = dir.file(std::string(shader.name) + ".frag");
        std::ofstream(file) << webglFragmentSource(program.value());
        std::string output;
        const int status = std::system(
            (glslang + " " + test::shellArg(file) + " > " + test::shellArg(file + ".log") + " 2>&1")
                .c_str());
        std::ifstream log(file + ".log");
        output.assign(std::istreambuf_iterator<char>(log), {});
        EXPECT_EQ(status, 0) << output;
    }
}

TEST(WebglView, ReportFrameInAHeadlessBrowserMatchesTheCpu) {
    const std::string chromium = findProgram("chromium");
    if (chromium.empty()) {
        if (const char* v = std::getenv("NDFMIP_REQUIRE_BROWSER"); v && std::string(v) == "1")
            FAIL() << "no chromium";
        GTEST_SKIP() << "chromium not installed (scripts/setup installs it)";
    }
    test::TempDir dir("ndfmip_webgl_report");
    std::string output;
    const std::string map = std::string(NDFMIP_SOURCE_DIR) + "/data/normalmaps/pyramidwall_256.png";
    ASSERT_EQ(test::runCli("eval " + test::shellArg(map) +
                               " --green-down --footprints 4,16 --methods toksvig,vmf:4,sh:4 "
                               "--brdfs ggx --roughness 0.1 --frames 1 -q -o " +
                               test::shellArg(dir.file("report")),
                           &output),
              0)
        << output;
    const std::string dom = dir.file("dom.html");
    const std::string command =
        "timeout 180 " + chromium +
        " --headless --no-sandbox --use-angle=swiftshader --enable-unsafe-swiftshader "
        "--virtual-time-budget=60000 --dump-dom " +
        test::shellArg("file://" + dir.file("report/report.html")) + " > " + test::shellArg(dom) +
        " 2>/dev/null";
    ASSERT_EQ(std::system(command.c_str()), 0);
    std::ifstream in(dom);
    const std::string page((std::istreambuf_iterator<char>(in)), {});
    const size_t at = page.find("data-rel-rmse=\"");
    ASSERT_NE(at, std::string::npos)
        << "the page did not check itself: "
        << page.substr(page.find("ndfmip-webgl-check") == std::string::npos
                           ? 0
                           : page.find("ndfmip-webgl-check"),
                       300);
    const double relRmse = std::atof(page.c_str() + at + 15);
    // The view draws vmf:4 first; measured 1e-6 against the CPU on SwiftShader.
    EXPECT_NE(page.find("WebGL2 frame of vmf:4"), std::string::npos);
    EXPECT_LE(relRmse, 0.02);
    EXPECT_GE(relRmse, 0.0);
}

} // namespace
} // namespace ndfmip
