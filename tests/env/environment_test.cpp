// Environment maps (environment.h): the equirectangular convention, loading checks, the SH
// projection and the GGX prefilter against closed forms and brute-force integrals, the DFG table.
#include <cmath>
#include <random>
#include <tuple>

#include <gtest/gtest.h>

#include "env/env_test_support.h"
#include "ndfmip/environment.h"
#include "ndfmip/environment_splitsum.h"
#include "ndfmip/sh_brdf.h"
#include "ndfmip/spherical_harmonics.h"

namespace ndfmip {
namespace {

using namespace envtest;

// A sky with a small, very bright sun: the case that makes prefiltering hard.
glm::dvec3 sunAndSky(glm::dvec3 d) {
    const glm::dvec3 sun = glm::normalize(glm::dvec3(0.6, 0.25, -0.4));
    const glm::dvec3 sky = glm::dvec3(0.3, 0.5, 0.9) * (0.6 + 0.4 * d.y) +
                           glm::dvec3(0.2, 0.15, 0.1) * (d.x > 0. ? 1. : 0.3);
    return sky +
           (glm::dot(d, sun) > std::cos(0.05) ? glm::dvec3(300., 250., 200.) : glm::dvec3(0.));
}

// ---- convention -------------------------------------------------------------------------------

TEST(EnvironmentConvention, CentreIsZTopIsYAndAQuarterIsX) {
    auto near = [](glm::dvec3 a, glm::dvec3 b) { return glm::length(a - b) < 1e-12; };
    EXPECT_TRUE(near(equirectDirection(0.5, 0.5), {0, 0, 1}));
    EXPECT_TRUE(near(equirectDirection(0.25, 0.5), {1, 0, 0}));
    EXPECT_TRUE(near(equirectDirection(0.75, 0.5), {-1, 0, 0}));
    EXPECT_TRUE(near(equirectDirection(0., 0.5), {0, 0, -1}));
    EXPECT_TRUE(near(equirectDirection(0.3, 0.), {0, 1, 0}));
    EXPECT_TRUE(near(equirectDirection(0.3, 1.), {0, -1, 0}));
}

TEST(EnvironmentConvention, CoordinatesInvertDirections) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(0., 1.), v(0.001, 0.999);
    for (int i = 0; i < 1000; ++i) {
        const glm::dvec2 uv(u(rng), v(rng));
        const glm::dvec2 back = equirectCoordinates(equirectDirection(uv.x, uv.y));
        EXPECT_NEAR(back.x, uv.x, 1e-12);
        EXPECT_NEAR(back.y, uv.y, 1e-12);
    }
}

TEST(EnvironmentConvention, RotationTurnsZTowardsX) {
    const glm::dvec3 d = rotateAboutY({0, 0, 1}, M_PI / 2.);
    EXPECT_NEAR(d.x, 1., 1e-15);
    EXPECT_NEAR(d.z, 0., 1e-15);
    // Turning about +Y by a quarter is a shift of u by a quarter.
    const glm::dvec3 e = rotateAboutY(equirectDirection(0.6, 0.3), M_PI / 2.);
    EXPECT_LT(glm::length(e - equirectDirection(0.35, 0.3)), 1e-12);
}

TEST(EnvironmentConvention, TexelSolidAnglesSumTo4Pi) {
    for (int height : {1, 2, 3, 64, 512, 4096}) {
        double sum = 0.;
        for (int y = 0; y < height; ++y)
            sum += 2 * height * equirectTexelSolidAngle(2 * height, height, y);
        EXPECT_NEAR(sum, 4. * M_PI, 1e-12) << height;
    }
    // A texel of row y: dphi (cos theta0 - cos theta1).
    EXPECT_NEAR(equirectTexelSolidAngle(8, 4, 0), 2. * M_PI / 8. * (1. - std::cos(M_PI / 4.)),
                1e-15);
}

// ---- loading
// --------------------------------------------------------------------------------------

TEST(EnvironmentLoad, RefusesWhatIsNoEquirectangularMap) {
    auto refused = [](Image image, EnvironmentOptions options, const std::string& mention) {
        Result<Environment> env = makeEnvironment(std::move(image), "map.exr", options);
        ASSERT_FALSE(env.ok()) << mention;
        EXPECT_EQ(env.error().message.rfind("map.exr: ", 0), 0u) << env.error().message;
        EXPECT_NE(env.error().message.find(mention), std::string::npos) << env.error().message;
        EXPECT_EQ(env.error().message.find('\n'), std::string::npos);
    };
    refused(Image(64, 64, 3), {}, "twice its height");
    refused(Image(2, 1, 3), {}, "too small");
    refused(Image(8, 4, 2), {}, "2 channels");
    Image nan(8, 4, 3);
    nan.at(5, 2)[1] = std::nanf("");
    refused(nan, {}, "texel (5, 2) is not a finite number");
    Image inf(8, 4, 3);
    inf.at(0, 3)[0] = INFINITY;
    refused(inf, {}, "texel (0, 3)");
    refused(Image(8, 4, 3), {-1.f, 0.f}, "intensity");
    refused(Image(8, 4, 3), {std::nanf(""), 0.f}, "intensity");
    refused(Image(8, 4, 3), {1.f, 400.f}, "rotation");
}

TEST(EnvironmentLoad, ScalesGreyRgbaAndZeroesNegativeTexels) {
    Image grey(8, 4, 1);
    for (float& v : grey.pixels) v = 0.5f;
    grey.pixels[3] = -0.25f;
    EnvironmentReport report;
    Result<Environment> env = makeEnvironment(grey, "g", {4.f, 90.f}, &report);
    ASSERT_TRUE(env.ok()) << env.error().message;
    EXPECT_EQ(env->radiance.channels, 3);
    EXPECT_FLOAT_EQ(env->radiance.at(0, 0)[2], 2.f);
    EXPECT_FLOAT_EQ(env->radiance.at(3, 0)[0], 0.f);
    EXPECT_EQ(report.negativeTexels, 1u);
    EXPECT_NEAR(env->rotation, M_PI / 2., 1e-7);
    Image rgba(8, 4, 4);
    rgba.at(1, 1)[2] = 3.f;
    rgba.at(1, 1)[3] = 9.f;
    env = makeEnvironment(rgba, "rgba");
    ASSERT_TRUE(env.ok());
    EXPECT_FLOAT_EQ(env->radiance.at(1, 1)[2], 3.f);
}

// ---- resampling ---------------------------------------------------------------------------------

TEST(EnvironmentResample, KeepsTheRadianceIntegral) {
    const Environment env = mapOf(64, sunAndSky);
    auto integral = [](const Image& m) {
        glm::dvec3 sum(0.);
        for (int y = 0; y < m.height; ++y)
            for (int x = 0; x < m.width; ++x) {
                const float* p = m.at(x, y);
                sum += equirectTexelSolidAngle(m.width, m.height, y) * glm::dvec3(p[0], p[1], p[2]);
            }
        return sum;
    };
    const glm::dvec3 before = integral(env.radiance);
    for (int width : {2, 8, 32, 48, 100, 128}) {
        const glm::dvec3 after = integral(resampleEquirect(env.radiance, width, 0.3));
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(after[c] / before[c], 1., 1e-6) << width;
    }
    // The same size and no rotation is the map itself; a rotation of whole texels shifts it.
    EXPECT_EQ(resampleEquirect(env.radiance, 64).pixels, env.radiance.pixels);
    const Image shifted = resampleEquirect(env.radiance, 64, 2. * M_PI * 5. / 64.);
    for (int c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(shifted.at(10, 7)[c], env.radiance.at(15, 7)[c]);
}

TEST(EnvironmentResample, BilinearLookupHitsTexelCentres) {
    const Environment env = mapOf(16, sunAndSky);
    float got[3];
    sampleEquirect(env.radiance, equirectDirection(5.5 / 16., 2.5 / 8.), got);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], env.radiance.at(5, 2)[c], 1e-5);
    // Across the seam at u = 0 and across the pole.
    sampleEquirect(env.radiance, equirectDirection(0., 3.5 / 8.), got);
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(got[c], 0.5f * (env.radiance.at(0, 3)[c] + env.radiance.at(15, 3)[c]), 1e-5);
    sampleEquirect(env.radiance, equirectDirection(2.5 / 16., 0.), got);
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(got[c], 0.5f * (env.radiance.at(2, 0)[c] + env.radiance.at(10, 0)[c]), 1e-5);
}

// ---- spherical harmonics ----------------------------------------------------------------------

// The GL/Vulkan rule for the face a direction r falls on (major axis ma) and its face
// coordinates: +X sc = -rz, tc = -ry; -X sc = rz, tc = -ry; +Y sc = rx, tc = rz; -Y sc = rx,
// tc = -rz; +Z sc = rx, tc = -ry; -Z sc = -rx, tc = -ry; s = (sc/ma + 1)/2, t = (tc/ma + 1)/2.
int glCubeFace(glm::dvec3 r, double& s, double& t) {
    const glm::dvec3 a = glm::abs(r);
    int face;
    double sc, tc, ma;
    if (a.x >= a.y && a.x >= a.z)
        face = r.x > 0 ? 0 : 1, ma = a.x, sc = r.x > 0 ? -r.z : r.z, tc = -r.y;
    else if (a.y >= a.z)
        face = r.y > 0 ? 2 : 3, ma = a.y, sc = r.x, tc = r.y > 0 ? r.z : -r.z;
    else
        face = r.z > 0 ? 4 : 5, ma = a.z, sc = r.z > 0 ? r.x : -r.x, tc = -r.y;
    s = (sc / ma + 1.) / 2., t = (tc / ma + 1.) / 2.;
    return face;
}

TEST(EnvironmentCube, FaceDirectionsFollowTheGlRule) {
    for (int i = 0; i < 2000; ++i) {
        const double z = 1. - 2. * (i + 0.5) / 2000., phi = i * 2.399963229728653,
                     q = std::sqrt(1. - z * z);
        const glm::dvec3 r(q * std::cos(phi), z, q * std::sin(phi));
        double s, t;
        const int face = glCubeFace(r, s, t);
        const glm::dvec3 d = cubeFaceDirection(face, s, t);
        EXPECT_NEAR(glm::length(d - r), 0., 1e-12)
            << "face " << cubeFaceName(face) << " s " << s << " t " << t;
    }
    EXPECT_STREQ(cubeFaceName(0), "px");
    EXPECT_STREQ(cubeFaceName(5), "nz");
}

TEST(EnvironmentCube, FacesOfASmoothMapHoldItsValues) {
    // Each channel a direction component: the faces must hold the direction each texel looks along.
    const Environment env = envtest::mapOf(512, [](glm::dvec3 d) { return d + glm::dvec3(2.); });
    for (int face = 0; face < kCubeFaces; ++face) {
        const Image image = cubeFaceFromEquirect(env.radiance, face, 16);
        ASSERT_EQ(image.width, 16);
        double worst = 0.;
        for (int y = 0; y < 16; ++y)
            for (int x = 0; x < 16; ++x) {
                const glm::dvec3 d =
                    cubeFaceDirection(face, (x + 0.5) / 16, (y + 0.5) / 16) + glm::dvec3(2.);
                for (int c = 0; c < 3; ++c)
                    worst = std::max(worst, std::abs(image.at(x, y)[c] - d[c]));
            }
        // The texel mean of a linear function is the function at the mean direction of the
        // texel, which is within a few thousandths of its centre direction at 16 texels a face.
        EXPECT_LT(worst, 0.01) << cubeFaceName(face);
    }
}

TEST(EnvironmentSh, ConstantMapHasOnlyL00) {
    // Integral of c Y_00 = c sqrt(4 pi); every other band integrates to 0 at any size (to 4e-11
    // of L_00 at 4 x 2, where a row spans 90 degrees of the 12-point rule in theta).
    for (int width : {4, 16, 256}) {
        const Environment env = mapOf(width, [](glm::dvec3) { return glm::dvec3(1., 2., 0.5); });
        const EnvironmentSh sh = projectEnvironmentSh(env, 8);
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(sh.radiance[0][c],
                        (c == 0   ? 1.
                         : c == 1 ? 2.
                                  : 0.5) *
                            std::sqrt(4. * M_PI),
                        1e-12);
        for (int i = 1; i < shCount(8); ++i)
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(sh.radiance[size_t(i)][c], 0., 1e-10) << width << " " << i;
        // Irradiance: E_00 = pi L_00.
        EXPECT_NEAR(sh.irradiance[0].y, M_PI * 2. * std::sqrt(4. * M_PI), 1e-12);
    }
}

TEST(EnvironmentSh, EachBasisFunctionProjectsOntoItself) {
    // The map read as constant per texel is Y_lm up to its texel-centre sampling, an error of
    // about l (l + 1) dtheta^2 / 24 (4.5e-4 for l = 8 at 512 x 256): measured at most 3.9e-4.
    const int order = 8;
    double worst = 0.;
    for (const int index :
         {shIndex(0, 0), shIndex(1, -1), shIndex(1, 0), shIndex(1, 1), shIndex(2, -2),
          shIndex(3, 2), shIndex(5, -4), shIndex(8, 8), shIndex(8, -7), shIndex(8, 0)}) {
        const Environment env = mapOf(
            512, [&](glm::dvec3 d) { return glm::dvec3(evaluateSh(d, order)[size_t(index)]); });
        const EnvironmentSh sh = projectEnvironmentSh(env, order);
        for (int i = 0; i < shCount(order); ++i) {
            const double error = std::abs(sh.radiance[size_t(i)].x - (i == index ? 1. : 0.));
            EXPECT_LT(error, 6e-4) << "Y at index " << index << ", coefficient " << i;
            worst = std::max(worst, error);
        }
    }
    std::printf("[ measured ] basis functions projected: largest error %.2e\n", worst);
}

TEST(EnvironmentSh, ClampedCosineHasTheLambertCoefficients) {
    // max(a.d, 0) = sum_l pi A_l sum_m Y_lm(a) Y_lm(d) (addition theorem), so L_lm = Ahat_l
    // Y_lm(a); measured within 1.1e-5 at 512 x 256.
    const glm::dvec3 a = glm::normalize(glm::dvec3(1., 2., -0.5));
    const Environment env =
        mapOf(512, [&](glm::dvec3 d) { return glm::dvec3(std::max(glm::dot(a, d), 0.)); });
    const EnvironmentSh sh = projectEnvironmentSh(env, 8);
    const std::vector<double> y = evaluateSh(a, 8), lambert = lambertCoefficients(8);
    double worst = 0.;
    for (int l = 0; l <= 8; ++l)
        for (int m = -l; m <= l; ++m) {
            const double want = M_PI * lambert[size_t(l)] * y[size_t(shIndex(l, m))];
            const double error = std::abs(sh.radiance[size_t(shIndex(l, m))].x - want);
            EXPECT_LT(error, 1e-4) << l << " " << m;
            worst = std::max(worst, error);
        }
    std::printf("[ measured ] clamped cosine: largest error %.2e\n", worst);
}

TEST(EnvironmentSh, RotationAboutYIsApplied) {
    // The map shows c x (Y_1,1). Turned a quarter about +Y, what the file shows along d is seen
    // along R_y(90) d, so its bright +X side is seen along -Z: the function seen is
    // c (R_y(-90) d).x = -c z, L_1,0 = -1.
    Environment env =
        mapOf(256, [](glm::dvec3 d) { return glm::dvec3(std::sqrt(3. / (4. * M_PI)) * d.x); });
    env.rotation = M_PI / 2.;
    const EnvironmentSh sh = projectEnvironmentSh(env, 2);
    EXPECT_NEAR(sh.radiance[size_t(shIndex(1, 0))].x, -1., 1e-4);
    EXPECT_NEAR(sh.radiance[size_t(shIndex(1, 1))].x, 0., 1e-12);
    EXPECT_NEAR(sh.radiance[size_t(shIndex(1, -1))].x, 0., 1e-12);
}

TEST(EnvironmentSh, MatchesATexelCentreSumOverTheMap) {
    // Brute force: every texel's radiance times Y_lm at its centre times its solid angle, a sum
    // that differs from the exact texel integrals by the midpoint rule's error; measured
    // 2.6e-4 of L_00 at 128 x 64 (2.2e-5 and 1.9e-4 on the shared 1k maps).
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> value(0.f, 4.f);
    Environment env;
    env.radiance = Image(128, 64, 3);
    for (float& v : env.radiance.pixels) v = value(rng);
    env.rotation = 0.4;
    const int order = 6;
    const EnvironmentSh sh = projectEnvironmentSh(env, order);
    std::vector<glm::dvec3> sum(size_t(shCount(order)), glm::dvec3(0.));
    std::vector<double> y(size_t(shCount(order)));
    for (int j = 0; j < 64; ++j)
        for (int i = 0; i < 128; ++i) {
            evaluateSh(rotateAboutY(equirectDirection((i + 0.5) / 128., (j + 0.5) / 64.), 0.4),
                       order, y.data());
            const float* p = env.radiance.at(i, j);
            for (size_t k = 0; k < y.size(); ++k)
                sum[k] += equirectTexelSolidAngle(128, 64, j) * y[k] * glm::dvec3(p[0], p[1], p[2]);
        }
    double worst = 0.;
    for (size_t k = 0; k < y.size(); ++k)
        for (int c = 0; c < 3; ++c) {
            const double error = std::abs(sh.radiance[k][c] - sum[k][c]) / sh.radiance[0][c];
            EXPECT_LT(error, 5e-4) << k;
            worst = std::max(worst, error);
        }
    std::printf("[ measured ] texel-centre sum: largest difference %.2e of L00\n", worst);
}

// ---- GGX prefilter
// ------------------------------------------------------------------------------------

TEST(GgxPrefilter, LodMappingsAreFilamentsAndLinear) {
    // cmgen 1.9 prints these for its 5 levels: 0, 0.134, 0.293, 0.5, 1.
    const double expected[] = {0., 0.134, 0.293, 0.5, 1.};
    for (int k = 0; k < 5; ++k) {
        EXPECT_NEAR(lodToPerceptualRoughness(LodMapping::Filament, k / 4.), expected[k], 5e-4);
        EXPECT_NEAR(perceptualRoughnessToLod(LodMapping::Filament, expected[k]), k / 4., 2e-3);
        EXPECT_DOUBLE_EQ(lodToPerceptualRoughness(LodMapping::Linear, k / 4.), k / 4.);
    }
    LodMapping mapping;
    EXPECT_TRUE(lodMappingFromString("linear", mapping));
    EXPECT_EQ(mapping, LodMapping::Linear);
    EXPECT_FALSE(lodMappingFromString("unreal", mapping));
}

TEST(GgxPrefilter, ConstantMapStaysConstant) {
    const Environment env = mapOf(128, [](glm::dvec3) { return glm::dvec3(0.25, 1., 3.); });
    PrefilterOptions options;
    options.levels = 4;
    options.samples = 64;
    const auto levels = prefilterGgx(env, options);
    ASSERT_EQ(levels.size(), 4u);
    EXPECT_EQ(levels[3].radiance.width, 16);
    EXPECT_EQ(levels[3].samples, 64 << 2);
    for (const PrefilteredLevel& level : levels)
        for (size_t i = 0; i < level.radiance.pixels.size(); i += 3) {
            ASSERT_NEAR(level.radiance.pixels[i], 0.25f, 1e-5f);
            ASSERT_NEAR(level.radiance.pixels[i + 2], 3.f, 1e-5f);
        }
}

TEST(GgxPrefilter, RoughnessZeroIsTheSourceResampled) {
    Environment env = mapOf(64, sunAndSky);
    PrefilterOptions options;
    options.levels = 2;
    options.size = 64;
    EXPECT_EQ(prefilterGgx(env, options)[0].radiance.pixels, env.radiance.pixels);
    options.size = 32;
    env.rotation = 0.7;
    EXPECT_EQ(prefilterGgx(env, options)[0].radiance.pixels,
              resampleEquirect(env.radiance, 32, 0.7).pixels);
}

TEST(GgxPrefilter, MatchesBruteForceIntegration) {
    // The default chain of a 512 x 256 sky with a sun 300 times brighter (0.05 rad): levels 512
    // to 64 wide, r = 0, 0.184, 0.423, 1, against the integral over every texel at 120
    // directions. Measured relative RMSE: r = 0.184 (1024 samples) 0.025, r = 0.423 (2048)
    // 0.0061, r = 1 (4096) 0.0068; cmgen is 4-26% off on the shared maps (cmgen_oracle_test.cpp).
    // At r = 0.184 the sun's edge texels are read bilinearly, which widens a lobe of a few
    // texels; the error shrinks with the map's resolution (0.7% at r = 0.293 on the 1k maps).
    Environment env = mapOf(512, sunAndSky);
    env.rotation = 0.3;
    PrefilterOptions options;
    const auto levels = prefilterGgx(env, options);
    ASSERT_EQ(levels.size(), 4u);
    for (auto [k, tolerance] : {std::pair{1, 0.05}, {2, 0.012}, {3, 0.012}}) {
        const double r = levels[size_t(k)].perceptualRoughness;
        const double error =
            relativeRmseAgainstBruteForce(env, levels[size_t(k)].radiance, r * r, 120);
        EXPECT_LT(error, tolerance) << "r = " << r;
        std::printf(
            "[ measured ] GGX r = %.3f, %d samples: relative RMSE %.4f against brute force\n", r,
            levels[size_t(k)].samples, error);
    }
}

TEST(GgxPrefilter, RoughestLevelIsIrradianceOverPi) {
    // alpha = 1: D = 1/pi, so LD(r) = integral over the hemisphere of L <r.l> / pi = E(r) / pi,
    // which is sum_l A_l L_lm Y_lm(r) for a map of bands <= 2 (up to the texels' own higher
    // bands). Measured largest relative error at 128 x 64: 0.0012 with 4096 samples, 0.0053
    // with 1024.
    const Environment env = mapOf(128, [](glm::dvec3 d) {
        return glm::dvec3(1. + 0.5 * d.x + 0.3 * d.y * d.z, 1. - 0.4 * d.y, 1. + 0.2 * d.z * d.z);
    });
    const EnvironmentSh sh = projectEnvironmentSh(env, 2);
    const Image level = prefilterGgxLevel(env, 1., 32, 4096);
    double worst = 0.;
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 32; ++x) {
            const std::vector<double> basis =
                evaluateSh(equirectDirection((x + 0.5) / 32., (y + 0.5) / 16.), 2);
            glm::dvec3 e(0.);
            for (int i = 0; i < shCount(2); ++i)
                e += sh.irradiance[size_t(i)] * basis[size_t(i)] / M_PI;
            for (int c = 0; c < 3; ++c)
                worst = std::max(worst, std::abs(level.at(x, y)[c] - e[c]) / e[c]);
        }
    EXPECT_LT(worst, 3e-3);
}

TEST(BlinnPhongPrefilter, MatchesBruteForceAndDiffersFromTheConvertedGgx) {
    // Against every texel of the map (BruteForceGgx::blinnPhong), and against the GGX level of the
    // alpha that blinnPhongAlpha gives the exponent: the chain a Blinn-Phong material read before
    // (it must be off by more than the Blinn-Phong level's own error, or this lobe adds nothing).
    const Environment env = mapOf(128, sunAndSky);
    const BruteForceGgx truthOf(env);
    for (auto [exponent, width, tolerance] :
         {std::tuple{8., 32, 0.02}, {32., 64, 0.02}, {128., 128, 0.035}}) {
        const Image level = prefilterBlinnPhongLevel(env, exponent, width, 2048);
        const double alpha = blinnPhongAlpha(exponent);
        const Image ggx = prefilterGgxLevel(env, std::sqrt(alpha), width, 2048);
        double error = 0., converted = 0., norm = 0.;
        for (int i = 0; i < 150; ++i) {
            const glm::dvec3 r = spiralDirection(i, 150);
            const glm::dvec3 truth = truthOf.blinnPhong(r, exponent);
            float a[3], b[3];
            sampleEquirect(level, r, a);
            sampleEquirect(ggx, r, b);
            for (int c = 0; c < 3; ++c) {
                error += (a[c] - truth[c]) * (a[c] - truth[c]);
                converted += (b[c] - truth[c]) * (b[c] - truth[c]);
                norm += truth[c] * truth[c];
            }
        }
        error = std::sqrt(error / norm), converted = std::sqrt(converted / norm);
        EXPECT_LT(error, tolerance) << "s = " << exponent;
        EXPECT_GT(converted, 1.5 * error) << "s = " << exponent;
        std::printf("[ measured ] Blinn-Phong s = %.0f at %d wide: relative RMSE %.4f; GGX alpha = "
                    "%.3f: %.4f\n",
                    exponent, width, error, alpha, converted);
    }
}

TEST(GgxPrefilter, RotationShiftsTheLevels) {
    // A quarter turn is a shift by a quarter of the width, texel for texel.
    Environment env = mapOf(128, sunAndSky);
    const Image plain = prefilterGgxLevel(env, 0.5, 32, 256);
    env.rotation = M_PI / 2.;
    const Image turned = prefilterGgxLevel(env, 0.5, 32, 256);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 32; ++x)
            for (int c = 0; c < 3; ++c)
                ASSERT_NEAR(turned.at(x, y)[c], plain.at((x + 8) % 32, y)[c],
                            1e-4 * (1. + plain.at(x, y)[c]))
                    << x << " " << y;
}

// ---- DFG table
// -----------------------------------------------------------------------------------------

// The DFG integrals by a product Gauss rule over l: theta_l in [0, pi/2] (cos theta), phi_l in
// [0, pi] (the integrand is symmetric in phi), fine enough for alpha >= 0.09.
glm::dvec2 bruteForceDfg(double mu, double r) {
    const double alpha = r * r, a2 = alpha * alpha;
    const glm::dvec3 v(std::sqrt(1. - mu * mu), 0., mu);
    const int n = 2000;
    glm::dvec2 sum(0.);
    for (int i = 0; i < n; ++i) {
        const double cl = (i + 0.5) / n, sl = std::sqrt(1. - cl * cl);
        for (int j = 0; j < n; ++j) {
            const double phi = M_PI * (j + 0.5) / n;
            const glm::dvec3 l(sl * std::cos(phi), sl * std::sin(phi), cl);
            const glm::dvec3 h = glm::normalize(l + v);
            const double f = h.z * h.z * (a2 - 1.) + 1., d = a2 / (M_PI * f * f);
            const double vis = 0.5 / (cl * std::sqrt(mu * mu * (1. - a2) + a2) +
                                      mu * std::sqrt(cl * cl * (1. - a2) + a2));
            const double fc = std::pow(1. - glm::dot(v, h), 5.);
            sum += d * vis * cl * glm::dvec2(1. - fc, fc);
        }
    }
    return sum * (2. * M_PI / n / n); // dl = d(cos theta) dphi, phi over [0, pi] counted twice
}

TEST(Dfg, MatchesBruteForceIntegration) {
    // Against 2000 x 2000 points, with 65536 samples: measured at most 7.9e-5 apart. With the
    // table's default 4096 samples the scale is off by up to 3.4e-3 at grazing n.v = 0.05
    // (under 1e-3 from n.v = 0.2 on), with 1024 by 7.8e-3.
    for (auto [mu, r] : {std::pair{0.5, 0.5}, {0.9, 0.3}, {0.2, 0.8}, {1., 1.}, {0.05, 0.6}}) {
        const glm::dvec2 got = dfgIntegral(mu, r, 65536), want = bruteForceDfg(mu, r);
        const glm::dvec2 table = dfgIntegral(mu, r, 4096);
        std::printf("[ measured ] DFG at n.v %.2f, r %.1f: 65536 samples off by %.1e %.1e, 4096 by "
                    "%.1e %.1e\n",
                    mu, r, std::abs(got.x - want.x), std::abs(got.y - want.y),
                    std::abs(table.x - want.x), std::abs(table.y - want.y));
        EXPECT_NEAR(got.x, want.x, 3e-4) << mu << " " << r;
        EXPECT_NEAR(got.y, want.y, 3e-4) << mu << " " << r;
        EXPECT_NEAR(table.x, want.x, 4e-3) << mu << " " << r;
        EXPECT_NEAR(table.y, want.y, 4e-3) << mu << " " << r;
    }
}

TEST(Dfg, TableHoldsTheIntegralAtTexelCentres) {
    const Image table = dfgTable(16, 256);
    ASSERT_EQ(table.channels, 3);
    const glm::dvec2 d = dfgIntegral(5.5 / 16., 9.5 / 16., 256);
    EXPECT_FLOAT_EQ(table.at(5, 9)[0], float(d.x));
    EXPECT_FLOAT_EQ(table.at(5, 9)[1], float(d.y));
    EXPECT_FLOAT_EQ(table.at(5, 9)[2], float(d.x + d.y));
    // A smooth surface seen head on reflects all of it (scale ~1, bias ~0); nothing reflects
    EXPECT_NEAR(table.at(15, 0)[0], 1., 0.02);
    EXPECT_LT(table.at(15, 0)[1], 0.01);
    // more than it receives (to the sampling error of 256 samples: at most 1.8e-4 over).
    for (size_t i = 0; i < table.texelCount(); ++i) EXPECT_LE(table.pixels[3 * i + 2], 1.001f);
}

} // namespace
} // namespace ndfmip
