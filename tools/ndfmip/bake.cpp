// ndfmip bake IN --method M -o DIR: per-level parameter images and a manifest.
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <thread>

#include <glob.h>
#include <omp.h>
#include <unistd.h>

#include <nlohmann/json.hpp>
#include <cstdio>
#include <memory>
#include <optional>
#include <set>
#include <tuple>

#include "cli.h"
#include "io/input_file.h"
#include "ndfmip/limits.h"
#include "ndfmip/engine_presets.h"
#include "ndfmip/bake.h"
#include "ndfmip/io.h"
#include "ndfmip/render.h"
#include "ndfmip/spherical_harmonics.h"
#include "ndfmip/toksvig.h"

namespace ndfmip::cli {
namespace {

struct BakeArgs {
    std::vector<std::string> inputs; // files, folders, globs
    std::string input, output, method = "toksvig", gloss, exportFormat; // input/output: the map at hand
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
    // Batch: parallel maps, rebake up-to-date ones, shard, JSON lines.
    int jobs = 1;
    bool force = false;
    bool json = false;
    std::string shard;
    int shards = 0;
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

// The options' checks that do not depend on the map; throws on the first problem.
void checkBakeOptionsOrFail(const BakeArgs& a) {
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
}

// Everything that decides a bake's files besides the map itself, as canonical JSON: two runs
// with the same text, the same sources and the same version write the same files.
std::string optionsText(const BakeArgs& a) {
    const DecodeOptions d = a.input_options.resolved();
    const nlohmann::json options = {
        {"method", a.method}, {"order", a.order}, {"lobes", a.lobes}, {"coherent", a.coherence},
        {"lobe_budget", a.lobeBudget}, {"max_iterations", a.maxIterations}, {"tolerance", a.tolerance},
        {"half", a.half}, {"max_exponent", a.maxExponent}, {"base_roughness", a.baseRoughness},
        {"roughness_channel", a.roughnessChannel}, {"roughness_encoding", a.roughnessEncoding},
        {"engine", a.engine}, {"metallic_channel", a.metallicChannel}, {"occlusion_channel", a.occlusionChannel},
        {"export", a.exportFormat}, {"export_textures", a.exportTextures}, {"normal_format", a.normalFormat},
        {"roughness_format", a.roughnessFormat}, {"zstd", a.zstd},
        {"green_down", d.greenDown}, {"two_channel", d.twoChannel}, {"signed", d.signedValues},
        {"height", d.height}, {"height_scale", d.heightScale}, {"clamp", d.address == AddressMode::Clamp}};
    return options.dump();
}

// The bake's cache key: SHA-256 over the version, the options and every source file's SHA-256.
std::string cacheKeyOrFail(const BakeArgs& a, const std::string& sourceHash) {
    std::string text = std::string("ndfmip ") + NDFMIP_VERSION + "\n" + optionsText(a) + "\nsource " + sourceHash;
    for (const auto& [name, path] : {std::pair{"gloss", &a.gloss}, {"albedo", &a.albedo}, {"roughness_map", &a.roughnessMap}})
        if (!path->empty()) {
            Result<std::string> hash = sha256File(*path);
            if (!hash) throw Failure(hash.error().message);
            text += std::string("\n") + name + " " + hash.value();
        }
    return sha256Text(text);
}

// Whether DIR holds a bake with this cache key (any problem reading it: no).
bool upToDate(const std::string& dir, const std::string& key) {
    Result<std::string> text = readRegularFile(dir + "/manifest.json", inputLimits().maxTextFileBytes);
    if (!text) return false;
    Result<LoadedBake> bake = parseBakeManifest(text.value(), dir);
    return bake && bake->source.cacheKey == key;
}

enum class MapStatus { Baked, Skipped };

// Bakes a.input into a.output (parent folders created); skips it when a.output already holds a
// bake with the same cache key, unless --force. Throws Failure on a problem with this map.
MapStatus bakeOne(const BakeArgs& a) {
    const auto method = methodFromString(a.method);
    std::set<std::string> exports =
        commaListOrFail(a.exportFormat.empty() ? "exr" : a.exportFormat, "--export", {"png16", "ktx2", "dds", "exr"});
    const std::set<std::string> textures =
        commaListOrFail(a.exportTextures, "--export-textures", {"normal", "roughness", "planes"});
    const EnginePreset* engine = a.engine.empty() ? nullptr : findEnginePreset(a.engine);
    if (engine && !exports.count("ktx2") && !exports.count("dds")) exports.insert("ktx2");
    DecodeOptions decode = a.input_options.resolved();
    recoverInterruptedBake(a.output);
    Result<std::string> hash = sha256File(a.input);
    if (!hash) throw Failure(hash.error().message);
    const std::string key = cacheKeyOrFail(a, hash.value());
    if (!a.force && upToDate(a.output, key)) return MapStatus::Skipped;
    {
        std::error_code ec;
        const std::filesystem::path parent = std::filesystem::path(a.output).lexically_normal().parent_path();
        // Only a missing folder is made (writeBake names a parent that is a file). Another map of
        // the batch may create it at the same moment: what counts is that it exists.
        if (!parent.empty() && !std::filesystem::exists(parent, ec) && !std::filesystem::create_directories(parent, ec) &&
            !std::filesystem::is_directory(parent, ec))
            throw Failure(a.output + ": cannot create the folder " + parent.string() + " (" + ec.message() + ")");
    }

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
    BakeSource source{a.input, hash.value(), width, height, decode, a.gloss, key};
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
    return MapStatus::Baked;
}

// ---- many maps --------------------------------------------------------------------------------

const char* kImageExtensions[] = {".png", ".jpg", ".jpeg", ".tga", ".bmp", ".exr"};

bool isImageFile(const std::filesystem::path& path) {
    std::string ext = path.extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    for (const char* known : kImageExtensions)
        if (ext == known) return true;
    return false;
}

// Files as given, the image files directly inside folders (sorted), and globs expanded by
// glob(3) for callers whose shell did not (farm job specs, Python).
std::vector<std::string> expandInputsOrFail(const std::vector<std::string>& inputs, bool* expanded) {
    std::vector<std::string> maps;
    *expanded = false;
    for (const std::string& input : inputs) {
        std::error_code ec;
        if (std::filesystem::is_directory(input, ec)) {
            *expanded = true;
            std::vector<std::string> inside;
            for (const auto& entry : std::filesystem::directory_iterator(input, ec))
                if (entry.is_regular_file(ec) && isImageFile(entry.path())) inside.push_back(entry.path().string());
            if (ec) throw Failure(input + ": cannot list the folder (" + ec.message() + ")");
            if (inside.empty()) throw Failure(input + ": the folder holds no image files (png, jpg, tga, bmp, exr)");
            std::sort(inside.begin(), inside.end());
            maps.insert(maps.end(), inside.begin(), inside.end());
        } else if (input.find_first_of("*?[") != std::string::npos && !std::filesystem::exists(input, ec)) {
            *expanded = true;
            glob_t found{};
            const int rc = ::glob(input.c_str(), 0, nullptr, &found);
            for (size_t i = 0; rc == 0 && i < found.gl_pathc; ++i) maps.emplace_back(found.gl_pathv[i]);
            ::globfree(&found);
            if (rc != 0) throw Failure(quote(input) + ": no file matches");
        } else {
            maps.push_back(input);
        }
    }
    return maps;
}

// The output pattern with {stem} (file name without extension), {name} (with it) and {parent}
// (the folder's name) of `input`.
std::string outputFor(const std::string& pattern, const std::string& input) {
    const std::filesystem::path path(input);
    const std::pair<std::string, std::string> fields[] = {
        {"{stem}", path.stem().string()},
        {"{name}", path.filename().string()},
        {"{parent}", path.parent_path().filename().string()}};
    std::string out = pattern;
    for (const auto& [field, value] : fields)
        for (size_t at = out.find(field); at != std::string::npos; at = out.find(field, at + value.size()))
            out.replace(at, field.size(), value);
    return out;
}

// Which shard a map belongs to: FNV-1a of its path as given, so the split is the same on every
// machine and a map's shard does not move when others are added.
int shardOf(const std::string& input, int shards) {
    uint64_t h = 1469598103934665603ull;
    for (unsigned char c : input) h = (h ^ c) * 1099511628211ull;
    return int(h % uint64_t(shards));
}

// --shard i/N, or --shards N with i from an indexed job's environment (Kubernetes Indexed Job,
// Slurm array); {0, 1} without either.
std::pair<int, int> shardOrFail(const BakeArgs& a) {
    if (!a.shard.empty() && a.shards != 0) throw Failure("--shard and --shards both pick the shard: give one");
    int index = 0, count = 1;
    if (!a.shard.empty()) {
        char extra = 0;
        if (std::sscanf(a.shard.c_str(), "%d/%d%c", &index, &count, &extra) != 2 || count < 1 || index < 0 ||
            index >= count)
            throw Failure("--shard " + quote(a.shard) + ": expected I/N with 0 <= I < N");
        return {index, count};
    }
    if (a.shards == 0) return {0, 1};
    auto fromEnv = [](const char* name) -> std::optional<long> {
        const char* v = std::getenv(name);
        if (!v || !*v) return std::nullopt;
        char* end = nullptr;
        const long n = std::strtol(v, &end, 10);
        if (*end) throw Failure(std::string(name) + "=" + quote(v) + " is not an integer");
        return n;
    };
    std::optional<long> i = fromEnv("JOB_COMPLETION_INDEX");
    if (!i) {
        i = fromEnv("SLURM_ARRAY_TASK_ID");
        if (i) i = *i - fromEnv("SLURM_ARRAY_TASK_MIN").value_or(0);
    }
    if (!i) throw Failure("--shards needs JOB_COMPLETION_INDEX or SLURM_ARRAY_TASK_ID in the environment, or --shard I/N");
    if (*i < 0 || *i >= a.shards)
        throw Failure("shard index " + std::to_string(*i) + " from the environment is not below --shards " +
                      std::to_string(a.shards));
    return {int(*i), a.shards};
}

struct MapResult {
    std::string input, output, status, error;
    double seconds = 0.0;
};

void runBake(const BakeArgs& args) {
    checkBakeOptionsOrFail(args);
    bool expanded = false; // a folder or a glob: many maps, whatever their number
    const std::vector<std::string> inputs = expandInputsOrFail(args.inputs, &expanded);
    const bool pattern = args.output.find('{') != std::string::npos;
    if (inputs.size() == 1 && !expanded && !pattern && args.shard.empty() && args.shards == 0 && !args.json) {
        BakeArgs one = args; // one map: its errors are the command's
        one.input = inputs.front();
        if (bakeOne(one) == MapStatus::Skipped && !args.quiet)
            std::printf("%s: up to date (same source, options and version; --force bakes again)\n", args.output.c_str());
        return;
    }
    if ((inputs.size() > 1 || expanded) && args.output.find("{stem}") == std::string::npos &&
        args.output.find("{name}") == std::string::npos)
        throw Failure("-o " + quote(args.output) + ": with " + std::to_string(inputs.size()) + " map(s) from " +
                      (expanded ? "a folder or glob" : "several inputs") +
                      ", -o needs {stem} or {name}, e.g. -o 'out/{stem}.bake'");
    const auto [shard, shards] = shardOrFail(args);
    std::vector<MapResult> jobs;
    std::map<std::string, std::string> outputs; // output -> the map writing it
    for (const std::string& input : inputs) {
        const std::string output = outputFor(args.output, input);
        const std::string normal = std::filesystem::path(output).lexically_normal().string();
        if (auto [it, fresh] = outputs.emplace(normal, input); !fresh)
            throw Failure(quote(it->second) + " and " + quote(input) + " would both be baked to " + quote(output) +
                          "; use {parent} or {name} in -o");
        if (shardOf(input, shards) == shard) jobs.push_back({input, output, "", "", 0.0});
    }

    std::mutex lock;
    std::atomic<size_t> next{0};
    size_t done = 0, failed = 0;
    const bool bar = !args.quiet && !args.json && isatty(2);
    const long long start = nowNanoseconds();
    const int workers = std::max(1, std::min(args.jobs, int(jobs.size())));
    const int cores = int(std::max(1u, std::thread::hardware_concurrency()));
    auto work = [&] {
        omp_set_num_threads(std::max(1, cores / workers)); // the maps share the cores
        for (size_t i; (i = next++) < jobs.size();) {
            MapResult& r = jobs[i];
            BakeArgs one = args;
            one.input = r.input;
            one.output = r.output;
            one.quiet = true;
            const long long t0 = nowNanoseconds();
            try {
                r.status = bakeOne(one) == MapStatus::Skipped ? "skipped" : "baked";
            } catch (const std::exception& e) { // one map's failure never stops the others
                r.status = "failed";
                r.error = e.what();
            }
            r.seconds = millisecondsSince(t0) / 1000.0;
            std::lock_guard<std::mutex> guard(lock);
            ++done;
            failed += r.status == "failed";
            if (args.json) {
                nlohmann::json line = {{"map", r.input}, {"output", r.output}, {"status", r.status}, {"seconds", r.seconds}};
                if (!r.error.empty()) line["error"] = r.error;
                std::printf("%s\n", line.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace).c_str());
                std::fflush(stdout);
            } else if (bar) {
                const double elapsed = millisecondsSince(start) / 1000.0;
                const int width = 30, filled = int(double(width) * double(done) / double(jobs.size()));
                std::fprintf(stderr, "\rbake [%s%s] %zu/%zu maps, %zu failed, %.0f s left   ", std::string(size_t(filled), '#').c_str(),
                             std::string(size_t(width - filled), '.').c_str(), done, jobs.size(), failed,
                             elapsed / double(done) * double(jobs.size() - done));
                std::fflush(stderr);
            }
        }
    };
    std::vector<std::thread> threads;
    for (int t = 1; t < workers; ++t) threads.emplace_back(work);
    work();
    for (std::thread& t : threads) t.join();
    if (bar) std::fprintf(stderr, "\n");

    size_t baked = 0, skipped = 0;
    std::vector<std::string> failures;
    for (const MapResult& r : jobs) {
        baked += r.status == "baked";
        skipped += r.status == "skipped";
        if (r.status == "failed") failures.push_back(r.input);
    }
    const double seconds = millisecondsSince(start) / 1000.0;
    if (args.json) {
        const nlohmann::json summary = {{"summary", {{"maps", jobs.size()}, {"baked", baked}, {"skipped", skipped},
                                                     {"failed", failures.size()}, {"failures", failures},
                                                     {"seconds", seconds}, {"shard", shard}, {"shards", shards}}}};
        std::printf("%s\n", summary.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace).c_str());
    } else if (!args.quiet) {
        std::printf("bake: %zu maps%s: %zu baked, %zu up to date, %zu failed (%.2f s, %d at a time)\n", jobs.size(),
                    shards > 1 ? (" (shard " + std::to_string(shard) + "/" + std::to_string(shards) + ")").c_str() : "",
                    baked, skipped, failures.size(), seconds, workers);
    }
    if (!args.json)
        for (const MapResult& r : jobs)
            if (r.status == "failed") std::fprintf(stderr, "  failed: %s\n", r.error.c_str());
    if (!failures.empty())
        throw Failure(std::to_string(failures.size()) + " of " + std::to_string(jobs.size()) + " maps failed");
}

} // namespace

void addBakeCommand(CLI::App& app) {
    auto args = std::make_shared<BakeArgs>();
    CLI::App* c = app.add_subcommand("bake", "filter a normal map into a per-level bake directory");
    c->add_option("input", args->inputs,
                  "normal map(s) (PNG 8/16-bit, JPEG, TGA, OpenEXR): files, folders (their image files) or quoted globs")
        ->required();
    c->add_option("-o,--output", args->output,
                  "output directory; for many maps a pattern with {stem}, {name} or {parent}, e.g. 'out/{stem}.bake' "
                  "(parent folders are created)")
        ->required();
    c->add_option("-j,--jobs", args->jobs, "maps baked at once (each with its share of the cores)")
        ->check(CLI::Range(1, 256))->capture_default_str();
    c->add_flag("--force", args->force, "bake even where the output holds a bake of the same source, options and version");
    c->add_flag("--json", args->json, "one JSON line per map (map, output, status, seconds, error) and a summary line");
    c->add_option("--shard", args->shard, "bake only shard I of N (I/N, 0-based; maps split by a hash of their path)");
    c->add_option("--shards", args->shards,
                  "N shards, this one's index from JOB_COMPLETION_INDEX (Kubernetes) or SLURM_ARRAY_TASK_ID (Slurm)")
        ->check(CLI::Range(1, 1000000));
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
