// RenderOptions::shViews: the SH-lighting methods reading, per pixel, the lighting of the sparse
// set of views (environment_sh_views.h) interpolated at the pixel's own view. In an orthographic
// view every pixel has the image centre's view, so the one prepared view (shViews = 0) is the
// exact lighting there: the set must approach it as it grows, and match it where the view is one
// of the set's.
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <omp.h>

#include <gtest/gtest.h>

#include "env/env_test_support.h"
#include "ndfmip/environment_cache.h"
#include "ndfmip/environment_lighting.h"
#include "ndfmip/render.h"
#include "render/render_program.h"
#include "test_support.h"

namespace ndfmip {
namespace {

// A sky with a soft sun, so L' changes with the view.
glm::dvec3 sunSky(glm::dvec3 d) {
    const glm::dvec3 sun = glm::normalize(glm::dvec3(0.6, 0.5, 0.4));
    return glm::dvec3(0.5 + 0.4 * d.y) + glm::dvec3(8. * std::exp(20. * (glm::dot(d, sun) - 1.)));
}

Material glossy() {
    Material m;
    m.brdf = Brdf::BlinnPhong;
    m.exponent = 32.f;
    m.albedo = glm::vec3(0.1f);
    m.specular = glm::vec3(1.f);
    return m;
}

// A 1 x 1 plane seen from `eye` (orthographic or perspective), lit only by the environment.
Scene planeScene(glm::vec3 eye, CameraType type) {
    Scene s;
    s.camera.type = type;
    s.camera.eye = eye;
    s.camera.target = glm::vec3(0.f);
    s.camera.up = {0.f, 1.f, 0.f};
    s.camera.orthoHeight = 0.5f;
    s.camera.fovY = 60.f;
    s.camera.width = s.camera.height = 12;
    s.geometry.size = {1.f, 1.f};
    s.material = glossy();
    s.environment.path = "(in memory)";
    return s;
}

RenderTextures shTextures(const std::string& method) {
    RenderTextures t;
    t.normals = std::make_shared<const Image>(test::randomNormals(64, 64, 0.4f, 5));
    t.environment = std::make_shared<const EnvironmentLighting>(
        makeEnvironmentLighting(envtest::mapOf(64, sunSky)));
    BakeOptions bake;
    bake.parameters["order"] = 7;
    bake.parameters["lobes"] = 2;
    t.bake = bakeMethod(method == "sh" ? Method::Sh : Method::Vmf, buildPyramid(t.normals), bake);
    return t;
}

RenderOptions withViews(int views, EnvironmentWay way = EnvironmentWay::ShLighting) {
    RenderOptions o;
    o.shViews = views;
    o.vmfEnvironment = way;
    return o;
}

double relativeRmse(const Image& a, const Image& reference) {
    double error = 0., norm = 0.;
    for (size_t i = 0; i < reference.pixels.size(); ++i) {
        const double d = double(a.pixels[i]) - double(reference.pixels[i]);
        error += d * d;
        norm += double(reference.pixels[i]) * double(reference.pixels[i]);
    }
    return std::sqrt(error / norm);
}

// Orthographic, 35 degrees off the normal and off every grid view: the one prepared view is exact,
// and the set's interpolation approaches it as the set grows.
TEST(ShViewsRender, OrthographicErrorFallsAsTheSetGrows) {
    const Scene scene =
        planeScene(4.f * glm::normalize(glm::vec3(0.35f, -0.45f, 0.82f)), CameraType::Orthographic);
    for (const std::string method : {"sh", "vmf"}) {
        const RenderTextures t = shTextures(method);
        Result<Image> exact = render(scene, t, method, withViews(0));
        ASSERT_TRUE(exact) << exact.error().message;
        double previous = 1e9;
        for (int views : {6, 18, 66}) {
            Result<Image> image = render(scene, t, method, withViews(views));
            ASSERT_TRUE(image) << image.error().message;
            const double error = relativeRmse(image.value(), exact.value());
            std::printf("[ measured ] %s, %d views: relative RMSE against the exact view %.5f\n",
                        method.c_str(), views, error);
            EXPECT_LT(error, previous) << method << " " << views;
            EXPECT_GT(error, 0.);
            previous = error;
        }
    }
}

// Straight down the world's -z: the view towards the camera is the environment's +y, a view of
// every grid, so the set gives the one prepared view's image (to the float rounding of the view
// through the tangent frame).
TEST(ShViewsRender, AtAGridViewMatchesTheFixedView) {
    const Scene scene = planeScene({0.f, 0.f, 4.f}, CameraType::Orthographic);
    const RenderTextures t = shTextures("sh");
    Result<Image> fixed = render(scene, t, "sh", withViews(0));
    Result<Image> set = render(scene, t, "sh", withViews(18));
    ASSERT_TRUE(fixed && set);
    EXPECT_LT(relativeRmse(set.value(), fixed.value()), 1e-5);
}

// In perspective each pixel reads its own lighting: the same image on any thread count, and not
// the fixed view's image away from the centre.
TEST(ShViewsRender, PerspectiveImageDoesNotDependOnTheThreadCount) {
    const Scene scene = planeScene({0.f, -1.2f, 0.7f}, CameraType::Perspective);
    for (const std::string method : {"sh", "vmf"}) {
        const RenderTextures t = shTextures(method);
        const int threads = omp_get_max_threads();
        omp_set_num_threads(1);
        Result<Image> one = render(scene, t, method, withViews(18));
        omp_set_num_threads(std::max(2, threads));
        Result<Image> many = render(scene, t, method, withViews(18));
        omp_set_num_threads(threads);
        ASSERT_TRUE(one && many);
        EXPECT_EQ(one->pixels, many->pixels) << method;
        Result<Image> fixed = render(scene, t, method, withViews(0));
        ASSERT_TRUE(fixed);
        EXPECT_GT(relativeRmse(one.value(), fixed.value()), 1e-3) << method;
    }
}

TEST(ShViewsRender, RefusesCountsOutOfRange) {
    const Scene scene = planeScene({0.f, 0.f, 4.f}, CameraType::Orthographic);
    const RenderTextures t = shTextures("sh");
    for (int views : {-1, kMaxShViews + 1}) {
        Result<Image> image = render(scene, t, "sh", withViews(views));
        ASSERT_FALSE(image);
        EXPECT_NE(image.error().message.find("SH views must be in 0 .. 1026"), std::string::npos)
            << image.error().message;
    }
}

// The GPU renderer has no set of views yet: it refuses one in a line, before any GL work.
TEST(ShViewsRender, TheGpuProgramRefusesASetOfViews) {
    const Scene scene = planeScene({0.f, 0.f, 4.f}, CameraType::Orthographic);
    const RenderTextures t = shTextures("sh");
    Result<RenderProgram> program = renderProgram(scene, t, "sh", withViews(18));
    ASSERT_FALSE(program);
    EXPECT_EQ(program.error().message, "render --gpu: --sh-views is rendered on the CPU only");
    EXPECT_TRUE(renderProgram(scene, t, "sh", withViews(0)));
}

// The set is prepared once per map, order, size and cosine, and every render shares it.
TEST(ShViewsRender, TheCacheSharesOneSetPerSize) {
    const EnvironmentLighting lighting = makeEnvironmentLighting(envtest::mapOf(32, sunSky));
    const auto a = cachedShViewSet(lighting, 2, 1), b = cachedShViewSet(lighting, 2, 1);
    const auto c = cachedShViewSet(lighting, 2, 2);
    EXPECT_EQ(a.get(), b.get());
    EXPECT_NE(a.get(), c.get());
    EXPECT_EQ(int(a->views.size()), shViewCount(1));
    EXPECT_EQ(int(c->views.size()), shViewCount(2));
}

} // namespace
} // namespace ndfmip
