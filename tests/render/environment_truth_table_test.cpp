// The tabulated ground truth under an environment (environment_truth_table.h): its octahedral
// grid, a closed form (a constant environment on a flat Lambertian plane), agreement with the
// sampled truth (an independent estimate of the same integral) within their noises, a noise that
// falls as the samples per node grow, and the views it refuses.
#include <cmath>
#include <cstdio>
#include <random>

#include <gtest/gtest.h>
#include <omp.h>

#include "env/env_test_support.h"
#include "ndfmip/environment_lighting.h"
#include "ndfmip/render.h"
#include "render/environment_truth_support.h"
#include "render/environment_truth_table.h"
#include "test_support.h"

namespace ndfmip {
namespace {

using envtruth::lightingOf;
using envtruth::texturesOf;
using envtruth::unevenMap;

// An orthographic view of a 1 x 1 plane (tangent +x, bitangent +y, normal +z) from `toEye`,
// tilted about the texel grid's x axis (toEye.x = 0), so every pixel sees the same view.
Scene tiltedScene(int pixels, glm::vec3 toEye, Material material) {
    Scene s;
    s.camera.type = CameraType::Orthographic;
    s.camera.target = {0.f, 0.f, 0.f};
    s.camera.eye = 5.f * glm::normalize(toEye);
    s.camera.up = glm::normalize(glm::vec3(0.f, toEye.z, -toEye.y));
    s.camera.orthoHeight = 0.5f;
    s.camera.width = s.camera.height = pixels;
    s.geometry.size = {1.f, 1.f};
    s.material = material;
    s.environment.path = "(in memory)";
    return s;
}

Material ggx(float roughness, float albedo) {
    Material m;
    m.brdf = Brdf::Ggx;
    m.roughness = roughness;
    m.albedo = glm::vec3(albedo);
    m.specular = glm::vec3(1.f);
    return m;
}

struct Rendered {
    Image image;
    RenderNoise noise;
};

Rendered renderTruth(const Scene& scene, const RenderTextures& textures, RenderOptions options) {
    Rendered r;
    Result<Image> image = render(scene, textures, kGroundTruth, options, &r.noise);
    EXPECT_TRUE(image) << image.error().message;
    if (image) r.image = std::move(image.value());
    return r;
}

double luminanceAt(const Image& image, size_t i) {
    return rec709Luminance(
        glm::dvec3(image.pixels[3 * i], image.pixels[3 * i + 1], image.pixels[3 * i + 2]));
}

TEST(EnvironmentTruthTable, OctahedralMapRoundTripsAndKeepsTheUpperHemisphereInside) {
    std::mt19937 rng(3);
    std::normal_distribution<float> g;
    for (int i = 0; i < 2000; ++i) {
        const glm::vec3 n = glm::normalize(glm::vec3(g(rng), g(rng), g(rng)));
        const glm::vec2 p = octahedralEncode(n);
        EXPECT_LE(std::abs(p.x), 1.f);
        EXPECT_LE(std::abs(p.y), 1.f);
        if (n.z >= 0.f) {
            EXPECT_LE(std::abs(p.x) + std::abs(p.y), 1.f + 1e-6f);
        }
        const glm::vec3 back = octahedralDecode(p);
        EXPECT_NEAR(glm::dot(back, n), 1.f, 1e-5f) << n.x << " " << n.y << " " << n.z;
    }
}

TEST(EnvironmentTruthTable, KeptForEqualKeysWithoutKeepingTheirLighting) {
    // Equal keys share one table (its estimated nodes) while the lighting is held; once the
    // lighting and the tables handed out are dropped, nothing here holds the environment.
    EnvironmentTruthKey key;
    key.lighting = lightingOf(envtest::mapOf(16, [](glm::dvec3) { return glm::dvec3(1.); }));
    key.material.brdf = Brdf::Lambert;
    key.samples = 64;
    const std::weak_ptr<const EnvironmentLighting> watch = key.lighting;
    std::shared_ptr<const EnvironmentTruthTable> first = environmentTruthTable(key);
    first->radiance({0.f, 0.f, 1.f});
    EnvironmentTruthKey other = key;
    other.samples = 128;
    {
        const std::shared_ptr<const EnvironmentTruthTable> again = environmentTruthTable(key);
        EXPECT_EQ(again.get(), first.get());
        EXPECT_EQ(again->nodesEstimated(), 4u);
        EXPECT_NE(environmentTruthTable(other).get(), first.get());
    }
    // The table handed out keeps the lighting alive after the key's own handle is gone.
    key.lighting.reset();
    other.lighting.reset();
    EXPECT_FALSE(watch.expired());
    EXPECT_EQ(first->radiance({0.f, 0.f, 1.f}), first->radiance({0.f, 0.f, 1.f}));
    first.reset();
    EXPECT_TRUE(watch.expired());
}

TEST(EnvironmentTruthTable, ConstantEnvironmentOnAFlatLambertPlaneIsTheAlbedoFromFourNodes) {
    // Under radiance 1 every normal facing up reflects its albedo (the cosine over pi integrates to
    // 1 over the hemisphere); straight up sits between four nodes, and only they are estimated.
    EnvironmentTruthKey key;
    key.lighting = lightingOf(envtest::mapOf(32, [](glm::dvec3) { return glm::dvec3(1.); }));
    key.material.brdf = Brdf::Lambert;
    key.material.albedo = {0.8f, 0.5f, 0.2f};
    key.samples = 4096;
    const EnvironmentTruthTable table(key);
    EnvironmentTruthNoise noise;
    const glm::vec3 r = table.radiance({0.f, 0.f, 1.f}, &noise);
    const double sigma = std::sqrt(noise.take(table));
    EXPECT_EQ(table.nodesEstimated(), 4u);
    // The nodes sit 0.35 degrees off the pole: their cosine-weighted hemispheres lose a sliver
    // below the plane (l.z > 0 only), 1e-3 of the albedo at most.
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(r[c], key.material.albedo[c], 4. * sigma + 1e-3 * key.material.albedo[c]) << c;
    EXPECT_LT(sigma, 0.01);
}

TEST(EnvironmentTruthTable, AgreesWithTheSampledTruthWithinTheirNoise) {
    auto lighting = lightingOf(unevenMap(128));
    const Scene scene = tiltedScene(8, {0.f, -0.6f, 1.f}, ggx(0.15f, 0.3f));
    const RenderTextures textures = texturesOf(test::randomNormals(16, 16, 0.5f, 9), lighting);
    RenderOptions options;
    options.truth = TruthFilter::Box; // one cell per texel: few nodes, a quick table
    options.spp = 256;
    options.environmentTruth = EnvironmentTruth::Table;
    const Rendered table = renderTruth(scene, textures, options);
    options.environmentTruth = EnvironmentTruth::Sampled;
    options.spp = 4096;
    const Rendered sampled = renderTruth(scene, textures, options);
    ASSERT_EQ(table.image.pixels.size(), sampled.image.pixels.size());
    // Pixel by pixel: the squared differences over their variances average about 1 (each truth's
    // standard errors are upper bounds, so below it), never far above.
    double chi2 = 0., meanTable = 0., meanSampled = 0., meanVariance = 0.;
    const size_t n = table.image.texelCount();
    for (size_t i = 0; i < n; ++i) {
        const double a = luminanceAt(table.image, i), b = luminanceAt(sampled.image, i);
        const double sa = table.noise.standardError.pixels[i],
                     sb = sampled.noise.standardError.pixels[i];
        ASSERT_GT(sb, 0.);
        chi2 += (a - b) * (a - b) / (sa * sa + sb * sb);
        meanTable += a;
        meanSampled += b;
        meanVariance += sa * sa + sb * sb;
    }
    EXPECT_LT(chi2 / double(n), 2.);
    EXPECT_NEAR(meanTable / double(n), meanSampled / double(n),
                4. * std::sqrt(meanVariance) / double(n));
    // At the same samples per node as per pixel the table is the less noisy: a pixel reads
    // several nodes, and a sampled pixel's samples also scatter over its normals.
    options.spp = 256;
    const Rendered same = renderTruth(scene, textures, options);
    EXPECT_LT(table.noise.relativeStandardError, same.noise.relativeStandardError);
    std::printf("[ measured ] relative standard error: table %.4f, sampled %.4f (same samples)\n",
                table.noise.relativeStandardError, same.noise.relativeStandardError);
}

TEST(EnvironmentTruthTable, NoiseHalvesAtFourTimesTheSamplesAndAnyThreadCountGivesOneImage) {
    auto lighting = lightingOf(unevenMap(64));
    const Scene scene = tiltedScene(6, {0.f, -0.3f, 1.f}, ggx(0.2f, 0.3f));
    const RenderTextures textures = texturesOf(test::randomNormals(12, 12, 0.4f, 4), lighting);
    RenderOptions options;
    options.truth = TruthFilter::Box;
    options.environmentTruth = EnvironmentTruth::Table;
    options.spp = 64;
    const Rendered coarse = renderTruth(scene, textures, options);
    options.spp = 256;
    const int threads = omp_get_max_threads();
    omp_set_num_threads(1);
    const Rendered fine = renderTruth(scene, textures, options);
    options.seed = 2; // a table of its own (the first is kept and would be read again)
    const Rendered one = renderTruth(scene, textures, options);
    omp_set_num_threads(std::max(threads, 3));
    const Rendered many = renderTruth(scene, textures, options);
    omp_set_num_threads(threads);
    const double ratio = fine.noise.relativeStandardError / coarse.noise.relativeStandardError;
    EXPECT_GT(ratio, 0.35);
    EXPECT_LT(ratio, 0.65);
    EXPECT_EQ(one.image.pixels, many.image.pixels);
}

TEST(EnvironmentTruthTable, ViewsThatDoNotFixTheDirectionsAreRefused) {
    auto lighting = lightingOf(unevenMap(32));
    const RenderTextures textures = texturesOf(test::randomNormals(8, 8, 0.3f, 1), lighting);
    RenderOptions options;
    options.environmentTruth = EnvironmentTruth::Table;
    Scene perspective = tiltedScene(4, {0.f, -0.3f, 1.f}, ggx(0.2f, 0.3f));
    perspective.camera.type = CameraType::Perspective;
    Result<Image> a = render(perspective, textures, kGroundTruth, options);
    ASSERT_FALSE(a);
    EXPECT_NE(a.error().message.find("tabulated truth"), std::string::npos) << a.error().message;
    RenderTextures albedo = textures;
    albedo.albedo = {std::make_shared<const Image>(8, 8, 3)};
    Result<Image> b =
        render(tiltedScene(4, {0.f, -0.3f, 1.f}, ggx(0.2f, 0.3f)), albedo, kGroundTruth, options);
    ASSERT_FALSE(b);
    EXPECT_NE(b.error().message.find("no albedo map"), std::string::npos) << b.error().message;
}

} // namespace
} // namespace ndfmip
