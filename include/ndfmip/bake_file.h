// A map file baked into a bake folder, as `ndfmip bake` does it for each map: the options as
// the command takes them (names and numbers, checked here), the cache key that lets a rerun
// skip an up-to-date bake, and the whole decode -> bake -> write path. The command-line tool
// and the Python module both call it, so a bake made by either is byte for byte the same.
#pragma once

#include <functional>
#include <map>
#include <string>

#include "ndfmip/bake.h"
#include "ndfmip/normal_map.h"
#include "ndfmip/result.h"

namespace ndfmip {

// Every option of `ndfmip bake` that decides the files (the CLI's names in brackets).
struct BakeFileOptions {
    std::string method = "toksvig"; // --method: naive, toksvig, sh, vmf, lean
    DecodeOptions decode;           // --green-down, --two-channel, --signed, --height, --clamp
    // The method's own options that were given (--order, --lobes, --coherent ...: its parameter
    // table, method_parameters.h), by key; the rest take the table's defaults.
    ParameterValues parameters;
    std::string albedo;                 // --albedo (vmf): colour map file
    bool half = false;                  // --half
    std::string gloss;                  // --gloss: gloss map file
    float maxExponent = 0.f;            // --max-exponent: S0 of gloss 1.0
    float baseRoughness = 0.f;          // --base-roughness
    std::string roughnessMap;           // --roughness-map (toksvig): packed material map file
    std::string roughnessChannel = "r"; // --roughness-channel: r, g, b or a
    std::string roughnessEncoding =
        "perceptual";   // --roughness-encoding: perceptual, alpha, smoothness
    std::string engine; // --engine: an engine preset's name
    std::string metallicChannel, occlusionChannel; // --metallic-channel, --occlusion-channel
    std::string exportFormat; // --export: comma-separated png16, ktx2, dds, exr ("" = exr)
    std::string exportTextures = "normal,roughness"; // --export-textures: normal, roughness, planes
    std::string normalFormat = "bc5";                // --normal-format: bc5, rg16, rgba8
    std::string roughnessFormat = "bc4";             // --roughness-format: bc4, r16f
    int zstd = 0;                           // --zstd: KTX2 supercompression level (0: none)
    bool force = false;                     // --force: bake even when the output is up to date
    std::function<void(int, int)> progress; // (levels done, levels in all)
    std::function<void(const DecodeReport&)>
        decoded; // once the map is decoded (the CLI's warnings)
};

// The options' checks that do not depend on the map: names, ranges, and options that apply to
// another method or need each other. The first problem as one line naming the option.
Status checkBakeFileOptions(const BakeFileOptions& options);

// The BakeWriteOptions the export options ask for (metallic and occlusion left empty).
Result<BakeWriteOptions> bakeWriteOptions(const BakeFileOptions& options);

// The bake's cache key: SHA-256 over the version, the options that decide the files, and the
// SHA-256 of the source and of every other file read (gloss, albedo, roughness map).
Result<std::string> bakeCacheKey(const BakeFileOptions& options, const std::string& sourceSha256);

// Whether `dir` holds a bake with this cache key (any problem reading it: no).
bool bakeUpToDate(const std::string& dir, const std::string& cacheKey);

// What bakeFile did.
struct BakeFileReport {
    bool skipped = false; // the output was up to date: nothing was read or written
    Method method = Method::Naive;
    int width = 0, height = 0;
    size_t levels = 0;
    std::map<std::string, double> parameters; // the bake's parameters
    DecodeReport decode;
    std::string cacheKey;
    double decodeMs = 0.0, bakeMs = 0.0, writeMs = 0.0;
};

// Bakes the map file `input` into the folder `output` (its parent folders created), skipping it
// when `output` already holds a bake with the same cache key unless options.force. The options
// are checked first (checkBakeFileOptions). Errors are one line naming the file or option.
Result<BakeFileReport> bakeFile(const std::string& input, const std::string& output,
                                const BakeFileOptions& options);

// BakeOptions ranges (the method's parameters as its table says, the base roughness)
// and per-texel maps of the right size, one channel for the roughness map and 3 for the albedo,
// with finite values: what bakeMethod needs before it is called on a width x height map.
Status checkBakeOptions(Method method, const BakeOptions& options, int width, int height);

} // namespace ndfmip
