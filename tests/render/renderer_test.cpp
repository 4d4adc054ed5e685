#include <cmath>
#include <random>

#include <gtest/gtest.h>
#include <omp.h>

#include "ndfmip/bake.h"
#include "ndfmip/brdf.h"
#include "ndfmip/method_shading.h"
#include "ndfmip/render.h"
#include "ndfmip/sh_brdf.h"
#include "ndfmip/spherical_harmonics.h"
#include "render/texture_sampling.h"
#include "test_support.h"

namespace ndfmip {
namespace {

Image flatNormals(int w, int h) {
    Image map(w, h, 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) test::setNormal(map, x, y, 0.f, 0.f, 1.f);
    return map;
}

RenderTextures texturesFor(const Image& normals, Method method) {
    RenderTextures t;
    t.normals = std::make_shared<const Image>(normals);
    t.bake = bakeMethod(method, buildPyramid(t.normals), {});
    return t;
}

// A GPU's plain trilinear lookup (one sample, one level, parameters blended): with it a pixel of
// an aligned view reads exactly one texel.
RenderOptions plainLookup(int spp = 1) {
    RenderOptions o;
    o.spp = spp;
    o.taps = 1;
    o.lodBias = 0.f;
    o.shadeFilter = ShadeFilter::Parameter;
    return o;
}

// A top-down orthographic view of a 1 x 1 plane carrying the map once, `pixels` pixels wide:
// with a map of W texels each pixel covers a (W / pixels)^2 block exactly.
Scene alignedScene(int pixels, Material material, glm::vec3 light) {
    Scene s;
    s.camera.type = CameraType::Orthographic;
    s.camera.eye = {0.f, 0.f, 5.f};
    s.camera.target = {0.f, 0.f, 0.f};
    s.camera.up = {0.f, 1.f, 0.f};
    s.camera.orthoHeight = 1.f;
    s.camera.width = s.camera.height = pixels;
    s.geometry.size = {1.f, 1.f};
    s.lights = {Light{LightType::Directional, glm::normalize(light), {}, glm::vec3(1.f)}};
    s.material = material;
    return s;
}

// A plane seen at a grazing angle in perspective: one image spans many mip levels.
Scene grazingScene(Material material) {
    Scene s;
    s.camera.eye = {0.f, -4.f, 0.6f};
    s.camera.target = {0.f, 0.f, 0.f};
    s.camera.width = 48;
    s.camera.height = 32;
    s.geometry.size = {8.f, 8.f};
    s.geometry.tiling = {8.f, 8.f};
    s.lights = {Light{LightType::Directional,
                      glm::normalize(glm::vec3(0.2f, 0.5f, 0.6f)),
                      {},
                      glm::vec3(1.f)},
                Light{LightType::Point, {}, {0.5f, -1.f, 1.f}, glm::vec3(0.5f, 0.3f, 0.2f)}};
    s.material = material;
    return s;
}

Material material(Brdf brdf, float exponent, float roughness, glm::vec3 albedo,
                  glm::vec3 specular) {
    Material m;
    m.brdf = brdf;
    m.exponent = exponent;
    m.roughness = roughness;
    m.albedo = albedo;
    m.specular = specular;
    return m;
}

// The example tables shipped in data/brdf (a two-lobe f(theta_h) and a Fresnel-like g(theta_d)).
Material tabulatedMaterial() {
    Material m = material(Brdf::Tabulated, 0.f, 0.f, glm::vec3(0.05f), glm::vec3(1.f));
    const std::string dir = NDFMIP_SOURCE_DIR;
    Result<TabulatedTransfer> f = loadTabulatedTransfer(dir + "/data/brdf/example_f_theta_h.txt");
    Result<TabulatedTransfer> g = loadTabulatedTransfer(dir + "/data/brdf/example_g_theta_d.txt");
    EXPECT_TRUE(f.ok() && g.ok());
    if (f.ok()) m.table = std::make_shared<const TabulatedTransfer>(f.value());
    if (g.ok()) m.factor = std::make_shared<const TabulatedTransfer>(g.value());
    return m;
}

std::vector<Material> allMaterials() {
    return {material(Brdf::Lambert, 32.f, 0.2f, glm::vec3(0.7f), glm::vec3(0.f)),
            material(Brdf::BlinnPhong, 64.f, 0.2f, glm::vec3(0.1f), glm::vec3(1.f)),
            material(Brdf::Beckmann, 32.f, 0.15f, glm::vec3(0.f), glm::vec3(1.f)),
            material(Brdf::Ggx, 32.f, 0.3f, glm::vec3(0.2f), glm::vec3(0.9f, 0.8f, 0.7f)),
            tabulatedMaterial()};
}

void expectImagesNear(const Image& a, const Image& b, float tolerance) {
    ASSERT_EQ(a.pixels.size(), b.pixels.size());
    float worst = 0.f;
    for (size_t i = 0; i < a.pixels.size(); ++i)
        worst = std::max(worst, std::abs(a.pixels[i] - b.pixels[i]) /
                                    std::max(1.f, std::abs(b.pixels[i])));
    EXPECT_LE(worst, tolerance);
}

TEST(Renderer, FlatMapEveryMethodEqualsGroundTruth) {
    const Image flat = flatNormals(32, 32);
    for (const Material& m : allMaterials()) {
        for (const Scene& scene : {grazingScene(m), alignedScene(8, m, {0.3f, 0.2f, 1.f})}) {
            RenderOptions truthOptions;
            truthOptions.spp = 4;
            Result<Image> truth =
                render(scene, texturesFor(flat, Method::Naive), kGroundTruth, truthOptions);
            ASSERT_TRUE(truth.ok()) << truth.error().message;
            // A flat map shades the same at every position of a pixel, so the pixel centre of
            // the method matches the mean of the truth's samples up to the lights' variation.
            // lean's lobe is Beckmann's: exact for a Beckmann material on a flat map.
            for (Method method : {Method::Naive, Method::Toksvig, Method::Lean}) {
                if (method == Method::Lean && m.brdf != Brdf::Beckmann && m.brdf != Brdf::Lambert)
                    continue;
                RenderOptions o = plainLookup(4);
                Result<Image> image =
                    render(scene, texturesFor(flat, method), methodName(method), o);
                ASSERT_TRUE(image.ok()) << image.error().message;
                expectImagesNear(image.value(), truth.value(), 1e-4f);
            }
            // vmf: a flat texel is one lobe at kappa's cap (1e5), a hair wider than a spike.
            if (m.brdf != Brdf::Tabulated) {
                RenderOptions o = plainLookup(4);
                Result<Image> vmf = render(scene, texturesFor(flat, Method::Vmf), "vmf", o);
                ASSERT_TRUE(vmf.ok());
                expectImagesNear(vmf.value(), truth.value(), 2e-3f);
            }
        }
    }
}

// On a flat map g_lm = Y_lm(z), so H eq. 17 collapses by the addition theorem to the Legendre
// series Sum_l A_l (2l + 1)/(4 pi) P_l(w.z): an independent check of the SH path, truncation
// included.
double legendreSeries(const std::vector<double>& A, double t) {
    double p0 = 1.0, p1 = t,
           sum = A[0] / (4.0 * M_PI) + (A.size() > 1 ? 3.0 * A[1] * t / (4.0 * M_PI) : 0.0);
    for (size_t l = 2; l < A.size(); ++l) {
        double p2 = ((2.0 * l - 1.0) * t * p1 - (l - 1.0) * p0) / double(l);
        sum += A[l] * (2.0 * l + 1.0) / (4.0 * M_PI) * p2;
        p0 = p1;
        p1 = p2;
    }
    return sum;
}

TEST(Renderer, ShOnAFlatMapIsTheTruncatedLegendreSeries) {
    const Image flat = flatNormals(16, 16);
    const glm::vec3 light = glm::normalize(glm::vec3(0.3f, 0.2f, 1.f)), view(0.f, 0.f, 1.f);
    for (int order : {2, 7}) {
        for (const Material& m : allMaterials()) {
            RenderTextures t;
            t.normals = std::make_shared<const Image>(flat);
            BakeOptions options;
            options.parameters["order"] = order;
            t.bake = bakeSh(buildPyramid(t.normals), options);
            Result<Image> image = render(alignedScene(4, m, light), t, "sh", {});
            ASSERT_TRUE(image.ok()) << image.error().message;
            Result<ShShading> a = shShadingFor(m, order);
            ASSERT_TRUE(a.ok());
            const glm::vec3 h = glm::normalize(light + view);
            const double diffuse = std::max(0.0, legendreSeries(a->diffuse, light.z));
            const double lobe =
                std::max(0.0, legendreSeries(a->specular, h.z)) * specularFactor(m, light, h);
            for (int c = 0; c < 3; ++c) {
                const double expected =
                    m.albedo[c] * diffuse +
                    (m.brdf == Brdf::Lambert ? 0.0 : m.specular[c] * light.z * lobe);
                EXPECT_NEAR(image->at(1, 2)[c], expected, 1e-5 * std::max(1.0, expected))
                    << brdfName(m.brdf) << " order " << order;
            }
        }
    }
}

TEST(Renderer, ShMipsAreTheMeanOfTheirChildren) {
    const Image normals = test::randomNormals(16, 8, 1.2f, 11);
    Pyramid p = buildPyramid(normals);
    BakeOptions options;
    options.parameters["order"] = 4;
    Bake bake = bakeSh(p, options);
    ASSERT_EQ(bake.planes.size(), size_t(shPlaneCount(4)));
    ASSERT_EQ(bake.planes.size(), 7u); // 25 coefficients, 4 per plane
    for (int k = 1; k < int(p.levels.size()); ++k)
        for (size_t plane = 0; plane < bake.planes.size(); ++plane) {
            const Image& fine = *bake.levels[k - 1][plane];
            const Image& coarse = *bake.levels[k][plane];
            for (int y = 0; y < coarse.height; ++y)
                for (int x = 0; x < coarse.width; ++x) {
                    Footprint f = footprint(p, k, x, y);
                    for (int c = 0; c < 4; ++c) {
                        // The mean of the level-0 Y_lm over the footprint, and of the 2x2 children.
                        double block = 0;
                        for (int by = f.y0; by < f.y1; ++by)
                            for (int bx = f.x0; bx < f.x1; ++bx)
                                block += (*bake.levels[0][plane]).at(bx, by)[c];
                        block /= double(f.count());
                        double children = 0;
                        for (int cy = 0; cy < 2; ++cy)
                            for (int cx = 0; cx < 2; ++cx)
                                children += fine.at(std::min(2 * x + cx, fine.width - 1),
                                                    std::min(2 * y + cy, fine.height - 1))[c];
                        EXPECT_NEAR(coarse.at(x, y)[c], block, 1e-6);
                        if (fine.width % 2 == 0 && fine.height % 2 == 0) {
                            EXPECT_NEAR(coarse.at(x, y)[c], children / 4, 1e-6);
                        }
                    }
                }
        }
    // Level 0 holds Y_lm(n): the l = 1 band is sqrt(3/(4 pi)) (y, z, x).
    const float c1 = std::sqrt(3.f / (4.f * kPi));
    const float* n = normals.at(5, 3);
    const float* g = bake.levels[0][0]->at(5, 3);
    EXPECT_NEAR(g[0], 1.f / std::sqrt(4.f * kPi), 1e-6f);
    EXPECT_NEAR(g[1], c1 * n[1], 1e-6f);
    EXPECT_NEAR(g[2], c1 * n[2], 1e-6f);
    EXPECT_NEAR(g[3], c1 * n[0], 1e-6f);
}

// The aligned-view truth with nearest texels and one stratum per texel: the block mean.
Result<Image> blockTruth(const Scene& scene, const RenderTextures& t, int spp) {
    RenderOptions o;
    o.truth = TruthFilter::Box;
    o.spp = spp;
    return render(scene, t, kGroundTruth, o);
}

// Two groove directions in a checkerboard: at level 1 every texel's NDF is two sharp spikes,
// which two vMF lobes represent exactly (each at kappa's cap) and one widened lobe cannot.
TEST(Renderer, VmfLobesReproduceATwoSpikeNdf) {
    const float theta = 0.5f;
    Image map(8, 8, 3);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) {
            const float sign = (x + y) % 2 == 0 ? 1.f : -1.f;
            test::setNormal(map, x, y, sign * std::sin(theta), 0.f, std::cos(theta));
        }
    const glm::vec3 light = glm::normalize(glm::vec3(0.35f, 0.1f, 1.f));
    for (const Material& m :
         {material(Brdf::BlinnPhong, 32.f, 0.f, glm::vec3(0.3f), glm::vec3(1.f)),
          material(Brdf::Beckmann, 0.f, 0.25f, glm::vec3(0.f), glm::vec3(1.f)),
          material(Brdf::Ggx, 0.f, 0.25f, glm::vec3(0.f), glm::vec3(1.f))}) {
        const Scene scene = alignedScene(4, m, light); // 2x2 texels per pixel: level 1
        RenderTextures t;
        t.normals = std::make_shared<const Image>(map);
        Result<Image> truth = blockTruth(scene, t, 4);
        BakeOptions options;
        options.parameters["lobes"] = 2;
        t.bake = bakeVmf(buildPyramid(t.normals), options);
        Result<Image> vmf = render(scene, t, "vmf", plainLookup());
        ASSERT_TRUE(truth.ok() && vmf.ok());
        float peak = 0.f;
        for (size_t i = 0; i < truth->pixels.size(); ++i) {
            EXPECT_NEAR(vmf->pixels[i], truth->pixels[i], 2e-3f * std::max(1.f, truth->pixels[i]))
                << brdfName(m.brdf);
            peak = std::max(peak, truth->pixels[i]);
        }
        EXPECT_GT(peak, 0.05f) << "the highlight is in view";
        // One lobe must widen to cover both spikes and misses the truth.
        options.parameters["lobes"] = 1;
        t.bake = bakeVmf(buildPyramid(t.normals), options);
        Result<Image> single = render(scene, t, "vmf", plainLookup());
        ASSERT_TRUE(single.ok());
        double error = 0, norm = 0;
        for (size_t i = 0; i < truth->pixels.size(); ++i) {
            error += std::pow(single->pixels[i] - truth->pixels[i], 2.0);
            norm += std::pow(truth->pixels[i], 2.0);
        }
        EXPECT_GT(std::sqrt(error / norm), 0.05) << brdfName(m.brdf);
    }
}

// Eq. 31: the same two-spike texels, the +theta normals red and the -theta normals blue. Two
// coloured lobes reproduce the truth (which reads the albedo map per sample); the naive mipmap
// with the mipmapped albedo (purple everywhere) cannot where the two spikes are lit unequally.
TEST(Renderer, VmfLobeColoursFollowTheirNormals) {
    const float theta = 0.5f;
    Image map(8, 8, 3);
    auto albedo = std::make_shared<Image>(8, 8, 3);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) {
            const float sign = (x + y) % 2 == 0 ? 1.f : -1.f;
            test::setNormal(map, x, y, sign * std::sin(theta), 0.f, std::cos(theta));
            float* c = albedo->at(x, y);
            c[0] = sign > 0 ? 0.9f : 0.1f;
            c[2] = sign > 0 ? 0.1f : 0.9f;
        }
    const Material m = material(Brdf::Lambert, 1.f, 0.f, glm::vec3(1.f), glm::vec3(0.f));
    const Scene scene = alignedScene(4, m, glm::normalize(glm::vec3(0.6f, 0.f, 1.f)));
    RenderTextures t;
    t.normals = std::make_shared<const Image>(map);
    const Pyramid pyramid = buildPyramid(t.normals);
    t.albedo = albedoMips(pyramid, albedo);
    Result<Image> truth = blockTruth(scene, t, 4);
    BakeOptions options;
    options.parameters["lobes"] = 2;
    options.albedo = albedo;
    t.bake = bakeVmf(pyramid, options);
    ASSERT_GE(findPlane(t.bake.planes, "color1"), 0);
    Result<Image> vmf = render(scene, t, "vmf", plainLookup());
    t.bake = bakeNaive(pyramid, {});
    Result<Image> naive = render(scene, t, "naive", plainLookup());
    ASSERT_TRUE(truth.ok() && vmf.ok() && naive.ok());
    double naiveError = 0;
    for (size_t i = 0; i < truth->pixels.size(); ++i) {
        EXPECT_NEAR(vmf->pixels[i], truth->pixels[i], 2e-3f * std::max(1.f, truth->pixels[i]));
        naiveError = std::max(naiveError, double(std::abs(naive->pixels[i] - truth->pixels[i])));
    }
    // The light leans towards +x: the red (+theta) normals face it, so the truth is red-heavy.
    EXPECT_GT(truth->at(1, 1)[0], 1.5f * truth->at(1, 1)[2]);
    EXPECT_GT(naiveError, 0.02);
}

TEST(Renderer, AlignedOrthographicTruthIsTheBlockMean) {
    const int size = 16, level = 2, block = 1 << level, pixels = size / block;
    const Image normals = test::randomNormals(size, size, 0.9f, 7);
    const glm::vec3 light = glm::normalize(glm::vec3(0.4f, -0.3f, 1.f));
    const glm::vec3 view(0.f, 0.f, 1.f);
    for (const Material& m : allMaterials()) {
        Scene scene = alignedScene(pixels, m, light);
        RenderOptions o;
        o.truth = TruthFilter::Box;
        o.spp = block * block; // one stratum per texel
        Result<Image> truth = render(scene, texturesFor(normals, Method::Toksvig), kGroundTruth, o);
        ASSERT_TRUE(truth.ok());
        RenderTextures toksvig = texturesFor(normals, Method::Toksvig);
        Result<Image> filtered = render(scene, toksvig, "toksvig", plainLookup());
        ASSERT_TRUE(filtered.ok());
        const Image& mean = *toksvig.bake.levels[level][0];
        const glm::vec3 h = glm::normalize(light + view);
        for (int py = 0; py < pixels; ++py)
            for (int px = 0; px < pixels; ++px) {
                glm::vec3 sum(0.f);
                bool allLit = true;
                for (int y = py * block; y < (py + 1) * block; ++y)
                    for (int x = px * block; x < (px + 1) * block; ++x) {
                        const float* n = normals.at(x, y);
                        glm::vec3 normal(n[0], n[1], n[2]);
                        sum += shadeNormal(m, normal, light, h);
                        allLit = allLit && glm::dot(normal, light) > 0.f;
                    }
                const glm::vec3 expected = sum / float(block * block);
                for (int c = 0; c < 3; ++c)
                    EXPECT_NEAR(truth->at(px, py)[c], expected[c],
                                1e-5f * std::max(1.f, expected[c]));
                // The method at level L sees exactly the block's texel.
                const float* na = mean.at(px, py);
                glm::vec3 own =
                    shadeToksvig(m, {na[0], na[1], na[2]}, light, view, RoughnessMapping::Ours);
                for (int c = 0; c < 3; ++c)
                    EXPECT_NEAR(filtered->at(px, py)[c], own[c], 1e-5f * std::max(1.f, own[c]));
                // Lambertian reflection is linear in n: the unnormalised mean is exact.
                if (m.brdf == Brdf::Lambert && allLit) {
                    for (int c = 0; c < 3; ++c)
                        EXPECT_NEAR(filtered->at(px, py)[c], expected[c], 1e-5f);
                }
            }
    }
}

TEST(Renderer, RayDifferentialLodMatchesTheAnalyticFootprint) {
    // Orthographic camera tilted by theta from the plane's normal: a pixel spans h/H world
    // units across and (h/H)/cos(theta) along the tilt; the map of W texels covers `size` units.
    const float theta = glm::radians(60.f);
    Camera camera;
    camera.type = CameraType::Orthographic;
    camera.eye = {0.f, -5.f * std::sin(theta), 5.f * std::cos(theta)};
    camera.target = {0.f, 0.f, 0.f};
    camera.up = {0.f, 0.f, 1.f};
    camera.orthoHeight = 2.f;
    camera.width = camera.height = 64;
    Geometry plane;
    plane.size = {4.f, 4.f};
    plane.tiling = {2.f, 2.f};
    const int mapSize = 256;
    const Ray ray = cameraRay(camera, 32.f, 32.f);
    const SurfaceHit hit = intersect(plane, ray);
    ASSERT_TRUE(hit.hit);
    const UvFootprint f = uvFootprint(camera, hit, 32.f, 32.f);
    const float pixelWorld = camera.orthoHeight / float(camera.height);
    const float texelsPerUnit = float(mapSize) * plane.tiling.x / plane.size.x;
    EXPECT_NEAR(glm::length(f.dx) * mapSize, pixelWorld * texelsPerUnit, 1e-3f);
    EXPECT_NEAR(glm::length(f.dy) * mapSize, pixelWorld / std::cos(theta) * texelsPerUnit, 1e-3f);
    EXPECT_NEAR(mipLod(f, mapSize, mapSize),
                std::log2(pixelWorld / std::cos(theta) * texelsPerUnit), 1e-4f);

    // Perspective, looking straight down from height d: a pixel at the centre spans
    // 2 d tan(fov/2) / H world units.
    camera.type = CameraType::Perspective;
    camera.eye = {0.f, 0.f, 3.f};
    camera.up = {0.f, 1.f, 0.f};
    camera.fovY = 30.f;
    const Ray down = cameraRay(camera, 32.f, 32.f);
    const SurfaceHit centre = intersect(plane, down);
    ASSERT_TRUE(centre.hit);
    const UvFootprint g = uvFootprint(camera, centre, 32.f, 32.f);
    const float expected = 2.f * 3.f * std::tan(glm::radians(15.f)) / 64.f * texelsPerUnit;
    EXPECT_NEAR(glm::length(g.dx) * mapSize, expected, expected * 1e-3f);
    EXPECT_NEAR(glm::length(g.dy) * mapSize, expected, expected * 1e-3f);
}

TEST(Renderer, AnisotropicProbesFollowTheFootprintsAxisRatio) {
    // Probes along the major axis: as many as it is longer than the minor one, at most the
    // limit, each a trilinear lookup of 8 taps (two levels of bilinear) between levels. A square
    // footprint whose float axes differ by rounding stays one trilinear lookup.
    const std::vector<glm::ivec2> sizes{{256, 256}, {128, 128}, {64, 64}, {32, 32}, {16, 16},
                                        {8, 8},     {4, 4},     {2, 2},   {1, 1}};
    const glm::vec2 uv(0.3f, 0.6f);
    auto probes = [&](glm::vec2 dx, glm::vec2 dy, int limit) {
        TapList taps;
        filteredTaps(sizes, uv, {dx, dy}, limit, 0.3f, taps);
        float total = 0.f;
        for (int t = 0; t < taps.count; ++t) total += taps.tap[t].weight;
        EXPECT_NEAR(total, 1.f, 1e-5f);
        return taps.count / 8;
    };
    const float texel = 1.f / 256.f;
    EXPECT_EQ(probes({4.f * texel, 0.f}, {0.f, 4.f * texel * (1.f + 3e-7f)}, 8), 1);
    EXPECT_EQ(probes({4.f * texel, 0.f}, {0.f, 4.f * texel}, 8), 1);
    EXPECT_EQ(probes({4.f * texel, 0.f}, {0.f, 6.f * texel}, 8), 2);
    EXPECT_EQ(probes({4.f * texel, 0.f}, {0.f, 16.f * texel}, 8), 4);
    EXPECT_EQ(probes({4.f * texel, 0.f}, {0.f, 64.f * texel}, 8), 8);
    EXPECT_EQ(probes({4.f * texel, 0.f}, {0.f, 64.f * texel}, 1), 1);
}

TEST(Renderer, SphereFrameIsOrthonormalAndFollowsUv) {
    Geometry sphere;
    sphere.type = GeometryType::Sphere;
    sphere.radius = 2.f;
    sphere.tiling = {4.f, 2.f};
    const Ray ray{{5.f, 1.f, 0.7f}, glm::normalize(glm::vec3(-1.f, -0.1f, -0.05f))};
    const SurfaceHit h = intersect(sphere, ray);
    ASSERT_TRUE(h.hit);
    EXPECT_NEAR(glm::length(h.position - sphere.center), sphere.radius, 1e-5f);
    EXPECT_NEAR(glm::dot(h.tangent, h.normal), 0.f, 1e-6f);
    EXPECT_NEAR(glm::dot(h.bitangent, h.normal), 0.f, 1e-6f);
    EXPECT_NEAR(glm::length(glm::cross(h.tangent, h.bitangent) - h.normal), 0.f, 1e-5f);
    // dp/du points along +x of the map, dp/dv against +y (v grows towards the bottom row).
    EXPECT_GT(glm::dot(h.dpdu, h.tangent), 0.f);
    EXPECT_LT(glm::dot(h.dpdv, h.bitangent), 0.f);
    // A small step along dp/du moves u by the step.
    const float eps = 1e-3f;
    glm::vec3 moved = h.position + eps * h.dpdu;
    const SurfaceHit h2 = intersect(sphere, {moved + 3.f * h.normal, -h.normal});
    ASSERT_TRUE(h2.hit);
    EXPECT_NEAR(h2.uv.x - h.uv.x, eps, 2e-5f);
}

TEST(Renderer, ImageDoesNotDependOnTheThreadCount) {
    const Image normals = test::randomNormals(32, 32, 0.8f, 3);
    Scene scene = grazingScene(allMaterials()[1]);
    RenderOptions o;
    o.spp = 9;
    o.seed = 42;
    RenderTextures t = texturesFor(normals, Method::Toksvig);
    const int threads = omp_get_max_threads();
    omp_set_num_threads(1);
    Result<Image> one = render(scene, t, kGroundTruth, o);
    omp_set_num_threads(std::max(2, threads));
    Result<Image> many = render(scene, t, kGroundTruth, o);
    omp_set_num_threads(threads);
    ASSERT_TRUE(one.ok() && many.ok());
    EXPECT_EQ(one->pixels, many->pixels);
    o.seed = 43;
    Result<Image> other = render(scene, t, kGroundTruth, o);
    EXPECT_NE(one->pixels, other->pixels);
}

TEST(Renderer, RejectsWrongMethodsAndBakes) {
    const Image normals = flatNormals(8, 8);
    Scene scene = grazingScene(allMaterials()[1]);
    RenderTextures t = texturesFor(normals, Method::Naive);
    Result<Image> r = render(scene, t, "bogus", {});
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("unknown method 'bogus'"), std::string::npos);
    r = render(scene, t, "toksvig", {});
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("no bake of method 'toksvig'"), std::string::npos);
    RenderOptions o;
    o.spp = 0;
    r = render(scene, t, kGroundTruth, o);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().message, "render: spp 0: expected 1 .. 1048576");
    // render() holds the options to checkRenderOptions' ranges, those Python's render() checks.
    RenderOptions scale;
    scale.varianceScale = 0.f;
    r = render(scene, t, "naive", scale);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().message, checkRenderOptions(scale).error.insert(0, "render: "));
    RenderOptions shift;
    shift.pixelShift.x = std::nanf("");
    EXPECT_FALSE(render(scene, t, "naive", shift).ok());
}

TEST(SpecularAntiAliasing, KernelIsTwiceTheVarianceOfTheNormalsChangeUpToTheThreshold) {
    const SpecularAntiAliasing filament{0.15f, 0.2f};
    // |du|^2 + |dv|^2 = 0.01 + 0.04: 2 x 0.15 x 0.05.
    EXPECT_NEAR(specularAntiAliasingKernel(filament, {0.1f, 0.f, 0.f}, {0.f, 0.2f, 0.f}), 0.015f,
                1e-7f);
    EXPECT_FLOAT_EQ(specularAntiAliasingKernel(filament, {1.f, 0.f, 0.f}, {0.f, 0.f, 0.f}), 0.2f);
    EXPECT_EQ(specularAntiAliasingKernel({0.f, 0.2f}, {1.f, 0.f, 0.f}, {0.f, 1.f, 0.f}), 0.f);
}

// Columns of normals tilted +-10 degrees about y, one texel per pixel and each pixel on its
// texel's centre: the next pixel across reads the other tilt, the next one down the same, so
// the engine's rule widens GGX alpha 0.2 to sqrt(0.04 + 2 x 0.15 x |a - b|^2), |a - b| = 2 sin 10.
// naive shades its material so; ggx-fit (its level 0 the material's alpha) and ggx-aniso (alpha^2
// I) the same lobe from their planes; a shader without the hook (toksvig), and a flat map (no
// change to the next pixel), are left as they were.
TEST(SpecularAntiAliasing, AlignedStripesWidenTheLobeByTheNeighboursDifference) {
    const int size = 8;
    const float tilt = glm::radians(10.f);
    const glm::vec3 a(std::sin(tilt), 0.f, std::cos(tilt)), b(-a.x, 0.f, a.z);
    Image stripes(size, size, 3);
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const glm::vec3 n = x % 2 ? b : a;
            test::setNormal(stripes, x, y, n.x, n.y, n.z);
        }
    const Material ggx = material(Brdf::Ggx, 0.f, 0.2f, glm::vec3(0.1f), glm::vec3(1.f));
    const glm::vec3 light = glm::normalize(glm::vec3(0.3f, 0.1f, 1.f));
    const Scene scene = alignedScene(size, ggx, light);
    RenderOptions aa = plainLookup();
    aa.specularAntiAliasing = {0.15f, 0.2f};
    const float kernel = 2.f * 0.15f * glm::dot(a - b, a - b);
    Material widened = ggx;
    widened.roughness = std::sqrt(0.04f + kernel);

    BakeOptions fitted;
    fitted.baseRoughness = 0.2f;
    const SharedImage normals = std::make_shared<const Image>(stripes);
    Result<Image> naive = render(scene, texturesFor(stripes, Method::Naive), "naive", aa);
    ASSERT_TRUE(naive.ok()) << naive.error().message;
    for (int y = 0; y + 1 < size; ++y)
        for (int x = 0; x + 1 < size; ++x) {
            const glm::vec3 expected =
                shadeNaive(widened, x % 2 ? b : a, light, glm::vec3(0.f, 0.f, 1.f));
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(naive->at(x, y)[c], expected[c], 1e-5f * std::max(1.f, expected[c]))
                    << x << "," << y;
        }
    // The single lobes' own planes at level 0 hold the same lobe: the same pixels.
    for (Method method : {Method::GgxFit, Method::GgxAniso}) {
        RenderTextures t;
        t.normals = normals;
        t.bake = bakeMethod(method, buildPyramid(normals), fitted);
        Result<Image> image = render(scene, t, methodName(method), aa);
        ASSERT_TRUE(image.ok()) << image.error().message;
        for (int y = 0; y + 1 < size; ++y)
            for (int x = 0; x + 1 < size; ++x)
                for (int c = 0; c < 3; ++c)
                    EXPECT_NEAR(image->at(x, y)[c], naive->at(x, y)[c],
                                1e-4f * std::max(1.f, naive->at(x, y)[c]))
                        << methodName(method) << " " << x << "," << y;
    }
    // Without the rule the stripes shade the material's own lobe: the rule changed the image.
    Result<Image> plain =
        render(scene, texturesFor(stripes, Method::Naive), "naive", plainLookup());
    ASSERT_TRUE(plain.ok());
    EXPECT_GT(std::abs(plain->at(0, 0)[0] - naive->at(0, 0)[0]), 1e-3f);
    // toksvig takes no rule; a flat map has no change to the next pixel.
    for (const auto& [map, method] :
         {std::pair{stripes, Method::Toksvig}, std::pair{flatNormals(size, size), Method::Naive}}) {
        const RenderTextures t = texturesFor(map, method);
        Result<Image> with = render(scene, t, methodName(method), aa);
        Result<Image> without = render(scene, t, methodName(method), plainLookup());
        ASSERT_TRUE(with.ok() && without.ok());
        EXPECT_EQ(with->pixels, without->pixels) << methodName(method);
    }
}

TEST(Flicker, ConstantFramesDoNotFlickerAndAlternatingOnesDo) {
    Image a(4, 4, 3), b(4, 4, 3);
    for (float& v : a.pixels) v = 1.f;
    for (float& v : b.pixels) v = 3.f;
    EXPECT_DOUBLE_EQ(temporalFlicker({a, a, a}), 0.0);
    // Frames 1 and 3: mean 2, population std 1 -> 0.5 at every pixel.
    EXPECT_NEAR(temporalFlicker({a, b, a, b}), 0.5, 1e-12);
    const auto shifts = flickerShifts(16);
    ASSERT_EQ(shifts.size(), 16u);
    for (glm::vec2 s : shifts) {
        EXPECT_GE(s.x, -0.5f);
        EXPECT_LT(s.x, 0.5f);
        EXPECT_GE(s.y, -0.5f);
        EXPECT_LT(s.y, 0.5f);
    }
}

} // namespace
} // namespace ndfmip

namespace ndfmip {
namespace {

// alignedScene with the map tiled 3 x 3 under the view and the view shifted by `shift` pixels:
// each pixel covers parts of several texels.
Scene shiftedScene(int pixels, Material material, glm::vec3 light, glm::vec2 shift) {
    Scene s = alignedScene(pixels, material, light);
    const glm::vec3 offset(shift.x / float(pixels), -shift.y / float(pixels), 0.f);
    s.camera.eye += offset;
    s.camera.target += offset;
    s.geometry.size = {3.f, 3.f};
    s.geometry.tiling = {3.f, 3.f};
    return s;
}

double relativeRmse(const Image& a, const Image& b) {
    double diff = 0, norm = 0;
    for (size_t i = 0; i < a.pixels.size(); ++i) {
        diff += std::pow(double(a.pixels[i]) - b.pixels[i], 2.0);
        norm += std::pow(double(b.pixels[i]), 2.0);
    }
    return std::sqrt(diff / norm);
}

TEST(MeasuringStick, ExactBoxTruthAgreesWithSupersampling) {
    // Pixels of 3.2 x 3.2 texels, off the grid: the sample-free integral (box: each texel by its
    // covered area; bilinear: the midpoint rule) against 128 x 128 stratified samples of the same
    // surface.
    const Image normals = test::randomNormals(16, 16, 0.8f, 21);
    EXPECT_TRUE(
        exactBoxView(shiftedScene(5, allMaterials()[1], {0.3f, 0.2f, 1.f}, {0.37f, 0.21f})));
    for (TruthFilter surface : {TruthFilter::Box, TruthFilter::Bilinear})
        for (const Material& m : allMaterials()) {
            const Scene scene = shiftedScene(5, m, {0.3f, 0.2f, 1.f}, {0.37f, 0.21f});
            const RenderTextures t = texturesFor(normals, Method::Naive);
            RenderOptions exact;
            exact.truth = surface;
            Result<Image> a = render(scene, t, kGroundTruth, exact);
            RenderOptions sampled = exact;
            sampled.exact = false;
            sampled.spp = 16384;
            Result<Image> b = render(scene, t, kGroundTruth, sampled);
            ASSERT_TRUE(a.ok() && b.ok());
            // Box: only the samples' error at texel edges is left. Bilinear: the midpoint rule's
            // own error, largest on these independent random normals (neighbours up to 90 degrees
            // apart; on real maps the rule agrees with 16384 samples to 0.5%, docs/RESULTS.md).
            const double tolerance = surface == TruthFilter::Box ? 0.01 : 0.03;
            EXPECT_LT(relativeRmse(a.value(), b.value()), tolerance)
                << brdfName(m.brdf) << " " << truthFilterName(surface);
            // Noise-free: another seed gives the same image.
            exact.seed = 99;
            Result<Image> c = render(scene, t, kGroundTruth, exact);
            ASSERT_TRUE(c.ok());
            EXPECT_EQ(a->pixels, c->pixels);
        }
    // Perspective or point lights: no exact integral.
    EXPECT_FALSE(exactBoxView(grazingScene(allMaterials()[1])));
}

// A camera tilted about the texel grid's x axis still sees each pixel as a rectangle of texels
// from one direction: the sample-free truth agrees with supersampling there too, and on a flat
// map it is the BRDF's own value at the view and light.
TEST(MeasuringStick, ExactBoxTruthHoldsForATiltedOrthographicView) {
    const Image normals = test::randomNormals(16, 16, 0.8f, 23);
    for (float elevation : {30.f, 60.f}) {
        Scene scene = shiftedScene(5, allMaterials()[1], {0.f, 0.5f, 0.6f}, {0.37f, 0.21f});
        const float e = glm::radians(elevation);
        scene.camera.eye = scene.camera.target + 10.f * glm::vec3(0.f, -std::cos(e), std::sin(e));
        scene.camera.up = {0.f, std::sin(e), std::cos(e)};
        ASSERT_TRUE(exactBoxView(scene)) << elevation;
        for (const Material& m : allMaterials()) {
            scene.material = m;
            const RenderTextures t = texturesFor(normals, Method::Naive);
            RenderOptions exact;
            Result<Image> a = render(scene, t, kGroundTruth, exact);
            RenderOptions sampled = exact;
            sampled.exact = false;
            sampled.spp = 16384;
            Result<Image> b = render(scene, t, kGroundTruth, sampled);
            ASSERT_TRUE(a.ok() && b.ok());
            EXPECT_LT(relativeRmse(a.value(), b.value()), 0.01)
                << brdfName(m.brdf) << " at " << elevation;
        }
        // A flat map: every pixel is the BRDF at the fixed view and light.
        scene.material = allMaterials()[1];
        Image flatMap(16, 16, 3);
        for (size_t i = 0; i < flatMap.texelCount(); ++i) flatMap.pixels[3 * i + 2] = 1.f;
        const RenderTextures flat = texturesFor(flatMap, Method::Naive);
        Result<Image> image = render(scene, flat, kGroundTruth, RenderOptions{});
        ASSERT_TRUE(image.ok());
        const glm::vec3 v = glm::normalize(scene.camera.eye - scene.camera.target);
        const glm::vec3 l = glm::normalize(scene.lights.front().direction);
        const glm::vec3 expected =
            shadeNormal(scene.material, glm::vec3(0.f, 0.f, 1.f), l, glm::normalize(l + v));
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(image->at(2, 2)[c], expected[c], 1e-4f * (1.f + expected[c]));
    }
    // Rolled about the view, the rows no longer follow the grid: sampled.
    Scene rolled = shiftedScene(5, allMaterials()[1], {0.f, 0.5f, 0.6f}, {0.f, 0.f});
    rolled.camera.eye = rolled.camera.target + 10.f * glm::vec3(0.3f, -0.5f, 0.8f);
    EXPECT_FALSE(exactBoxView(rolled));
}

TEST(MeasuringStick, ExactMethodIsTheTruthWhereEachLookupIsOneTexel) {
    // 16 texels over 4 pixels: one lookup reads one level-2 texel (plain rule), or 2 x 2
    // sub-samples read one level-1 texel each; either way 'exact' shades exactly the pixel.
    const Image normals = test::randomNormals(16, 16, 1.0f, 5);
    for (const Material& m : allMaterials()) {
        const Scene scene = alignedScene(4, m, {0.4f, -0.3f, 1.f});
        const RenderTextures t = texturesFor(normals, Method::Naive);
        Result<Image> truth = render(scene, t, kGroundTruth, {});
        RenderOptions twoByTwo = plainLookup();
        twoByTwo.taps = 2;
        for (const RenderOptions& o : {plainLookup(), twoByTwo}) {
            Result<Image> exact = render(scene, t, kExact, o);
            ASSERT_TRUE(truth.ok() && exact.ok()) << exact.error().message;
            expectImagesNear(exact.value(), truth.value(), 1e-5f);
        }
    }
    RenderTextures t = texturesFor(normals, Method::Naive);
    Result<Image> perspective = render(grazingScene(allMaterials()[1]), t, kExact, {});
    ASSERT_FALSE(perspective.ok());
    EXPECT_NE(perspective.error().message.find("orthographic"), std::string::npos);
}

TEST(MeasuringStick, TexelFilteringIsExactForLobesThatHoldTheirTexelsNormals) {
    // Level 1 of a random map: four normals a texel, which J = 4 lobes hold exactly (spikes at
    // kappa's cap). Pixels of two texels off the grid blend four level-1 texels: shading each
    // texel's lobes and blending is the exact reference's blend; blending the lobes' parameters
    // first mixes unrelated lobes.
    const Image normals = test::randomNormals(16, 16, 0.7f, 8);
    const Material m = material(Brdf::BlinnPhong, 64.f, 0.f, glm::vec3(0.f), glm::vec3(1.f));
    const Scene scene = shiftedScene(8, m, {0.3f, 0.1f, 1.f}, {0.3f, 0.4f});
    RenderTextures t = texturesFor(normals, Method::Naive);
    Result<Image> exact = render(scene, t, kExact, plainLookup());
    BakeOptions options;
    options.parameters["lobes"] = 4;
    t.bake = bakeVmf(buildPyramid(t.normals), options);
    RenderOptions texel = plainLookup();
    texel.shadeFilter = ShadeFilter::Texel;
    Result<Image> shaded = render(scene, t, "vmf", texel);
    Result<Image> blended = render(scene, t, "vmf", plainLookup());
    ASSERT_TRUE(exact.ok() && shaded.ok() && blended.ok());
    EXPECT_LT(relativeRmse(shaded.value(), exact.value()), 2e-3);
    EXPECT_GT(relativeRmse(blended.value(), exact.value()), 0.05);
}

TEST(MeasuringStick, DefaultFilteringRuleLowersTheFloor) {
    // The exact reference against the exact truth at 4 x 4 texels a pixel, off the grid: what is
    // left is partial coverage of the texels a lookup reads. 2 x 2 sub-samples half a level
    // finer read smaller texels and leave less of it.
    const Image normals = test::randomNormals(64, 64, 0.8f, 13);
    const Material m = material(Brdf::BlinnPhong, 32.f, 0.f, glm::vec3(0.f), glm::vec3(1.f));
    const Scene scene = shiftedScene(16, m, {0.3f, 0.2f, 1.f}, {0.31f, 0.17f});
    const RenderTextures t = texturesFor(normals, Method::Naive);
    Result<Image> truth = render(scene, t, kGroundTruth, {});
    Result<Image> plain = render(scene, t, kExact, plainLookup());
    Result<Image> rule = render(scene, t, kExact, {});
    ASSERT_TRUE(truth.ok() && plain.ok() && rule.ok());
    const double before = relativeRmse(plain.value(), truth.value()),
                 after = relativeRmse(rule.value(), truth.value());
    EXPECT_GT(before, 0.05);
    EXPECT_LT(after, 0.8 * before) << before << " -> " << after;
}

TEST(MeasuringStick, ToksvigLutIsForBlinnPhong) {
    const Image normals = test::randomNormals(16, 16, 0.5f, 3);
    const RenderTextures t = texturesFor(normals, Method::Toksvig);
    Result<Image> ggx =
        render(alignedScene(4, allMaterials()[3], {0.f, 0.f, 1.f}), t, kToksvigLut, {});
    ASSERT_FALSE(ggx.ok());
    EXPECT_NE(ggx.error().message.find("Blinn-Phong"), std::string::npos);
    Result<Image> phong =
        render(alignedScene(4, allMaterials()[1], {0.f, 0.f, 1.f}), t, kToksvigLut, {});
    EXPECT_TRUE(phong.ok());
    EXPECT_NE(renderMethodNames().find("toksvig-lut"), std::string::npos);
}

} // namespace
} // namespace ndfmip
