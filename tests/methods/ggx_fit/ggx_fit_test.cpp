// ggx-fit: one GGX lobe per texel whose roughness is fitted to the texel's filtered NDF. Checked
// against closed forms (one normal, a constant map) and against an independent brute-force fit
// in double precision over every normal of the footprint on real maps.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <vector>

#include <gtest/gtest.h>

#include "methods/method_unit.h"
#include "ndfmip/normal_map.h"
#include "ndfmip/pyramid.h"
#include "ndfmip/roughness.h"
#include "test_support.h"

namespace ndfmip {
namespace {

constexpr double kPiD = 3.14159265358979323846;

float alphaAt(const Bake& bake, int level, int x, int y) {
    return bake.levels[level][1]->at(x, y)[0];
}

TEST(GgxFit, OneNormalPerTexelIsTheMaterialsRoughness) {
    // A constant (tilted) map: every footprint holds one direction, whose filtered NDF is the
    // material's own lobe about it.
    const glm::vec3 tilt = glm::normalize(glm::vec3(0.3f, -0.2f, 1.f));
    const Pyramid pyramid =
        buildPyramid(test::filledNormals(32, 32, [&](int, int) { return tilt; }));
    for (float alpha : {0.05f, 0.1f, 0.3f, 0.7f}) {
        const Bake bake = bakeGgxFit(pyramid, test::withBaseRoughness(alpha));
        ASSERT_EQ(bake.levels.size(), pyramid.levels.size());
        for (size_t k = 0; k < bake.levels.size(); ++k) {
            EXPECT_NEAR(alphaAt(bake, int(k), 0, 0), alpha, 3e-3f * alpha)
                << "alpha " << alpha << " level " << k;
            const float* n = bake.levels[k][0]->at(0, 0);
            EXPECT_NEAR(glm::dot(glm::vec3(n[0], n[1], n[2]), tilt), 1.f, 1e-5f);
        }
    }
}

TEST(GgxFit, LevelZeroIsTheMapAndAxesLieAmongTheFootprintsNormals) {
    const Pyramid pyramid = buildPyramid(test::filledNormals(16, 8, [](int x, int y) {
        return glm::vec3(0.6f * std::sin(x), 0.4f * std::cos(y), 1.f);
    }));
    const Bake bake = bakeGgxFit(pyramid, test::withBaseRoughness(0.2f));
    const Bake naive = bakeNaive(pyramid, {});
    EXPECT_EQ(bake.levels[0][0]->pixels, naive.levels[0][0]->pixels);
    for (size_t k = 1; k < bake.levels.size(); ++k) {
        // The axis is a positive combination of the footprint's normals, so it is unit and no
        // further from their mean normal than the furthest of them.
        const Image& axes = *bake.levels[k][0];
        for (int y = 0; y < axes.height; ++y)
            for (int x = 0; x < axes.width; ++x) {
                const float* a = axes.at(x, y);
                const float* m = naive.levels[k][0]->at(x, y);
                const glm::vec3 axis(a[0], a[1], a[2]), mean(m[0], m[1], m[2]);
                EXPECT_NEAR(glm::length(axis), 1.f, 1e-5f);
                const Footprint f = footprint(pyramid, int(k), x, y);
                float nearest = 1.f;
                for (int by = f.y0; by < f.y1; ++by)
                    for (int bx = f.x0; bx < f.x1; ++bx) {
                        const float* n = pyramid.base->at(bx, by);
                        nearest = std::min(nearest, glm::dot(glm::vec3(n[0], n[1], n[2]), mean));
                    }
                EXPECT_GE(glm::dot(axis, mean), nearest - 1e-5f) << "level " << k;
            }
    }
    for (size_t k = 0; k < bake.levels.size(); ++k) {
        for (float a : bake.levels[k][1]->pixels) {
            if (k == 0) {
                EXPECT_EQ(a, 0.2f);
            }
            EXPECT_GE(a, 0.1f);
            EXPECT_LE(a, 1.f);
        }
    }
}

// A skewed footprint: three quarters of the normals flat, a quarter tilted 40 degrees about y.
// Their mean normal leans 8.6 degrees towards the few; the lobe's axis stays on the many (the
// highlight's peak), within a degree of the flat normal.
TEST(GgxFit, TheAxisIsTheModeOfASkewedFootprint) {
    const float tilt = 40.f * float(kPiD) / 180.f;
    const Pyramid pyramid = buildPyramid(test::filledNormals(8, 8, [&](int x, int y) {
        return x % 2 == 1 && y % 2 == 1 ? glm::vec3(std::sin(tilt), 0.f, std::cos(tilt))
                                        : glm::vec3(0.f, 0.f, 1.f);
    }));
    const Bake bake = bakeGgxFit(pyramid, test::withBaseRoughness(0.1f));
    for (size_t k = 1; k < bake.levels.size(); ++k) {
        const float* mean = levelMean(pyramid, int(k)).at(0, 0);
        const float* axis = bake.levels[k][0]->at(0, 0);
        const float meanAngle = std::atan2(mean[0], mean[2]);
        EXPECT_NEAR(meanAngle, std::atan2(0.25f * std::sin(tilt), 0.75f + 0.25f * std::cos(tilt)),
                    1e-5f);
        EXPECT_GT(meanAngle, 0.14f); // 8.6 degrees
        EXPECT_LT(std::atan2(axis[0], axis[2]), 1.f * float(kPiD) / 180.f) << "level " << k;
        EXPECT_NEAR(axis[1], 0.f, 1e-6f);
    }
}

TEST(GgxFit, NormalsAtPlusMinusThetaWidenTheLobeMonotonically) {
    // A checkerboard of normals at +-theta about x: every 2x2 block is the NDF of two
    // directions, wider the further apart they are; the fit is the material's lobe at theta = 0.
    float previous = 0.f;
    for (float theta : {0.f, 0.05f, 0.1f, 0.2f, 0.35f}) {
        const Pyramid pyramid = buildPyramid(test::filledNormals(8, 8, [&](int x, int y) {
            const float s = (x + y) % 2 ? 1.f : -1.f;
            return glm::vec3(s * std::sin(theta), 0.f, std::cos(theta));
        }));
        const float alpha = alphaAt(bakeGgxFit(pyramid, test::withBaseRoughness(0.1f)), 1, 0, 0);
        if (theta == 0.f) {
            EXPECT_NEAR(alpha, 0.1f, 3e-4f);
        }
        EXPECT_GT(alpha, previous) << "theta " << theta;
        previous = alpha;
    }
    EXPECT_GT(previous, 0.3f); // normals 40 degrees apart against a lobe of alpha 0.1
}

TEST(GgxFit, NonPowerOfTwoMapsGiveFiniteRoughnessEverywhere) {
    const Pyramid pyramid = buildPyramid(test::filledNormals(13, 7, [](int x, int y) {
        return glm::vec3(0.8f * std::sin(1.7f * x), 0.5f * std::cos(2.3f * y), 1.f);
    }));
    const Bake bake = bakeGgxFit(pyramid, test::withBaseRoughness(0.05f));
    for (const auto& level : bake.levels)
        for (float a : level[1]->pixels) {
            EXPECT_TRUE(std::isfinite(a));
            EXPECT_GE(a, 0.025f);
            EXPECT_LE(a, 1.f);
        }
}

// ---- Against an independent fit on real maps ---------------------------------------------

// The NDF L2 distance that ggx-fit minimises, written out in double with every normal of the
// footprint and more samples: 96 rings of equal width in theta up to 60 degrees past the
// footprint's widest normal, 24 azimuths each.
struct DenseObjective {
    std::vector<double> cosTheta, weight, target;

    DenseObjective(const std::vector<glm::dvec3>& normals, const std::vector<double>& alphas,
                   glm::dvec3 axis) {
        double widest = 0.;
        for (const glm::dvec3& n : normals)
            widest = std::max(widest, std::acos(std::clamp(glm::dot(n, axis), -1., 1.)));
        const double reach = std::min(widest + 1.05, kPiD / 2);
        const glm::dvec3 t = glm::normalize(glm::cross(axis, glm::dvec3(1, 0, 0)));
        const glm::dvec3 b = glm::cross(axis, t);
        constexpr int kRings = 96, kAzimuths = 24;
        for (int j = 0; j < kRings; ++j) {
            const double lo = reach * j / kRings, hi = reach * (j + 1) / kRings;
            const double theta = 0.5 * (lo + hi);
            double sum = 0.;
            for (int m = 0; m < kAzimuths; ++m) {
                const double phi = 2. * kPiD * (m + 0.5) / kAzimuths;
                const glm::dvec3 h = std::cos(theta) * axis +
                                     std::sin(theta) * (std::cos(phi) * t + std::sin(phi) * b);
                for (size_t i = 0; i < normals.size(); ++i)
                    sum += test::ggxReference(glm::dot(h, normals[i]), alphas[i]);
            }
            cosTheta.push_back(std::cos(theta));
            weight.push_back(std::cos(lo) - std::cos(hi));
            target.push_back(sum / (double(normals.size()) * kAzimuths));
        }
    }

    double error(double alpha) const {
        double e = 0.;
        for (size_t j = 0; j < target.size(); ++j) {
            const double d = test::ggxReference(cosTheta[j], alpha) - target[j];
            e += weight[j] * d * d;
        }
        return e;
    }

    // The best alpha by brute force: 2000 log-spaced candidates over [1e-3, 1], then the
    // neighbourhood of the best refined 200 times finer.
    double bestAlpha() const {
        double best = 1e-3, bestError = error(best);
        auto scan = [&](double lo, double hi, int count) {
            for (int i = 0; i <= count; ++i) {
                const double a = std::exp(std::log(lo) + (std::log(hi) - std::log(lo)) * i / count);
                const double e = error(a);
                if (e < bestError) best = a, bestError = e;
            }
        };
        scan(1e-3, 1., 2000);
        scan(best * 0.995, std::min(best * 1.005, 1.), 200);
        return best;
    }
};

// ggx-fit against the brute-force fit on 128 x 128 crops of two real maps (one per green
// convention and bit depth), levels 2, 4 and 6, for each material: a constant alpha, or a
// roughness map (`roughness` non-null, its alpha per texel). Sums of the texels' L2 errors.
struct AgainstBruteForce {
    double fit = 0., reference = 0., toksvig = 0., worst = 0.;
    double logPeak = 0.; // Sum of ln T(axis) / T(mean normal): where the filtered NDF is higher
    int texels = 0;
};

// The texel's filtered NDF T(h) = mean_i D_ai(h . n_i).
double filteredNdf(const std::vector<glm::dvec3>& normals, const std::vector<double>& alphas,
                   glm::dvec3 h) {
    double sum = 0.;
    for (size_t i = 0; i < normals.size(); ++i)
        sum += test::ggxReference(glm::dot(h, normals[i]), alphas[i]);
    return sum / double(normals.size());
}

AgainstBruteForce againstBruteForce(const std::filesystem::path& dir,
                                    const std::vector<float>& alphas,
                                    const std::function<float(int, int)>& roughness) {
    AgainstBruteForce out;
    for (const test::SharedMap& c : test::kReferenceMaps) {
        Result<Image> map = test::sharedMapCrop(dir, c, 256, 384, 128);
        EXPECT_TRUE(map.ok()) << map.error().message;
        if (!map.ok()) return out;
        const auto crop = std::make_shared<Image>(std::move(map.value()));
        const Pyramid pyramid = buildPyramid(crop);
        for (float a0 : alphas) {
            BakeOptions options = test::withBaseRoughness(a0);
            if (roughness) {
                auto r = std::make_shared<Image>(128, 128, 1);
                for (int y = 0; y < 128; ++y)
                    for (int x = 0; x < 128; ++x) r->at(x, y)[0] = roughness(x, y);
                options = {};
                options.roughnessMap = r;
            }
            const Bake bake = bakeGgxFit(pyramid, options);
            for (int level : {2, 4, 6}) {
                const int side = 128 >> level, step = std::max(1, side / 4);
                for (int y = 0; y < side; y += step)
                    for (int x = 0; x < side; x += step) {
                        const Footprint f = footprint(pyramid, level, x, y);
                        std::vector<glm::dvec3> normals;
                        std::vector<double> lobes;
                        glm::dvec3 sum(0.);
                        double alpha2 = 0.;
                        for (int by = f.y0; by < f.y1; ++by)
                            for (int bx = f.x0; bx < f.x1; ++bx) {
                                const float* p = crop->at(bx, by);
                                normals.push_back(glm::normalize(glm::dvec3(p[0], p[1], p[2])));
                                lobes.push_back(roughness ? roughness(bx, by) : a0);
                                sum += normals.back();
                                alpha2 += lobes.back() * lobes.back();
                            }
                        // The fit and the reference about the bake's axis (its normal plane);
                        // Toksvig's rule, with the footprint's mean alpha^2 (as toksvig bakes
                        // a roughness map), about the mean normal, its own.
                        const float* stored = bake.levels[size_t(level)][0]->at(x, y);
                        const glm::dvec3 axis(stored[0], stored[1], stored[2]);
                        const glm::dvec3 mean = glm::normalize(sum);
                        const DenseObjective objective(normals, lobes, axis);
                        const double reference = objective.error(objective.bestAlpha());
                        const double mine = objective.error(alphaAt(bake, level, x, y));
                        const double toksvig =
                            DenseObjective(normals, lobes, mean)
                                .error(varianceRoughness(
                                    float(glm::length(sum) / double(normals.size())),
                                    float(std::sqrt(alpha2 / double(normals.size())))));
                        out.logPeak += std::log(filteredNdf(normals, lobes, axis) /
                                                filteredNdf(normals, lobes, mean));
                        out.worst = std::max(out.worst, std::sqrt(mine / reference));
                        out.fit += std::sqrt(mine);
                        out.reference += std::sqrt(reference);
                        out.toksvig += std::sqrt(toksvig);
                        ++out.texels;
                    }
            }
            if (roughness) break; // the map is the material: one bake per map
        }
    }
    return out;
}

TEST(GgxFit, MatchesABruteForceFitOnRealMaps) {
    const std::filesystem::path dir = test::sharedNormalMaps();
    if (dir.empty()) GTEST_SKIP() << "../shared/data/normalmaps not found";
    const AgainstBruteForce r = againstBruteForce(dir, {0.05f, 0.1f, 0.3f}, nullptr);
    const double peak = std::exp(r.logPeak / r.texels);
    std::printf("ggx-fit on %d texels: L2 error / brute force's %.4f (worst %.4f), Toksvig's / "
                "brute force's %.4f; T(axis) / T(mean normal) %.4f\n",
                r.texels, r.fit / r.reference, r.worst, r.toksvig / r.reference, peak);
    EXPECT_LT(r.fit / r.reference, 1.01);
    EXPECT_LT(r.worst, 1.07);
    // The axis sits nearer the filtered NDF's peak than the mean normal does. (In L2 over the
    // sphere the lobe about it is about as far from T as Toksvig's about the mean normal: the
    // images are what it is for, docs/RESULTS.md.)
    EXPECT_GT(peak, 1.02);
    EXPECT_LT(r.fit, 1.05 * r.toksvig);
}

TEST(GgxFit, MatchesABruteForceFitWithARoughnessMap) {
    // A material of blocks (alpha 0.06 and 0.25, 16 texels wide) on a gradient: every footprint
    // above level 4 mixes lobes of different widths, which the tables' grid interpolates.
    const std::filesystem::path dir = test::sharedNormalMaps();
    if (dir.empty()) GTEST_SKIP() << "../shared/data/normalmaps not found";
    const auto roughness = [](int x, int y) {
        return ((x / 16 + y / 16) % 2 ? 0.06f : 0.25f) + 0.1f * float(x) / 127.f;
    };
    const AgainstBruteForce r = againstBruteForce(dir, {0.f}, roughness);
    std::printf("ggx-fit with a roughness map, %d texels: L2 error / brute force's %.4f (worst "
                "%.4f), Toksvig's / brute force's %.4f\n",
                r.texels, r.fit / r.reference, r.worst, r.toksvig / r.reference);
    // Measured 1.015 (worst 1.048), unchanged with twice the rings, a grid of tables twice as
    // fine or four times the reference's azimuths: what costs the 1.5% is not found.
    EXPECT_LT(r.fit / r.reference, 1.03);
    EXPECT_LT(r.worst, 1.07);
    EXPECT_LT(r.fit, 0.95 * r.toksvig);
}

TEST(GgxFit, AConstantRoughnessMapIsThatRoughness) {
    const Pyramid pyramid = buildPyramid(test::filledNormals(16, 16, [](int x, int y) {
        return glm::vec3(0.5f * std::sin(x), 0.3f * std::cos(y), 1.f);
    }));
    BakeOptions map;
    auto r = std::make_shared<Image>(16, 16, 1);
    std::fill(r->pixels.begin(), r->pixels.end(), 0.2f);
    map.roughnessMap = r;
    const Bake withMap = bakeGgxFit(pyramid, map),
               constant = bakeGgxFit(pyramid, test::withBaseRoughness(0.2f));
    EXPECT_EQ(withMap.parameters.at("roughness_map"), 1.0);
    // Within the search's resolution (its parabolic steps stop within about 3e-4 of alpha): the
    // map's path takes the mode's width from the RMS of its alphas, which differs from the
    // material's alpha in the last bits, and the search follows such changes by up to that much
    // (measured 1.7e-4 and, with the angles' division moved, 3.1e-4).
    for (size_t k = 0; k < constant.levels.size(); ++k)
        for (size_t i = 0; i < constant.levels[k][1]->pixels.size(); ++i)
            EXPECT_NEAR(withMap.levels[k][1]->pixels[i], constant.levels[k][1]->pixels[i],
                        5e-4f * constant.levels[k][1]->pixels[i])
                << "level " << k << " texel " << i;
    // Two materials side by side, one normal everywhere: each texel is its own alpha until a
    // footprint spans both.
    const Pyramid flat =
        buildPyramid(test::filledNormals(8, 8, [](int, int) { return glm::vec3(0, 0, 1); }));
    auto halves = std::make_shared<Image>(8, 8, 1);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) halves->at(x, y)[0] = x < 4 ? 0.1f : 0.3f;
    map.roughnessMap = halves;
    const Bake split = bakeGgxFit(flat, map);
    EXPECT_NEAR(alphaAt(split, 0, 1, 1), 0.1f, 1e-6f);
    EXPECT_NEAR(alphaAt(split, 1, 0, 0), 0.1f, 3e-3f * 0.1f);
    EXPECT_NEAR(alphaAt(split, 2, 1, 1), 0.3f, 3e-3f * 0.3f);
    const float mixed = alphaAt(split, 3, 0, 0); // half 0.1, half 0.3 about one normal
    EXPECT_GT(mixed, 0.1f);
    EXPECT_LT(mixed, 0.3f);
}

// ---- The shader ---------------------------------------------------------------------------

TEST(GgxFit, ShaderIsAnEnginesGgxLobeAtTheStoredRoughness) {
    const MethodShader* shader = findShader("ggx-fit");
    ASSERT_NE(shader, nullptr);
    EXPECT_EQ(shader->bake, Method::GgxFit);
    Material m;
    m.brdf = Brdf::Ggx;
    m.roughness = 0.1f;
    m.albedo = glm::vec3(0.f);
    m.specular = glm::vec3(1.f);
    RenderTextures textures;
    textures.bake.parameters["base_roughness"] = 0.1;
    ShaderSetup setup;
    ASSERT_TRUE(shader->prepare(m, textures, {}, setup));
    const float p[4] = {0.f, 0.f, 2.f, 0.3f}; // an unnormalised normal, alpha 0.3
    const glm::vec3 l = glm::normalize(glm::vec3(0.2f, 0.1f, 1.f)), v(0.f, 0.f, 1.f);
    Material widened = m;
    widened.roughness = 0.3f;
    const glm::vec3 expected = shadeNaive(widened, glm::vec3(0.f), glm::vec3(0.f, 0.f, 1.f), l, v);
    const glm::vec3 got = shader->shade(setup, m, p, glm::vec3(0.f), l, v);
    EXPECT_NEAR(got.x, expected.x, 1e-5f * expected.x);
    EXPECT_NEAR(shader->lobe(setup, m, p, glm::normalize(l + v)),
                float(test::ggxReference(glm::normalize(l + v).z, 0.3)), 1e-4f);
}

TEST(GgxFit, ShaderRefusesAnotherMaterial) {
    const MethodShader* shader = findShader("ggx-fit");
    ASSERT_NE(shader, nullptr);
    RenderTextures textures;
    textures.bake.parameters["base_roughness"] = 0.1;
    ShaderSetup setup;
    Material phong;
    phong.brdf = Brdf::BlinnPhong;
    phong.exponent = 64.f;
    const Status blinnPhong = shader->prepare(phong, textures, {}, setup);
    ASSERT_FALSE(blinnPhong);
    EXPECT_NE(blinnPhong.error.find("GGX"), std::string::npos) << blinnPhong.error;
    Material rougher;
    rougher.brdf = Brdf::Ggx;
    rougher.roughness = 0.3f;
    const Status other = shader->prepare(rougher, textures, {}, setup);
    ASSERT_FALSE(other);
    EXPECT_NE(other.error.find("--base-roughness 0.3"), std::string::npos) << other.error;
}

} // namespace
} // namespace ndfmip
