// The glTF container as tinygltf reads it, handed over as plain bytes (tinygltf lives in
// gltf_container.cpp alone: its JSON names must not meet nlohmann's ordered_json elsewhere).
#pragma once

#include <string>
#include <vector>

#include "ndfmip/result.h"

namespace ndfmip {

struct GltfContainer {
    std::string json;                    // the JSON text (a GLB's first chunk)
    std::vector<std::string> buffers;    // every buffer's bytes, resolved
    std::vector<std::string> imageBytes; // images given by a uri: their bytes (empty: unreadable)
    std::vector<std::string> imageMimeTypes; // from a data URI's header, else empty
};

// Reads `path` (.gltf, or .glb recognised by its first bytes): external files beside it through
// readRegularFile, data URIs decoded, nothing decoded as an image. Errors start with `path`.
Result<GltfContainer> readGltfContainer(const std::string& path);

} // namespace ndfmip
