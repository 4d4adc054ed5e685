// Pieces every subcommand shares: its registration, the error it throws, decode options.
#pragma once

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <CLI/CLI.hpp>

#include "ndfmip/bake.h"
#include "ndfmip/clock.h" // nowNanoseconds, millisecondsSince
#include "ndfmip/environment_sh_shading.h"
#include "ndfmip/method_parameters.h"
#include "ndfmip/normal_map.h"
#include "ndfmip/render.h"
#include "ndfmip/roughness.h"
#include "ndfmip/scene.h"

namespace ndfmip {
struct RenderOptions; // render.h
}

namespace ndfmip::cli {

// A user-facing failure: main prints "ndfmip: error: <message>" and exits with 1.
struct Failure : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// Each subcommand adds itself to the app (one file per subcommand).
void addBakeCommand(CLI::App& app);
void addInspectCommand(CLI::App& app);
void addLutCommand(CLI::App& app);
void addDemoCommand(CLI::App& app);
void addCompareCommand(CLI::App& app);
void addRenderCommand(CLI::App& app);
void addEvalCommand(CLI::App& app);
void addViewCommand(CLI::App& app);
void addGltfCommand(CLI::App& app);
void addEnvmapCommand(CLI::App& app);

// The options that say how a file's pixels become normals (bake, demo).
struct InputOptions {
    DecodeOptions decode;
    float heightScale = 0.f; // > 0: --height given
    bool clamp = false;
    DecodeOptions resolved() const; // decode with height and address filled in
};
void addInputOptions(CLI::App* command, InputOptions& options);

// The truth surface and the methods' filtering rule (render, eval): --truth, --taps, --lod-bias,
// --lobe-filter, with the renderer's defaults.
struct FilteringArgs {
    std::string truth = "box";
    int taps;
    float lodBias;
    std::string lobeFilter;
    SpecularAntiAliasing specularAntiAliasing;
    FilteringArgs();
    // The options into `o` (truth, taps, lodBias, shadeFilter, specularAntiAliasing); throws on a
    // bad name.
    void apply(RenderOptions& o) const;
};
void addFilteringOptions(CLI::App* command, FilteringArgs& args);

// An environment map lighting the scene (render, eval): --environment, --env-intensity,
// --env-rotation.
struct EnvironmentArgs {
    std::string path;
    float intensity = std::numeric_limits<float>::quiet_NaN();       // NaN: not given
    float rotationDegrees = std::numeric_limits<float>::quiet_NaN(); // NaN: not given
    bool adjusted() const { return !std::isnan(intensity) || !std::isnan(rotationDegrees); }
    // `base` with the given values in place of its own.
    EnvironmentOptions options(EnvironmentOptions base = {}) const;
    // `scene`'s environment replaced by --environment, or its intensity and rotation changed;
    // throws when these are given without any environment.
    void apply(Scene& scene) const;
};
void addEnvironmentOptions(CLI::App* command, EnvironmentArgs& args);

// How the methods shade under an environment (render): --env-lod RULE, --vmf-environment WAY,
// --sh-views N.
struct EnvironmentShadingArgs {
    std::string lod = "filament";
    std::string vmfWay = "prefiltered";
    int shViews = 0;
    SpecularCosine shCosine = SpecularCosine::Reflecting;
    int environmentShOrder = 8;
    bool dominantDirection = true;
    // The choices into `o`; throws on an unknown name.
    void apply(RenderOptions& o) const;
};
void addEnvironmentShadingOptions(CLI::App* command, EnvironmentShadingArgs& args);
// --sh-views N alone (eval; render takes it with the options above).
void addShViewsOption(CLI::App* command, int& views);
// --sh-cosine NAME and --env-sh-order N (render and eval): SH lighting's specular cosine and order.
void addShLightingOptions(CLI::App* command, SpecularCosine& cosine, int& order);
// --env-direction dominant|mirror: where the split-sum rows read the prefiltered radiance.
void addEnvDirectionOption(CLI::App* command, bool& dominant);
// --env-truth sampled|table (render and eval): how the ground truth under an environment is made;
// `byDefault` names `truth`'s initial value for the help.
void addEnvTruthOption(CLI::App* command, EnvironmentTruth& truth, const char* byDefault);

// The methods' own options a command takes (`use`: a ParameterCommand bit), registered from
// their parameter tables: one option per flag, its range and help from the table.
struct MethodParameterArgs {
    std::map<std::string, int64_t> integers; // by key: what the parser fills
    std::map<std::string, double> numbers;
    std::map<std::string, float> floats;
    std::map<std::string, CLI::Option*> options;
    // The values given on the command line (Float ones at float precision, as the bake keeps them).
    ParameterValues given() const;
    // The value of `key` for `method`: given, or the table's default.
    double value(Method method, const std::string& key) const;
};
void addMethodParameterOptions(CLI::App* command, unsigned use, MethodParameterArgs& args);

// Warns on stderr about suspicious normals that decoding found in `path`.
void warnAboutDecode(const std::string& path, const DecodeReport& report);

// Loads and decodes a normal map, warns on stderr about suspicious normals, throws on error.
Image loadNormalsOrFail(const std::string& path, const DecodeOptions& decode, bool quiet,
                        DecodeReport* report = nullptr);

// An albedo (colour) map as linear RGB, 3 channels: 8/16-bit files are sRGB-decoded, EXR is taken
// as linear. Throws unless it has `width` x `height` texels and 3 or 4 channels.
SharedImage loadAlbedoOrFail(const std::string& path, int width, int height);

// ours, hdrp, filament, godot or unreal (roughness.h); throws on anything else.
RoughnessMapping roughnessMappingOrFail(const std::string& name);

// Adds a finite-number check to every floating-point option of `app` and its subcommands, so
// "nan" and "inf" fail like any other out-of-range value (CLI::Range lets NaN through, and
// every comparison with NaN is false). Call once every subcommand is registered.
void requireFiniteNumbers(CLI::App& app);

// The options that raise the input limits (limits.h): --max-pixels and --max-memory.
void addLimitOptions(CLI::App& app);

// A bake of `method` with `options` over a width x height map within the memory limit, or throws.
void checkBakeMemoryOrFail(const std::string& name, Method method, const BakeOptions& options,
                           int width, int height);

// A short "\r<label> k/n" progress line on stderr when it is a terminal.
void showProgress(const char* label, int done, int total);

} // namespace ndfmip::cli
