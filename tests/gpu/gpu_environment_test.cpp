// The GPU renderer under an environment against the CPU renderer: the split-sum methods (naive,
// roughness-mips, toksvig, vmf prefiltered; the radiance at the widened roughness, the albedo
// factor at the material's over the texel's spread) for every level rule and the SH-lighting ones
// (vmf with --vmf-environment sh; sh) give the CPU's image, on the plane and the sphere, with
// parameter blending and texel shading; what the GPU cannot draw is refused in one line naming the
// method.
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "env/env_test_support.h"
#include "gpu_test_support.h"
#include "ndfmip/compare.h"
#include "ndfmip/environment_lighting.h"
#include "ndfmip/gpu_render.h"
#include "ndfmip/render.h"

namespace ndfmip {
namespace {

using test::bumpyMap;

// A 128x64 sky with detail at every scale: a gradient, a ground, a small bright sun and
// stripes in azimuth, so that every prefiltered level differs from the next.
std::shared_ptr<const EnvironmentLighting> skyLighting(double rotation = 0.) {
    const glm::dvec3 sun = glm::normalize(glm::dvec3(0.5, 0.6, 0.6));
    Environment env = envtest::mapOf(128, [&](glm::dvec3 d) {
        glm::dvec3 c =
            d.y > 0. ? glm::dvec3(0.5, 0.6, 0.9) * (0.4 + 0.6 * d.y) : glm::dvec3(0.3, 0.25, 0.2);
        c += 30. * std::exp(-60. * (1. - glm::dot(d, sun))) * glm::dvec3(1., 0.9, 0.7);
        if (std::sin(10. * std::atan2(d.x, d.z)) > 0.) c += glm::dvec3(0.3, 0.1, 0.05);
        return c;
    });
    env.rotation = rotation;
    return std::make_shared<const EnvironmentLighting>(makeEnvironmentLighting(std::move(env)));
}

// A 32x32 view of a sphere (the map visible around it) or of a grazing plane, lit by the
// environment alone.
Scene environmentScene(bool sphere, Brdf brdf) {
    Scene s;
    s.camera.width = s.camera.height = 32;
    if (sphere) {
        s.camera.eye = {0.f, -4.f, 1.5f};
        s.camera.fovY = 35.f;
        s.geometry.type = GeometryType::Sphere;
        s.geometry.tiling = {4.f, 2.f};
        s.environment.visible = true;
    } else {
        s.camera.eye = {0.f, -17.5f, 0.75f};
        s.camera.target = {0.f, -14.f, 0.f};
        s.camera.fovY = 22.f;
        s.geometry.size = {32.f, 32.f};
        s.geometry.tiling = {32.f, 32.f};
    }
    s.environment.path = "(in memory)";
    s.material.brdf = brdf;
    s.material.exponent = 64.f;
    s.material.roughness = 0.2f;
    s.material.albedo = glm::vec3(0.3f);
    s.material.specular = glm::vec3(0.5f);
    s.background = glm::vec3(0.02f);
    return s;
}

RenderTextures texturesFor(const std::string& method,
                           std::shared_ptr<const EnvironmentLighting> lighting) {
    RenderTextures t;
    t.normals = bumpyMap();
    t.environment = std::move(lighting);
    const Pyramid pyramid = buildPyramid(t.normals);
    BakeOptions options;
    options.parameters["lobes"] = 3;
    options.parameters["order"] = 6;
    t.bake = bakeMethod(*methodFromString(method == kRoughnessMips ? "naive" : method), pyramid,
                        options);
    if (method == kRoughnessMips) { // Toksvig's alpha, as an engine's roughness mips would hold
        BakeOptions base;
        base.baseRoughness = 0.2f;
        const Bake toksvig = bakeMethod(Method::Toksvig, pyramid, base);
        for (const auto& level : toksvig.levels) t.roughness.push_back(level[2]); // roughness_ggx
        t.roughnessIsAlpha = true;
    }
    return t;
}

struct Agreement {
    double meanRelative = 0.; // sum |gpu - cpu| / sum |cpu|, over pixels and channels
    double relativeRmse = 0.;
};

Agreement agreement(const Image& gpu, const Image& cpu) {
    double difference = 0., total = 0.;
    for (size_t i = 0; i < cpu.pixels.size(); ++i) {
        difference += std::abs(double(gpu.pixels[i]) - double(cpu.pixels[i]));
        total += std::abs(double(cpu.pixels[i]));
    }
    Result<ImageComparison> c = compareImages(gpu, cpu);
    return {total > 0. ? difference / total : 0., c ? c->relativeRmse : 1.};
}

struct Case {
    const char* method;
    Brdf brdf;
    EnvironmentLod lod;
    EnvironmentWay way = EnvironmentWay::Prefiltered;
};

class GpuEnvironment : public ::testing::TestWithParam<Case> {};

// Measured on llvmpipe: split sum mean relative error 1.2e-5 .. 1.1e-4 (log2sigma's cube faces:
// 1.6e-7 .. 2.4e-7 on the plane, 1.1e-5 .. 2.5e-5 on the sphere), relative RMSE 2e-5 ..
// 3.5e-4 (float against the CPU's double SH and equirect coordinates, and the GPU's atan and
// asin); SH lighting 2.6e-7 .. 9.7e-6 and 8.8e-7 .. 2.1e-5.
TEST_P(GpuEnvironment, MatchesTheCpuOnThePlaneAndTheSphere) {
    NDFMIP_GL_OR_SKIP(gl);
    const Case c = GetParam();
    const auto lighting = skyLighting(0.7);
    const RenderTextures t = texturesFor(c.method, lighting);
    for (bool sphere : {false, true})
        for (ShadeFilter filter : {ShadeFilter::Texel, ShadeFilter::Parameter}) {
            const Scene scene = environmentScene(sphere, c.brdf);
            RenderOptions options;
            options.environmentLod = c.lod;
            options.vmfEnvironment = c.way;
            options.shadeFilter = filter;
            Result<Image> cpu = render(scene, t, c.method, options);
            ASSERT_TRUE(cpu) << cpu.error().message;
            Result<Image> gpu = renderGpu(scene, t, c.method, options);
            ASSERT_TRUE(gpu) << gpu.error().message;
            const Agreement a = agreement(gpu.value(), cpu.value());
            std::printf(
                "[ measured ] %s %s %s %s %s: mean relative error %.2e, relative RMSE %.2e\n",
                c.method, brdfName(c.brdf),
                c.way == EnvironmentWay::ShLighting ? "sh-lighting" : environmentLodName(c.lod),
                sphere ? "sphere" : "plane", shadeFilterName(filter), a.meanRelative,
                a.relativeRmse);
            EXPECT_LT(a.meanRelative, 1e-3)
                << c.method << (sphere ? " sphere " : " plane ") << shadeFilterName(filter);
            EXPECT_LT(a.relativeRmse, 3e-3)
                << c.method << (sphere ? " sphere " : " plane ") << shadeFilterName(filter);
        }
}

INSTANTIATE_TEST_SUITE_P(
    SplitSum, GpuEnvironment,
    ::testing::Values(
        Case{"naive", Brdf::Ggx, EnvironmentLod::Filament},
        Case{"naive", Brdf::BlinnPhong, EnvironmentLod::Filament},
        Case{"roughness-mips", Brdf::Ggx, EnvironmentLod::Unity},
        // The albedo factor over the spread read back from the stored roughness.
        Case{"roughness-mips", Brdf::Beckmann, EnvironmentLod::Filament},
        Case{"toksvig", Brdf::BlinnPhong, EnvironmentLod::Unity},
        Case{"toksvig", Brdf::Ggx, EnvironmentLod::Unreal},
        Case{"toksvig", Brdf::Beckmann, EnvironmentLod::Filament},
        Case{"vmf", Brdf::Beckmann, EnvironmentLod::Filament},
        Case{"vmf", Brdf::BlinnPhong, EnvironmentLod::Unreal},
        // Toksvig's log2 sigma rule on its box chain of cube faces.
        Case{"toksvig", Brdf::BlinnPhong, EnvironmentLod::Log2Sigma},
        Case{"toksvig", Brdf::Ggx, EnvironmentLod::Log2Sigma},
        Case{"naive", Brdf::Beckmann, EnvironmentLod::Log2Sigma},
        Case{"roughness-mips", Brdf::Ggx, EnvironmentLod::Log2Sigma},
        Case{"vmf", Brdf::Ggx, EnvironmentLod::Log2Sigma},
        Case{"vmf", Brdf::BlinnPhong, EnvironmentLod::Filament, EnvironmentWay::ShLighting},
        Case{"vmf", Brdf::Ggx, EnvironmentLod::Filament, EnvironmentWay::ShLighting},
        Case{"sh", Brdf::BlinnPhong, EnvironmentLod::Filament, EnvironmentWay::ShLighting},
        Case{"sh", Brdf::Beckmann, EnvironmentLod::Filament, EnvironmentWay::ShLighting}),
    [](const auto& param) {
        std::string name = param.param.method;
        name.append("_").append(brdfName(param.param.brdf)).append("_");
        name.append(param.param.way == EnvironmentWay::ShLighting
                        ? "shlighting"
                        : environmentLodName(param.param.lod));
        for (char& ch : name)
            if (ch == '-') ch = '_';
        return name;
    });

// sh on the sphere at the highest order the SH lighting has (8) and the default rule (2 x 2 taps,
// texel shading): the shader's per-hit rotation of the lighting stays within llvmpipe's loop
// limit (a cut loop would leave the rotated lighting partial and the image wrong).
TEST(GpuEnvironmentSh, OrderEightOnTheSphereAtTheDefaultRuleMatchesTheCpu) {
    NDFMIP_GL_OR_SKIP(gl);
    RenderTextures t;
    t.normals = bumpyMap();
    t.environment = skyLighting(0.7);
    BakeOptions options;
    options.parameters["order"] = 8;
    t.bake = bakeMethod(Method::Sh, buildPyramid(t.normals), options);
    for (Brdf brdf : {Brdf::Ggx, Brdf::Lambert}) {
        const Scene scene = environmentScene(true, brdf);
        Result<Image> cpu = render(scene, t, "sh", RenderOptions{});
        ASSERT_TRUE(cpu) << cpu.error().message;
        Result<Image> gpu = renderGpu(scene, t, "sh", RenderOptions{});
        ASSERT_TRUE(gpu) << gpu.error().message;
        const Agreement a = agreement(gpu.value(), cpu.value());
        std::printf("[ measured ] sh order 8 %s sphere, default rule: mean relative error %.2e, "
                    "relative RMSE %.2e\n",
                    brdfName(brdf), a.meanRelative, a.relativeRmse);
        EXPECT_LT(a.meanRelative, 1e-3) << brdfName(brdf);
        EXPECT_LT(a.relativeRmse, 3e-3) << brdfName(brdf);
    }
}

// sh on the sphere at order 8 with 4 x 4 taps and texel shading, and with 3 x 3 taps and parameter
// blending (16 and 9 hits per pixel, each rotating the lighting into its own frame): the SH loops
// are unrolled (the order is a compile-time constant), so llvmpipe's loop limit of 65535 iterations
// per fragment is not reached (before, 3 x 3 taps came out 9% off).
TEST(GpuEnvironmentSh, OrderEightOnTheSphereWithMoreTapsMatchesTheCpu) {
    NDFMIP_GL_OR_SKIP(gl);
    RenderTextures t;
    t.normals = bumpyMap();
    t.environment = skyLighting(0.7);
    BakeOptions bake;
    bake.parameters["order"] = 8;
    t.bake = bakeMethod(Method::Sh, buildPyramid(t.normals), bake);
    Scene scene = environmentScene(true, Brdf::Ggx);
    scene.camera.width = scene.camera.height = 16; // the sphere fills most of it
    // Two programs, not four: each compiles for ~20 s on llvmpipe. 4 x 4 taps with texel shading
    // is the most iterations (13k in the busiest SIMD group), 3 x 3 the case that failed before.
    for (auto [taps, filter] :
         {std::pair{4, ShadeFilter::Texel}, std::pair{3, ShadeFilter::Parameter}}) {
        RenderOptions options;
        options.taps = taps;
        options.shadeFilter = filter;
        Result<Image> cpu = render(scene, t, "sh", options);
        ASSERT_TRUE(cpu) << cpu.error().message;
        Result<Image> gpu = renderGpu(scene, t, "sh", options);
        ASSERT_TRUE(gpu) << gpu.error().message;
        const Agreement a = agreement(gpu.value(), cpu.value());
        std::printf("[ measured ] sh order 8 sphere, %d x %d taps, %s: mean relative error %.2e, "
                    "relative RMSE "
                    "%.2e\n",
                    taps, taps, shadeFilterName(filter), a.meanRelative, a.relativeRmse);
        EXPECT_LT(a.meanRelative, 1e-3) << taps << " taps " << shadeFilterName(filter);
        EXPECT_LT(a.relativeRmse, 3e-3) << taps << " taps " << shadeFilterName(filter);
    }
}

// An albedo map: its filtered chain multiplies the albedo (toksvig), or the vmf bake's lobe
// colours replace it (H eq. 31), under both ways of shading vmf.
TEST(GpuEnvironmentAlbedo, AlbedoChainsAndLobeColoursMatchTheCpu) {
    NDFMIP_GL_OR_SKIP(gl);
    const auto lighting = skyLighting();
    auto colours = std::make_shared<Image>(64, 64, 3);
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            float* p = colours->at(x, y);
            p[0] = 0.2f + 0.6f * float((x / 8 + y / 8) % 2), p[1] = 0.5f,
            p[2] = 0.1f + 0.01f * float(y);
        }
    const Scene scene = environmentScene(true, Brdf::Ggx);
    for (const char* method : {"toksvig", "vmf"})
        for (EnvironmentWay way : {EnvironmentWay::Prefiltered, EnvironmentWay::ShLighting}) {
            if (std::string(method) == "toksvig" && way == EnvironmentWay::ShLighting) continue;
            RenderTextures t;
            t.normals = bumpyMap();
            t.environment = lighting;
            const Pyramid pyramid = buildPyramid(t.normals);
            t.albedo = albedoMips(pyramid, colours);
            BakeOptions options;
            options.parameters["lobes"] = 2;
            options.albedo = colours;
            t.bake = bakeMethod(*methodFromString(method), pyramid, options);
            if (std::string(method) == "vmf") {
                ASSERT_GE(findPlane(t.bake.planes, "color0"), 0); // the lobes carry colours
            }
            RenderOptions render;
            render.vmfEnvironment = way;
            Result<Image> cpu = ndfmip::render(scene, t, method, render);
            ASSERT_TRUE(cpu) << cpu.error().message;
            Result<Image> gpu = renderGpu(scene, t, method, render);
            ASSERT_TRUE(gpu) << gpu.error().message;
            const Agreement a = agreement(gpu.value(), cpu.value());
            std::printf("[ measured ] %s %s with an albedo map: mean relative error %.2e, relative "
                        "RMSE %.2e\n",
                        method, environmentWayName(way), a.meanRelative, a.relativeRmse);
            EXPECT_LT(a.meanRelative, 1e-3) << method << " " << environmentWayName(way);
            EXPECT_LT(a.relativeRmse, 3e-3) << method << " " << environmentWayName(way);
        }
}

// Refused before any GL work, so this needs no context.
TEST(GpuEnvironmentErrors, MethodsWithoutAGpuEnvironmentShadingAreRefusedByName) {
    const auto lighting = skyLighting();
    const Scene scene = environmentScene(false, Brdf::BlinnPhong);
    struct Refusal {
        const char* method;
        bool sphere;
        const char* says;
    };
    for (const Refusal& r : {Refusal{"lean", true, "cannot shade under an environment"},
                             Refusal{"lean", false, "cannot shade under an environment"},
                             Refusal{kToksvigLut, false, "cannot shade under an environment"}}) {
        RenderTextures t;
        t.normals = bumpyMap();
        t.environment = lighting;
        Result<Image> image =
            renderGpu(environmentScene(r.sphere, Brdf::BlinnPhong), t, r.method, RenderOptions{});
        ASSERT_FALSE(image) << r.method;
        const std::string& message = image.error().message;
        std::string quoted(1, '\'');
        quoted.append(r.method).push_back('\'');
        EXPECT_NE(message.find(quoted), std::string::npos) << message;
        EXPECT_NE(message.find(r.says), std::string::npos) << message;
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
    RenderTextures unloaded; // the scene names an environment the caller did not load
    unloaded.normals = bumpyMap();
    Result<Image> image = renderGpu(scene, unloaded, "naive", RenderOptions{});
    ASSERT_FALSE(image);
    EXPECT_NE(image.error().message.find("not loaded"), std::string::npos) << image.error().message;
}

} // namespace
} // namespace ndfmip
