// A map file baked into a bake folder, as `ndfmip bake` does it: checks, cache key, decode,
// extra maps, bake, write. Problems deep inside throw BakeProblem, caught at the boundary.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <new>
#include <optional>
#include <set>
#include <tuple>

#include <nlohmann/json.hpp>

#include "io/input_file.h"
#include "ndfmip/bake_file.h"
#include "ndfmip/clock.h"
#include "ndfmip/engine_presets.h"
#include "ndfmip/io.h"
#include "ndfmip/limits.h"
#include "ndfmip/method_parameters.h"
#include "ndfmip/paths.h"
#include "ndfmip/render.h"
#include "ndfmip/spherical_harmonics.h"
#include "ndfmip/toksvig.h"
#include "ndfmip/vmf.h"

namespace ndfmip {
namespace {

struct BakeProblem {
    std::string message;
};

[[noreturn]] void failBake(std::string message) {
    throw BakeProblem{std::move(message)};
}

// The method parameters a bake written to files uses (method_parameters.h's fileDefault; an
// unknown method keeps those given, and the checks name it).
ParameterValues fileParameters(const BakeFileOptions& a) {
    const auto method = methodFromString(a.method);
    return method ? fileParameterValues(*method, a.parameters) : a.parameters;
}

// A comma-separated list of words from `allowed`.
std::set<std::string> commaList(const std::string& list, const char* option,
                                const std::set<std::string>& allowed) {
    std::set<std::string> words;
    for (std::string rest = list;;) {
        const size_t comma = rest.find(',');
        const std::string word = rest.substr(0, comma);
        if (!allowed.count(word)) {
            std::string expected;
            for (const std::string& w : allowed) expected += (expected.empty() ? "" : ", ") + w;
            failBake(std::string(option) + " " + quote(word) + ": expected " + expected +
                     " (comma-separated)");
        }
        words.insert(word);
        if (comma == std::string::npos) return words;
        rest = rest.substr(comma + 1);
    }
}

std::set<std::string> exportsOf(const BakeFileOptions& o) {
    std::set<std::string> exports = commaList(o.exportFormat.empty() ? "exr" : o.exportFormat,
                                              "--export", {"png16", "ktx2", "dds", "exr"});
    // An engine's files are KTX2 or DDS: KTX2 unless one of them is asked for.
    if (!o.engine.empty() && !exports.count("ktx2") && !exports.count("dds"))
        exports.insert("ktx2");
    return exports;
}

std::string number(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", value);
    return text;
}

// `value` within [lo, hi] (NaN is not), or a problem naming the option.
void requireRange(const char* option, double value, double lo, double hi) {
    if (!(value >= lo && value <= hi))
        failBake(std::string(option) + " " + number(value) + ": expected " + number(lo) + " .. " +
                 number(hi));
}

void requireOneOf(const char* option, const std::string& value,
                  const std::set<std::string>& allowed) {
    if (allowed.count(value)) return;
    std::string expected;
    for (const std::string& w : allowed) expected += (expected.empty() ? "" : ", ") + w;
    failBake(std::string(option) + " " + quote(value) + ": expected " + expected);
}

void checkFileOptions(const BakeFileOptions& a) {
    auto method = methodFromString(a.method);
    if (!method) failBake("unknown method " + quote(a.method) + " (" + methodNames() + ")");
    // The ranges the command line's parser holds its options to, for callers without it; the
    // method's own options as its table says (and those of other methods refused).
    if (Status s = checkParameterValues(*method, a.parameters, ParameterNaming::Flag); !s)
        failBake(s.error);
    requireRange("--base-roughness", a.baseRoughness, 0.0, 1.0);
    if (a.maxExponent != 0.f) requireRange("--max-exponent", a.maxExponent, 1e-3, 1e6);
    if (a.decode.height) requireRange("--height", a.decode.heightScale, 1e-6, 1e6);
    requireRange("--zstd", a.zstd, 0, 22);
    requireOneOf("--roughness-channel", a.roughnessChannel, {"r", "g", "b", "a"});
    requireOneOf("--roughness-encoding", a.roughnessEncoding,
                 {"perceptual", "alpha", "smoothness"});
    if (!a.metallicChannel.empty())
        requireOneOf("--metallic-channel", a.metallicChannel, {"r", "g", "b", "a"});
    if (!a.occlusionChannel.empty())
        requireOneOf("--occlusion-channel", a.occlusionChannel, {"r", "g", "b", "a"});
    requireOneOf("--normal-format", a.normalFormat, {"bc5", "rg16", "rgba8", "uastc"});
    requireOneOf("--roughness-format", a.roughnessFormat, {"bc4", "r16f", "uastc"});

    if (!a.albedo.empty() && *method != Method::Vmf)
        failBake("--albedo applies to --method vmf only");
    // Without --export the bake is the EXR planes; with it, exactly what it lists.
    std::set<std::string> exports = commaList(a.exportFormat.empty() ? "exr" : a.exportFormat,
                                              "--export", {"png16", "ktx2", "dds", "exr"});
    commaList(a.exportTextures, "--export-textures", {"normal", "roughness", "planes"});
    if (a.zstd != 0 && !exports.count("ktx2"))
        failBake("--zstd supercompresses KTX2 files: add ktx2 to --export");
    // DDS has no UASTC format: the normal and roughness go to KTX2 only.
    if (exports.count("dds") && (a.normalFormat == "uastc" || a.roughnessFormat == "uastc"))
        failBake(std::string(a.normalFormat == "uastc" ? "--normal-format" : "--roughness-format") +
                 " uastc is a KTX2 format (DDS holds no UASTC): --export ktx2");
    if (!a.engine.empty()) {
        if (!findEnginePreset(a.engine))
            failBake("--engine " + quote(a.engine) + ": expected " + enginePresetNames());
        if (*method != Method::Toksvig && *method != Method::Naive && *method != Method::Lean &&
            *method != Method::GgxFit && *method != Method::GgxAniso)
            failBake(
                "--engine writes a normal map and a roughness map: --method toksvig, ggx-fit (or "
                "naive), or ggx-aniso or lean (one anisotropic lobe per texel, in the engine's "
                "anisotropy inputs)");
        if (!exports.count("ktx2") && !exports.count("dds")) exports.insert("ktx2");
    }
    if (exports.count("png16") &&
        (*method == Method::Sh || *method == Method::Vmf || *method == Method::Lean))
        failBake("--export png16 needs a method that stores a normal (naive, toksvig)");
    if (!a.roughnessMap.empty() && *method != Method::Toksvig &&
        !bakeFitsMaterialRoughness(*method))
        failBake(
            "--roughness-map applies to --method toksvig, ggx-fit and ggx-aniso (their roughness "
            "planes)");
    if (bakeFitsMaterialRoughness(*method) && a.baseRoughness == 0.f && a.roughnessMap.empty())
        failBake(std::string("--method ") + methodName(*method) +
                 " fits one GGX lobe to the material's: give its --base-roughness (at least 0.01) "
                 "or --roughness-map");
    if (bakeFitsMaterialRoughness(*method) && a.roughnessMap.empty() &&
        a.baseRoughness < kMinFittedRoughness)
        failBake("--base-roughness " + number(a.baseRoughness) + ": --method " +
                 methodName(*method) + " fits a GGX alpha of at least 0.01");
    if (!a.roughnessMap.empty() && a.baseRoughness != 0.f)
        failBake(
            "--roughness-map and --base-roughness both set the material's roughness: give one");
    if (!a.gloss.empty() && a.maxExponent <= 0.f)
        failBake("--gloss needs --max-exponent S0 (the exponent of gloss 1.0)");
}

BakeWriteOptions writeOptionsOf(const BakeFileOptions& a) {
    const std::set<std::string> exports = exportsOf(a);
    const std::set<std::string> textures =
        commaList(a.exportTextures, "--export-textures", {"normal", "roughness", "planes"});
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
    write.engine = a.engine.empty() ? nullptr : findEnginePreset(a.engine);
    write.baseRoughness = a.baseRoughness;
    write.half = a.half;
    return write;
}

// Everything that decides a bake's files besides the map itself, as canonical JSON: two runs
// with the same text, the same sources and the same version write the same files.
std::string optionsText(const BakeFileOptions& a) {
    const DecodeOptions& d = a.decode;
    nlohmann::json options = {{"method", a.method},
                              {"half", a.half},
                              {"max_exponent", a.maxExponent},
                              {"base_roughness", a.baseRoughness},
                              {"roughness_channel", a.roughnessChannel},
                              {"roughness_encoding", a.roughnessEncoding},
                              {"engine", a.engine},
                              {"metallic_channel", a.metallicChannel},
                              {"occlusion_channel", a.occlusionChannel},
                              {"export", a.exportFormat},
                              {"export_textures", a.exportTextures},
                              {"normal_format", a.normalFormat},
                              {"roughness_format", a.roughnessFormat},
                              {"zstd", a.zstd},
                              {"green_down", d.greenDown},
                              {"two_channel", d.twoChannel},
                              {"signed", d.signedValues},
                              {"height", d.height},
                              {"height_scale", d.heightScale},
                              {"clamp", d.address == AddressMode::Clamp}};
    // Every method's bake parameters, given or not, each as its type is written (the keys stay
    // those of earlier versions, so their bakes stay up to date).
    const ParameterValues parameters = fileParameters(a);
    for (const auto& [method, p] : allMethodParameters()) {
        if (!(p->commands & kParameterBake)) continue;
        auto given = parameters.find(p->key);
        const double value = given != parameters.end() ? given->second
                             : p->keyedZeroWhenUnset   ? 0.0
                                                       : p->defaultValue;
        if (p->type == ParameterType::Integer)
            options[p->key] = int64_t(value);
        else if (p->type == ParameterType::Float)
            options[p->key] = float(value);
        else
            options[p->key] = value;
    }
    return options.dump();
}

std::string cacheKeyOf(const BakeFileOptions& a, const std::string& sourceHash) {
    std::string text =
        std::string("ndfmip ") + NDFMIP_VERSION + "\n" + optionsText(a) + "\nsource " + sourceHash;
    for (const auto& [name, path] :
         {std::pair{"gloss", &a.gloss}, {"albedo", &a.albedo}, {"roughness_map", &a.roughnessMap}})
        if (!path->empty()) {
            Result<std::string> hash = sha256File(*path);
            if (!hash) failBake(hash.error().message);
            text += std::string("\n") + name + " " + hash.value();
        }
    return sha256Text(text);
}

void applyGloss(Image& normals, const BakeFileOptions& a) {
    Result<SourceImage> gloss = loadImage(a.gloss);
    if (!gloss) failBake(gloss.error().message);
    const Image& g = gloss->image;
    if (g.width != normals.width || g.height != normals.height)
        failBake(a.gloss + ": gloss map is " + std::to_string(g.width) + "x" +
                 std::to_string(g.height) + " but the normal map is " +
                 std::to_string(normals.width) + "x" + std::to_string(normals.height));
    for (size_t i = 0; i < g.texelCount(); ++i)
        if (!std::isfinite(g.pixels[i * g.channels]))
            failBake(a.gloss + ": NaN or infinite gloss value at texel (" +
                     std::to_string(i % g.width) + ", " + std::to_string(i / g.width) + ")");
    applyGlossMap(normals, g, a.maxExponent);
}

// The roughness map (a packed material map), read once for all the channels taken from it.
SourceImage loadMaterialMap(const BakeFileOptions& a, int width, int height) {
    Result<SourceImage> map = loadImage(a.roughnessMap);
    if (!map) failBake(map.error().message);
    const Image& image = map->image;
    if (image.width != width || image.height != height)
        failBake(a.roughnessMap + ": roughness map is " + std::to_string(image.width) + "x" +
                 std::to_string(image.height) + " but the normal map is " + std::to_string(width) +
                 "x" + std::to_string(height));
    return std::move(map.value());
}

// One channel (r, g, b or a) of the material map, clamped to [0, 1]; `option` names it in messages.
std::shared_ptr<Image> materialChannel(const BakeFileOptions& a, const Image& map,
                                       const std::string& channelName, const char* option) {
    const int channel = int(std::string("rgba").find(channelName[0]));
    if (channel >= map.channels)
        failBake(a.roughnessMap + ": " + option + " " + channelName + " but the map has " +
                 std::to_string(map.channels) + " channel(s)");
    auto out = std::make_shared<Image>(map.width, map.height, 1);
    for (size_t i = 0; i < map.texelCount(); ++i) {
        const float v = map.pixels[i * size_t(map.channels) + size_t(channel)];
        if (!std::isfinite(v))
            failBake(a.roughnessMap + ": NaN or infinite value at texel (" +
                     std::to_string(i % size_t(map.width)) + ", " +
                     std::to_string(i / size_t(map.width)) + ") in " + option);
        out->pixels[i] = std::clamp(v, 0.f, 1.f);
    }
    return out;
}

// The material's alpha per texel: the roughness channel perceptual (alpha = p^2: glTF, Unreal,
// Filament), alpha, or Unity's smoothness (alpha = (1 - s)^2).
SharedImage roughnessAlpha(const BakeFileOptions& a, const Image& map) {
    std::shared_ptr<Image> alpha =
        materialChannel(a, map, a.roughnessChannel, "--roughness-channel");
    for (float& x : alpha->pixels)
        x = a.roughnessEncoding == "alpha"        ? x
            : a.roughnessEncoding == "smoothness" ? (1.f - x) * (1.f - x)
                                                  : x * x;
    return alpha;
}

// The options of the bake as far as they are known before any image is read: stand-ins for the
// albedo and roughness maps, which the methods' memory estimates count.
BakeOptions plannedOptions(const BakeFileOptions& a) {
    BakeOptions options;
    options.parameters = fileParameters(a);
    if (!a.albedo.empty()) options.albedo = std::make_shared<Image>();
    if (!a.roughnessMap.empty()) options.roughnessMap = std::make_shared<Image>();
    return options;
}

// The peak per texel of the map: the bake, the decoded file beside the normals (four floats at
// most), and the gloss, albedo and material maps with their mip chains.
double plannedBytesPerTexel(Method method, const BakeFileOptions& a) {
    double bytes = bakeBytesPerTexel(method, plannedOptions(a)) + 16.0;
    if (!a.gloss.empty()) bytes += 16.0;
    if (!a.albedo.empty()) bytes += 12.0 + 12.0 * 4.0 / 3.0;
    if (!a.roughnessMap.empty()) bytes += 16.0 + 4.0 * 3 * 4.0 / 3.0;
    return bytes;
}

BakeFileReport bakeOrThrow(const std::string& input, const std::string& output,
                           const BakeFileOptions& a) {
    checkFileOptions(a);
    // Before anything is cleaned up or created under a path that a NUL would cut short.
    for (const std::string* path : {&input, &output, &a.gloss, &a.albedo, &a.roughnessMap})
        if (Status s = checkUntrustedPath(*path); !s) failBake(s.error);
    const Method method = *methodFromString(a.method);
    BakeWriteOptions write = writeOptionsOf(a);
    recoverInterruptedBake(output);
    Result<std::string> hash = sha256File(input);
    if (!hash) failBake(hash.error().message);
    BakeFileReport report;
    report.method = method;
    report.cacheKey = cacheKeyOf(a, hash.value());
    if (!a.force && bakeUpToDate(output, report.cacheKey)) {
        report.skipped = true;
        return report;
    }
    {
        std::error_code ec;
        const std::filesystem::path parent =
            std::filesystem::path(output).lexically_normal().parent_path();
        // Only a missing folder is made (writeBake names a parent that is a file). Another map of
        // a batch may create it at the same moment: what counts is that it exists.
        if (!parent.empty() && !std::filesystem::exists(parent, ec) &&
            !std::filesystem::create_directories(parent, ec) &&
            !std::filesystem::is_directory(parent, ec))
            failBake(output + ": cannot create the folder " + parent.string() + " (" +
                     ec.message() + ")");
    }

    // The bake's peak from the options alone, checked against --max-memory by the decoder once
    // it has read the map's header, before it allocates.
    const PlannedPeak planned(bakeDescription(method, plannedOptions(a)),
                              plannedBytesPerTexel(method, a));
    long long start = nowNanoseconds();
    Result<Image> decoded = loadNormalMap(input, a.decode, &report.decode);
    if (!decoded) failBake(decoded.error().message);
    if (a.decoded) a.decoded(report.decode);
    Image normals = std::move(decoded.value());
    if (!a.gloss.empty()) applyGloss(normals, a);
    report.decodeMs = millisecondsSince(start);

    start = nowNanoseconds();
    const int width = normals.width, height = normals.height;
    Pyramid pyramid = buildPyramid(std::make_shared<const Image>(std::move(normals)));
    BakeOptions options;
    options.baseRoughness = a.baseRoughness;
    options.parameters = fileParameters(a);
    if (!a.albedo.empty()) {
        Result<SharedImage> albedo = loadAlbedo(a.albedo, width, height);
        if (!albedo) failBake(albedo.error().message);
        options.albedo = albedo.value();
    }
    std::optional<SourceImage> materialMap;
    if (!a.roughnessMap.empty()) {
        materialMap = loadMaterialMap(a, width, height);
        options.roughnessMap = roughnessAlpha(a, materialMap->image);
    }
    options.progress = a.progress;
    if (Status s = checkBakeMemory(input, method, options, width, height); !s) failBake(s.error);
    Bake bake = bakeMethod(method, pyramid, options);
    if (!a.gloss.empty()) bake.parameters["max_exponent"] = a.maxExponent;
    report.bakeMs = millisecondsSince(start);

    start = nowNanoseconds();
    BakeSource source{input, hash.value(), width, height, a.decode, a.gloss, report.cacheKey};
    // Metallic and occlusion are linear: their mips are footprint means, as an albedo map's.
    for (const auto& [channel, option, chain] :
         {std::tuple{&a.metallicChannel, "--metallic-channel", &write.metallic},
          std::tuple{&a.occlusionChannel, "--occlusion-channel", &write.occlusion}}) {
        if (channel->empty()) continue;
        if (!materialMap)
            failBake(std::string(option) +
                     " reads a channel of --roughness-map, which is not given");
        *chain = albedoMips(pyramid, materialChannel(a, materialMap->image, *channel, option));
    }
    if (Status s = writeBake(output, bake, source, write); !s) failBake(s.error);
    report.writeMs = millisecondsSince(start);
    report.width = width;
    report.height = height;
    report.levels = bake.levels.size();
    report.parameters = bake.parameters;
    return report;
}

} // namespace

Status checkBakeFileOptions(const BakeFileOptions& options) {
    try {
        checkFileOptions(options);
        return Status::success();
    } catch (const BakeProblem& p) {
        return Status::failure(p.message);
    }
}

Result<BakeWriteOptions> bakeWriteOptions(const BakeFileOptions& options) {
    try {
        checkFileOptions(options);
        return writeOptionsOf(options);
    } catch (const BakeProblem& p) {
        return Error{p.message};
    }
}

Result<std::string> bakeCacheKey(const BakeFileOptions& options, const std::string& sourceSha256) {
    try {
        return cacheKeyOf(options, sourceSha256);
    } catch (const BakeProblem& p) {
        return Error{p.message};
    }
}

namespace {

// Whether `file` is a regular file (not a link) with some bytes: the manifest records no sizes,
// and no image, KTX2 or DDS file is empty.
bool presentFile(const std::filesystem::path& file) {
    std::error_code ec;
    const std::filesystem::file_status status = std::filesystem::symlink_status(file, ec);
    if (ec || !std::filesystem::is_regular_file(status)) return false;
    const auto size = std::filesystem::file_size(file, ec);
    return !ec && size > 0;
}

} // namespace

bool bakeUpToDate(const std::string& dir, const std::string& cacheKey) {
    Result<std::string> text =
        readRegularFile(dir + "/manifest.json", inputLimits().maxTextFileBytes);
    if (!text) return false;
    Result<LoadedBake> bake = parseBakeManifest(text.value(), dir);
    if (!bake || bake->source.cacheKey != cacheKey) return false;
    // A file deleted or emptied since: bake again rather than skip and leave a broken bake.
    const std::filesystem::path folder(dir);
    for (const std::vector<std::string>& files : bake->levelFiles)
        for (const std::string& name : files)
            if (!presentFile(folder / name)) return false;
    for (const std::string& name : bake->exports)
        if (!presentFile(folder / name)) return false;
    return true;
}

Result<BakeFileReport> bakeFile(const std::string& input, const std::string& output,
                                const BakeFileOptions& options) {
    try {
        return bakeOrThrow(input, output, options);
    } catch (const BakeProblem& p) {
        return Error{p.message};
    } catch (const std::bad_alloc&) {
        return Error{outOfMemoryMessage(input)};
    }
}

Status checkBakeOptions(Method method, const BakeOptions& o, int width, int height) {
    try {
        if (Status s = checkParameterValues(method, o.parameters, ParameterNaming::Key); !s)
            failBake(s.error);
        requireRange("base_roughness", o.baseRoughness, 0.0, 1.0);
        if (bakeFitsMaterialRoughness(method) && !o.roughnessMap &&
            o.baseRoughness < kMinFittedRoughness)
            failBake(std::string(methodName(method)) +
                     " fits one GGX lobe to the material's: base_roughness must be at least 0.01");
        if (o.roughnessMap) {
            const Image& r = *o.roughnessMap;
            if (method != Method::Toksvig && !bakeFitsMaterialRoughness(method))
                failBake("roughness: applies to methods toksvig, ggx-fit and ggx-aniso (their "
                         "roughness planes)");
            if (r.width != width || r.height != height || r.channels != 1)
                failBake("roughness: " + std::to_string(r.width) + "x" + std::to_string(r.height) +
                         "x" + std::to_string(r.channels) + " but the normal map is " +
                         std::to_string(width) + "x" + std::to_string(height) +
                         " (one channel of alpha expected)");
            for (size_t i = 0; i < r.pixels.size(); ++i)
                if (!(r.pixels[i] >= 0.f && r.pixels[i] <= 1.f))
                    failBake("roughness: value " + number(r.pixels[i]) + " at texel (" +
                             std::to_string(i % size_t(width)) + ", " +
                             std::to_string(i / size_t(width)) + ") is not in 0 .. 1");
        }
        if (o.albedo) {
            if (method != Method::Vmf) failBake("albedo: applies to method vmf only");
            if (Status s = checkAlbedoSize(*o.albedo, width, height, "albedo"); !s)
                failBake(s.error);
            for (float v : o.albedo->pixels)
                if (!(v >= 0.f) || !std::isfinite(v))
                    failBake("albedo: NaN, infinite or negative value");
        }
        return checkBakeMemory("bake", method, o, width, height);
    } catch (const BakeProblem& p) {
        return Status::failure(p.message);
    }
}

} // namespace ndfmip
