#include <cstdio>
#include <unistd.h>

#include "cli.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>

#include "ndfmip/environment_sh_views.h"
#include "ndfmip/io.h"
#include "ndfmip/limits.h"
#include "ndfmip/render.h"
#include "ndfmip/spherical_harmonics.h"
#include "ndfmip/vmf.h"

namespace ndfmip::cli {

DecodeOptions InputOptions::resolved() const {
    DecodeOptions d = decode;
    d.height = heightScale > 0.f;
    d.heightScale = d.height ? heightScale : 1.f;
    d.address = clamp ? AddressMode::Clamp : AddressMode::Wrap;
    return d;
}

void addInputOptions(CLI::App* command, InputOptions& o) {
    command->add_flag("--green-down", o.decode.greenDown,
                      "DirectX-style map (green points down): flip Y");
    command->add_flag("--two-channel", o.decode.twoChannel,
                      "use R,G only and rebuild z (BC5-style maps)");
    command->add_flag("--signed", o.decode.signedValues,
                      "float (EXR) maps already hold n in [-1,1]");
    command
        ->add_option("--height", o.heightScale,
                     "input is a height map; SCALE is the height of value 1.0 in texels")
        ->check(CLI::Range(1e-6f, 1e6f));
    command->add_flag("--clamp", o.clamp, "the map does not tile (default: wrap)");
}

ParameterValues MethodParameterArgs::given() const {
    ParameterValues values;
    for (const auto& [key, option] : options) {
        if (option->count() == 0) continue;
        if (integers.count(key))
            values[key] = double(integers.at(key));
        else if (floats.count(key))
            values[key] = double(floats.at(key));
        else
            values[key] = numbers.at(key);
    }
    return values;
}

double MethodParameterArgs::value(Method method, const std::string& key) const {
    return parameterValue(method, given(), key);
}

void addMethodParameterOptions(CLI::App* command, unsigned use, MethodParameterArgs& args) {
    // A flag that several methods take is one option; its help names them all.
    std::map<std::string, std::vector<std::pair<Method, const MethodParameter*>>> byKey;
    std::vector<std::string> order;
    for (const auto& entry : allMethodParameters()) {
        if (!(entry.second->commands & use)) continue;
        auto& takers = byKey[entry.second->key];
        if (takers.empty()) order.push_back(entry.second->key);
        takers.push_back(entry);
    }
    for (const std::string& key : order) {
        const MethodParameter& p = *byKey[key].front().second;
        std::string methods;
        for (const auto& [method, unused] : byKey[key])
            methods += (methods.empty() ? "" : ", ") + std::string(methodName(method));
        char shown[32];
        std::snprintf(shown, sizeof shown, "%g",
                      use == kParameterBake && !std::isnan(p.fileDefault) ? p.fileDefault
                                                                          : p.defaultValue);
        const std::string help = methods + (use == kParameterBake ? "" : " baked on the fly") +
                                 ": " + p.help + " (default " + shown + ")";
        CLI::Option* option = nullptr;
        if (p.type == ParameterType::Integer)
            option = command->add_option(p.flag, args.integers[key], help)
                         ->check(CLI::Range(int64_t(p.min), int64_t(p.max)));
        else if (p.type == ParameterType::Float)
            option = command->add_option(p.flag, args.floats[key], help)
                         ->check(CLI::Range(float(p.min), float(p.max)));
        else
            option = command->add_option(p.flag, args.numbers[key], help)
                         ->check(CLI::Range(p.min, p.max));
        args.options[key] = option;
    }
}

void warnAboutDecode(const std::string& path, const DecodeReport& report) {
    auto percent = [&](size_t n) { return 100.0 * double(n) / double(report.texels); };
    if (report.offUnitLength * 20 > report.texels)
        std::fprintf(stderr,
                     "ndfmip: warning: %s: %.1f%% of the normals are far from unit length "
                     "(wrong convention, or not a normal map?)\n",
                     path.c_str(), percent(report.offUnitLength));
    if (report.degenerate)
        std::fprintf(stderr, "ndfmip: warning: %s: %zu zero-length normals replaced by (0,0,1)\n",
                     path.c_str(), report.degenerate);
    if (report.facingDown)
        std::fprintf(stderr,
                     "ndfmip: warning: %s: %zu normals face away from the surface (z < 0)\n",
                     path.c_str(), report.facingDown);
}

Image loadNormalsOrFail(const std::string& path, const DecodeOptions& decode, bool quiet,
                        DecodeReport* reportOut) {
    DecodeReport report;
    Result<Image> normals = loadNormalMap(path, decode, &report);
    if (!normals) throw Failure(normals.error().message);
    if (!quiet) warnAboutDecode(path, report);
    if (reportOut) *reportOut = report;
    return std::move(normals.value());
}

void requireFiniteNumbers(CLI::App& app) {
    const CLI::Validator finite(
        [](std::string& text) -> std::string {
            char* end = nullptr;
            const double value = std::strtod(text.c_str(), &end);
            // Text that is no number at all is left to the option's own conversion error.
            if (end == text.c_str() || std::isfinite(value)) return "";
            return "must be a finite number, not " + quote(text);
        },
        "", "FINITE");
    for (CLI::Option* option : app.get_options())
        if (option->get_type_name().rfind("FLOAT", 0) == 0) option->check(finite); // "FLOAT:..."
    for (CLI::App* command : app.get_subcommands({})) requireFiniteNumbers(*command);
}

void addLimitOptions(CLI::App& app) {
    const InputLimits defaults;
    app.add_option_function<int64_t>(
           "--max-pixels",
           [](int64_t pixels) {
               InputLimits limits = inputLimits();
               limits.maxPixels = limits.maxCameraPixels = pixels;
               setInputLimits(limits);
           },
           "largest image read or rendered, in pixels (default " +
               std::to_string(defaults.maxPixels) + " for files, " +
               std::to_string(defaults.maxCameraPixels) + " for renders)")
        ->check(CLI::Range(int64_t(1), int64_t(1) << 40));
    app.add_option_function<double>(
           "--max-memory",
           [](double gib) {
               InputLimits limits = inputLimits();
               limits.maxMemoryBytes = int64_t(gib * double(int64_t(1) << 30));
               setInputLimits(limits);
           },
           "memory a bake may need, in GiB (default " +
               std::to_string(defaults.maxMemoryBytes >> 30) + ")")
        ->check(CLI::Range(1e-6, 1e6));
}

void checkBakeMemoryOrFail(const std::string& name, Method method, const BakeOptions& options,
                           int width, int height) {
    Status s = checkBakeMemory(name, method, options, width, height);
    if (!s) throw Failure(s.error);
}

void showProgress(const char* label, int done, int total) {
    static const bool terminal = isatty(2);
    if (!terminal) return;
    std::fprintf(stderr, "\r%s %d/%d%s", label, done, total, done == total ? "\n" : "");
    std::fflush(stderr);
}

SharedImage loadAlbedoOrFail(const std::string& path, int width, int height) {
    Result<SharedImage> albedo = loadAlbedo(path, width, height);
    if (!albedo) throw Failure(albedo.error().message);
    return albedo.value();
}

FilteringArgs::FilteringArgs()
    : taps(RenderOptions{}.taps), lodBias(RenderOptions{}.lodBias),
      lobeFilter(shadeFilterName(RenderOptions{}.shadeFilter)) {}

void FilteringArgs::apply(RenderOptions& o) const {
    if (!truthFilterFromString(truth, o.truth))
        throw Failure("--truth: " + quote(truth) + " is not box or bilinear");
    if (!shadeFilterFromString(lobeFilter, o.shadeFilter))
        throw Failure("--lobe-filter: " + quote(lobeFilter) + " is not parameter or texel");
    o.taps = taps;
    o.lodBias = lodBias;
    o.specularAntiAliasing = specularAntiAliasing;
}

void addFilteringOptions(CLI::App* c, FilteringArgs& a) {
    c->add_option(
         "--truth", a.truth,
         "ground truth surface: box (each texel's normal over its square, as the mip levels "
         "average it; an exact, noise-free integral where the view allows) or bilinear")
        ->capture_default_str();
    c->add_option("--taps", a.taps,
                  "methods: K x K sub-samples per pixel, each a K times smaller footprint")
        ->check(CLI::Range(1, 16))
        ->capture_default_str();
    c->add_option("--lod-bias", a.lodBias, "methods: added to every lookup's LOD")
        ->check(CLI::Range(-16.f, 16.f))
        ->capture_default_str();
    c->add_option(
         "--lobe-filter", a.lobeFilter,
         "methods: parameter (blend the texels' parameters, then shade) or texel (shade each "
         "texel, then blend)")
        ->capture_default_str();
    c->add_option("--specular-aa", a.specularAntiAliasing.variance,
                  "methods with one GGX or Beckmann lobe an engine shades (naive, roughness-mips, "
                  "ggx-fit, ggx-aniso): an engine's geometric specular anti-aliasing, the "
                  "normal's change to the next pixels as a spread added to alpha^2 (Filament's "
                  "and HDRP's screen-space variance: 0.15 is Filament's default; 0 = off)")
        ->check(CLI::Range(0.f, 1000.f))
        ->capture_default_str();
    c->add_option("--specular-aa-threshold", a.specularAntiAliasing.threshold,
                  "with --specular-aa: the most it adds to alpha^2 (Filament's default 0.2)")
        ->check(CLI::Range(0.f, 1.f))
        ->capture_default_str();
}

void addEnvironmentOptions(CLI::App* c, EnvironmentArgs& a) {
    c->add_option("--environment", a.path,
                  "light with this equirectangular HDR/EXR map (docs/ENVIRONMENT.md), in place of "
                  "the scene's");
    c->add_option("--env-intensity", a.intensity, "the environment's radiance scale (default 1)")
        ->check(CLI::PositiveNumber);
    c->add_option("--env-rotation", a.rotationDegrees,
                  "the environment's rotation about its up axis, degrees")
        ->check(CLI::Range(-360.f, 360.f));
}

void addEnvironmentShadingOptions(CLI::App* c, EnvironmentShadingArgs& a) {
    c->add_option("--env-lod", a.lod,
                  "under an environment, the prefiltered levels' rule of naive, toksvig, "
                  "roughness-mips and vmf "
                  "(prefiltered): log2sigma (Toksvig's), filament, unity or unreal")
        ->capture_default_str();
    c->add_option("--vmf-environment", a.vmfWay,
                  "under an environment, vmf shades by prefiltered levels per lobe (prefiltered, "
                  "the engine way) "
                  "or by SH lighting (sh, Han et al. eqs. 34-37)")
        ->capture_default_str();
    addShViewsOption(c, a.shViews);
    addShLightingOptions(c, a.shCosine, a.environmentShOrder);
    addEnvDirectionOption(c, a.dominantDirection);
}

void addEnvDirectionOption(CLI::App* c, bool& dominant) {
    const std::map<std::string, bool> names = {{"dominant", true}, {"mirror", false}};
    c->add_option("--env-direction", dominant,
                  "under an environment, where the split-sum rows (every method but sh and vmf "
                  "with --vmf-environment sh) read the prefiltered radiance: dominant (the "
                  "lobe's centroid, bent from the mirror direction towards the normal at grazing "
                  "views) or mirror (the reflection of the view, the split sum as Karis wrote it)")
        ->transform(CLI::CheckedTransformer(names).description(""))
        ->type_name("NAME")
        ->default_str("dominant");
}

void addEnvTruthOption(CLI::App* c, EnvironmentTruth& truth, const char* byDefault) {
    const std::map<std::string, EnvironmentTruth> names = {
        {environmentTruthName(EnvironmentTruth::Sampled), EnvironmentTruth::Sampled},
        {environmentTruthName(EnvironmentTruth::Table), EnvironmentTruth::Table}};
    c->add_option("--env-truth", truth,
                  "under an environment, the ground truth: sampled (--spp samples per pixel) or "
                  "table (where an orthographic view of a plane fixes every direction but the "
                  "normal's: the light each normal reflects, --spp samples per node of a grid "
                  "over the normals, integrated over each pixel's texels; far less noise)")
        ->transform(CLI::CheckedTransformer(names).description(""))
        ->type_name("NAME")
        ->default_str(byDefault);
}

void addShLightingOptions(CLI::App* c, SpecularCosine& cosine, int& order) {
    std::map<std::string, SpecularCosine> names;
    for (SpecularCosine each : {SpecularCosine::Reflecting, SpecularCosine::MeanNormal,
                                SpecularCosine::HalfVector, SpecularCosine::None})
        names[specularCosineName(each)] = each;
    c->add_option("--sh-cosine", cosine,
                  "under an environment, the specular cosine of SH lighting (sh, vmf with "
                  "--vmf-environment sh): reflecting (the normals' that reflect the light into "
                  "the view), mean-normal (the mean normal's; Han et al. footnote 5), half-vector "
                  "or none (eq. 36 as printed)")
        ->transform(CLI::CheckedTransformer(names).description(""))
        ->type_name("NAME")
        ->default_str("reflecting");
    c->add_option("--env-sh-order", order,
                  "under an environment, the order of SH lighting (sh, vmf with --vmf-environment "
                  "sh): the paper's 8; higher orders resolve sharp lobes under small bright lights "
                  "(up to 30 on the CPU, 10 with --gpu)")
        ->check(CLI::Range(1, kMaxShOrder))
        ->capture_default_str();
}

void addShViewsOption(CLI::App* c, int& views) {
    c->add_option("--sh-views", views,
                  "under an environment, SH lighting (sh, vmf with --vmf-environment sh) prepared "
                  "for a set of at "
                  "least N views, interpolated at each pixel's own view (0: one view, the image "
                  "centre's; CPU only)")
        ->check(CLI::Range(0, kMaxShViews))
        ->capture_default_str();
}

void EnvironmentShadingArgs::apply(RenderOptions& o) const {
    if (!environmentLodFromString(lod, o.environmentLod))
        throw Failure("--env-lod " + quote(lod) +
                      ": expected log2sigma, filament, unity or unreal");
    if (!environmentWayFromString(vmfWay, o.vmfEnvironment))
        throw Failure("--vmf-environment " + quote(vmfWay) + ": expected prefiltered or sh");
    o.shViews = shViews;
    o.shCosine = shCosine;
    o.environmentShOrder = environmentShOrder;
    o.dominantDirection = dominantDirection;
}

EnvironmentOptions EnvironmentArgs::options(EnvironmentOptions base) const {
    if (!std::isnan(intensity)) base.intensity = intensity;
    if (!std::isnan(rotationDegrees)) base.rotationDegrees = rotationDegrees;
    return base;
}

void EnvironmentArgs::apply(Scene& scene) const {
    if (!path.empty()) {
        scene.environment.path = path;
        scene.environment.options = options();
    } else if (adjusted()) {
        if (scene.environment.path.empty())
            throw Failure("--env-intensity and --env-rotation need --environment or a scene with "
                          "an environment");
        scene.environment.options = options(scene.environment.options);
    }
}

RoughnessMapping roughnessMappingOrFail(const std::string& name) {
    RoughnessMapping mapping;
    if (!roughnessMappingFromString(name, mapping))
        throw Failure("unknown roughness mapping " + quote(name) +
                      " (expected ours, hdrp, filament, godot, unreal)");
    return mapping;
}

} // namespace ndfmip::cli
