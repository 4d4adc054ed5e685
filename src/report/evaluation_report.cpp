// The last steps of `ndfmip eval` (evaluation_steps.h): report.json's document and the
// report's paragraphs.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "report/evaluation_steps.h"

namespace ndfmip::evaluation {

using json = nlohmann::json;

json jsonNumber(double v) {
    return std::isfinite(v) ? json(v) : json(nullptr);
}

json caseJson(const ReportCase& c) {
    return {{"map", c.map},
            {"footprint", c.footprint},
            {"method", c.method},
            {"brdf", c.brdf},
            {"exponent", c.exponent},
            {"roughness", c.roughness},
            {"rel_rmse", jsonNumber(c.relRmse)},
            {"rmse", jsonNumber(c.rmse)},
            {"psnr", jsonNumber(c.psnr)},
            {"energy_ratio", jsonNumber(c.energyRatio)},
            {"flicker", jsonNumber(c.flicker)}};
}

json reportJson(const Plan& plan, const Lighting& lighting, const Gathered& gathered,
                std::string& calibrationBest) {
    const EvalOptions& a = plan.options;
    const RenderOptions& filtering = plan.filtering;
    const glm::vec2 shift = plan.shift;
    json root;
    root["version"] = NDFMIP_VERSION;
    root["maps"] = a.maps;
    char viewText[96], lightText[96];
    if (a.elevation >= 90.f) {
        std::snprintf(viewText, sizeof viewText, "orthographic, straight down");
        std::snprintf(lightText, sizeof lightText, "directional, %g deg off the normal",
                      a.lightPolar);
    } else {
        std::snprintf(viewText, sizeof viewText, "orthographic, %g deg above the plane",
                      a.elevation);
        std::snprintf(lightText, sizeof lightText,
                      "directional, %g deg above the plane, 30 deg from the mirror azimuth",
                      a.elevation);
    }
    root["setup"] = {{"view", viewText},
                     {"light", lightText},
                     {"elevation_degrees", a.elevation},
                     {"light_polar_degrees", a.lightPolar},
                     {"footprints", a.footprints},
                     {"methods", a.methods},
                     {"frames", a.frames},
                     {"truth", a.truth},
                     {"truth_spp", filtering.truth == TruthFilter::Box
                                       ? json("exact integral, no samples")
                                   : a.spp > 0 ? json(a.spp)
                                               : json("max(64, footprint^2), at most 1024")},
                     {"aligned", a.aligned},
                     {"offset", {shift.x, shift.y}},
                     {"taps", filtering.taps},
                     {"lod_bias", filtering.lodBias},
                     {"anisotropy", filtering.anisotropy},
                     {"specular_aa",
                      {{"variance", filtering.specularAntiAliasing.variance},
                       {"threshold", filtering.specularAntiAliasing.threshold}}},
                     {"lobe_filter", *a.lobeFilter},
                     {"eval_view", a.view},
                     {"coherent", a.coherence.value_or(0.f)},
                     {"seed", a.seed}};
    if (lighting.environment) {
        root["setup"]["light"] = "environment";
        root["setup"]["environment"] = {
            {"path", a.environment},
            {"intensity", a.environmentOptions.intensity},
            {"rotation_degrees", a.environmentOptions.rotationDegrees},
            {"sh_views", a.shViews},
            {"sh_cosine", specularCosineName(a.shCosine)},
            {"env_sh_order", a.environmentShOrder},
            {"env_direction", a.dominantDirection ? "dominant" : "mirror"},
            {"env_truth", environmentTruthName(a.environmentTruth)}};
        root["setup"]["truth_spp"] = // per pixel, or per node of the table
            a.spp > 0 ? json(a.spp) : json("max(64, footprint^2), at most 1024");
        root["setup"]["truth_max_rel_std_error"] = jsonNumber(gathered.truthNoise);
        json left = json::array();
        for (const auto& [method, reason] : lighting.skipped)
            left.push_back({{"method", method}, {"reason", reason}});
        root["skipped"] = left;
    }
    root["cases"] = gathered.cases;
    if (a.calibrate) {
        json summary = json::object();
        std::string best;
        double bestError = std::numeric_limits<double>::infinity();
        for (const auto& [name, value] : gathered.candidateError) {
            double mean = std::exp(value.first / std::max(1, value.second));
            summary[name] = mean;
            if (mean < bestError) bestError = mean, best = name;
        }
        root["calibration"] = {
            {"cases", gathered.calibration}, {"mean_rel_rmse", summary}, {"best", best}};
        calibrationBest = best;
    }
    return root;
}

std::vector<std::string> reportNotes(const Plan& plan, const Lighting& lighting, double truthNoise,
                                     const std::string& calibrationBest) {
    const EvalOptions& a = plan.options;
    const RenderOptions& filtering = plan.filtering;
    const glm::vec2 shift = plan.shift;
    std::vector<std::string> notes;
    if (a.calibrate)
        notes.push_back("Roughness calibration (GGX, geometric mean of the relative RMSE over "
                        "maps, footprints and base roughness): best is " +
                        calibrationBest + ".");
    char view[160];
    std::snprintf(view, sizeof view,
                  a.aligned ? "on the texel grid (aligned: each pixel one texel of a level)"
                            : "offset from the texel grid by (%g, %g) pixels",
                  shift.x, shift.y);
    const std::string truthText = filtering.truth == TruthFilter::Box
                                      ? "the box surface of the finest normals (each texel's "
                                        "normal over its square, what the mip levels "
                                        "average), integrated exactly over each pixel"
                                      : "stratified supersampling of the bilinear, renormalised "
                                        "surface of the finest normals, "
                                        "max(64, footprint^2) samples per pixel up to 1024";
    char rule[160];
    std::snprintf(rule, sizeof rule, "%d x %d sub-samples per pixel, LOD bias %g, %s filtering",
                  filtering.taps, filtering.taps, filtering.lodBias, a.lobeFilter->c_str());
    std::string filter = rule;
    if (filtering.anisotropy > 1)
        filter += ", up to " + std::to_string(filtering.anisotropy) + " anisotropic probes";
    if (filtering.specularAntiAliasing.variance > 0.f) {
        char aa[128];
        std::snprintf(aa, sizeof aa, ", specular anti-aliasing (variance %g, threshold %g)",
                      filtering.specularAntiAliasing.variance,
                      filtering.specularAntiAliasing.threshold);
        filter += aa;
    }
    if (lighting.environment) {
        char noiseText[128];
        std::snprintf(noiseText, sizeof noiseText, "%.3f%%", 100. * truthNoise);
        std::string left;
        for (const auto& [method, reason] : lighting.skipped)
            left += (left.empty() ? "" : ", ") + method;
        notes.insert(
            notes.begin(),
            "Lit by the environment " + a.environment +
                " instead of the directional light: the truth is " +
                (a.environmentTruth == EnvironmentTruth::Table
                     ? std::string("tabulated (the light each normal reflects, estimated per "
                                   "node of a grid over the normals by environment and BRDF "
                                   "samples, MIS, and integrated over each pixel's texels)")
                     : std::string("sampled (environment and BRDF samples, MIS)")) +
                " with a relative standard error of at most " + noiseText +
                (left.empty()
                     ? std::string(".")
                     : "; left out (they cannot shade under an environment): " + left + "."));
    }
    notes.insert(notes.begin(),
                 "Each case: a top-down orthographic view of the map tiled on a plane, one "
                 "pixel covering footprint x "
                 "footprint texels, " +
                     std::string(view) +
                     "; one directional light 25 degrees off the normal. Ground "
                     "truth: " +
                     truthText + ". Methods: trilinear filtering, " + filter +
                     "; 'exact' shades each texel "
                     "read as the exact mean over its normals (the floor of any per-texel "
                     "NDF). Flicker: mean over pixels "
                     "of temporal std / mean over " +
                     std::to_string(a.frames) + " sub-pixel-shifted frames.");
    EvalResult result;
    return notes;
}

} // namespace ndfmip::evaluation
