// The prepared-lighting cache (environment_cache.h): one preparation per key, shared by later
// calls and threads, and renders through it identical to renders that prepare afresh.
#include <cstring>
#include <memory>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "env/env_test_support.h"
#include "ndfmip/environment_cache.h"
#include "ndfmip/render.h"
#include "test_support.h"

namespace ndfmip {
namespace {

Environment smoothSky() {
    return envtest::mapOf(64, [](glm::dvec3 d) {
        return glm::dvec3(1.) + glm::dvec3(0.8, 0.7, 0.5) * d.y + glm::dvec3(0.3, 0.2, 0.1) * d.x;
    });
}

TEST(EnvironmentCache, SecondPreparationIsTheFirstsData) {
    const EnvironmentLighting lighting = makeEnvironmentLighting(smoothSky());
    const auto filament = cachedSplitSum(lighting, EnvironmentLod::Filament);
    EXPECT_EQ(cachedSplitSum(lighting, EnvironmentLod::Filament), filament);
    const auto unity = cachedSplitSum(lighting, EnvironmentLod::Unity);
    EXPECT_NE(unity, filament);
    ASSERT_TRUE(findChain(*unity, EnvironmentLod::Unity));
    EXPECT_FALSE(findChain(*unity, EnvironmentLod::Filament)); // only the chain asked for

    const glm::dvec3 view(0.2, 0.5, 0.8);
    const auto sh = cachedShLighting(lighting, 4, view);
    EXPECT_EQ(cachedShLighting(lighting, 4, view), sh);
    EXPECT_NE(cachedShLighting(lighting, 4, glm::dvec3(0.2, 0.5, 0.81)), sh);
    EXPECT_NE(cachedShLighting(lighting, 3, view), sh);
    EXPECT_NE(cachedShLighting(lighting, 4, view, SpecularCosine::HalfVector), sh);
}

TEST(EnvironmentCache, CachedDataEqualsAFreshPreparation) {
    const Environment env = smoothSky();
    const EnvironmentLighting lighting = makeEnvironmentLighting(env);
    SplitSumOptions options;
    options.rules = {EnvironmentLod::Filament};
    const SplitSumLighting fresh = prepareSplitSum(env, options);
    const SplitSumLighting& cached = *cachedSplitSum(lighting, EnvironmentLod::Filament);
    ASSERT_EQ(cached.chains.size(), 1u);
    ASSERT_EQ(cached.chains[0].levels.size(), fresh.chains[0].levels.size());
    for (size_t k = 0; k < fresh.chains[0].levels.size(); ++k)
        EXPECT_EQ(cached.chains[0].levels[k].pixels, fresh.chains[0].levels[k].pixels)
            << "level " << k;
    const glm::dvec3 view(0., 0.6, 0.8);
    const ShLighting sh = prepareShLighting(env, 8, view);
    const ShLighting& cachedSh = *cachedShLighting(lighting, 8, view);
    EXPECT_EQ(cachedSh.radiance, sh.radiance);
    for (int k = 0; k < 3; ++k)
        EXPECT_EQ(cachedSh.reparameterisedAxes[k], sh.reparameterisedAxes[k]);
}

TEST(EnvironmentCache, ACopyStartsEmpty) {
    const EnvironmentLighting lighting = makeEnvironmentLighting(smoothSky());
    const auto original = cachedSplitSum(lighting, EnvironmentLod::Filament);
    EnvironmentLighting copy = lighting;
    EXPECT_TRUE(copy.cache.entries.empty());
    EXPECT_NE(cachedSplitSum(copy, EnvironmentLod::Filament), original);
    copy = lighting;
    EXPECT_TRUE(copy.cache.entries.empty());
}

TEST(EnvironmentCache, OnlyTheLatestShViewsAreKept) {
    const EnvironmentLighting lighting = makeEnvironmentLighting(smoothSky());
    const auto chain = cachedSplitSum(lighting, EnvironmentLod::Filament);
    const auto first = cachedShLighting(lighting, 1, glm::dvec3(0., 0., 1.));
    for (int i = 1; i <= kMaxCachedShViews; ++i)
        cachedShLighting(lighting, 1, glm::dvec3(0.01 * i, 0., 1.));
    EXPECT_EQ(lighting.cache.entries.size(), size_t(kMaxCachedShViews) + 1); // the chain stays
    EXPECT_EQ(cachedSplitSum(lighting, EnvironmentLod::Filament), chain);
    EXPECT_NE(cachedShLighting(lighting, 1, glm::dvec3(0., 0., 1.)), first); // dropped, made again
}

TEST(EnvironmentCache, ConcurrentCallersShareOnePreparation) {
    const EnvironmentLighting lighting = makeEnvironmentLighting(smoothSky());
    constexpr int kThreads = 8;
    std::vector<std::shared_ptr<const SplitSumLighting>> chains(kThreads);
    std::vector<std::shared_ptr<const ShLighting>> sh(kThreads);
    std::vector<std::thread> threads;
    for (int i = 0; i < kThreads; ++i)
        threads.emplace_back([&, i] {
            chains[size_t(i)] =
                cachedSplitSum(lighting, i % 2 ? EnvironmentLod::Unity : EnvironmentLod::Filament);
            sh[size_t(i)] = cachedShLighting(lighting, 4, glm::dvec3(0., 0., 1.));
        });
    for (std::thread& t : threads) t.join();
    for (int i = 2; i < kThreads; ++i) {
        EXPECT_EQ(chains[size_t(i)], chains[size_t(i % 2)]);
        EXPECT_EQ(sh[size_t(i)], sh[0]);
    }
    EXPECT_NE(chains[0], chains[1]);
}

// Renders under a lighting twice (the second reuses the first's data) and under a copy (which
// prepares afresh): the three images are bit-identical for every way a method shades.
TEST(EnvironmentCache, RendersAreBitIdenticalWithAndWithoutTheCache) {
    Scene scene;
    scene.camera.type = CameraType::Orthographic;
    scene.camera.eye = 5.f * glm::normalize(glm::vec3(0.f, -0.5f, 0.866f));
    scene.camera.target = glm::vec3(0.f);
    scene.camera.up = {0.f, 1.f, 0.f};
    scene.camera.orthoHeight = 0.4f;
    scene.camera.width = scene.camera.height = 8;
    scene.geometry.size = {1.f, 1.f};
    scene.material.brdf = Brdf::Ggx;
    scene.material.roughness = 0.3f;
    scene.material.albedo = glm::vec3(0.3f);
    scene.environment.path = "(in memory)";
    const auto lighting =
        std::make_shared<const EnvironmentLighting>(makeEnvironmentLighting(smoothSky()));
    RenderTextures textures;
    textures.normals = std::make_shared<const Image>(test::randomNormals(64, 64, 0.5f, 3));
    const Pyramid pyramid = buildPyramid(textures.normals);
    struct Case {
        const char* method;
        Method bake;
        EnvironmentLod lod;
        EnvironmentWay way;
    };
    for (const Case& c :
         {Case{"toksvig", Method::Toksvig, EnvironmentLod::Log2Sigma, EnvironmentWay::Prefiltered},
          Case{"toksvig", Method::Toksvig, EnvironmentLod::Filament, EnvironmentWay::Prefiltered},
          Case{"sh", Method::Sh, EnvironmentLod::Filament, EnvironmentWay::ShLighting},
          Case{"vmf", Method::Vmf, EnvironmentLod::Unity, EnvironmentWay::Prefiltered},
          Case{"vmf", Method::Vmf, EnvironmentLod::Filament, EnvironmentWay::ShLighting}}) {
        BakeOptions bake;
        bake.parameters["order"] = 4;
        bake.parameters["lobes"] = 2;
        textures.bake = bakeMethod(c.bake, pyramid, bake);
        RenderOptions options;
        options.environmentLod = c.lod;
        options.vmfEnvironment = c.way;
        std::vector<Image> images;
        for (int i = 0; i < 3; ++i) {
            textures.environment =
                i < 2 ? lighting
                      : std::make_shared<const EnvironmentLighting>(EnvironmentLighting(*lighting));
            Result<Image> image = render(scene, textures, c.method, options);
            ASSERT_TRUE(image) << c.method << ": " << image.error().message;
            images.push_back(std::move(image.value()));
        }
        EXPECT_EQ(images[1].pixels, images[0].pixels)
            << c.method << " " << environmentLodName(c.lod);
        EXPECT_EQ(images[2].pixels, images[0].pixels)
            << c.method << " " << environmentLodName(c.lod);
    }
}

} // namespace
} // namespace ndfmip
