// Judging a method against the truth where a pixel covers exactly one texel of a level (the
// aligned case): the truth is then the mean of the BRDF over the level-0 normals the texel
// covers (Han et al. eq. 8), and the method shades the texel's own stored parameters.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "ndfmip/bake.h"
#include "ndfmip/environment.h"
#include "ndfmip/environment_sh_shading.h"
#include "ndfmip/html_report.h"
#include "ndfmip/pyramid.h"
#include "ndfmip/render.h"
#include "ndfmip/shading.h"
#include "ndfmip/vmf.h"

namespace ndfmip {

// The specular lobe (normalised Blinn-Phong, exponent ctx.exponent, no cosine) that the bake's
// method gives every texel of `level` from its stored parameters (one channel).
Image shadeLevel(const Bake& bake, int level, const ShadeContext& ctx);

// The truth for every texel of `level`: the mean over its footprint of the lobe at each
// level-0 normal (one channel).
Image groundTruthLevel(const Pyramid& pyramid, int level, const ShadeContext& ctx);

struct ErrorStats {
    double rmse = 0;         // sqrt(mean (a - b)^2)
    double relativeRmse = 0; // ||a - b|| / ||b||
    double energyRatio = 0;  // mean a / mean b
};

// Compares an image with the truth (same size, first channel).
ErrorStats compareToTruth(const Image& image, const Image& truth);

// The same pooled over several image/truth pairs (e.g. one per light): every pixel of every pair
// counts once, so a pair whose truth is near zero cannot dominate a ratio.
ErrorStats compareToTruth(const std::vector<Image>& images, const std::vector<Image>& truths);

// ---- The evaluation of `ndfmip eval` ---------------------------------------------------------
// Every map rendered from straight above at each footprint (texels per pixel side), with every
// method and as the ground truth, for every material setting; docs/RENDERING.md. The defaults
// are the command's (its option names in brackets).
// vmf's C of H eq. 32 in eval's engine view: coherent lobes, so that blending slot j of
// neighbouring texels and levels blends like lobes (vmf.h).
constexpr float kEngineViewCoherence = kHardwareFilteringCoherence;

struct EvalOptions {
    std::vector<std::string> maps;
    DecodeOptions decode;
    std::string output; // folder for report.json and report.html; empty: nothing written
    std::vector<int> footprints{1, 4, 16, 64};
    // naive, toksvig, toksvig-lut, sh[:ORDER], vmf[:LOBES[:BUDGET]], lean, exact
    std::vector<std::string> methods{"naive", "toksvig", "toksvig-lut", "sh:2",  "sh:4",
                                     "sh:7",  "sh:10",   "vmf:1",       "vmf:2", "vmf:4",
                                     "vmf:6", "vmf:8",   "exact"};
    std::vector<std::string> brdfs{"blinnphong", "ggx"};
    std::vector<float> exponents{8.f, 32.f, 128.f, 512.f}; // Blinn-Phong
    std::vector<float> roughness{0.1f, 0.3f};              // Beckmann / GGX alpha
    int maxPixels = 128;                                   // --pixels: largest image side
    int spp = 0;    // ground-truth samples per pixel; 0: max(64, footprint^2), at most 1024
    int frames = 8; // flicker frames (0: none)
    uint64_t seed = 1;
    bool calibrate = false; // also the engines' roughness mappings on GGX
    std::vector<float> calibrationRoughness{0.05f, 0.1f, 0.2f, 0.3f, 0.5f};
    std::vector<float> calibrationScales{0.25f, 0.5f, 0.75f, 1.f, 1.5f, 2.f, 3.f, 4.f};
    bool allImages = false;
    bool webgl = true; // the report's live WebGL2 view of the first map
    // The view (--view): lab (the renderer's default rule: 2 x 2 taps, LOD bias -0.5, each
    // texel shaded), engine (what an engine's one trilinear lookup gives: 1 tap, LOD bias 0,
    // parameters blended, vmf baked with coherent lobes) or aligned (as `aligned`). It is a
    // name for the options below that are left unset; those that are set win.
    std::string view = "lab";
    std::optional<float> coherence; // vmf methods: C of H eq. 32; unset: 0, or kEngineViewCoherence
                                    // in the engine view
    bool aligned = false;           // each pixel exactly one texel of a level
    // The camera's elevation above the plane in degrees (--elevation): 90 looks straight down;
    // lower tilts it about the texel grid's x axis (a pixel covers footprint / sin(elevation)
    // texels along the view), the light near the view's mirror direction. 5 .. 90.
    float elevation = 90.f;
    // Straight down (elevation 90), the directional light's angle from the normal in degrees
    // (--light-polar), 30 degrees in azimuth from the texel grid's x axis. 0 .. 85.
    float lightPolar = 25.f;
    std::vector<float> offset{0.31f,
                              0.17f}; // the pixel grid's shift from the texel grid, in pixels
    std::vector<std::string> externalRoughness;  // NAME=PATTERN
    std::string externalEncoding = "perceptual"; // or alpha
    std::string truth = "box";                   // or bilinear
    std::optional<int> taps;      // unset: 1 when aligned, else RenderOptions' default
    std::optional<float> lodBias; // unset: 0 when aligned, else RenderOptions' default
    // Methods: up to this many trilinear probes along each footprint's major axis (--aniso; an
    // engine's anisotropic filtering), 1 .. 64. A straight-down view's footprints are square, so
    // only tilted views (--elevation) read more than one.
    int anisotropy = 1;
    // Methods with one lobe an engine shades: the engine's specular anti-aliasing (render.h;
    // --specular-aa), off unless its variance is set.
    SpecularAntiAliasing specularAntiAliasing;
    std::optional<std::string>
        lobeFilter; // texel or parameter; unset: texel, or parameter in the engine view
    // An environment map (environment.h) that lights every view instead of the directional light:
    // the truth is sampled under it (its noise recorded), and only methods whose shader shades
    // under an environment get rows; the others are listed in EvalResult::skipped.
    std::string environment;
    EnvironmentOptions environmentOptions;
    int shViews = 0; // RenderOptions::shViews of every method row
    SpecularCosine shCosine = SpecularCosine::Reflecting; // RenderOptions::shCosine, likewise
    int environmentShOrder = 8;    // RenderOptions::environmentShOrder, likewise
    bool dominantDirection = true; // RenderOptions::dominantDirection, likewise
    // The truth's (RenderOptions::environmentTruth): eval's views (orthographic, straight down or
    // tilted about the texel grid) fix every direction but the normal's, so by default a table.
    EnvironmentTruth environmentTruth = EnvironmentTruth::Table;
    std::function<void(const std::string&)> log; // a progress line per map
    std::function<void(const std::string& map, const DecodeReport&)> decoded;
};

struct EvalResult {
    std::string json;              // report.json's text
    std::vector<ReportCase> cases; // every case, as in the report
    std::string calibrationBest;   // with calibrate: the mapping with the lowest error
    // Methods (and --external-roughness rows) left out, with the reason ("cannot shade under an
    // environment").
    std::vector<std::pair<std::string, std::string>> skipped;
    double truthNoise = 0.; // under an environment: the largest relative standard error of a truth
    double seconds = 0.0;
};

// Runs the evaluation; writes report.json and report.html into options.output when it is set.
// Errors are one line naming the option or file.
Result<EvalResult> evaluateMaps(const EvalOptions& options);

} // namespace ndfmip
