// bake --engine: each engine's normal map convention and packed material map, where the engine
// reads them (glTF: roughness in G), in the asked normal format, saying what they hold in their
// KTX2 key/value data (read back by ktx-parse too).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "methods/lean/engine_anisotropy.h"
#include "ndfmip/io.h"
#include "ndfmip/texture_container.h"
#include "test_support.h"

namespace ndfmip {
namespace {

std::string slurp(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), {});
}

// The first texel of level 0 of an uncompressed RGBA8 DDS with the DX10 header (4 + 124 + 20
// bytes).
std::array<int, 4> firstTexel(const std::string& dds) {
    const std::string bytes = slurp(dds);
    std::array<int, 4> out{};
    for (int c = 0; c < 4; ++c) out[c] = (unsigned char)bytes.at(148 + c);
    return out;
}

TEST(EngineCli, PackedMapsFollowEachEnginesLayout) {
    test::TempDir dir("ndfmip_engine");
    // Normals tilted in y (so the green convention shows) and a packed map: R occlusion 0.5,
    // G perceptual roughness 0.6, B metallic 0.25.
    Image normal(8, 8, 3), packed(8, 8, 4);
    for (size_t i = 0; i < 64; ++i) {
        normal.pixels[3 * i] = 0.5f, normal.pixels[3 * i + 1] = 0.8f,
                          normal.pixels[3 * i + 2] = 0.9f;
        packed.pixels[4 * i] = 0.5f, packed.pixels[4 * i + 1] = 0.6f,
                          packed.pixels[4 * i + 2] = 0.25f;
    }
    ASSERT_TRUE(savePng(dir.file("n.png"), normal, 16));
    ASSERT_TRUE(savePng(dir.file("m.png"), packed, 16));
    const std::string common =
        " --roughness-map " + test::shellArg(dir.file("m.png")) +
        " --roughness-channel g --metallic-channel b --occlusion-channel r --export dds -q -o ";
    std::string output;
    for (const char* engine : {"unity", "gltf", "unreal"}) {
        const std::string out = dir.file(engine);
        ASSERT_EQ(test::runCli("bake " + test::shellArg(dir.file("n.png")) + " --engine " + engine +
                                   common + test::shellArg(out),
                               &output),
                  0)
            << output;
    }
    // Unity's mask map: metallic, occlusion, detail mask 1, smoothness 1 - 0.6 (flat: no widening).
    EXPECT_EQ(firstTexel(dir.file("unity") + "/dds/unity_mask_map.dds"),
              (std::array<int, 4>{64, 128, 255, 102}));
    // glTF's ORM: occlusion, roughness, metallic.
    EXPECT_EQ(firstTexel(dir.file("gltf") + "/dds/gltf_occlusion_roughness_metallic.dds"),
              (std::array<int, 4>{128, 153, 64, 255}));
    // Unreal flips green: its BC5 normal map differs from glTF's for normals tilted in y.
    EXPECT_NE(slurp(dir.file("unreal") + "/dds/unreal_normal.dds"),
              slurp(dir.file("gltf") + "/dds/gltf_normal.dds"));
    test::expectCliRefuses("bake " + test::shellArg(dir.file("n.png")) + " --engine cryengine -o " +
                               test::shellArg(dir.file("x")),
                           {"--engine", "cryengine", "unity"});
    test::expectCliRefuses("bake " + test::shellArg(dir.file("n.png")) +
                               " --engine gltf --metallic-channel b -o " +
                               test::shellArg(dir.file("x")),
                           {"--metallic-channel", "--roughness-map"});
}

uint32_t u32(const std::string& bytes, size_t at) {
    uint32_t v = 0;
    std::memcpy(&v, bytes.data() + at, 4);
    return v;
}

// Level k of a KTX2 file without supercompression, where its level index puts it.
std::string ktx2Level(const std::string& file, uint32_t k) {
    uint64_t offset = 0, length = 0;
    std::memcpy(&offset, file.data() + 80 + 24 * k, 8);
    std::memcpy(&length, file.data() + 88 + 24 * k, 8);
    return file.substr(offset, length);
}

// The "ndfmip" key of a KTX2 file, parsed.
nlohmann::json aboutOf(const std::string& file) {
    Result<Ktx2KeyValues> kv = readKtx2KeyValues(file);
    if (!kv || !kv->count("ndfmip")) return nullptr;
    return nlohmann::json::parse(kv->at("ndfmip"), nullptr, false);
}

// A 16-bit PNG of normals in columns: n on even columns, n with x negated on odd ones.
void saveColumns(const std::string& path, float x, float y, float z) {
    Image normal(8, 8, 3);
    for (int row = 0; row < 8; ++row)
        for (int col = 0; col < 8; ++col) {
            float* p = normal.at(col, row);
            p[0] = 0.5f * ((col % 2 ? -x : x) + 1.f), p[1] = 0.5f * (y + 1.f),
            p[2] = 0.5f * (z + 1.f);
        }
    ASSERT_TRUE(savePng(path, normal, 16));
}

// `bake MAP --engine ENGINE --method lean --base-roughness 0.2 --export ktx2 -q -o OUT`: its
// exit status, with stdout and stderr in `output`.
int bakeLeanFor(const std::string& map, const std::string& engine, const std::string& out,
                std::string* output) {
    return test::runCli("bake " + test::shellArg(map) + " --engine " + engine +
                            " --method lean --base-roughness 0.2 --export ktx2 -q -o " +
                            test::shellArg(out),
                        output);
}

// Normals at +-theta (sin theta = 0.6) in alternate columns: level 0 is unit length, every texel
// of level k >= 1 averages as many of each, |Na| = cos theta = 0.8. With --base-roughness 0.2
// Toksvig's alpha is 0.2 at level 0 and sqrt(0.2^2 + 2 (1 - 0.8)/0.8) above it; the glTF-layout
// maps (gltf, three, bevy, filament) hold sqrt(alpha) in G, where the engines read roughness,
// with R occlusion 1, B metallic 0, A 1.
TEST(EngineCli, GltfLayoutPackedMapHoldsThePerceptualRoughnessInG) {
    test::TempDir dir("ndfmip_engine_g");
    saveColumns(dir.file("n.png"), 0.6f, 0.f, 0.8f);
    for (const char* engine : {"gltf", "three", "bevy", "filament"}) {
        const std::string out = dir.file(engine);
        std::string output;
        ASSERT_EQ(test::runCli("bake " + test::shellArg(dir.file("n.png")) + " --engine " + engine +
                                   " --base-roughness 0.2 --export ktx2 -q -o " +
                                   test::shellArg(out),
                               &output),
                  0)
            << output;
        const std::string file =
            slurp(out + "/ktx2/" + engine + "_occlusion_roughness_metallic.ktx2");
        ASSERT_GT(file.size(), 80u);
        EXPECT_EQ(u32(file, 12), 37u); // VK_FORMAT_R8G8B8A8_UNORM
        ASSERT_EQ(u32(file, 40), 4u);  // 8, 4, 2, 1
        for (uint32_t k = 0; k < 4; ++k) {
            const double alpha = k == 0 ? 0.2 : std::sqrt(0.04 + 2.0 * 0.2 / 0.8);
            const std::string level = ktx2Level(file, k);
            ASSERT_EQ(level.size(), size_t(4 * (8 >> k) * (8 >> k)));
            for (size_t i = 0; i < level.size(); i += 4) {
                EXPECT_EQ((unsigned char)level[i], 255) << engine << " level " << k;
                EXPECT_NEAR((unsigned char)level[i + 1], 255.0 * std::sqrt(alpha), 0.6)
                    << engine << " level " << k;
                EXPECT_EQ((unsigned char)level[i + 2], 0) << engine << " level " << k;
                EXPECT_EQ((unsigned char)level[i + 3], 255) << engine << " level " << k;
            }
        }
        const nlohmann::json about = aboutOf(file);
        ASSERT_TRUE(about.is_object()) << engine;
        EXPECT_EQ(about["content"], "material");
        EXPECT_EQ(about["channels"], (nlohmann::json{{"r", "occlusion"},
                                                     {"g", "roughness: perceptual, sqrt(alpha)"},
                                                     {"b", "metallic"},
                                                     {"a", "1"}}));
    }
}

// --method lean: one anisotropic GGX lobe per texel from the slope moments, as
// KHR_materials_anisotropy stores it. Columns at +-theta with sin theta = 0.28 (slopes +-7/24
// along x): level 0 has no spread, every coarser texel a slope variance of (7/24)^2 along x
// only, so with --base-roughness 0.2 alpha_b = 0.2 (G = sqrt 0.2 in the packed map at every
// level) and alpha_t^2 = 0.04 + 2 (7/24)^2 along x: direction (1, 0), strength s^2 = (alpha_t -
// alpha_b) / (1 - alpha_b).
TEST(EngineCli, LeanBakeWritesKhrMaterialsAnisotropyFiles) {
    test::TempDir dir("ndfmip_engine_lean");
    saveColumns(dir.file("n.png"), 0.28f, 0.f, 0.96f);
    for (const char* engine : {"gltf", "three", "bevy", "filament"}) {
        const std::string out = dir.file(engine);
        std::string output;
        ASSERT_EQ(bakeLeanFor(dir.file("n.png"), engine, out, &output), 0) << output;
        const std::string anisotropy = slurp(out + "/ktx2/" + engine + "_anisotropy.ktx2");
        const std::string packed =
            slurp(out + "/ktx2/" + engine + "_occlusion_roughness_metallic.ktx2");
        ASSERT_GT(anisotropy.size(), 80u);
        ASSERT_GT(packed.size(), 80u);
        EXPECT_EQ(u32(anisotropy, 12), 37u); // VK_FORMAT_R8G8B8A8_UNORM
        ASSERT_EQ(u32(anisotropy, 40), 4u);
        const double slope = 7.0 / 24.0;
        const double alphaT = std::sqrt(0.04 + 2.0 * slope * slope);
        const double strength = std::sqrt((alphaT - 0.2) / 0.8);
        for (uint32_t k = 0; k < 4; ++k) {
            const std::string a = ktx2Level(anisotropy, k), g = ktx2Level(packed, k);
            ASSERT_EQ(a.size(), size_t(4 * (8 >> k) * (8 >> k)));
            for (size_t i = 0; i < a.size(); i += 4) {
                EXPECT_EQ((unsigned char)a[i], 255) << engine << " level " << k;
                EXPECT_NEAR((unsigned char)a[i + 1], 127.5, 0.6) << engine << " level " << k;
                EXPECT_NEAR((unsigned char)a[i + 2], k == 0 ? 0.0 : 255.0 * strength, 0.6)
                    << engine << " level " << k;
                EXPECT_NEAR((unsigned char)g[i + 1], 255.0 * std::sqrt(0.2), 0.6)
                    << engine << " level " << k;
            }
        }
        EXPECT_EQ(aboutOf(anisotropy)["content"], "KHR_materials_anisotropy anisotropyTexture");
    }
}

// The same stripes for the engines with their own anisotropy inputs: Unreal's and Unity HDRP's
// Kulla parametrisation (alpha_t,b = alpha (1 +- k)), Godot's Burley one (aspect sqrt(1 - 0.9 k)),
// each texel against the closed form of the lobe alpha_t = sqrt(0.2^2 + 2 s^2), alpha_b = 0.2
// along x (level 0: one normal a texel, isotropic).
TEST(EngineCli, LeanBakeWritesEachEnginesOwnAnisotropyInputs) {
    test::TempDir dir("ndfmip_engine_lean_own");
    saveColumns(dir.file("n.png"), 0.28f, 0.f, 0.96f);
    const double slope = 7.0 / 24.0, alphaB = 0.2;
    const double alphaT = std::sqrt(alphaB * alphaB + 2.0 * slope * slope);
    const double kulla = (alphaT - alphaB) / (alphaT + alphaB);
    const double burley = std::min((1.0 - alphaB / alphaT) / 0.9, 1.0);
    struct Case {
        const char* engine;
        const char* packedFile;
        int roughnessChannel; // in the packed map
        bool smoothness;
        double roughness; // perceptual, levels >= 1
        double isotropic; // level 0's
    };
    for (const Case& c :
         {Case{"unreal", "occlusion_roughness_metallic", 1, false,
               std::sqrt(0.5 * (alphaT + alphaB)), std::sqrt(alphaB)},
          Case{"unity", "mask_map", 3, true, std::sqrt(0.5 * (alphaT + alphaB)), std::sqrt(alphaB)},
          Case{"godot", "orm", 1, false, std::pow(alphaT * alphaB, 0.25), std::sqrt(alphaB)}}) {
        const std::string out = dir.file(c.engine), engine = c.engine;
        std::string output;
        ASSERT_EQ(bakeLeanFor(dir.file("n.png"), engine, out, &output), 0) << output;
        const std::string anisotropy = slurp(out + "/ktx2/" + engine + "_anisotropy.ktx2");
        const std::string packed = slurp(out + "/ktx2/" + engine + "_" + c.packedFile + ".ktx2");
        const std::string tangent = slurp(out + "/ktx2/" + engine + "_tangent.ktx2");
        ASSERT_GT(anisotropy.size(), 80u);
        ASSERT_GT(packed.size(), 80u);
        EXPECT_EQ(tangent.empty(), engine != "unity") << engine;
        for (uint32_t k = 0; k < 4; ++k) {
            const std::string a = ktx2Level(anisotropy, k), g = ktx2Level(packed, k);
            const double k8 = 255.0 * (k == 0 ? 0.0 : engine == "godot" ? burley : kulla);
            const double r8 = 255.0 * (k == 0 ? c.isotropic : c.roughness);
            ASSERT_EQ(a.size(), size_t(4 * (8 >> k) * (8 >> k)));
            for (size_t i = 0; i < a.size(); i += 4) {
                const auto at = [&](const std::string& t, size_t channel) {
                    return double((unsigned char)t[i + channel]);
                };
                EXPECT_NEAR(at(g, size_t(c.roughnessChannel)), c.smoothness ? 255.0 - r8 : r8, 0.6)
                    << engine << " level " << k;
                if (engine == "unity") {
                    EXPECT_NEAR(at(a, 0), k8, 0.6) << "level " << k; // R = G = B = k
                    const std::string t = ktx2Level(tangent, k);
                    EXPECT_EQ(at(t, 0), 255.0); // the x axis, as a normal map texel
                    EXPECT_NEAR(at(t, 1), 127.5, 0.6);
                    EXPECT_NEAR(at(t, 2), 127.5, 0.6);
                } else {
                    EXPECT_EQ(at(a, 0), 255.0) << engine << " level " << k;
                    EXPECT_NEAR(at(a, 1), 127.5, 0.6) << engine << " level " << k;
                    EXPECT_NEAR(at(a, engine == "godot" ? 3 : 2), k8, 0.6)
                        << engine << " level " << k;
                }
            }
        }
    }
    EXPECT_EQ(aboutOf(slurp(dir.file("godot") + "/ktx2/godot_anisotropy.ktx2"))["content"],
              "Godot anisotropy flowmap");
}

// ggx-aniso's fitted lobe in each engine's anisotropy inputs: every texel of levels 0-3 of the
// files against the lobe of the bake's own alpha_moments and normal planes (written beside them as
// EXR; anisotropicLobeOfGgxAniso), in
// KHR's, Kulla's (Unreal) and Burley's (Godot) parametrisation; the axis on x from level 1 on.
TEST(EngineCli, GgxAnisoBakeWritesItsFittedLobeInEachEnginesInputs) {
    test::TempDir dir("ndfmip_engine_ggx_aniso");
    saveColumns(dir.file("n.png"), 0.28f, 0.f, 0.96f);
    for (const std::string engine : {"gltf", "unreal", "godot"}) {
        const std::string out = dir.file(engine);
        std::string output;
        ASSERT_EQ(test::runCli("bake " + test::shellArg(dir.file("n.png")) + " --engine " + engine +
                                   " --method ggx-aniso --base-roughness 0.2 --export ktx2,exr "
                                   "-q -o " +
                                   test::shellArg(out),
                               &output),
                  0)
            << output;
        const std::string anisotropy = slurp(out + "/ktx2/" + engine + "_anisotropy.ktx2");
        const std::string packed =
            slurp(out + "/ktx2/" + engine +
                  (engine == "godot" ? "_orm" : "_occlusion_roughness_metallic") + ".ktx2");
        ASSERT_GT(anisotropy.size(), 80u);
        ASSERT_GT(packed.size(), 80u);
        for (uint32_t k = 0; k < 4; ++k) {
            Result<SourceImage> moments =
                loadImage(out + "/alpha_moments_L" + std::to_string(k) + ".exr");
            ASSERT_TRUE(moments) << moments.error().message;
            Result<SourceImage> normal = loadImage(out + "/normal_L" + std::to_string(k) + ".exr");
            ASSERT_TRUE(normal) << normal.error().message;
            const std::string a = ktx2Level(anisotropy, k), g = ktx2Level(packed, k);
            ASSERT_EQ(a.size(), size_t(4 * (8 >> k) * (8 >> k)));
            for (size_t i = 0; i < a.size() / 4; ++i) {
                const AnisotropicLobe lobe = anisotropicLobeOfGgxAniso(
                    &moments->image.pixels[size_t(moments->image.channels) * i],
                    &normal->image.pixels[size_t(normal->image.channels) * i]);
                const auto at = [&](const std::string& s, size_t channel) {
                    return double((unsigned char)s[4 * i + channel]);
                };
                double strength = 0.0, roughness = 0.0;
                if (engine == "gltf") {
                    const KhrAnisotropy khr = khrAnisotropy(lobe);
                    strength = khr.strength, roughness = khr.roughness;
                } else {
                    const RoughnessAnisotropy r =
                        engine == "godot" ? burleyAnisotropy(lobe) : kullaAnisotropy(lobe);
                    strength = r.anisotropy, roughness = r.roughness;
                }
                EXPECT_NEAR(at(a, engine == "godot" ? 3 : 2), 255.0 * strength, 0.6)
                    << engine << " level " << k;
                EXPECT_NEAR(at(g, 1), 255.0 * roughness, 0.6) << engine << " level " << k;
                if (k > 0) {
                    EXPECT_EQ(at(a, 0), 255.0) << engine << " level " << k;
                    EXPECT_NEAR(at(a, 1), 127.5, 0.6) << engine << " level " << k;
                    EXPECT_GT(strength, 0.3) << engine << " level " << k;
                }
            }
        }
    }
}

// test::blocksAcrossTheVertical: level 1's lobes point near the y axis, each neighbour on the
// other side of it. Each engine's direction texture signs them alike (coherentDirections), so
// the sampler's blend of two neighbours turns between them; stored with x >= 0 every neighbour
// would point against the texel (dot -0.96), and their blend would read along x.
TEST(EngineCli, GgxAnisoDirectionsAgreeBetweenNeighboursAcrossTheVertical) {
    test::TempDir dir("ndfmip_engine_ggx_aniso_signs");
    ASSERT_TRUE(
        savePng(dir.file("n.png"), test::encodedNormals(test::blocksAcrossTheVertical(16)), 16));
    for (const std::string engine : {"gltf", "unreal", "godot"}) {
        const std::string out = dir.file(engine);
        std::string output;
        ASSERT_EQ(test::runCli("bake " + test::shellArg(dir.file("n.png")) + " --engine " + engine +
                                   " --method ggx-aniso --base-roughness 0.1 --export ktx2 -q -o " +
                                   test::shellArg(out),
                               &output),
                  0)
            << output;
        const std::string a = ktx2Level(slurp(out + "/ktx2/" + engine + "_anisotropy.ktx2"), 1);
        ASSERT_EQ(a.size(), size_t(4 * 8 * 8));
        auto direction = [&](int x, int y) {
            const size_t i = 4 * size_t(y * 8 + x);
            return glm::normalize(glm::vec2(2.f * float((unsigned char)a[i]) / 255.f - 1.f,
                                            2.f * float((unsigned char)a[i + 1]) / 255.f - 1.f));
        };
        for (int y = 0; y < 8; ++y)
            for (int x = 0; x < 8; ++x) {
                EXPECT_GT(std::abs(direction(x, y).y), 0.99f) << engine << " " << x << "," << y;
                if (x + 1 < 8) {
                    EXPECT_GT(glm::dot(direction(x, y), direction(x + 1, y)), 0.95f)
                        << engine << " " << x << "," << y;
                }
                if (y + 1 < 8) {
                    EXPECT_GT(glm::dot(direction(x, y), direction(x, y + 1)), 0.95f)
                        << engine << " " << x << "," << y;
                }
            }
    }
}

// The stripes turned 90 degrees: the direction is the y axis, and Unreal's texture holds it
// in the frame of its normal maps (green down), Godot's in the +Y-up frame.
TEST(EngineCli, LeanBakeDirectionFollowsEachEnginesGreenConvention) {
    test::TempDir dir("ndfmip_engine_lean_turned");
    saveColumns(dir.file("n.png"), 0.28f, 0.f, 0.96f);
    // Rows instead of columns: the same map transposed, normals turned to the y axis.
    Result<SourceImage> columns = loadImage(dir.file("n.png"));
    ASSERT_TRUE(columns);
    Image rows(columns->image.height, columns->image.width, 3);
    for (int y = 0; y < rows.height; ++y)
        for (int x = 0; x < rows.width; ++x) {
            const float* n = columns->image.at(y, x);
            rows.at(x, y)[0] = n[1];
            rows.at(x, y)[1] = n[0];
            rows.at(x, y)[2] = n[2];
        }
    ASSERT_TRUE(savePng(dir.file("rows.png"), rows, 16));
    for (const char* engine : {"unreal", "godot"}) {
        const std::string out = dir.file(engine);
        std::string output;
        ASSERT_EQ(bakeLeanFor(dir.file("rows.png"), engine, out, &output), 0) << output;
        const std::string a =
            ktx2Level(slurp(out + "/ktx2/" + std::string(engine) + "_anisotropy.ktx2"), 1);
        ASSERT_FALSE(a.empty());
        // x = 0 (127.5); y = +-1, which an axis may take either sign of: 0 or 255, flipped in
        // Unreal's frame against the +Y-up frame's.
        EXPECT_NEAR((unsigned char)a[0], 127.5, 0.6) << engine;
        EXPECT_TRUE((unsigned char)a[1] == 0 || (unsigned char)a[1] == 255) << engine;
    }
    const std::string unreal =
        ktx2Level(slurp(dir.file("unreal") + "/ktx2/unreal_anisotropy.ktx2"), 1);
    const std::string godot =
        ktx2Level(slurp(dir.file("godot") + "/ktx2/godot_anisotropy.ktx2"), 1);
    EXPECT_EQ(int((unsigned char)unreal[1]) + int((unsigned char)godot[1]), 255);
}

// Runs the CLI with stdout and stderr kept apart; returns the status.
int runApart(const test::TempDir& dir, const std::string& args, std::string* err) {
    const std::string errFile = dir.file("stderr.txt");
    const int status = std::system((std::string("\"") + NDFMIP_CLI_PATH + "\" " + args +
                                    " > /dev/null 2> " + test::shellArg(errFile))
                                       .c_str());
    *err = slurp(errFile);
    return status;
}

// --engine without the material's roughness: level 0 would be ~0, a mirror; one line on stderr
// says so. With --base-roughness or --roughness-map, or with -q, nothing.
TEST(EngineCli, EngineWithoutMaterialRoughnessWarns) {
    test::TempDir dir("ndfmip_engine_warn");
    saveColumns(dir.file("n.png"), 0.6f, 0.f, 0.8f);
    const std::string bake = "bake " + test::shellArg(dir.file("n.png")) + " --engine three -o ";
    std::string err;
    ASSERT_EQ(runApart(dir, bake + test::shellArg(dir.file("a")), &err), 0) << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
    for (const char* word :
         {"warning", "--engine three", "--base-roughness", "--roughness-map", "mirror"})
        EXPECT_NE(err.find(word), std::string::npos) << word << " in " << err;
    ASSERT_EQ(runApart(dir, bake + test::shellArg(dir.file("b")) + " --base-roughness 0.3", &err),
              0)
        << err;
    EXPECT_EQ(err, "");
    ASSERT_EQ(runApart(dir, bake + test::shellArg(dir.file("c")) + " -q", &err), 0) << err;
    EXPECT_EQ(err, "");
    ASSERT_EQ(runApart(dir,
                       "bake " + test::shellArg(dir.file("n.png")) + " --export ktx2 -o " +
                           test::shellArg(dir.file("d")),
                       &err),
              0)
        << err;
    EXPECT_EQ(err, "");
}

// The npm package ktx-parse's ES module, or "" where node or the package is missing.
std::string ktxParseModule() {
    const char* modules = std::getenv("NDFMIP_NODE_MODULES");
    const std::string path =
        modules ? modules : std::string(NDFMIP_SOURCE_DIR) + "/.npm/node_modules";
    if (!std::filesystem::exists("/usr/bin/node")) return "";
    for (const char* candidate :
         {"/ktx-parse/dist/ktx-parse.modern.js", "/ktx-parse/dist/index.mjs"})
        if (std::filesystem::exists(path + candidate)) return path + candidate;
    return "";
}

// The key/value data of a KTX2 file as ktx-parse reads it (values as text, trailing NUL dropped).
nlohmann::json ktxParseKeys(const test::TempDir& dir, const std::string& module,
                            const std::string& file) {
    const std::string script = dir.file("keys.mjs"), out = dir.file("keys.json");
    std::ofstream(script) << "import { read } from '" << module << "';\n"
                          << "import { readFileSync } from 'fs';\n"
                          << "const c = read(new Uint8Array(readFileSync(process.argv[2])));\n"
                          << "const kv = {};\n"
                          << "for (const [k, v] of Object.entries(c.keyValue))\n"
                          << "  kv[k] = typeof v === 'string' ? v : new "
                             "TextDecoder().decode(v).replace(/\\0$/, '');\n"
                          << "console.log(JSON.stringify(kv));\n";
    if (std::system(("node " + test::shellArg(script) + " " + test::shellArg(file) + " > " +
                     test::shellArg(out) + " 2>&1")
                        .c_str()) != 0)
        return "node failed: " + slurp(out);
    return nlohmann::json::parse(slurp(out), nullptr, false);
}

// --normal-format reaches the engine's normal map: its VkFormat, its texels (y flipped for
// Unreal's -Y), its KTXswizzle, and an ndfmip key saying the green convention; the plain
// normal file says the source's (+Y here). The roughness file says it is one channel of
// sqrt(alpha).
TEST(EngineCli, EngineNormalMapTakesTheNormalFormatAndSaysItsConvention) {
    test::TempDir dir("ndfmip_engine_format");
    saveColumns(dir.file("n.png"), 0.f, 0.6f, 0.8f); // tilted in y: (0, 0.6, 0.8) everywhere
    const std::string module = ktxParseModule();
    struct Case {
        const char* format;
        uint32_t vkFormat;
        const char* swizzle;
    };
    for (const Case& c :
         {Case{"bc5", 141, "rg01"}, Case{"rg16", 77, "rg01"}, Case{"rgba8", 37, "rgb1"}}) {
        const std::string out = dir.file(c.format);
        std::string output;
        ASSERT_EQ(test::runCli("bake " + test::shellArg(dir.file("n.png")) +
                                   " --engine unreal --normal-format " + c.format +
                                   " --base-roughness 0.2 --export ktx2 -q -o " +
                                   test::shellArg(out),
                               &output),
                  0)
            << output;
        const std::string engineFile = out + "/ktx2/unreal_normal.ktx2";
        const std::string plainFile = out + "/ktx2/normal_" + c.format + ".ktx2";
        const std::string engine = slurp(engineFile), plain = slurp(plainFile);
        ASSERT_GT(engine.size(), 80u) << c.format;
        EXPECT_EQ(u32(engine, 12), c.vkFormat) << c.format;
        EXPECT_EQ(u32(plain, 12), c.vkFormat) << c.format;
        // Level 0's first texel: x 0 -> 0.5, y -0.6 (Unreal's -Y) -> 0.2, z 0.8 -> 0.9.
        const std::string level0 = ktx2Level(engine, 0);
        if (std::string(c.format) == "rgba8") {
            EXPECT_EQ((unsigned char)level0[0], 128);
            EXPECT_NEAR((unsigned char)level0[1], 0.2 * 255, 1.0);
            EXPECT_NEAR((unsigned char)level0[2], 0.9 * 255, 1.0);
            EXPECT_EQ((unsigned char)level0[3], 255);
        } else if (std::string(c.format) == "rg16") {
            uint16_t xy[2];
            std::memcpy(xy, level0.data(), 4);
            EXPECT_NEAR(xy[0], 32768, 1.0);
            EXPECT_NEAR(xy[1], 0.2 * 65535, 2.0);
        }
        Result<Ktx2KeyValues> kv = readKtx2KeyValues(engine);
        ASSERT_TRUE(kv) << kv.error().message;
        EXPECT_EQ(kv->at("KTXswizzle"), c.swizzle);
        EXPECT_EQ(kv->at("KTXwriter").rfind("ndfmip ", 0), 0u);
        const nlohmann::json about = aboutOf(engine), plainAbout = aboutOf(plain);
        EXPECT_EQ(about["content"], "normal");
        EXPECT_EQ(about["encoding"], "(n+1)/2");
        EXPECT_EQ(about["green"], "down");
        EXPECT_EQ(plainAbout["green"], "up");
        EXPECT_EQ(about["channels"].size(), std::string(c.format) == "rgba8" ? 4u : 2u);
        const nlohmann::json rough = aboutOf(slurp(out + "/ktx2/roughness_bc4.ktx2"));
        EXPECT_EQ(rough["content"], "roughness");
        EXPECT_EQ(rough["encoding"], "sqrt(alpha)");
        EXPECT_EQ(rough["channels"].size(), 1u);
        EXPECT_FALSE(
            readKtx2KeyValues(slurp(out + "/ktx2/roughness_bc4.ktx2"))->count("KTXswizzle"));
        if (module.empty()) continue;
        // ktx-parse, a reader ndfmip did not write, reads the same keys.
        const nlohmann::json parsed = ktxParseKeys(dir, module, engineFile);
        ASSERT_TRUE(parsed.is_object()) << parsed.dump();
        EXPECT_EQ(parsed.size(), 3u) << parsed.dump();
        EXPECT_EQ(parsed["KTXswizzle"], c.swizzle);
        EXPECT_EQ(parsed["KTXwriter"], kv->at("KTXwriter"));
        EXPECT_EQ(parsed["ndfmip"], kv->at("ndfmip"));
    }
    if (module.empty())
        GTEST_SKIP() << "node and the npm package ktx-parse not found: ndfmip's own reader only";
}

} // namespace
} // namespace ndfmip
