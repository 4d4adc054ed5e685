// ndfmip eval MAP... -o DIR: every map rendered at several view distances with every method
// and with the ground truth (evaluateMaps, evaluate.h), written as DIR/report.json (every
// number) and DIR/report.html (tables, plots, images; one self-contained file), with a summary
// table on stdout.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

#include "cli.h"
#include "ndfmip/evaluate.h"

namespace ndfmip::cli {
namespace {

struct EvalArgs {
    EvalOptions options;
    InputOptions input;
    FilteringArgs filtering;
    EnvironmentArgs environment;
    bool quiet = false;
};

void runEval(EvalOptions o, const EvalArgs& a) {
    o.decode = a.input.resolved();
    o.truth = a.filtering.truth;
    if (!a.quiet) {
        o.log = [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); };
        o.decoded = [](const std::string& map, const DecodeReport& report) {
            warnAboutDecode(map, report);
        };
    }
    Result<EvalResult> result = evaluateMaps(o);
    if (!result) throw Failure(result.error().message);
    const std::vector<ReportCase>& cases = result->cases;

    // Summary on stdout: geometric mean of the relative RMSE per method and footprint (errors
    // differ by orders of magnitude between settings).
    std::printf("%-12s", "footprint");
    for (int f : o.footprints) std::printf(" %9d", f);
    std::printf("   (geometric mean of rel. RMSE over maps and settings)\n");
    std::vector<std::string> rows = o.methods;
    for (const std::string& spec : o.externalRoughness)
        rows.push_back(spec.substr(0, spec.find('=')));
    for (const std::string& method : rows) {
        if (std::any_of(result->skipped.begin(), result->skipped.end(),
                        [&](const auto& s) { return s.first == method; }))
            continue;
        std::printf("%-12s", method.c_str());
        for (int f : o.footprints) {
            double logSum = 0;
            int n = 0;
            for (const ReportCase& c : cases)
                if (c.method == method && c.footprint == f && c.relRmse > 0 &&
                    std::isfinite(c.relRmse))
                    logSum += std::log(c.relRmse), ++n;
            std::printf(" %9.4f", n ? std::exp(logSum / n) : 0.0);
        }
        std::printf("\n");
    }
    if (o.calibrate) std::printf("calibration best: %s\n", result->calibrationBest.c_str());
    if (!o.environment.empty()) {
        std::printf("environment %s: truth relative standard error at most %.3f%%\n",
                    o.environment.c_str(), 100. * result->truthNoise);
        for (const auto& [method, reason] : result->skipped)
            std::printf("skipped %s: %s\n", method.c_str(), reason.c_str());
    }
    std::printf("eval: %zu cases in %.1f s -> %s/report.html, %s/report.json\n", cases.size(),
                result->seconds, o.output.c_str(), o.output.c_str());
}

} // namespace

void addEvalCommand(CLI::App& app) {
    auto args = std::make_shared<EvalArgs>();
    EvalOptions* a = &args->options;
    CLI::App* c = app.add_subcommand(
        "eval", "judge every method against the supersampled ground truth; HTML + JSON report");
    c->add_option("maps", a->maps, "normal maps")->required()->check(CLI::ExistingFile);
    addInputOptions(c, args->input);
    c->add_option("-o,--output", a->output, "report folder (report.html, report.json)")->required();
    c->add_flag("!--no-webgl", a->webgl, "leave the live WebGL2 view out of report.html");
    c->add_option("--footprints", a->footprints, "texels per pixel side")
        ->delimiter(',')
        ->capture_default_str();
    c->add_option("--methods", a->methods, "methods to judge")
        ->delimiter(',')
        ->capture_default_str();
    c->add_option("--brdfs", a->brdfs, "lambert, blinnphong, beckmann, ggx")
        ->delimiter(',')
        ->capture_default_str();
    c->add_option("--exponents", a->exponents, "Blinn-Phong exponents")
        ->delimiter(',')
        ->check(CLI::Range(1e-3f, 1e5f))
        ->capture_default_str();
    c->add_option("--roughness", a->roughness, "Beckmann/GGX alphas")
        ->delimiter(',')
        ->check(CLI::Range(1e-3f, 1.f))
        ->capture_default_str();
    c->add_option("--pixels", a->maxPixels,
                  "largest image side; smaller when the map is covered sooner")
        ->check(CLI::Range(8, 2048))
        ->capture_default_str();
    c->add_option("--spp", a->spp,
                  "ground-truth samples per pixel (default: max(64, footprint^2), at most 1024)")
        ->check(CLI::Range(1, 1 << 16));
    c->add_option("--frames", a->frames, "frames for the flicker measure (0: none)")
        ->check(CLI::Range(0, 256))
        ->capture_default_str();
    c->add_option("--seed", a->seed, "jitter seed")->capture_default_str();
    c->add_flag("--calibrate", a->calibrate, "also compare engines' roughness mappings on GGX");
    c->add_option_function<float>(
         "--coherent", [a](float value) { a->coherence = value; },
         "vmf methods: coherent lobes with alignment strength C (H eq. 32); default 0, " +
             std::to_string(int(kEngineViewCoherence)) + " in the engine view")
        ->check(CLI::Range(0.f, 1e6f));
    c->add_option(
         "--elevation", a->elevation,
         "the camera's elevation above the plane in degrees: 90 looks straight down; lower tilts "
         "it "
         "(orthographic, the truth still exact), the light near the view's mirror direction")
        ->check(CLI::Range(5.f, 90.f))
        ->capture_default_str();
    c->add_option("--light-polar", a->lightPolar,
                  "a straight-down view's light: its angle from the normal in degrees (30 deg in "
                  "azimuth from the map's x axis)")
        ->check(CLI::Range(0.f, 85.f))
        ->capture_default_str();
    c->add_option(
         "--view", a->view,
         "lab (the renderer's default rule), engine (what an engine's one trilinear lookup gives: "
         "--taps 1 --lod-bias 0 --lobe-filter parameter, vmf's lobes coherent) or aligned (as "
         "--aligned); "
         "options given beside it win")
        ->check(CLI::IsMember({"lab", "engine", "aligned"}))
        ->capture_default_str();
    c->add_option("--calibration-roughness", a->calibrationRoughness,
                  "base alphas of the calibration")
        ->delimiter(',')
        ->check(CLI::Range(1e-3f, 1.f))
        ->capture_default_str();
    c->add_flag("--all-images", a->allImages,
                "images of every setting (default: s=32 and the first GGX alpha)");
    c->add_flag("--aligned", a->aligned,
                "each pixel exactly one texel of a level (no offset, one lookup: "
                "--taps 1 --lod-bias 0 unless given): only the representation error is left");
    c->add_option("--offset", a->offset, "the pixel grid's shift from the texel grid, in pixels")
        ->delimiter(',')
        ->expected(2)
        ->capture_default_str();
    addFilteringOptions(c, args->filtering);
    c->add_option("--aniso", a->anisotropy,
                  "methods: anisotropic probes along each footprint (an engine's anisotropic "
                  "filtering; 1 = trilinear): only tilted views (--elevation) read more than one")
        ->check(CLI::Range(1, 64))
        ->capture_default_str();
    addEnvironmentOptions(c, args->environment);
    addShViewsOption(c, a->shViews);
    addShLightingOptions(c, a->shCosine, a->environmentShOrder);
    addEnvDirectionOption(c, a->dominantDirection);
    addEnvTruthOption(c, a->environmentTruth, "table");
    c->add_option(
        "--external-roughness", a->externalRoughness,
        "NAME=PATTERN: another tool's perceptual-roughness mips (one file per level; PATTERN with "
        "{level}, {stem} of the map, {roughness} the base alpha) beside the standard normal "
        "mipmap, "
        "judged on the Beckmann/GGX settings");
    c->add_option("--external-encoding", a->externalEncoding,
                  "what the external roughness files store: perceptual (alpha = value^2) or alpha")
        ->capture_default_str();
    c->add_flag("-q,--quiet", args->quiet, "no progress or warnings");
    c->callback([args, c] {
        EvalOptions o = args->options;
        // The filtering rule as given; what is not given is the view's (evaluate.h).
        if (c->count("--taps") != 0) o.taps = args->filtering.taps;
        if (c->count("--lod-bias") != 0) o.lodBias = args->filtering.lodBias;
        if (c->count("--lobe-filter") != 0) o.lobeFilter = args->filtering.lobeFilter;
        o.specularAntiAliasing = args->filtering.specularAntiAliasing;
        if (!args->environment.path.empty()) {
            o.environment = args->environment.path;
            o.environmentOptions = args->environment.options();
        } else if (args->environment.adjusted()) {
            throw Failure("--env-intensity and --env-rotation need --environment");
        }
        runEval(std::move(o), *args);
    });
}

} // namespace ndfmip::cli
