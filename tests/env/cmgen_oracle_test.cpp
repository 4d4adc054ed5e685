// Filament's cmgen (Debian libfilament-tools 1.9) as an oracle for `ndfmip envmap`. Skipped where
// cmgen is not installed; the shared-map cases also where ../shared/data/envmaps is missing.
//
// cmgen's SH (--sh=N --sh-window=no: raw, unwindowed L_lm) uses the Condon-Shortley phase, so
// its L_lm is (-1)^m ours, in the same frame and order; scripts/compare-cmgen runs the long
// comparisons (full size, NDFMIP_CMGEN_FULL=1). Every difference is measured relative to the
// largest coefficient's magnitude in each channel (L_00 in practice): single coefficients near
// zero have no meaningful relative error.
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "env/env_test_support.h"
#include "ndfmip/environment.h"
#include "ndfmip/io.h"
#include "ndfmip/spherical_harmonics.h"
#include "test_support.h"

namespace fs = std::filesystem;

namespace ndfmip {
namespace {

using namespace envtest;

bool haveCmgen() {
    return std::system("command -v cmgen >/dev/null 2>&1") == 0;
}

bool fullComparison() {
    const char* full = std::getenv("NDFMIP_CMGEN_FULL");
    return full && std::string(full) == "1";
}

// Runs cmgen quietly; true when it exits with 0.
bool cmgen(const std::string& args) {
    return std::system(("cmgen -q " + args + " >/dev/null 2>&1").c_str()) == 0;
}

// The coefficients of cmgen's SH text file, "( r, g, b); // Llm" per line (bands below 10),
// turned into ours by the Condon-Shortley sign (-1)^m.
std::vector<glm::dvec3> readCmgenSh(const std::string& path) {
    std::ifstream in(path);
    std::vector<glm::dvec3> coefficients;
    for (std::string text; std::getline(in, text);) {
        const size_t open = text.find('('), name = text.find("// L");
        if (open == std::string::npos || name == std::string::npos) continue;
        glm::dvec3 c;
        const char* p = text.c_str() + open + 1;
        for (int i = 0; i < 3; ++i) {
            char* end = nullptr;
            c[i] = std::strtod(p, &end);
            p = end + 1; // past the comma
        }
        // "L10" is band 1, m = 0 and "L1-1" band 1, m = -1: the band is one digit (l < 10).
        const int l = int(text[name + 4] - '0');
        const int m = int(std::strtol(text.c_str() + name + 5, nullptr, 10));
        EXPECT_EQ(shIndex(l, m), int(coefficients.size())) << text;
        coefficients.push_back((m % 2 == 0 ? 1. : -1.) * c);
    }
    return coefficients;
}

// Per channel, the largest |ours - cmgen| over the coefficients cmgen wrote, relative to the
// largest |coefficient| of ours.
glm::dvec3 shDifference(const std::vector<glm::dvec3>& ours,
                        const std::vector<glm::dvec3>& theirs) {
    glm::dvec3 largest(0.), worst(0.);
    for (size_t i = 0; i < theirs.size(); ++i) largest = glm::max(largest, glm::abs(ours[i]));
    for (size_t i = 0; i < theirs.size(); ++i)
        worst = glm::max(worst, glm::abs(ours[i] - theirs[i]) / largest);
    return worst;
}

// Filament's cube faces in its file order px, nx, py, ny, pz, nz: texel (x, y) of a dim x dim
// face looks along this direction (ibl/Cubemap.h getDirectionFor, y from the top row).
constexpr std::array<const char*, 6> kFaces = {"px", "nx", "py", "ny", "pz", "nz"};
glm::dvec3 faceDirection(int face, double x, double y, int dim) {
    const double cx = 2. * x / dim - 1., cy = 1. - 2. * y / dim;
    const glm::dvec3 d[6] = {{1, cy, -cx}, {-1, cy, cx}, {cx, 1, -cy},
                             {cx, -1, cy}, {cx, cy, 1},  {-cx, cy, -1}};
    return glm::normalize(d[face]);
}

// A horizontal cross (4 dim x 3 dim, the layout cmgen reads) holding at each texel the mean of
// `f` over n x n points of it, weighted by solid angle. `mirrored`: the cross holds f(-x, y, z),
// which cmgen's default mirror turns back into f.
Image crossOf(const Radiance& f, int dim, int n, bool mirrored) {
    const int origin[6][2] = {{2, 1}, {0, 1}, {1, 0}, {1, 2}, {1, 1}, {3, 1}};
    Image cross(4 * dim, 3 * dim, 3);
#pragma omp parallel for collapse(2) schedule(dynamic, 4)
    for (int face = 0; face < 6; ++face)
        for (int y = 0; y < dim; ++y)
            for (int x = 0; x < dim; ++x) {
                glm::dvec3 sum(0.);
                double weights = 0.;
                for (int j = 0; j < n; ++j)
                    for (int i = 0; i < n; ++i) {
                        const double sx = x + (i + 0.5) / n, sy = y + (j + 0.5) / n;
                        const double cx = 2. * sx / dim - 1., cy = 1. - 2. * sy / dim;
                        const double w = std::pow(cx * cx + cy * cy + 1., -1.5);
                        glm::dvec3 d = faceDirection(face, sx, sy, dim);
                        if (mirrored) d.x = -d.x;
                        sum += w * f(d);
                        weights += w;
                    }
                float* p = cross.at(origin[face][0] * dim + x, origin[face][1] * dim + y);
                for (int c = 0; c < 3; ++c) p[c] = float(sum[c] / weights);
            }
    return cross;
}

// The map read as constant per texel, as a function of direction.
Radiance texelsOf(const Image& map) {
    return [&map](glm::dvec3 d) {
        const glm::dvec2 uv = equirectCoordinates(d);
        const float* p = map.at(std::min(int(uv.x * map.width), map.width - 1),
                                std::min(int(uv.y * map.height), map.height - 1));
        return glm::dvec3(p[0], p[1], p[2]);
    };
}

// Broad coloured lobes: smooth enough for any resampling to keep its SH to 1e-5.
glm::dvec3 smoothSky(glm::dvec3 d) {
    auto lobe = [&](glm::dvec3 mu, double kappa) {
        return std::exp(kappa * (glm::dot(d, glm::normalize(mu)) - 1.));
    };
    return glm::dvec3(3, 1, 0.5) * lobe({1, 0.3, 0.2}, 8.) +
           glm::dvec3(0.2, 0.8, 2) * lobe({-0.3, 0.8, -0.5}, 4.) +
           glm::dvec3(1, 1, 1) * lobe({0.2, -0.6, 0.9}, 12.) + glm::dvec3(0.1, 0.15, 0.2);
}

class CmgenOracle : public ::testing::Test {
  protected:
    test::TempDir tmp{"cmgen_oracle"};
    void SetUp() override {
        if (!haveCmgen()) GTEST_SKIP() << "cmgen (Debian libfilament-tools) is not installed";
    }
    // The shared .hdr maps, or none (the test then skips).
    std::vector<fs::path> sharedMaps() {
        std::vector<fs::path> maps;
        const fs::path dir = test::sharedEnvMaps();
        if (!dir.empty())
            for (const auto& entry : fs::directory_iterator(dir))
                if (entry.path().extension() == ".hdr") maps.push_back(entry.path());
        std::sort(maps.begin(), maps.end());
        return maps;
    }
};

TEST_F(CmgenOracle, ShOfASmoothSkyAgreesToAThousandth) {
    // One function given to both: to us as a 1024 x 512 map, to cmgen as a 128-texel cube cross
    // it copies texel for texel, so only the projections differ. Measured: 3.6e-5 of L_00 with
    // cmgen's mirror (the cross holds the mirrored sky) and without (--no-mirror). This pins the
    // basis, its order and normalisation, the sign convention and the frame.
    const EnvironmentSh ours = projectEnvironmentSh(mapOf(1024, smoothSky), 8);
    for (bool mirror : {true, false}) {
        const std::string cross = tmp.file("cross.exr"), sh = tmp.file("sh.txt");
        ASSERT_TRUE(saveExr(cross, crossOf(smoothSky, 128, 2, mirror)));
        ASSERT_TRUE(cmgen(std::string(mirror ? "" : "--no-mirror ") +
                          "-s 128 --sh=9 --sh-window=no --sh-output=" + sh + " " + cross));
        const std::vector<glm::dvec3> theirs = readCmgenSh(sh);
        ASSERT_EQ(theirs.size(), 81u);
        const glm::dvec3 d = shDifference(ours.radiance, theirs);
        std::printf("[ measured ] smooth sky, mirror %d: SH difference %.2e %.2e %.2e of L00\n",
                    mirror, d.x, d.y, d.z);
        for (int c = 0; c < 3; ++c) EXPECT_LT(d[c], 1e-3) << "channel " << c;
    }
    // cmgen -i: the irradiance coefficients E_lm = Ahat_l L_lm (with its sign (-1)^m).
    const std::string cross = tmp.file("cross.exr"), sh = tmp.file("sh.txt");
    ASSERT_TRUE(
        cmgen("--no-mirror -s 128 --sh=9 -i --sh-window=no --sh-output=" + sh + " " + cross));
    const glm::dvec3 d = shDifference(ours.irradiance, readCmgenSh(sh));
    for (int c = 0; c < 3; ++c) EXPECT_LT(d[c], 1e-3) << "irradiance, channel " << c;
}

TEST_F(CmgenOracle, BrightSpotAtPlusXIsPlusXForBoth) {
    // An equirectangular map lit only around +X (u = 1/4 in our convention), through cmgen's
    // default path (equirect to cube, mirror): L_1,1 (~x) carries it, with cmgen's sign flipped.
    const Environment env =
        mapOf(256, [](glm::dvec3 d) { return glm::dvec3(std::exp(10. * (d.x - 1.))); });
    const std::string map = tmp.file("x.exr"), sh = tmp.file("x.txt");
    ASSERT_TRUE(saveExr(map, env.radiance));
    ASSERT_TRUE(cmgen("-s 64 --sh=2 --sh-window=no --sh-output=" + sh + " " + map));
    std::ifstream in(sh);
    std::string l00, l1m1, l10, l11;
    std::getline(in, l00);
    std::getline(in, l1m1);
    std::getline(in, l10);
    std::getline(in, l11);
    const double theirs11 = std::stod(l11.substr(l11.find('(') + 1));
    const EnvironmentSh ours = projectEnvironmentSh(env, 1);
    EXPECT_GT(ours.radiance[size_t(shIndex(1, 1))].x, 0.5 * ours.radiance[0].x);
    EXPECT_LT(theirs11, -0.5 * ours.radiance[0].x) << l11; // cmgen's Y_1,1 ~ -x
    EXPECT_NEAR(ours.radiance[size_t(shIndex(1, -1))].x, 0., 1e-9);
    EXPECT_NEAR(ours.radiance[size_t(shIndex(1, 0))].x, 0., 1e-9);
}

TEST_F(CmgenOracle, ShOfTheSharedMaps) {
    // cmgen on the .hdr itself resamples it to a 256 cube first (nearest texel, positions scaled
    // by width - 1), which moves its own coefficients by up to 2% between cube sizes 256, 512 and
    // 1024. Measured against ours, of L_00: venice_sunset 2.4e-2 / 7.4e-3 / 9.0e-3 (r, g, b),
    // studio_small_03 2.6e-2. Given the same map as an accurate cube (32 x 32 points per texel
    // of a 256 cube; NDFMIP_CMGEN_FULL=1, scripts/compare-cmgen): 1.3e-4 and 2.6e-4.
    const auto maps = sharedMaps();
    if (maps.empty()) GTEST_SKIP() << "no ../shared/data/envmaps";
    for (const fs::path& path : maps) {
        Result<Environment> env = loadEnvironment(path.string());
        ASSERT_TRUE(env.ok()) << env.error().message;
        const EnvironmentSh ours = projectEnvironmentSh(env.value(), 8);
        const std::string sh = tmp.file("sh.txt");
        ASSERT_TRUE(cmgen("--sh=9 --sh-window=no --sh-output=" + sh + " " + path.string()));
        glm::dvec3 d = shDifference(ours.radiance, readCmgenSh(sh));
        std::printf("[ measured ] %s: SH difference to cmgen's equirect path %.2e %.2e %.2e\n",
                    path.filename().c_str(), d.x, d.y, d.z);
        for (int c = 0; c < 3; ++c) EXPECT_LT(d[c], 4e-2) << path;
        if (!fullComparison()) continue;
        const std::string cross = tmp.file("cross.exr");
        ASSERT_TRUE(saveExr(cross, crossOf(texelsOf(env->radiance), 256, 32, false)));
        ASSERT_TRUE(
            cmgen("--no-mirror -s 256 --sh=9 --sh-window=no --sh-output=" + sh + " " + cross));
        d = shDifference(ours.radiance, readCmgenSh(sh));
        std::printf("[ measured ] %s: SH difference to cmgen given a 256 cube %.2e %.2e %.2e\n",
                    path.filename().c_str(), d.x, d.y, d.z);
        for (int c = 0; c < 3; ++c) EXPECT_LT(d[c], 1e-3) << path;
    }
}

// Relative RMSE over cmgen's face texels (weighted by solid angle) between its level in
// `dir`/m<k>_<face>.exr and our equirectangular level read at the same directions.
double levelDifference(const std::string& dir, int k, const Image& ours) {
    double error = 0., norm = 0.;
    for (int face = 0; face < 6; ++face) {
        Result<SourceImage> image =
            loadImage(dir + "/m" + std::to_string(k) + "_" + kFaces[size_t(face)] + ".exr");
        EXPECT_TRUE(image.ok());
        if (!image) return 1e9;
        const Image& theirs = image->image;
        const int dim = theirs.width;
        for (int y = 0; y < dim; ++y)
            for (int x = 0; x < dim; ++x) {
                const double cx = 2. * (x + 0.5) / dim - 1., cy = 1. - 2. * (y + 0.5) / dim;
                const double w = std::pow(cx * cx + cy * cy + 1., -1.5);
                float got[3];
                sampleEquirect(ours, faceDirection(face, x + 0.5, y + 0.5, dim), got);
                for (int c = 0; c < 3; ++c) {
                    error += w * (got[c] - theirs.at(x, y)[c]) * (got[c] - theirs.at(x, y)[c]);
                    norm += w * theirs.at(x, y)[c] * theirs.at(x, y)[c];
                }
            }
    }
    return std::sqrt(error / norm);
}

// cmgen's level k along r: the nearest face, bilinear inside it.
glm::dvec3 cmgenLookup(const std::vector<Image>& faces, glm::dvec3 r) {
    const glm::dvec3 a = glm::abs(r);
    int face;
    double sc, tc, ma;
    if (a.x >= a.y && a.x >= a.z) {
        face = r.x >= 0 ? 0 : 1, ma = a.x, sc = r.x >= 0 ? -r.z : r.z, tc = -r.y;
    } else if (a.y >= a.z) {
        face = r.y >= 0 ? 2 : 3, ma = a.y, sc = r.x, tc = r.y >= 0 ? r.z : -r.z;
    } else {
        face = r.z >= 0 ? 4 : 5, ma = a.z, sc = r.z >= 0 ? r.x : -r.x, tc = -r.y;
    }
    const Image& f = faces[size_t(face)];
    const int dim = f.width;
    const double fs = (sc / ma + 1.) * 0.5 * dim - 0.5, ft = (tc / ma + 1.) * 0.5 * dim - 0.5;
    const int x0 = std::clamp(int(std::floor(fs)), 0, dim - 2),
              y0 = std::clamp(int(std::floor(ft)), 0, dim - 2);
    const double u = std::clamp(fs - x0, 0., 1.), v = std::clamp(ft - y0, 0., 1.);
    glm::dvec3 c(0.);
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 2; ++i) {
            const float* p = f.at(x0 + i, y0 + j);
            c += (i ? u : 1. - u) * (j ? v : 1. - v) * glm::dvec3(p[0], p[1], p[2]);
        }
    return c;
}

TEST_F(CmgenOracle, PrefilteredLevelsOfTheSharedMaps) {
    // The maps averaged down to 256 x 128; cmgen -s 64 --ibl-ld makes 3 cube levels 64, 32, 16
    // at perceptual roughness 0, 0.293, 1 (its lod mapping, ours by default), ours 256, 128, 64
    // wide. Each is compared with the other at cmgen's texels and with the brute-force integral
    // at 300 directions. Measured (relative RMSE, levels 1 and 2):
    //   ours vs cmgen:        venice 0.082, 0.084   studio 0.223, 0.180
    //   ours vs brute force:  venice 0.010, 0.006   studio 0.014, 0.031
    //   cmgen vs brute force: venice 0.076, 0.083   studio 0.263, 0.190
    // so the difference is cmgen's error (at 64 texels its cube reads the sources through few
    // texels). At full size (NDFMIP_CMGEN_FULL=1, scripts/compare-cmgen: the 1k maps, cmgen's
    // default 256 cube and 5 levels, r = 0.134, 0.293, 0.5, 1 for levels 1-4):
    //   ours vs cmgen:        venice 0.204, 0.053, 0.040, 0.045   studio 0.127, 0.071, 0.055, 0.067
    //   ours vs brute force:  venice 0.013, 0.006, 0.003, 0.002   studio 0.013, 0.007, 0.006, 0.008
    //   cmgen vs brute force: venice 0.044, 0.049, 0.040, 0.045   studio 0.260, 0.085, 0.052, 0.062
    // (at r = 0.134 "ours vs cmgen" counts every texel around the sun, which the 300 directions
    // mostly miss).
    const auto maps = sharedMaps();
    if (maps.empty()) GTEST_SKIP() << "no ../shared/data/envmaps";
    const bool full = fullComparison();
    for (const fs::path& path : maps) {
        Result<Environment> loaded = loadEnvironment(path.string());
        ASSERT_TRUE(loaded.ok()) << loaded.error().message;
        Environment env;
        env.radiance = full ? loaded->radiance : resampleEquirect(loaded->radiance, 256);
        const std::string map = tmp.file("map.exr"), dir = tmp.file("ld");
        ASSERT_TRUE(saveExr(map, env.radiance));
        ASSERT_TRUE(
            cmgen((full ? "" : "-s 64 ") + std::string("--ibl-ld=") + dir + " -f exr " + map));
        PrefilterOptions options;
        options.levels = full ? 0 : 3;
        const auto ours = prefilterGgx(env, options);
        for (int k = 1; k < int(ours.size()); ++k) {
            const double r = ours[size_t(k)].perceptualRoughness;
            std::vector<Image> faces;
            for (const char* face : kFaces)
                faces.push_back(loadImage(dir + "/map/m" + std::to_string(k) + "_" + face + ".exr")
                                    .value()
                                    .image);
            const double apart = levelDifference(dir + "/map", k, ours[size_t(k)].radiance);
            // Our cube faces of the level (envmap --layout cube) against cmgen's, texel for
            // texel: as close as our equirectangular level read at its texels.
            double faceError = 0., faceNorm = 0.;
            for (int face = 0; face < 6; ++face) {
                const Image& theirs = faces[size_t(face)];
                const Image mine =
                    cubeFaceFromEquirect(ours[size_t(k)].radiance, face, theirs.width);
                for (size_t i = 0; i < theirs.pixels.size(); ++i) {
                    const double d = mine.pixels[i] - theirs.pixels[i];
                    faceError += d * d, faceNorm += double(theirs.pixels[i]) * theirs.pixels[i];
                }
            }
            const double faceApart = std::sqrt(faceError / faceNorm);
            std::printf("[ measured ] %s level %d: our cube faces vs cmgen's %.3f\n",
                        path.filename().c_str(), k, faceApart);
            EXPECT_LT(faceApart, 1.25 * apart + 0.02) << path << " level " << k;
            const double oursError =
                relativeRmseAgainstBruteForce(env, ours[size_t(k)].radiance, r * r, 300);
            const double theirError = relativeRmseAgainstBruteForce(
                env, r * r, 300, [&](glm::dvec3 d) { return cmgenLookup(faces, d); });
            std::printf("[ measured ] %s level %d (r = %.3f): ours vs cmgen %.3f, vs brute force: "
                        "ours %.3f, cmgen %.3f\n",
                        path.filename().c_str(), k, r, apart, oursError, theirError);
            EXPECT_LT(oursError, 0.04) << path << " level " << k;
            EXPECT_LT(oursError, theirError) << path << " level " << k;
            EXPECT_LT(apart, 0.3) << path << " level " << k;
        }
    }
}

} // namespace
} // namespace ndfmip
