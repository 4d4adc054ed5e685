// The ground truth under an environment: closed forms (a constant environment on a Lambertian
// plane), an independent hemisphere integration (white furnace with GGX and Beckmann), the limit
// of a small bright source (a directional light), agreement of MIS with its two halves, and the
// noise it reaches.
#include <cmath>
#include <cstdio>
#include <random>

#include <gtest/gtest.h>
#include <omp.h>

#include "env/env_test_support.h"
#include "ndfmip/brdf.h"
#include "ndfmip/environment_lighting.h"
#include "ndfmip/render.h"
#include "render/environment_truth.h"
#include "render/environment_truth_support.h"
#include "test_support.h"

namespace ndfmip {
namespace {

using envtruth::lightingOf;
using envtruth::texturesOf;
using envtruth::unevenMap;

Image constantNormals(int w, int h, glm::vec3 n) {
    Image map(w, h, 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) test::setNormal(map, x, y, n.x, n.y, n.z);
    return map;
}

// An orthographic view of a 1 x 1 plane (default frame: tangent +x, bitangent +y, normal +z)
// from direction `toEye`, so the view is the same at every pixel and equals toEye in the
// tangent frame. No lights: the environment is the only light.
Scene orthographicScene(int pixels, glm::vec3 toEye, Material material) {
    Scene s;
    s.camera.type = CameraType::Orthographic;
    s.camera.target = {0.f, 0.f, 0.f};
    s.camera.eye = 5.f * glm::normalize(toEye);
    s.camera.up = std::abs(toEye.y) < 0.9f * glm::length(toEye) ? glm::vec3(0.f, 1.f, 0.f)
                                                                : glm::vec3(0.f, 0.f, 1.f);
    s.camera.orthoHeight = 0.5f; // inside the plane for any view used here
    s.camera.width = s.camera.height = pixels;
    s.geometry.size = {1.f, 1.f};
    s.material = material;
    s.environment.path = "(in memory)";
    return s;
}

struct Measured {
    glm::dvec3 mean{0.};
    double meanError = 0.; // standard error of the mean luminance over the image
};

Measured measure(const Scene& scene, const RenderTextures& textures, RenderOptions options) {
    RenderNoise noise;
    Result<Image> image = render(scene, textures, kGroundTruth, options, &noise);
    EXPECT_TRUE(image) << image.error().message;
    Measured m;
    if (!image) return m;
    double variance = 0.;
    const size_t n = image->texelCount();
    for (size_t i = 0; i < n; ++i) {
        m.mean +=
            glm::dvec3(image->pixels[3 * i], image->pixels[3 * i + 1], image->pixels[3 * i + 2]);
        variance += double(noise.standardError.pixels[i]) * noise.standardError.pixels[i];
    }
    m.mean /= double(n);
    m.meanError = std::sqrt(variance) / double(n);
    return m;
}

const Material kLambert = [] {
    Material m;
    m.brdf = Brdf::Lambert;
    m.albedo = {0.8f, 0.5f, 0.2f};
    return m;
}();

Material specularMaterial(Brdf brdf, float roughness) {
    Material m;
    m.brdf = brdf;
    m.roughness = roughness;
    m.exponent = 64.f;
    m.albedo = glm::vec3(0.f);
    m.specular = glm::vec3(1.f);
    return m;
}

// The truth's integral by a midpoint rule over the hemisphere l.z > 0, in (cos theta, phi).
glm::dvec3 hemisphereIntegral(const Material& m, glm::vec3 n, glm::vec3 v, int steps) {
    glm::dvec3 sum(0.);
    const double dz = 1. / steps, dphi = 2. * M_PI / (2 * steps);
    for (int i = 0; i < steps; ++i) {
        const double z = (i + 0.5) * dz, r = std::sqrt(1. - z * z);
        for (int j = 0; j < 2 * steps; ++j) {
            const double phi = (j + 0.5) * dphi;
            const glm::vec3 l(float(r * std::cos(phi)), float(r * std::sin(phi)), float(z));
            sum += glm::dvec3(shadeNormal(m, m.albedo, n, l, glm::normalize(l + v)));
        }
    }
    return sum * dz * dphi;
}

TEST(EnvironmentTruthSampling, LobeHalfVectorDensitiesIntegrateToOne) {
    for (Material m :
         {specularMaterial(Brdf::BlinnPhong, 0.f), specularMaterial(Brdf::Beckmann, 0.2f),
          specularMaterial(Brdf::Ggx, 0.2f), specularMaterial(Brdf::Ggx, 0.9f)}) {
        const int steps = 200000;
        double sum = 0.;
        for (int i = 0; i < steps; ++i) sum += lobeHalfVectorPdf(m, (i + 0.5) / steps);
        EXPECT_NEAR(sum * 2. * M_PI / steps, 1., 2e-4) << brdfName(m.brdf);
        // The sampler's cos(theta) quantiles: the mass above c(u) is 1 - u where c grows with u
        // (Blinn-Phong), u where it falls (Beckmann, GGX).
        const double u = 0.37;
        const double c = sampleLobeHalfVector(m, u, 0.).z;
        double tail = 0.;
        for (int i = 0; i < steps; ++i) {
            const double x = c + (1. - c) * (i + 0.5) / steps;
            tail += lobeHalfVectorPdf(m, x);
        }
        EXPECT_NEAR(tail * 2. * M_PI * (1. - c) / steps, m.brdf == Brdf::BlinnPhong ? 1. - u : u,
                    2e-4)
            << brdfName(m.brdf);
    }
}

TEST(EnvironmentTruth, ConstantEnvironmentOnLambertIsAlbedoTimesRadiance) {
    const glm::dvec3 c(2., 1.5, 0.5);
    auto lighting = lightingOf(envtest::mapOf(32, [&](glm::dvec3) { return c; }));
    const Scene scene = orthographicScene(8, {0.3f, -0.4f, 1.f}, kLambert);
    const RenderTextures textures = texturesOf(constantNormals(8, 8, {0.f, 0.f, 1.f}), lighting);
    const glm::dvec3 expected = glm::dvec3(kLambert.albedo) * c;
    for (EnvironmentEstimator estimator :
         {EnvironmentEstimator::Mis, EnvironmentEstimator::Light, EnvironmentEstimator::Brdf}) {
        RenderOptions options;
        options.spp = 64;
        options.environmentEstimator = estimator;
        const Measured m = measure(scene, textures, options);
        for (int i = 0; i < 3; ++i) {
            EXPECT_NEAR(m.mean[i], expected[i], 4. * m.meanError + 1e-5 * expected[i])
                << int(estimator) << " " << i;
            EXPECT_LT(m.meanError, 0.03 * rec709Luminance(expected))
                << int(estimator); // the check has teeth
        }
        // Cosine sampling of a flat Lambertian surface under constant light has no variance.
        if (estimator == EnvironmentEstimator::Brdf) {
            EXPECT_LT(m.meanError, 1e-5);
        }
    }
}

TEST(EnvironmentTruth, WhiteFurnaceMatchesAHemisphereIntegration) {
    auto lighting = lightingOf(envtest::mapOf(32, [](glm::dvec3) { return glm::dvec3(1.); }));
    const glm::vec3 toEye = glm::normalize(glm::vec3(0.5f, -0.6f, 1.f));
    const glm::vec3 normal = glm::normalize(glm::vec3(-0.3f, 0.2f, 1.f));
    for (Material m : {specularMaterial(Brdf::Ggx, 0.3f), specularMaterial(Brdf::Beckmann, 0.3f)}) {
        m.albedo = glm::vec3(0.2f);
        const Scene scene = orthographicScene(8, toEye, m);
        const RenderTextures textures = texturesOf(constantNormals(4, 4, normal), lighting);
        RenderOptions options;
        options.spp = 64;
        const Measured measured = measure(scene, textures, options);
        const glm::dvec3 expected = hemisphereIntegral(m, normal, toEye, 1000);
        EXPECT_NEAR(measured.mean.x, expected.x, 4. * measured.meanError) << brdfName(m.brdf);
        EXPECT_NEAR(measured.mean.x, expected.x, 0.01 * expected.x) << brdfName(m.brdf);
    }
}

TEST(EnvironmentTruth, SmallBrightSourceApproachesADirectionalLight) {
    // A cap of 2 degrees about d (world) and the light of the same direction and irradiance.
    const glm::vec3 dWorld = glm::normalize(glm::vec3(0.4f, -0.3f, 1.f));
    const glm::dvec3 dEnv = worldToEnvironment(glm::dvec3(dWorld));
    const double capCos = std::cos(2. * M_PI / 180.);
    Environment env = envtest::mapOf(
        1024, [&](glm::dvec3 d) { return glm::dvec3(glm::dot(d, dEnv) > capCos ? 1. : 0.); });
    double irradiance = 0.; // the source's integral of radiance (map read per texel)
    for (int y = 0; y < env.radiance.height; ++y)
        for (int x = 0; x < env.radiance.width; ++x)
            irradiance += env.radiance.at(x, y)[0] *
                          equirectTexelSolidAngle(env.radiance.width, env.radiance.height, y);
    auto lighting = lightingOf(std::move(env));
    Material m = specularMaterial(Brdf::BlinnPhong, 0.f);
    m.exponent = 32.f;
    m.albedo = glm::vec3(0.3f);
    const Image normals = test::randomNormals(16, 16, 0.4f, 5);
    Scene underEnv = orthographicScene(16, {0.f, 0.f, 1.f}, m);
    const RenderTextures envTextures = texturesOf(normals, lighting);
    RenderOptions options;
    options.spp = 16;
    options.exact = false;
    Result<Image> a = render(underEnv, envTextures, kGroundTruth, options);
    Scene underLight = underEnv;
    underLight.environment = {};
    underLight.lights = {Light{LightType::Directional, dWorld, {}, glm::vec3(float(irradiance))}};
    Result<Image> b = render(underLight, texturesOf(normals, nullptr), kGroundTruth, options);
    ASSERT_TRUE(a && b);
    double diff = 0., ref = 0.;
    for (size_t i = 0; i < a->pixels.size(); ++i) {
        diff += std::pow(double(a->pixels[i]) - b->pixels[i], 2.);
        ref += std::pow(double(b->pixels[i]), 2.);
    }
    EXPECT_LT(std::sqrt(diff / ref), 0.02); // the cap's width and its noise
}

TEST(EnvironmentTruth, MisAgreesWithEitherSamplerAlone) {
    auto lighting = lightingOf(unevenMap(128));
    Material m = specularMaterial(Brdf::Ggx, 0.15f);
    m.albedo = glm::vec3(0.3f);
    const Scene scene = orthographicScene(8, {0.2f, -0.5f, 1.f}, m);
    const RenderTextures textures = texturesOf(test::randomNormals(16, 16, 0.5f, 9), lighting);
    RenderOptions options;
    options.spp = 256;
    options.exact = false;
    const Measured mis = measure(scene, textures, options);
    options.environmentEstimator = EnvironmentEstimator::Light;
    const Measured light = measure(scene, textures, options);
    options.environmentEstimator = EnvironmentEstimator::Brdf;
    const Measured brdf = measure(scene, textures, options);
    auto lum = [](glm::dvec3 c) { return rec709Luminance(c); };
    EXPECT_NEAR(lum(mis.mean), lum(light.mean), 4. * std::hypot(mis.meanError, light.meanError));
    EXPECT_NEAR(lum(mis.mean), lum(brdf.mean), 4. * std::hypot(mis.meanError, brdf.meanError));
    // MIS is the least noisy of the three here.
    EXPECT_LT(mis.meanError, light.meanError);
    EXPECT_LT(mis.meanError, brdf.meanError);
}

TEST(EnvironmentTruth, ImageIsTheSameOnAnyThreadCountAndPointLightsStillAdd) {
    auto lighting = lightingOf(unevenMap(64));
    Material m = specularMaterial(Brdf::Beckmann, 0.2f);
    m.albedo = glm::vec3(0.4f);
    Scene scene = orthographicScene(12, {0.2f, -0.5f, 1.f}, m);
    const RenderTextures textures = texturesOf(test::randomNormals(16, 16, 0.5f, 2), lighting);
    RenderOptions options;
    options.spp = 4;
    const int threads = omp_get_max_threads();
    omp_set_num_threads(1);
    Result<Image> one = render(scene, textures, kGroundTruth, options);
    omp_set_num_threads(std::max(threads, 3));
    Result<Image> many = render(scene, textures, kGroundTruth, options);
    omp_set_num_threads(threads);
    ASSERT_TRUE(one && many);
    EXPECT_EQ(one->pixels, many->pixels);
    // A light adds what it gives alone: lit = environment + light (same samples, same seed).
    Scene lit = scene;
    lit.lights = {Light{
        LightType::Directional, glm::normalize(glm::vec3(0.2f, 0.1f, 1.f)), {}, glm::vec3(2.f)}};
    Scene lightOnly = lit;
    lightOnly.environment = {};
    Result<Image> both = render(lit, textures, kGroundTruth, options);
    RenderOptions sampled = options;
    sampled.exact = false;
    Result<Image> alone =
        render(lightOnly, texturesOf(*textures.normals, nullptr), kGroundTruth, sampled);
    ASSERT_TRUE(both && alone);
    for (size_t i = 0; i < both->pixels.size(); ++i)
        ASSERT_NEAR(both->pixels[i], one->pixels[i] + alone->pixels[i],
                    1e-4f * (1.f + both->pixels[i]))
            << i;
}

TEST(EnvironmentTruth, VisibleEnvironmentShowsWhereRaysMissAndMethodsWithoutAHookRefuse) {
    auto lighting =
        lightingOf(envtest::mapOf(16, [](glm::dvec3 d) { return glm::dvec3(d.y > 0. ? 3. : 1.); }));
    Scene scene = orthographicScene(8, {0.f, 0.f, 1.f}, kLambert);
    scene.camera.orthoHeight = 4.f; // wider than the plane
    scene.environment.visible = true;
    scene.background = glm::vec3(7.f);
    const RenderTextures textures = texturesOf(constantNormals(4, 4, {0.f, 0.f, 1.f}), lighting);
    Result<Image> image = render(scene, textures, kGroundTruth, RenderOptions{});
    ASSERT_TRUE(image);
    // The corner ray looks down (-z world = -y environment): radiance 1, not the background.
    EXPECT_EQ(image->at(0, 0)[0], 1.f);
    scene.environment.visible = false;
    image = render(scene, textures, kGroundTruth, RenderOptions{});
    ASSERT_TRUE(image);
    EXPECT_EQ(image->at(0, 0)[0], 7.f);

    RenderTextures baked = textures;
    baked.bake = bakeMethod(Method::Lean, buildPyramid(baked.normals), {});
    Result<Image> method = render(scene, baked, "lean", RenderOptions{});
    ASSERT_FALSE(method);
    EXPECT_EQ(method.error().message, "render: method 'lean' cannot shade under an environment");
    Result<Image> exact = render(scene, baked, kExact, RenderOptions{});
    ASSERT_FALSE(exact);
    EXPECT_NE(exact.error().message.find("environment"), std::string::npos);
    RenderTextures unloaded = textures;
    unloaded.environment = nullptr;
    Result<Image> missing = render(scene, unloaded, kGroundTruth, RenderOptions{});
    ASSERT_FALSE(missing);
    EXPECT_NE(missing.error().message.find("not loaded"), std::string::npos);
}

// The noise the truth reaches on a plane in perspective (the default camera), docs/RENDERING.md.
double planeNoise(const Environment& env, int pixels, int spp) {
    Scene s;
    s.camera.width = s.camera.height = pixels;
    s.geometry.size = {4.f, 4.f};
    s.geometry.tiling = {4.f, 4.f};
    s.material = specularMaterial(Brdf::Ggx, 0.2f);
    s.material.albedo = glm::vec3(0.3f);
    s.environment.path = "(in memory)";
    const RenderTextures textures =
        texturesOf(test::randomNormals(64, 64, 0.4f, 4), lightingOf(env));
    RenderOptions options;
    options.spp = spp;
    RenderNoise noise;
    Result<Image> image = render(s, textures, kGroundTruth, options, &noise);
    EXPECT_TRUE(image);
    EXPECT_GE(noise.coveredPixels, size_t(pixels * pixels / 2));
    std::printf("[ measured ] %dx%d pixels, %d spp: relative standard error %.4f\n", pixels, pixels,
                spp, noise.relativeStandardError);
    return noise.relativeStandardError;
}

// The reported standard error against the spread of the same pixels over independent seeds: a
// pixel four texels wide of widely spread normals, GGX under a sky lit from one side, where much
// of a sample's variance is which normal it lands on, which the pixel's stratified jitter (32 x 32
// strata, an eighth of a texel each) removes.
TEST(EnvironmentTruth, ReportedStandardErrorMatchesTheSpreadOverSeeds) {
    constexpr int kPixels = 16;
    const Scene s =
        orthographicScene(kPixels, glm::vec3(0.3f, 0.2f, 1.f), specularMaterial(Brdf::Ggx, 0.2f));
    const RenderTextures textures = texturesOf(test::randomNormals(64, 64, 0.8f, 7),
                                               lightingOf(envtest::mapOf(64, [](glm::dvec3 d) {
                                                   return glm::dvec3(0.05 + std::max(d.x, 0.) * 4.);
                                               })));
    RenderOptions options;
    options.spp = 1024;
    constexpr int kSeeds = 12;
    const size_t pixels = kPixels * kPixels;
    std::vector<double> sum(pixels, 0.), sum2(pixels, 0.), reported(pixels, 0.);
    for (int seed = 0; seed < kSeeds; ++seed) {
        options.seed = uint64_t(seed + 1);
        RenderNoise noise;
        Result<Image> image = render(s, textures, kGroundTruth, options, &noise);
        ASSERT_TRUE(image) << image.error().message;
        for (size_t i = 0; i < pixels; ++i) {
            const double y = rec709Luminance(glm::dvec3(
                image->pixels[3 * i], image->pixels[3 * i + 1], image->pixels[3 * i + 2]));
            sum[i] += y;
            sum2[i] += y * y;
            reported[i] += double(noise.standardError.pixels[i]) * noise.standardError.pixels[i];
        }
    }
    double empirical = 0., claimed = 0.;
    for (size_t i = 0; i < pixels; ++i) {
        empirical += (sum2[i] - sum[i] * sum[i] / kSeeds) / (kSeeds - 1);
        claimed += reported[i] / kSeeds;
    }
    const double ratio = std::sqrt(claimed / empirical);
    std::printf("[ measured ] reported / observed standard error %.3f\n", ratio);
    EXPECT_GT(ratio, 0.88);
    EXPECT_LT(ratio, 1.12); // the samples' plain standard deviation over sqrt(spp) gave 1.26
}

TEST(EnvironmentTruth, SyntheticEnvironmentReachesHalfAPercentRelativeStandardError) {
    EXPECT_LE(planeNoise(unevenMap(256), 4, 65536), 0.005);
}

TEST(EnvironmentTruth, SharedEnvironmentsReachHalfAPercentRelativeStandardError) {
    const auto dir = test::sharedEnvMaps();
    if (dir.empty()) GTEST_SKIP() << "no shared envmaps";
    for (const char* name : {"studio_small_03_1k.hdr", "venice_sunset_1k.hdr"}) {
        Result<Environment> env = loadEnvironment((dir / name).string());
        if (!env) GTEST_SKIP() << env.error().message;
        EXPECT_LE(planeNoise(env.value(), 4, 65536), 0.005) << name;
    }
}

} // namespace
} // namespace ndfmip
