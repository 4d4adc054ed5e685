// ndfmip bake IN --method M -o DIR: per-level parameter images and a manifest.
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <set>
#include <tuple>

#include "cli.h"
#include "ndfmip/engine_presets.h"
#include "ndfmip/bake.h"
#include "ndfmip/io.h"
#include "ndfmip/render.h"
#include "ndfmip/spherical_harmonics.h"
#include "ndfmip/toksvig.h"

namespace ndfmip::cli {
namespace {

struct BakeArgs {
    std::string input, output, method = "toksvig", gloss, exportFormat;
    std::string exportTextures = "normal,roughness,planes", normalFormat = "bc5", roughnessFormat = "bc4";
    int zstd = 0;
    InputOptions input_options;
    float maxExponent = 0.f;
    float baseRoughness = 0.f;
    std::string roughnessMap, roughnessChannel = "r", roughnessEncoding = "perceptual";
    std::string engine, metallicChannel, occlusionChannel; // channels of the roughness map
    int order = 0; // sh: 0 = the default l* = 7
    int lobes = 0; // vmf: 0 = the default J = 4
    std::string albedo; // vmf: colour per lobe
    float coherence = 0.f;
    float lobeBudget = 0.f;
    int maxIterations = 50;
    double tolerance = 1e-5;
    bool half = false;
    bool quiet = false;
};

void applyGlossOrFail(Image& normals, const BakeArgs& a) {
    Result<SourceImage> gloss = loadImage(a.gloss);
    if (!gloss) throw Failure(gloss.error().message);
    const Image& g = gloss->image;
    if (g.width != normals.width || g.height != normals.height)
        throw Failure(a.gloss + ": gloss map is " + std::to_string(g.width) + "x" +
                      std::to_string(g.height) + " but the normal map is " +
                      std::to_string(normals.width) + "x" + std::to_string(normals.height));
    for (size_t i = 0; i < g.texelCount(); ++i)
        if (!std::isfinite(g.pixels[i * g.channels]))
            throw Failure(a.gloss + ": NaN or infinite gloss value at texel (" +
                          std::to_string(i % g.width) + ", " + std::to_string(i / g.width) + ")");
    applyGlossMap(normals, g, a.maxExponent);
}

// The roughness map (a packed material map), read once for all the channels taken from it.
SourceImage loadMaterialMapOrFail(const BakeArgs& a, int width, int height) {
    Result<SourceImage> map = loadImage(a.roughnessMap);
    if (!map) throw Failure(map.error().message);
    const Image& image = map->image;
    if (image.width != width || image.height != height)
        throw Failure(a.roughnessMap + ": roughness map is " + std::to_string(image.width) + "x" +
                      std::to_string(image.height) + " but the normal map is " + std::to_string(width) + "x" +
                      std::to_string(height));
    return std::move(map.value());
}

// One channel (r, g, b or a) of the material map, clamped to [0, 1]; `option` names it in messages.
std::shared_ptr<Image> materialChannelOrFail(const BakeArgs& a, const Image& map, const std::string& channelName,
                                             const char* option) {
    const int channel = int(std::string("rgba").find(channelName[0]));
    if (channel >= map.channels)
        throw Failure(a.roughnessMap + ": " + option + " " + channelName + " but the map has " +
                      std::to_string(map.channels) + " channel(s)");
    auto out = std::make_shared<Image>(map.width, map.height, 1);
    for (size_t i = 0; i < map.texelCount(); ++i) {
        const float v = map.pixels[i * size_t(map.channels) + size_t(channel)];
        if (!std::isfinite(v))
            throw Failure(a.roughnessMap + ": NaN or infinite value at texel (" + std::to_string(i % size_t(map.width)) +
                          ", " + std::to_string(i / size_t(map.width)) + ") in " + option);
        out->pixels[i] = std::clamp(v, 0.f, 1.f);
    }
    return out;
}

// The material's alpha per texel: the roughness channel perceptual (alpha = p^2: glTF, Unreal,
// Filament), alpha, or Unity's smoothness (alpha = (1 - s)^2).
SharedImage roughnessAlphaOrFail(const BakeArgs& a, const Image& map) {
    std::shared_ptr<Image> alpha = materialChannelOrFail(a, map, a.roughnessChannel, "--roughness-channel");
    for (float& x : alpha->pixels)
        x = a.roughnessEncoding == "alpha" ? x : a.roughnessEncoding == "smoothness" ? (1.f - x) * (1.f - x) : x * x;
    return alpha;
}

// A comma-separated list of words from `allowed`.
std::set<std::string> commaListOrFail(const std::string& list, const char* option, const std::set<std::string>& allowed) {
    std::set<std::string> words;
    for (std::string rest = list;;) {
        const size_t comma = rest.find(',');
        const std::string word = rest.substr(0, comma);
        if (!allowed.count(word)) {
            std::string expected;
            for (const std::string& w : allowed) expected += (expected.empty() ? "" : ", ") + w;
            throw Failure(std::string(option) + " " + quote(word) + ": expected " + expected + " (comma-separated)");
        }
        words.insert(word);
        if (comma == std::string::npos) return words;
        rest = rest.substr(comma + 1);
    }
}

void runBake(const BakeArgs& a) {
    auto method = methodFromString(a.method);
    if (!method) throw Failure("unknown method " + quote(a.method) + " (" + methodNames() + ")");
    if (a.order != 0 && *method != Method::Sh) throw Failure("--order applies to --method sh only");
    if (a.lobes != 0 && *method != Method::Vmf) throw Failure("--lobes applies to --method vmf only");
    if (!a.albedo.empty() && *method != Method::Vmf) throw Failure("--albedo applies to --method vmf only");
    if (a.coherence != 0.f && *method != Method::Vmf) throw Failure("--coherent applies to --method vmf only");
    if (a.lobeBudget != 0.f && *method != Method::Vmf) throw Failure("--lobe-budget applies to --method vmf only");
    if (a.lobeBudget != 0.f && a.coherence != 0.f) throw Failure("--lobe-budget does not apply to coherent lobes");
    // Without --export the bake is the EXR planes; with it, exactly what it lists.
    std::set<std::string> exports =
        commaListOrFail(a.exportFormat.empty() ? "exr" : a.exportFormat, "--export", {"png16", "ktx2", "dds", "exr"});
    const std::set<std::string> textures =
        commaListOrFail(a.exportTextures, "--export-textures", {"normal", "roughness", "planes"});
    if (a.zstd != 0 && !exports.count("ktx2")) throw Failure("--zstd supercompresses KTX2 files: add ktx2 to --export");
    const EnginePreset* engine = nullptr;
    if (!a.engine.empty()) {
        engine = findEnginePreset(a.engine);
        if (!engine) throw Failure("--engine " + quote(a.engine) + ": expected " + enginePresetNames());
        if (*method != Method::Toksvig && *method != Method::Naive)
            throw Failure("--engine writes a normal map and a roughness map: --method toksvig (or naive)");
        if (!exports.count("ktx2") && !exports.count("dds")) exports.insert("ktx2");
    }
    if (exports.count("png16") && (*method == Method::Sh || *method == Method::Vmf || *method == Method::Lean))
        throw Failure("--export png16 needs a method that stores a normal (naive, toksvig)");
    if (!a.roughnessMap.empty() && *method != Method::Toksvig)
        throw Failure("--roughness-map applies to --method toksvig (its roughness planes)");
    if (!a.roughnessMap.empty() && a.baseRoughness != 0.f)
        throw Failure("--roughness-map and --base-roughness both set the material's roughness: give one");
    if (!a.gloss.empty() && a.maxExponent <= 0.f)
        throw Failure("--gloss needs --max-exponent S0 (the exponent of gloss 1.0)");
    DecodeOptions decode = a.input_options.resolved();
    recoverInterruptedBake(a.output);

    long long start = nowNanoseconds();
    DecodeReport report;
    Image normals = loadNormalsOrFail(a.input, decode, a.quiet, &report);
    if (!a.gloss.empty()) applyGlossOrFail(normals, a);
    double decodeMs = millisecondsSince(start);

    start = nowNanoseconds();
    const int width = normals.width, height = normals.height;
    Pyramid pyramid = buildPyramid(std::make_shared<const Image>(std::move(normals)));
    BakeOptions options;
    options.baseRoughness = a.baseRoughness;
    if (a.order != 0) options.shOrder = a.order;
    if (a.lobes != 0) options.vmfLobes = a.lobes;
    options.vmfMaxIterations = a.maxIterations;
    options.vmfTolerance = a.tolerance;
    options.vmfCoherence = a.coherence;
    options.vmfLobeBudget = a.lobeBudget;
    if (!a.albedo.empty()) options.albedo = loadAlbedoOrFail(a.albedo, width, height);
    std::optional<SourceImage> materialMap;
    if (!a.roughnessMap.empty()) {
        materialMap = loadMaterialMapOrFail(a, width, height);
        options.roughnessMap = roughnessAlphaOrFail(a, materialMap->image);
    }
    if (!a.quiet) options.progress = [](int done, int total) { showProgress("bake: level", done, total); };
    checkBakeMemoryOrFail(a.input, *method, options, width, height);
    Bake bake = bakeMethod(*method, pyramid, options);
    if (!a.gloss.empty()) bake.parameters["max_exponent"] = a.maxExponent;
    double bakeMs = millisecondsSince(start);

    start = nowNanoseconds();
    Result<std::string> hash = sha256File(a.input);
    if (!hash) throw Failure(hash.error().message);
    BakeSource source{a.input, hash.value(), width, height, decode, a.gloss};
    BakeWriteOptions write;
    write.exr = exports.count("exr") > 0;
    write.png16 = exports.count("png16") > 0;
    write.exportNormal = textures.count("normal") > 0;
    write.exportRoughness = textures.count("roughness") > 0;
    write.exportPlanes = textures.count("planes") > 0;
    write.normalFormat = *textureFormatFromName(a.normalFormat);
    write.roughnessFormat = *textureFormatFromName(a.roughnessFormat);
    write.zstdLevel = a.zstd;
    write.ktx2 = exports.count("ktx2") > 0;
    write.dds = exports.count("dds") > 0;
    write.engine = engine;
    // Metallic and occlusion are linear: their mips are footprint means, as an albedo map's.
    for (const auto& [channel, option, chain] :
         {std::tuple{&a.metallicChannel, "--metallic-channel", &write.metallic},
          std::tuple{&a.occlusionChannel, "--occlusion-channel", &write.occlusion}}) {
        if (channel->empty()) continue;
        if (!materialMap)
            throw Failure(std::string(option) + " reads a channel of --roughness-map, which is not given");
        *chain = albedoMips(pyramid, materialChannelOrFail(a, materialMap->image, *channel, option));
    }
    write.half = a.half;
    Status status = writeBake(a.output, bake, source, write);
    if (!status) throw Failure(status.error);
    double writeMs = millisecondsSince(start);

    if (!a.quiet) {
        std::printf("%-8s: %dx%d, %zu levels -> %s (decode %.1f ms, bake %.1f ms, write %.1f ms; "
                    "%zu normals more than 10%% off unit length)\n",
                    methodName(*method), width, height, bake.levels.size(), a.output.c_str(),
                    decodeMs, bakeMs, writeMs, report.offUnitLength);
        if (*method == Method::Vmf)
            std::printf("vmf     : J = %d lobes (%.2f used per texel on average), EM iterations per texel %.2f on "
                        "average, %g at most, %g texels stopped at --max-iterations; lobe mismatch %.2f degrees "
                        "(coherence %g)\n",
                        bakeVmfLobes(bake), bake.parameters.at("mean_lobes"), bake.parameters.at("em_mean_iterations"),
                        bake.parameters.at("em_most_iterations"), bake.parameters.at("em_not_converged"),
                        bake.parameters.at("lobe_mismatch_degrees"), bake.parameters.at("coherence"));
        if (*method == Method::Sh) {
            const int order = bakeShOrder(bake);
            const int planes = shPlaneCount(order);
            std::printf("sh      : l* = %d, %d coefficients in %d planes: %d bytes per texel of level 0 "
                        "(%.1f with every level) in memory, %d on disk before compression\n",
                        order, shCount(order), planes, planes * 16, planes * 16 * 4.0 / 3.0,
                        planes * (a.half ? 8 : 16));
        }
    }
}

} // namespace

void addBakeCommand(CLI::App& app) {
    auto args = std::make_shared<BakeArgs>();
    CLI::App* c = app.add_subcommand("bake", "filter a normal map into a per-level bake directory");
    c->add_option("input", args->input, "normal map (PNG 8/16-bit, JPEG, TGA, OpenEXR)")->required();
    c->add_option("-o,--output", args->output, "output directory")->required();
    c->add_option("--method", args->method, methodSummaries())->capture_default_str();
    c->add_option("--order", args->order, "sh: highest band l* ((l*+1)^2 coefficients; default 7)")
        ->check(CLI::Range(1, kMaxShOrder));
    c->add_flag("--half", args->half, "store the planes as 16-bit half floats");
    c->add_option("--lobes", args->lobes, "vmf: lobes per texel J (default 4)")->check(CLI::Range(1, 8));
    c->add_option("--albedo", args->albedo, "vmf: colour map (sRGB PNG/JPEG or linear EXR): a colour per lobe");
    c->add_option("--coherent", args->coherence,
                  "vmf: C of the alignment term (eq. 32): lobes fitted top-down, slot j matched across texels")
        ->check(CLI::Range(0.f, 1e6f));
    c->add_option("--lobe-budget", args->lobeBudget,
                  "vmf: merge a texel's lobes while a merge loses at most this much (Runnalls' bound, "
                  "e.g. 0.01): fewer lobes where more buy little; 0 = J everywhere")
        ->check(CLI::Range(0.f, 10.f));
    c->add_option("--max-iterations", args->maxIterations, "vmf: EM iterations per texel at most")
        ->check(CLI::Range(1, 10000))->capture_default_str();
    c->add_option("--tolerance", args->tolerance, "vmf: relative log-likelihood gain that ends EM")
        ->check(CLI::Range(0.0, 1.0))->capture_default_str();
    addInputOptions(c, args->input_options);
    c->add_option("--roughness-map", args->roughnessMap,
                  "toksvig: the material's roughness per texel (same size as the map), combined with the "
                  "normals' variance at every level");
    c->add_option("--roughness-channel", args->roughnessChannel, "the roughness map's channel: r, g, b or a")
        ->check(CLI::IsMember({"r", "g", "b", "a"}))->capture_default_str();
    c->add_option("--roughness-encoding", args->roughnessEncoding,
                  "perceptual (alpha = value^2: glTF, Unreal, Filament), alpha, or smoothness (Unity: alpha = "
                  "(1 - value)^2)")
        ->check(CLI::IsMember({"perceptual", "alpha", "smoothness"}))->capture_default_str();
    c->add_option("--engine", args->engine,
                  "also write an engine's own files (ktx2/dds): its normal map (green convention) and packed material "
                  "map: " + enginePresetNames() + " (docs/ENGINES.md)");
    c->add_option("--metallic-channel", args->metallicChannel, "--engine: metallic from this channel of --roughness-map")
        ->check(CLI::IsMember({"r", "g", "b", "a"}));
    c->add_option("--occlusion-channel", args->occlusionChannel,
                  "--engine: ambient occlusion from this channel of --roughness-map")
        ->check(CLI::IsMember({"r", "g", "b", "a"}));
    c->add_option("--gloss", args->gloss, "gloss map in [0,1]: s = gloss * S0 (Toksvig eq. 12)");
    c->add_option("--max-exponent", args->maxExponent, "S0, the exponent of gloss 1.0")
        ->check(CLI::Range(1e-3f, 1e6f));
    c->add_option("--base-roughness", args->baseRoughness,
                  "GGX/Beckmann alpha of the material before filtering")
        ->check(CLI::Range(0.f, 1.f))->capture_default_str();
    c->add_option("--export", args->exportFormat,
                  "what to write, comma-separated: exr (the planes that render, inspect and eval read; the "
                  "default), png16 (16-bit PNG per level), ktx2 and dds (normal, roughness and every linear plane, "
                  "all levels in one file each). Only what is listed is written: e.g. --export ktx2 writes no EXR");
    c->add_option("--export-textures", args->exportTextures,
                  "what the png16/ktx2/dds files hold, comma-separated: normal, roughness, planes")
        ->capture_default_str();
    c->add_option("--normal-format", args->normalFormat, "the exported normal: bc5, rg16 or rgba8")
        ->check(CLI::IsMember({"bc5", "rg16", "rgba8"}))->capture_default_str();
    c->add_option("--roughness-format", args->roughnessFormat, "the exported roughness: bc4 or r16f")
        ->check(CLI::IsMember({"bc4", "r16f"}))->capture_default_str();
    c->add_option("--zstd", args->zstd, "ktx2: Zstandard supercompression level 1-22 (0: none)")
        ->check(CLI::Range(0, 22))->capture_default_str();
    c->add_flag("-q,--quiet", args->quiet, "print nothing but errors");
    c->callback([args] { runBake(*args); });
}

} // namespace ndfmip::cli
