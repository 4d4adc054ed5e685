// The steps of `ndfmip eval` one by one (report/evaluation_steps.h): the plan the options
// resolve to, the method-row grammar, the view of a footprint, one setting's rows on a map whose
// truth is known, and the report's document.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "ndfmip/io.h"
#include "report/evaluation_steps.h"
#include "test_support.h"

namespace ndfmip {
namespace {

using evaluation::Problem;

// The message of the Problem `f` throws, or "" when it throws none.
template <class F> std::string problemOf(F f) {
    try {
        f();
    } catch (const Problem& p) {
        return p.message;
    }
    return "";
}

EvalOptions optionsFor(std::vector<std::string> methods) {
    EvalOptions o;
    o.maps = {"unused.png"};
    o.methods = std::move(methods);
    return o;
}

TEST(EvaluationPlan, EngineViewIsOneTapLodZeroParametersBlendedAndCoherentVmf) {
    EvalOptions o = optionsFor({"vmf:4", "toksvig"});
    o.view = "engine";
    const evaluation::Plan plan = evaluation::planEvaluation(o);
    EXPECT_EQ(plan.filtering.taps, 1);
    EXPECT_EQ(plan.filtering.lodBias, 0.f);
    EXPECT_EQ(plan.filtering.shadeFilter, ShadeFilter::Parameter);
    ASSERT_EQ(plan.specs.size(), 2u);
    EXPECT_EQ(plan.specs[0].options.parameters.at("coherent"), kEngineViewCoherence);
    EXPECT_EQ(plan.specs[0].options.parameters.at("lobes"), 4.0);
    EXPECT_EQ(plan.specs[1].options.parameters.count("coherent"), 0u);
    // The lab view keeps the renderer's rule and shades each texel.
    const evaluation::Plan lab = evaluation::planEvaluation(optionsFor({"vmf:4"}));
    EXPECT_EQ(lab.filtering.taps, RenderOptions{}.taps);
    EXPECT_EQ(lab.filtering.shadeFilter, ShadeFilter::Texel);
    EXPECT_EQ(lab.specs[0].options.parameters.count("coherent"), 0u);
    EXPECT_EQ(lab.shift, glm::vec2(0.31f, 0.17f));
}

TEST(EvaluationPlan, OptionsGivenBesideTheViewWin) {
    EvalOptions o = optionsFor({"vmf:2"});
    o.view = "engine";
    o.taps = 3;
    o.coherence = 0.f;
    const evaluation::Plan plan = evaluation::planEvaluation(o);
    EXPECT_EQ(plan.filtering.taps, 3);
    EXPECT_EQ(plan.specs[0].options.parameters.count("coherent"), 0u);
}

TEST(EvaluationPlan, AlignedIsOnTheGridAndRefusesFootprintsThatAreNoLevel) {
    EvalOptions o = optionsFor({"naive"});
    o.aligned = true;
    o.footprints = {1, 4, 16};
    const evaluation::Plan plan = evaluation::planEvaluation(o);
    EXPECT_EQ(plan.shift, glm::vec2(0.f));
    EXPECT_EQ(plan.filtering.taps, 1);
    EXPECT_EQ(plan.options.view, "aligned");
    o.footprints = {4, 6};
    EXPECT_EQ(problemOf([&] { evaluation::planEvaluation(o); }),
              "--aligned: footprint 6 is not a power of two (one texel of a level)");
}

TEST(EvaluationPlan, RefusesWhatNoRunCanDo) {
    EvalOptions variant = optionsFor({"toksvig@filament"});
    EXPECT_NE(problemOf([&] {
                  evaluation::planEvaluation(variant);
              }).find("a variant after @ applies under --environment only"),
              std::string::npos);
    EXPECT_NE(problemOf([&] {
                  evaluation::planEvaluation(optionsFor({"bogus"}));
              }).find("unknown method 'bogus'"),
              std::string::npos);
    EvalOptions view = optionsFor({"naive"});
    view.view = "orbit";
    EXPECT_EQ(problemOf([&] { evaluation::planEvaluation(view); }),
              "--view 'orbit': expected lab, engine or aligned");
    EvalOptions brdf = optionsFor({"naive"});
    brdf.brdfs = {"phong"};
    EXPECT_NE(problemOf([&] { evaluation::planEvaluation(brdf); }).find("unknown BRDF 'phong'"),
              std::string::npos);
    EvalOptions none = optionsFor({"naive"});
    none.maps.clear();
    EXPECT_EQ(problemOf([&] { evaluation::planEvaluation(none); }), "no maps to evaluate");
}

TEST(EvaluationPlan, SettingsAreEveryBrdfWithItsValues) {
    EvalOptions o = optionsFor({"naive"});
    o.brdfs = {"lambert", "blinnphong", "ggx"};
    o.exponents = {32.f, 128.f};
    o.roughness = {0.1f};
    const evaluation::Plan plan = evaluation::planEvaluation(o);
    std::vector<std::string> labels;
    for (const evaluation::Setting& s : plan.settings) labels.push_back(s.label());
    EXPECT_EQ(labels, (std::vector<std::string>{"lambert", "blinnphong s=32", "blinnphong s=128",
                                                "ggx alpha=0.1"}));
    EXPECT_EQ(plan.settings[0].material.albedo, glm::vec3(1.f));
    EXPECT_EQ(plan.settings[0].material.specular, glm::vec3(0.f));
    EXPECT_EQ(plan.settings[3].material.roughness, 0.1f);
    EXPECT_EQ(plan.settings[3].material.specular, glm::vec3(1.f));
}

TEST(EvaluationMethodSpec, TheRowGrammar) {
    const evaluation::MethodSpec vmf = evaluation::methodSpec("vmf:6:3");
    EXPECT_EQ(vmf.method, Method::Vmf);
    EXPECT_EQ(vmf.render, "vmf");
    EXPECT_EQ(vmf.options.parameters.at("lobes"), 6.0);
    EXPECT_EQ(vmf.options.parameters.at("lobe_budget"), 3.0);
    const evaluation::MethodSpec sh = evaluation::methodSpec("sh:4");
    EXPECT_EQ(sh.method, Method::Sh);
    EXPECT_TRUE(sh.options.parameters.count("order"));
    const evaluation::MethodSpec lod = evaluation::methodSpec("toksvig@filament");
    EXPECT_EQ(lod.label, "toksvig@filament");
    EXPECT_EQ(lod.bakeKey, "toksvig");
    ASSERT_TRUE(lod.lod.has_value());
    EXPECT_EQ(*lod.lod, EnvironmentLod::Filament);
    const evaluation::MethodSpec way = evaluation::methodSpec("vmf:2@sh");
    ASSERT_TRUE(way.way.has_value());
    EXPECT_EQ(way.bakeKey, "vmf:2");
    // A second shader of a bake is a row over its own bake; exact bakes nothing.
    const evaluation::MethodSpec sggx = evaluation::methodSpec("sggx");
    EXPECT_EQ(sggx.render, "sggx");
    EXPECT_EQ(sggx.method, Method::Lean);
    EXPECT_FALSE(evaluation::methodSpec("exact").baked);
    EXPECT_NE(problemOf([] { evaluation::methodSpec("exact@sh"); }).find("@log2sigma"),
              std::string::npos);
}

// A flat map: every texel's normal is z, so every method, the floor and the truth agree.
struct FlatMap {
    test::TempDir dir{"evaluation_steps"};
    std::string path = dir.file("flat.png");
    FlatMap() {
        Image map(64, 64, 3);
        for (int y = 0; y < 64; ++y)
            for (int x = 0; x < 64; ++x) test::setNormal(map, x, y, 0.f, 0.f, 1.f);
        EXPECT_TRUE(savePng(path, test::encodedNormals(map), 8));
    }
};

// The truth's and the rows' cases of the first map's first setting at `footprint`, each step as
// `ndfmip eval` runs it.
std::vector<ReportCase> firstSettingsRows(const EvalOptions& o, int footprint) {
    evaluation::Plan plan = evaluation::planEvaluation(o);
    const evaluation::Lighting lighting = evaluation::prepareLighting(plan);
    evaluation::MapData map = evaluation::loadAndBake(plan, 0, lighting);
    evaluation::Gathered gathered;
    const Scene scene = evaluation::footprintScene(plan, map, footprint, lighting);
    evaluation::evaluateSetting(plan, lighting, map, scene, footprint, plan.settings[0], gathered);
    return gathered.report.cases;
}

TEST(EvaluationSteps, LoadAndBakeMakesEachRowsBakeOnce) {
    FlatMap flat;
    EvalOptions o = optionsFor({"naive", "toksvig", "sggx", "lean", "vmf:2", "exact"});
    o.maps = {flat.path};
    evaluation::Plan plan = evaluation::planEvaluation(o);
    const evaluation::Lighting lighting = evaluation::prepareLighting(plan);
    EXPECT_FALSE(lighting.environment);
    EXPECT_TRUE(lighting.skipped.empty());
    const evaluation::MapData map = evaluation::loadAndBake(plan, 0, lighting);
    EXPECT_EQ(map.name, "flat.png");
    EXPECT_EQ(map.normals->width, 64);
    EXPECT_EQ(map.pyramid.levels.size(), 7u);
    std::vector<std::string> keys;
    for (const auto& [key, bake] : map.bakes) keys.push_back(key);
    EXPECT_EQ(keys, (std::vector<std::string>{"lean", "naive", "sggx", "toksvig", "vmf:2"}));
}

TEST(EvaluationSteps, FootprintSceneCoversFootprintTexelsPerPixelUnderTheLight) {
    FlatMap flat;
    EvalOptions o = optionsFor({"naive"});
    o.maps = {flat.path};
    evaluation::Plan plan = evaluation::planEvaluation(o);
    const evaluation::Lighting lighting = evaluation::prepareLighting(plan);
    const evaluation::MapData map = evaluation::loadAndBake(plan, 0, lighting);
    // 64 texels at footprint 4: 16 pixels, raised to the smallest image side, 32.
    const Scene scene = evaluation::footprintScene(plan, map, 4, lighting);
    EXPECT_EQ(scene.camera.width, 32);
    EXPECT_EQ(scene.camera.type, CameraType::Orthographic);
    EXPECT_FLOAT_EQ(scene.camera.orthoHeight, 4.f / 64.f * 32.f);
    ASSERT_EQ(scene.lights.size(), 1u);
    EXPECT_NEAR(scene.lights[0].direction.z, std::cos(glm::radians(25.f)), 1e-6);
    // Tilted 30 degrees: the light near the view's mirror direction, 30 degrees above the plane.
    plan.options.elevation = 30.f;
    const Scene tilted = evaluation::footprintScene(plan, map, 4, lighting);
    EXPECT_NEAR(tilted.lights[0].direction.z, std::sin(glm::radians(30.f)), 1e-6);
    EXPECT_NEAR(glm::normalize(tilted.camera.eye - tilted.camera.target).z,
                std::sin(glm::radians(30.f)), 1e-5);
}

TEST(EvaluationSteps, OnAFlatMapEveryRowIsTheTruth) {
    FlatMap flat;
    EvalOptions o = optionsFor({"naive", "toksvig", "vmf:2", "exact"});
    o.maps = {flat.path};
    o.frames = 0;
    o.brdfs = {"ggx"};
    o.roughness = {0.2f};
    evaluation::Plan plan = evaluation::planEvaluation(o);
    const evaluation::Lighting lighting = evaluation::prepareLighting(plan);
    evaluation::MapData map = evaluation::loadAndBake(plan, 0, lighting);
    evaluation::Gathered gathered;
    const Scene scene = evaluation::footprintScene(plan, map, 4, lighting);
    evaluation::evaluateSetting(plan, lighting, map, scene, 4, plan.settings[0], gathered);
    ASSERT_EQ(gathered.report.cases.size(), 5u);
    EXPECT_EQ(gathered.report.cases[0].method, kGroundTruth);
    EXPECT_TRUE(std::isinf(gathered.report.cases[0].psnr));
    for (size_t i = 1; i < gathered.report.cases.size(); ++i) {
        const ReportCase& c = gathered.report.cases[i];
        EXPECT_EQ(c.method, o.methods[i - 1]);
        EXPECT_EQ(c.footprint, 4);
        EXPECT_EQ(c.brdf, "ggx");
        // vmf's concentration cap (1e5) widens alpha^2 = 0.04 by 2/kappa: 0.3% more light.
        EXPECT_LT(c.relRmse, 4e-3) << c.method;
        EXPECT_NEAR(c.energyRatio, 1.0, 4e-3) << c.method;
        EXPECT_TRUE(std::isnan(c.flicker)); // frames 0: no flicker measured
    }
    EXPECT_EQ(gathered.cases.size(), 5u);
    EXPECT_TRUE(gathered.cases[1]["flicker"].is_null());
    // The showcase setting (the first GGX alpha) gives the truth, then image and error per row.
    ASSERT_EQ(gathered.report.groups.size(), 1u);
    EXPECT_EQ(gathered.report.groups[0].images.size(), 1u + 2u * 4u);
}

TEST(EvaluationSteps, AFittedBakeIsMadePerGgxRoughnessAndJudgedUnderGgxOnly) {
    // ggx-fit is fitted to the material's roughness: one bake per GGX alpha, no row under
    // Blinn-Phong; on a flat map its one lobe is the material's, so the row is the truth.
    FlatMap flat;
    EvalOptions o = optionsFor({"toksvig", "ggx-fit"});
    o.maps = {flat.path};
    o.frames = 0;
    o.brdfs = {"blinnphong", "ggx"};
    o.exponents = {32.f};
    o.roughness = {0.1f, 0.3f};
    evaluation::Plan plan = evaluation::planEvaluation(o);
    const evaluation::Lighting lighting = evaluation::prepareLighting(plan);
    evaluation::MapData map = evaluation::loadAndBake(plan, 0, lighting);
    std::vector<std::string> keys;
    for (const auto& [key, bake] : map.bakes) keys.push_back(key);
    EXPECT_EQ(keys,
              (std::vector<std::string>{"ggx-fit alpha=0.1", "ggx-fit alpha=0.3", "toksvig"}));
    EXPECT_FLOAT_EQ(float(map.bakes.at("ggx-fit alpha=0.3").parameters.at("base_roughness")), 0.3f);
    const Scene scene = evaluation::footprintScene(plan, map, 4, lighting);
    for (const evaluation::Setting& setting : plan.settings) {
        evaluation::Gathered gathered;
        evaluation::evaluateSetting(plan, lighting, map, scene, 4, setting, gathered);
        std::vector<std::string> rows;
        for (const ReportCase& c : gathered.report.cases) {
            rows.push_back(c.method);
            if (c.method == "ggx-fit") {
                EXPECT_LT(c.relRmse, 3e-3) << setting.label(); // the fit: alpha to 0.3%
            }
        }
        std::vector<std::string> expected{kGroundTruth, "toksvig"};
        if (setting.brdf == "ggx") expected.push_back("ggx-fit");
        EXPECT_EQ(rows, expected) << setting.label();
    }
}

TEST(EvaluationSteps, AnisotropicProbesChangeOnlyATiltedViewsRows) {
    // Rows of normals tilted +-30 degrees about x, alternating along y: a view tilted about x
    // stretches each pixel's footprint along y, where a trilinear lookup at the long side's LOD
    // averages rows the truth keeps apart, and probes along it do not. Straight down the
    // footprints are square, so the probes change nothing.
    test::TempDir dir{"evaluation_steps"};
    const std::string path = dir.file("rows.png");
    Image rows(64, 64, 3);
    const float s = std::sin(glm::radians(30.f)), c = std::cos(glm::radians(30.f));
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) test::setNormal(rows, x, y, 0.f, (y / 2) % 2 ? s : -s, c);
    ASSERT_TRUE(savePng(path, test::encodedNormals(rows), 8));
    auto naiveError = [&](float elevation, int anisotropy, int footprint) {
        EvalOptions o = optionsFor({"naive"});
        o.maps = {path};
        o.frames = 0;
        o.brdfs = {"ggx"};
        o.roughness = {0.3f};
        o.elevation = elevation;
        o.anisotropy = anisotropy;
        EXPECT_EQ(evaluation::planEvaluation(o).filtering.anisotropy, anisotropy);
        const std::vector<ReportCase> cases = firstSettingsRows(o, footprint);
        EXPECT_EQ(cases.size(), 2u);
        return cases.back().relRmse;
    };
    const double down = naiveError(90.f, 1, 8);
    EXPECT_GT(down, 0.05); // the mip averages the two normals
    EXPECT_NEAR(naiveError(90.f, 8, 8), down, 1e-3 * down);
    const double trilinear = naiveError(20.f, 1, 4), probed = naiveError(20.f, 8, 4);
    EXPECT_LT(probed, 0.5 * trilinear) << trilinear;
    EvalOptions bad = optionsFor({"naive"});
    bad.anisotropy = 65;
    EXPECT_EQ(problemOf([&] { evaluation::planEvaluation(bad); }), "--aniso 65: expected 1 .. 64");
}

TEST(EvaluationSteps, EachEnginesChannelsBlendedAcrossTheVerticalKeepTheTensorsError) {
    // 2 x 2 blocks of normals at +-20 degrees along 84 or 96 degrees from x, in a checkerboard of
    // blocks: level 1's lobes point near the y axis, which KHR_materials_anisotropy's direction
    // (x >= 0 as a lobe's axis is given) crosses between neighbours. One trilinear lookup at
    // footprint 2 blends neighbouring level-1 texels: ggx-aniso blends their moments, the engine
    // rows their files' channels (8-bit, decoded after the blend as the engines do). With the
    // files' directions signed to agree, the channels' blend loses next to nothing (measured, KHR's
    // 0.361, Kulla's 0.355, Burley's 0.363 against 0.363); KHR's stored with x >= 0 blend to
    // directions along x (0.474).
    test::TempDir dir{"evaluation_steps"};
    const std::string path = dir.file("blocks.png");
    ASSERT_TRUE(savePng(path, test::encodedNormals(test::blocksAcrossTheVertical(64)), 16));
    EvalOptions o =
        optionsFor({"ggx-aniso", "ggx-aniso-khr", "ggx-aniso-kulla", "ggx-aniso-burley"});
    o.maps = {path};
    o.frames = 0;
    o.view = "engine";
    o.brdfs = {"ggx"};
    o.roughness = {0.3f};
    const std::vector<ReportCase> cases = firstSettingsRows(o, 2);
    ASSERT_EQ(cases.size(), 5u);
    const ReportCase& tensor = cases[1];
    ASSERT_EQ(tensor.method, "ggx-aniso");
    EXPECT_GT(tensor.relRmse, 0.01);
    // Each engine's files (glTF's, Unreal's and HDRP's, Godot's), all signed alike.
    for (size_t row = 2; row < 5; ++row) {
        const ReportCase& engine = cases[row];
        EXPECT_LT(engine.relRmse, 1.05 * tensor.relRmse) << engine.method;
        EXPECT_NEAR(engine.energyRatio, tensor.energyRatio, 0.02) << engine.method;
    }
}

TEST(EvaluationSteps, ReportSaysTheViewItRan) {
    EvalOptions o = optionsFor({"naive"});
    o.view = "engine";
    o.calibrate = true;
    o.anisotropy = 4;
    const evaluation::Plan plan = evaluation::planEvaluation(o);
    evaluation::Gathered gathered;
    gathered.candidateError["c=1"] = {std::log(0.2) * 2, 2};
    gathered.candidateError["filament"] = {std::log(0.1) * 2, 2};
    std::string best;
    const nlohmann::json root = evaluation::reportJson(plan, {}, gathered, best);
    EXPECT_EQ(best, "filament");
    EXPECT_EQ(root["setup"]["eval_view"], "engine");
    EXPECT_EQ(root["setup"]["taps"], 1);
    EXPECT_EQ(root["setup"]["lobe_filter"], "parameter");
    EXPECT_EQ(root["setup"]["anisotropy"], 4);
    EXPECT_NEAR(root["calibration"]["mean_rel_rmse"]["c=1"].get<double>(), 0.2, 1e-12);
    EXPECT_FALSE(root.contains("skipped"));
    const std::vector<std::string> notes = evaluation::reportNotes(plan, {}, 0., best);
    ASSERT_EQ(notes.size(), 2u);
    EXPECT_EQ(notes[0].rfind("Each case: a top-down orthographic view", 0), 0u);
    EXPECT_NE(notes[0].find("1 x 1 sub-samples per pixel, LOD bias 0, parameter filtering, up to 4 "
                            "anisotropic probes"),
              std::string::npos);
    EXPECT_NE(notes[1].find("best is filament."), std::string::npos);
}

} // namespace
} // namespace ndfmip
