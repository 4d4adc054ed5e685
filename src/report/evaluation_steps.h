// The steps of `ndfmip eval` (evaluate.h's evaluateMaps), each a function of plain data so that
// each can be run and tested alone:
//
//   planEvaluation     the options checked and resolved: the view's rule, the settings, the
//                      method rows (the `vmf:J:B` / `@RULE` grammar), the filtering rule
//   prepareLighting    under an environment: the lighting loaded, the rows it cannot light
//                      set aside
//   loadAndBake        one map decoded, its pyramid built, every bake its rows read
//   footprintScene     the view of one footprint (camera, light or environment)
//   evaluateSetting    one material setting at one footprint: the truth, every row, compared
//   calibrateFootprint with --calibrate: the engines' roughness mappings at one footprint
//   reportJson         report.json's document; reportNotes: the report's paragraphs
//
// A problem at any step is an evaluation::Problem, one line naming the option or file.
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "ndfmip/environment_lighting.h"
#include "ndfmip/evaluate.h"
#include "ndfmip/html_report.h"
#include "ndfmip/render.h"

namespace ndfmip::evaluation {

struct Problem {
    std::string message;
};
[[noreturn]] void fail(std::string message);

// One material setting of the matrix.
struct Setting {
    Material material;
    std::string brdf;
    float exponent = 0.f, roughness = 0.f;
    std::string label() const; // "blinnphong s=32", "ggx alpha=0.1", "lambert"
};
Setting makeSetting(Brdf brdf, float exponent, float roughness);

// A method row as the matrix names it: "sh:L" is sh baked at order L ("sh" alone: 7), "vmf:J"
// is vmf with J lobes ("vmf" alone: 4), a second shader of a bake (toksvig-lut, sggx) a row over
// its own bake, and under an environment "ROW@VARIANT" a way of shading it.
struct MethodSpec {
    std::string label;  // as in the report
    std::string render; // the name render() takes
    Method method;      // the bake it shades (exact: none)
    BakeOptions options;
    bool baked = true;
    std::string bakeKey; // the label without its @VARIANT: variants share one bake
    // Under an environment, "@RULE" (log2sigma, filament, unity, unreal) or, for vmf, "@sh" or
    // "@prefiltered": the RenderOptions the row is rendered with.
    std::optional<EnvironmentLod> lod;
    std::optional<EnvironmentWay> way;
};
MethodSpec methodSpec(const std::string& label);

// An --external-roughness row: a peer's perceptual-roughness mips beside the standard normal
// mipmap, rendered as kRoughnessMips for Beckmann and GGX settings.
struct ExternalRoughness {
    std::string name, pattern;
};

// What a run does, resolved from the options once.
struct Plan {
    EvalOptions options; // with the view's rule where the options left it open
    std::vector<Setting> settings;
    std::vector<MethodSpec> specs;
    std::vector<ExternalRoughness> externals;
    RenderOptions filtering; // the rows' filtering rule (taps, LOD bias, lobe filter, truth)
    glm::vec2 shift{0.f};    // the pixel grid's offset from the texel grid, in pixels
};
Plan planEvaluation(const EvalOptions& options);

struct Lighting {
    std::shared_ptr<const EnvironmentLighting> environment;   // null: the directional light
    std::vector<std::pair<std::string, std::string>> skipped; // rows left out, and why
    bool externalRows = false; // the --external-roughness rows are drawn
};
// Under an environment the rows that cannot shade under it leave plan.specs for `skipped`.
Lighting prepareLighting(Plan& plan);

struct MapData {
    std::string name;
    SharedImage normals;
    Pyramid pyramid;
    std::map<std::string, Bake> bakes;                         // by MethodSpec::bakeKey
    std::map<std::string, std::vector<SharedImage>> roughness; // external mips by "NAME alpha"
};
MapData loadAndBake(const Plan& plan, size_t mapIndex, const Lighting& lighting);

Scene footprintScene(const Plan& plan, const MapData& map, int footprint, const Lighting& lighting);

// What the steps gather for the report.
struct Gathered {
    EvalReport report;
    nlohmann::json cases = nlohmann::json::array();
    nlohmann::json calibration = nlohmann::json::array();
    // Sum of log relative RMSE and count per calibration candidate, over every calibration case.
    std::map<std::string, std::pair<double, int>> candidateError;
    double truthNoise = 0.; // under an environment: the largest relative standard error
};

void evaluateSetting(const Plan& plan, const Lighting& lighting, MapData& map, Scene scene,
                     int footprint, const Setting& setting, Gathered& out);
void calibrateFootprint(const Plan& plan, const Lighting& lighting, const MapData& map, Scene scene,
                        int footprint, Gathered& out);

// The report's WebGL2 view of the first map (empty when nothing can be drawn).
std::string liveViewOf(const Plan& plan, const MapData& map);

// report.json's document; with --calibrate `calibrationBest` is set to the best mapping.
nlohmann::json reportJson(const Plan& plan, const Lighting& lighting, const Gathered& gathered,
                          std::string& calibrationBest);
// The paragraphs under the report's title, in order.
std::vector<std::string> reportNotes(const Plan& plan, const Lighting& lighting, double truthNoise,
                                     const std::string& calibrationBest);

// A case as report.json writes it; a number that is not finite as null.
nlohmann::json caseJson(const ReportCase& c);
nlohmann::json jsonNumber(double v);

} // namespace ndfmip::evaluation
