// The GPU renderer on faceted-sphere scenes (interpolated normals) against the CPU's
// renderInterpolated: the same mesh, the same interpolated normal, Toksvig's cube map at the
// same LOD, the same shading (Mesa's llvmpipe where there is no GPU).
#include <cmath>
#include <cstdio>
#include <string>

#include <gtest/gtest.h>

#include "gpu_test_support.h"
#include "ndfmip/compare.h"
#include "ndfmip/gpu_render.h"
#include "ndfmip/interpolated.h"

namespace ndfmip {
namespace {

// A 12 x 6 faceted sphere in an imageSize x imageSize image, its size on screen set by the field
// of view; a sharp highlight from a point light near the camera (the far sphere of
// tests/render/interpolated_test.cpp) and a dimmer, coloured one from the side.
Scene facetedScene(int imageSize, float fovY, Brdf brdf) {
    Scene s;
    s.geometry.type = GeometryType::FacetedSphere;
    s.geometry.segments = 12;
    s.geometry.rings = 6;
    s.geometry.radius = 1.f;
    s.camera.eye = {0.f, -20.f, 4.f};
    s.camera.target = {0.f, 0.f, 0.f};
    s.camera.fovY = fovY;
    s.camera.width = s.camera.height = imageSize;
    Light key;
    key.type = LightType::Point;
    key.position = {6.f, -18.f, 10.f};
    key.color = glm::vec3(400.f);
    Light side;
    side.type = LightType::Point;
    side.position = {-12.f, -4.f, 3.f};
    side.color = glm::vec3(60.f, 90.f, 120.f);
    s.lights = {key, side};
    s.material.brdf = brdf;
    s.material.exponent = 256.f;
    s.material.roughness = 0.1f;
    s.material.albedo = glm::vec3(0.05f);
    s.background = glm::vec3(0.02f);
    return s;
}

// Mean relative error: sum |gpu - cpu| / sum |cpu| over every pixel and channel.
double meanRelativeError(const Image& gpu, const Image& cpu) {
    double difference = 0.0, reference = 0.0;
    for (size_t i = 0; i < cpu.pixels.size(); ++i) {
        difference += std::abs(double(gpu.pixels[i]) - double(cpu.pixels[i]));
        reference += std::abs(double(cpu.pixels[i]));
    }
    return reference > 0.0 ? difference / reference : difference;
}

void expectSameImage(const Scene& scene, const std::string& method, const char* what) {
    NDFMIP_GL_OR_SKIP(gl);
    Result<Image> cpu = renderInterpolated(scene, method, RenderOptions{});
    ASSERT_TRUE(cpu) << cpu.error().message;
    Result<Image> gpu = renderGpu(scene, RenderTextures{}, method, RenderOptions{});
    ASSERT_TRUE(gpu) << gpu.error().message;
    const double relative = meanRelativeError(gpu.value(), cpu.value());
    Result<ImageComparison> c = compareImages(gpu.value(), cpu.value());
    ASSERT_TRUE(c);
    std::printf("%s %s %s: mean relative error %.3g, relative RMSE %.3g, max abs error %.3g\n",
                method.c_str(), brdfName(scene.material.brdf), what, relative, c->relativeRmse,
                c->maxAbsError);
    EXPECT_LE(relative, 1e-3) << method << " " << what;
    EXPECT_LE(c->relativeRmse, 1e-3) << method << " " << what;
}

struct Case {
    const char* method;
    Brdf brdf;
};

class GpuInterpolated : public ::testing::TestWithParam<Case> {};

// 32 x 32 with the sphere filling most of it; and a 16 x 16 image where it is 9 px across,
// several facets and a whole highlight per pixel (the cube map's coarse levels).
TEST_P(GpuInterpolated, MatchesTheCpuOnASmallAndATinyFacetedSphere) {
    const Case c = GetParam();
    expectSameImage(facetedScene(32, 7.f, c.brdf), c.method, "32 px");
    // 9 px across: 2 r / (2 d tan(fov/2)) of 16 px, d = |eye| = 20.4.
    const float fov =
        float(2.0 * std::atan(2.0 * 16.0 / (9.0 * 2.0 * std::sqrt(416.0))) * 180.0 / M_PI);
    expectSameImage(facetedScene(16, fov, c.brdf), c.method, "9 px");
}

TEST_P(GpuInterpolated, MatchesTheCpuWithASubPixelShift) {
    const Case c = GetParam();
    NDFMIP_GL_OR_SKIP(gl);
    const Scene scene = facetedScene(24, 7.f, c.brdf);
    RenderOptions shifted;
    shifted.pixelShift = {0.3f, -0.2f};
    Result<Image> cpu = renderInterpolated(scene, c.method, shifted);
    Result<Image> gpu = renderGpu(scene, RenderTextures{}, c.method, shifted);
    ASSERT_TRUE(cpu && gpu);
    EXPECT_LE(meanRelativeError(gpu.value(), cpu.value()), 1e-3);
}

INSTANTIATE_TEST_SUITE_P(BothMethods, GpuInterpolated,
                         ::testing::Values(Case{kRenormalized, Brdf::BlinnPhong},
                                           Case{kCubemapToksvig, Brdf::BlinnPhong},
                                           Case{kCubemapToksvig, Brdf::Ggx}),
                         [](const auto& param) {
                             std::string name =
                                 std::string(param.param.method) + "_" + brdfName(param.param.brdf);
                             for (char& ch : name)
                                 if (ch == '-') ch = '_';
                             return name;
                         });

TEST(GpuInterpolatedErrors, GroundTruthAndUnknownMethodsAreOneLineErrors) {
    NDFMIP_GL_OR_SKIP(gl);
    const Scene scene = facetedScene(16, 7.f, Brdf::BlinnPhong);
    Result<Image> truth = renderGpu(scene, RenderTextures{}, kGroundTruth, RenderOptions{});
    ASSERT_FALSE(truth);
    EXPECT_EQ(truth.error().message,
              "render --gpu: 'groundtruth' of a faceted-sphere scene is rendered on the CPU only");
    Result<Image> other = renderGpu(scene, RenderTextures{}, "toksvig", RenderOptions{});
    ASSERT_FALSE(other);
    EXPECT_NE(other.error().message.find("expected renormalized, cubemap-toksvig"),
              std::string::npos)
        << other.error().message;
    EXPECT_EQ(other.error().message.find('\n'), std::string::npos);
}

} // namespace
} // namespace ndfmip
