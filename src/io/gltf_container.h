// The glTF container, read by ndfmip itself: a GLB's chunks checked strictly, the JSON parsed
// once under the text limit, and the bytes that buffer and image uris name (base64 data URIs,
// or files inside the asset's folder).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "ndfmip/result.h"

namespace ndfmip {

// Binary glTF's magic and chunk types (glTF 2.0, "GLB File Format Specification").
constexpr uint32_t kGlbMagic = 0x46546C67;  // "glTF"
constexpr uint32_t kJsonChunk = 0x4E4F534A; // "JSON"
constexpr uint32_t kBinChunk = 0x004E4942;  // "BIN\0"

struct GltfContainer {
    nlohmann::ordered_json json;      // the JSON (a GLB's first chunk), parsed once
    std::vector<std::string> buffers; // every buffer's bytes, resolved
};

// Reads `path` (.gltf, or .glb recognised by its first bytes). A GLB must be version 2 with its
// header's length, a JSON chunk first, at most one BIN chunk right after it, every chunk
// 4-byte aligned; asset.version must be 2.x. The JSON outside data URIs is held to the text
// limit (InputLimits::maxTextFileBytes). Buffers resolve as readGltfUri says. Errors, one
// line, start with `path`.
Result<GltfContainer> readGltfContainer(const std::string& path, bool allowOutside = false);

struct UriBytes {
    std::string bytes;
    std::string mimeType; // a data URI's, else empty
};

// The bytes a glTF uri names: a base64 data URI, or a file relative to `folder`. Absolute
// paths, schemes (file:), '..' out of the folder, percent-encoded separators and files whose
// real path leaves the folder are refused unless `allowOutside`; NUL and control characters,
// raw or percent-encoded, always. Errors are the problem alone: the caller names the asset.
Result<UriBytes> readGltfUri(const std::string& uri, const std::filesystem::path& folder,
                             bool allowOutside);

} // namespace ndfmip
