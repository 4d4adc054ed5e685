// Interpolated normals: the faceted sphere, Toksvig's unnormalised normal cube map, and the
// claim of his last section measured on a far, sharp highlight.
#include <cmath>
#include <cstdio>
#include <random>

#include <gtest/gtest.h>

#include "ndfmip/compare.h"
#include "ndfmip/environment.h"
#include "ndfmip/interpolated.h"
#include "test_support.h"

namespace ndfmip {
namespace {

Geometry facetedSphere(int segments, int rings, float radius = 1.f) {
    Geometry g;
    g.type = GeometryType::FacetedSphere;
    g.segments = segments;
    g.rings = rings;
    g.radius = radius;
    return g;
}

glm::vec3 randomDirection(std::mt19937& rng) {
    std::normal_distribution<float> n(0.f, 1.f);
    return glm::normalize(glm::vec3(n(rng), n(rng), n(rng)));
}

// ---- faceted sphere ---------------------------------------------------------------------------

TEST(FacetedSphere, MeshHasTheTrianglesAndNormalsOfAUvSphere) {
    const FacetedSphereMesh mesh = facetedSphereMesh(facetedSphere(12, 6, 2.f));
    EXPECT_EQ(mesh.triangles.size(),
              size_t(12 * (2 * 6 - 2))); // one per segment at each pole, two between
    for (size_t i = 0; i < mesh.positions.size(); ++i) {
        EXPECT_NEAR(glm::length(mesh.normals[i]), 1.f, 1e-6f);
        EXPECT_NEAR(glm::length(mesh.positions[i] - 2.f * mesh.normals[i]), 0.f, 1e-5f);
    }
    for (size_t k = 0; k < mesh.triangles.size(); ++k) { // outward, non-degenerate facets
        const glm::ivec3 t = mesh.triangles[k];
        const glm::vec3 centroid =
            (mesh.positions[t.x] + mesh.positions[t.y] + mesh.positions[t.z]) / 3.f;
        EXPECT_GT(glm::dot(mesh.faceNormals[k], centroid), 0.f);
        EXPECT_GT(glm::length(glm::cross(mesh.positions[t.y] - mesh.positions[t.x],
                                         mesh.positions[t.z] - mesh.positions[t.x])),
                  1e-3f);
    }
}

TEST(FacetedSphere, RaysHitTheFacetsInsideTheSphereWithInterpolatedNormals) {
    const Geometry g = facetedSphere(8, 4);
    const FacetedSphereMesh mesh = facetedSphereMesh(g);
    std::mt19937 rng(5);
    int hits = 0;
    for (int i = 0; i < 400; ++i) {
        const glm::vec3 origin = 4.f * randomDirection(rng);
        const glm::vec3 target = 0.5f * randomDirection(rng) *
                                 std::cbrt(std::uniform_real_distribution<float>(0, 1)(rng));
        const Ray ray{origin, glm::normalize(target - origin)};
        const FacetedHit h = intersectFacetedSphere(mesh, ray);
        // Every ray towards a point well inside the inscribed polyhedron hits.
        ASSERT_TRUE(h.hit) << "ray " << i;
        ++hits;
        const float r = glm::length(h.position);
        EXPECT_LE(r, 1.f + 1e-5f);
        EXPECT_GE(r, 0.6f); // no facet of an 8 x 4 sphere comes nearer the centre
        // The hit lies on its facet's plane and sees the ray from the front.
        const glm::vec3 p0 = mesh.positions[size_t(mesh.triangles[size_t(h.triangle)].x)];
        EXPECT_NEAR(glm::dot(h.position - p0, h.faceNormal), 0.f, 1e-5f);
        EXPECT_LT(glm::dot(ray.direction, h.faceNormal), 0.f);
        // The interpolated normal lies within the cone of its facet's vertex normals: its
        // renormalised form is close to the radial direction.
        EXPECT_GT(glm::dot(glm::normalize(h.interpolated), h.position / r), std::cos(kPi / 4.f));
        // Extrapolating on the facet's own plane gives the same normal at the hit.
        const glm::vec3 again = interpolatedNormalOnPlane(mesh, h.triangle, ray, glm::vec3(0.f));
        EXPECT_NEAR(glm::length(again - h.interpolated), 0.f, 1e-4f);
    }
    EXPECT_EQ(hits, 400);
    EXPECT_FALSE(
        intersectFacetedSphere(mesh, {{0.f, -5.f, 1.01f}, {0.f, 1.f, 0.f}}).hit); // passes above
}

TEST(FacetedSphere, AVertexHitGivesTheVertexNormal) {
    const FacetedSphereMesh mesh = facetedSphereMesh(facetedSphere(6, 3));
    // Straight down onto the north pole: every pole facet shares the normal +z there.
    const FacetedHit h = intersectFacetedSphere(mesh, {{0.f, 0.f, 5.f}, {0.f, 0.f, -1.f}});
    ASSERT_TRUE(h.hit);
    EXPECT_NEAR(h.t, 4.f, 1e-5f);
    EXPECT_NEAR(glm::length(h.interpolated - glm::vec3(0.f, 0.f, 1.f)), 0.f, 1e-5f);
}

// ---- normal cube map -------------------------------------------------------------------------

TEST(NormalCubeMap, FaceCoordinatesRoundTrip) {
    for (int face = 0; face < 6; ++face)
        for (float a : {-0.9f, -0.3f, 0.f, 0.55f})
            for (float b : {-0.7f, 0.2f, 0.95f}) {
                int f;
                float a2, b2;
                cubeFaceCoordinates(3.f * cubeFaceDirection(face, a, b), f, a2, b2);
                EXPECT_EQ(f, face);
                EXPECT_NEAR(a2, a, 1e-6f);
                EXPECT_NEAR(b2, b, 1e-6f);
            }
}

// The float lookup (the normal cube map's) and the double one (the environment's cube faces,
// environment.h) are one GLSL source compiled twice: the same face everywhere, (s, t) = ((a + 1)/2,
// (b + 1)/2) to float rounding, and the zero vector on +Z's centre in both.
TEST(NormalCubeMap, FloatAndDoubleFaceLookupsAgree) {
    std::mt19937 rng(11);
    for (int i = 0; i < 5000; ++i) {
        const glm::vec3 d = randomDirection(rng) * (i % 2 == 0 ? 1.f : 7.f);
        int f, g;
        float a, b;
        double s, t;
        cubeFaceCoordinates(d, f, a, b);
        cubeFaceCoordinates(glm::dvec3(d), g, s, t);
        ASSERT_EQ(f, g) << "direction " << i;
        EXPECT_NEAR(0.5 * (a + 1.), s, 1e-6) << "direction " << i;
        EXPECT_NEAR(0.5 * (b + 1.), t, 1e-6) << "direction " << i;
    }
    int f, g;
    float a, b;
    double s, t;
    cubeFaceCoordinates(glm::vec3(0.f), f, a, b);
    cubeFaceCoordinates(glm::dvec3(0.), g, s, t);
    EXPECT_EQ(f, 4);
    EXPECT_EQ(g, 4);
    EXPECT_EQ(a, 0.f);
    EXPECT_EQ(b, 0.f);
    EXPECT_EQ(s, 0.5);
    EXPECT_EQ(t, 0.5);
}

TEST(NormalCubeMap, LevelZeroLookupsAreUnitVectorsInTheirDirection) {
    const NormalCubeMap map = buildNormalCubeMap(64);
    ASSERT_EQ(map.levels.size(), 7u); // 64 .. 1
    std::mt19937 rng(3);
    const float texelAngle = 2.f / 64.f; // at most, at a face's centre
    for (int i = 0; i < 2000; ++i) {
        const glm::vec3 d = randomDirection(rng);
        const glm::vec3 n = sampleNormalCubeMap(map, 2.5f * d, 0.f);
        // Bilinear blends of neighbouring unit texels: shorter by at most 1 - cos(texel / 2).
        EXPECT_NEAR(glm::length(n), 1.f, 1.f - std::cos(texelAngle)) << "direction " << i;
        EXPECT_GT(glm::dot(glm::normalize(n), d), std::cos(0.5f * texelAngle));
    }
    // At a texel's centre the lookup is that texel: exactly unit.
    const glm::vec3 centre =
        cubeFaceDirection(4, (2.f * 10.f + 1.f) / 64.f - 1.f, (2.f * 40.f + 1.f) / 64.f - 1.f);
    EXPECT_NEAR(glm::length(sampleNormalCubeMap(map, centre, 0.f)), 1.f, 1e-6f);
}

// (1/Omega) Int w dw over the face rectangle [a0, a1] x [b0, b1] of `face`, by a fine midpoint
// rule on the face plane (dw = da db / r^3), independent of the map's recursion.
glm::dvec3 meanUnitVector(int face, double a0, double a1, double b0, double b1) {
    const int n = 600;
    glm::dvec3 sum(0.0);
    double omega = 0.0;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const double a = a0 + (a1 - a0) * (i + 0.5) / n, b = b0 + (b1 - b0) * (j + 0.5) / n;
            const glm::dvec3 d = cubeFaceDirection(face, float(a), float(b));
            const double r = glm::length(d);
            const double w = 1.0 / (r * r * r);
            sum += w * d / r;
            omega += w;
        }
    return sum / omega;
}

TEST(NormalCubeMap, CoarseTexelsAreTheMeanUnitVectorOverTheirSolidAngle) {
    const NormalCubeMap map = buildNormalCubeMap(128);
    // A whole face (the 1 x 1 level) in closed form: Int over [-1,1]^2 of (1 + a^2 + b^2)^-2
    // = 4 F(1, 1) with F(x, y) = x/(2 sqrt(1+x^2)) atan(y/sqrt(1+x^2)) + (x <-> y), over the
    // face's solid angle 4 pi / 6.
    const double f11 = 2.0 * (1.0 / (2.0 * std::sqrt(2.0))) * std::atan(1.0 / std::sqrt(2.0));
    const double faceMean = 4.0 * f11 / (4.0 * M_PI / 6.0);
    for (int face = 0; face < 6; ++face) {
        const glm::vec3 t = map.levels.back().at(face, 0, 0);
        EXPECT_NEAR(glm::length(t), faceMean, 2e-5) << "face " << face;
        EXPECT_NEAR(glm::dot(glm::normalize(t), glm::normalize(cubeFaceDirection(face, 0.f, 0.f))),
                    1.f, 1e-6f);
    }
    // Texels of several levels, corner and centre, against the numerical mean.
    struct Case {
        int level, face, x, y;
    };
    for (const Case c : {Case{3, 0, 0, 0}, Case{3, 4, 7, 3}, Case{5, 2, 1, 2}, Case{5, 5, 3, 0},
                         Case{6, 1, 0, 1}}) {
        const CubeLevel& level = map.levels[size_t(c.level)];
        const double w = 2.0 / level.size;
        const glm::dvec3 expected = meanUnitVector(c.face, -1 + c.x * w, -1 + (c.x + 1) * w,
                                                   -1 + c.y * w, -1 + (c.y + 1) * w);
        const glm::vec3 got = level.at(c.face, c.x, c.y);
        // Level 0's midpoint rule (texels 2/128 wide) leaves about 2e-5; weighing the children
        // equally instead would be off by far more (the 1 x 1 face above: 0.79 against 0.83).
        EXPECT_NEAR(glm::length(glm::dvec3(got) - expected), 0.0, 5e-5)
            << "level " << c.level << " face " << c.face << " texel " << c.x << "," << c.y
            << ": length " << glm::length(got) << " vs " << glm::length(expected);
        EXPECT_LT(glm::length(got), 1.f); // shortened: never renormalised
    }
}

TEST(NormalCubeMap, LengthShrinksAsTheLodGrows) {
    const NormalCubeMap map = buildNormalCubeMap(64);
    std::mt19937 rng(11);
    for (int i = 0; i < 300; ++i) {
        const glm::vec3 d = randomDirection(rng);
        float previous = glm::length(sampleNormalCubeMap(map, d, 0.f));
        for (float lod = 0.25f; lod <= 6.f; lod += 0.25f) {
            const float length = glm::length(sampleNormalCubeMap(map, d, lod));
            EXPECT_LE(length, previous + 1e-6f) << "direction " << i << " lod " << lod;
            previous = length;
        }
        EXPECT_LT(previous, 0.9f); // the coarsest level holds face means (0.83 ... 1)
    }
}

TEST(NormalCubeMap, LodIsLog2OfTheFootprintInTexels) {
    const NormalCubeMap map = buildNormalCubeMap(128);
    const glm::vec3 n(0.f, 0.f, 1.f);
    // Face +z: a = x / z, so a step of 0.1 in x is 0.1 face units = 6.4 texels of 128.
    EXPECT_NEAR(
        normalCubeMapLod(map, n, n + glm::vec3(0.1f, 0.f, 0.f), n + glm::vec3(0.f, 0.02f, 0.f)),
        std::log2(6.4f), 1e-4f);
    // The longer axis wins, and scale of the lookup vectors does not matter.
    EXPECT_NEAR(normalCubeMapLod(map, 3.f * n, 3.f * n + glm::vec3(0.f, 0.f, 0.f),
                                 3.f * (n + glm::vec3(0.f, 0.25f, 0.f))),
                std::log2(16.f), 1e-4f);
    EXPECT_EQ(normalCubeMapLod(map, n, n, n), 0.f); // no change: the finest level
}

// ---- the claim on a rendered scene
// ---------------------------------------------------------------

// A 12 x 6 faceted sphere about 18 pixels across in a 64 x 64 image, a sharp Blinn-Phong
// highlight (s = 256) from a point light near the camera: the interpolated normal turns by
// about 0.17 rad per pixel, several times the lobe's width 1/sqrt(s).
Scene farSphere(Brdf brdf) {
    Scene s;
    s.geometry = facetedSphere(12, 6);
    s.camera.eye = {0.f, -20.f, 4.f};
    s.camera.target = {0.f, 0.f, 0.f};
    s.camera.fovY = 20.f;
    s.camera.width = s.camera.height = 64;
    Light light;
    light.type = LightType::Point;
    light.position = {6.f, -18.f, 10.f};
    light.color = glm::vec3(400.f);
    s.lights = {light};
    s.material.brdf = brdf;
    s.material.exponent = 256.f;
    s.material.roughness = 0.1f;
    s.material.albedo = glm::vec3(0.05f);
    return s;
}

struct Measured {
    double relativeRmse = 0, flicker = 0, errorFlicker = 0;
};

constexpr int kFrames = 8;

std::vector<Image> shiftedFrames(const Scene& scene, const std::string& method, RenderOptions o) {
    std::vector<Image> frames;
    for (glm::vec2 shift : flickerShifts(kFrames)) {
        o.pixelShift = shift;
        frames.push_back(renderInterpolated(scene, method, o).value());
    }
    return frames;
}

Measured measure(const Scene& scene, const std::string& method, const Image& truth,
                 const std::vector<Image>& truthFrames) {
    Result<Image> image = renderInterpolated(scene, method, RenderOptions{});
    EXPECT_TRUE(image) << image.error().message;
    Measured m;
    m.relativeRmse = compareImages(image.value(), truth)->relativeRmse;
    const std::vector<Image> frames = shiftedFrames(scene, method, RenderOptions{});
    m.flicker = temporalFlicker(frames);
    m.errorFlicker = temporalErrorFlicker(frames, truthFrames);
    return m;
}

TEST(InterpolatedRender, CubeMapToksvigBeatsRenormalizedOnAFarSharpHighlight) {
    for (Brdf brdf : {Brdf::BlinnPhong, Brdf::Ggx}) {
        const Scene scene = farSphere(brdf);
        RenderOptions truthOptions;
        truthOptions.spp = 256;
        const Result<Image> truth = renderInterpolated(scene, kGroundTruth, truthOptions);
        ASSERT_TRUE(truth) << truth.error().message;
        // The truth's own noise: another seed, for scale.
        truthOptions.seed = 2;
        const double truthNoise =
            compareImages(renderInterpolated(scene, kGroundTruth, truthOptions).value(),
                          truth.value())
                ->relativeRmse;
        RenderOptions truthFrameOptions;
        truthFrameOptions.spp = 64;
        const std::vector<Image> truthFrames =
            shiftedFrames(scene, kGroundTruth, truthFrameOptions);
        const Measured renormalized = measure(scene, kRenormalized, truth.value(), truthFrames);
        const Measured cubemap = measure(scene, kCubemapToksvig, truth.value(), truthFrames);
        std::printf(
            "%s: relative RMSE renormalized %.4f, cubemap-toksvig %.4f (truth vs truth %.4f); "
            "error flicker %.4f, %.4f; flicker %.4f, %.4f (truth %.4f)\n",
            brdfName(brdf), renormalized.relativeRmse, cubemap.relativeRmse, truthNoise,
            renormalized.errorFlicker, cubemap.errorFlicker, renormalized.flicker, cubemap.flicker,
            temporalFlicker(truthFrames));
        EXPECT_LT(truthNoise, 0.5 * cubemap.relativeRmse);
        EXPECT_LT(cubemap.relativeRmse, renormalized.relativeRmse) << brdfName(brdf);
        EXPECT_LT(cubemap.errorFlicker, renormalized.errorFlicker) << brdfName(brdf);
    }
}

TEST(InterpolatedRender, MagnifiedCubeMapLookupMatchesRenormalized) {
    // Close up, the normal turns by far less than a level-0 texel per pixel: LOD 0, |N| ~ 1, and
    // the Toksvig shading is the plain one.
    Scene scene = farSphere(Brdf::BlinnPhong);
    scene.camera.eye = {0.f, -2.2f, 0.6f};
    scene.camera.fovY = 10.f;
    scene.camera.width = scene.camera.height = 32;
    RenderOptions o;
    const Image a = renderInterpolated(scene, kCubemapToksvig, o).value();
    const Image b = renderInterpolated(scene, kRenormalized, o).value();
    EXPECT_LT(compareImages(a, b)->relativeRmse, 0.02);
}

TEST(InterpolatedRender, RejectsOtherMethodsAndScenes) {
    Scene scene = farSphere(Brdf::BlinnPhong);
    const Result<Image> wrong = renderInterpolated(scene, "toksvig", RenderOptions{});
    ASSERT_FALSE(wrong);
    EXPECT_NE(wrong.error().message.find("cubemap-toksvig"), std::string::npos);
    scene.geometry.type = GeometryType::Sphere;
    EXPECT_FALSE(renderInterpolated(scene, kRenormalized, RenderOptions{}));
    scene.geometry = facetedSphere(2, 6);
    EXPECT_FALSE(renderInterpolated(scene, kRenormalized, RenderOptions{}));
}

TEST(InterpolatedRender, SceneFileNeedsNoNormalMap) {
    const char* text = R"({
        "camera": {"eye": [0, -20, 4], "width": 16, "height": 16},
        "object": {"type": "faceted-sphere", "segments": 10, "rings": 5, "radius": 0.5, "center": [0, 0, 1]},
        "lights": [{"type": "point", "position": [1, -5, 3]}]
    })";
    const Result<Scene> scene = parseScene(text, "s.json", "/base");
    ASSERT_TRUE(scene) << scene.error().message;
    EXPECT_EQ(scene->geometry.type, GeometryType::FacetedSphere);
    EXPECT_EQ(scene->geometry.segments, 10);
    EXPECT_EQ(scene->geometry.rings, 5);
    EXPECT_EQ(scene->geometry.radius, 0.5f);
    EXPECT_EQ(scene->method, kGroundTruth);
    const Result<Image> image =
        render(scene.value(), RenderTextures{}, kRenormalized, RenderOptions{});
    ASSERT_TRUE(image) << image.error().message;
    EXPECT_EQ(image->width, 16);

    auto refused = [](const std::string& object, const std::string& extra,
                      const std::string& mention) {
        const std::string t = R"({"camera": {}, "lights": [{}], "object": )" + object + extra + "}";
        const Result<Scene> s = parseScene(t, "s.json", "");
        ASSERT_FALSE(s) << object << extra;
        EXPECT_NE(s.error().message.find(mention), std::string::npos) << s.error().message;
    };
    refused(R"({"type": "faceted-sphere", "segments": 2})", "", "object.segments");
    refused(R"({"type": "faceted-sphere", "rings": 6.5})", "", "object.rings");
    refused(R"({"type": "faceted-sphere", "tiling": [1, 1]})", "", "tiling");
    refused(R"({"type": "faceted-sphere"})", R"(, "normal_map": "n.png")", "normal_map");
}

} // namespace
} // namespace ndfmip

namespace ndfmip {
namespace {

TEST(InterpolatedRender, ErrorFlickerCountsOnlyTheChangingError) {
    auto grey = [](float value) {
        Image image(2, 1, 3);
        for (float& p : image.pixels) p = value;
        return image;
    };
    const std::vector<Image> truth = {grey(1.f), grey(2.f)};
    EXPECT_EQ(temporalErrorFlicker(truth, truth), 0.0); // no error
    EXPECT_NEAR(temporalErrorFlicker({grey(1.5f), grey(2.5f)}, truth), 0.0,
                1e-12); // a steady error
    // Errors +0.3 and -0.3: standard deviation 0.3 in every pixel, over a truth of RMS sqrt(2.5).
    EXPECT_NEAR(temporalErrorFlicker({grey(1.3f), grey(1.7f)}, truth), 0.3 / std::sqrt(2.5), 1e-6);
}

} // namespace
} // namespace ndfmip

namespace ndfmip {
namespace {

TEST(InterpolatedCli, RendersAFacetedSphereAndPrintsTheErrorFlicker) {
    test::TempDir tmp("interp_cli");
    const std::string scene = tmp.file("faceted.json");
    test::writeBytes(scene,
                     R"({"camera": {"eye": [0, -20, 4], "fov": 20, "width": 24, "height": 24},
        "object": {"type": "faceted-sphere", "segments": 8, "rings": 4},
        "lights": [{"type": "point", "position": [6, -18, 10], "intensity": 400}],
        "material": {"brdf": "blinnphong", "exponent": 256}})");
    std::string out;
    const int status = test::runCli("render " + test::shellArg(scene) +
                                        " --method cubemap-toksvig --frames 2 "
                                        "--truth-spp 4 -q -o " +
                                        test::shellArg(tmp.file("c.exr")),
                                    &out);
    ASSERT_EQ(status, 0) << out;
    EXPECT_NE(out.find("error flicker (2 frames, truth 4 spp): "), std::string::npos) << out;
    EXPECT_TRUE(std::filesystem::exists(tmp.file("c.png")));
    test::expectCliRefuses("render " + test::shellArg(scene) + " --gpu -o " +
                               test::shellArg(tmp.file("g.exr")),
                           {"faceted-sphere", "CPU only"});
    test::expectCliRefuses("render " + test::shellArg(scene) + " --method toksvig -o " +
                               test::shellArg(tmp.file("t.exr")),
                           {"toksvig", "cubemap-toksvig"});
}

} // namespace
} // namespace ndfmip
