// A glTF asset in memory, to be changed and written back as one GLB: its JSON as read (key
// order kept, every property kept) and every buffer's bytes. gltf_container.h reads the container
// (GLB chunks, external files, data URIs); nothing is decoded or re-encoded, so images and buffers
// come out byte for byte as they went in.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "ndfmip/result.h"

namespace ndfmip {

struct GltfAsset {
    nlohmann::ordered_json json;
    std::vector<std::string> buffers;     // bytes of json["buffers"][i]
    std::vector<std::string> imageLabels; // "image 2 'wall_n.png'" (its uri or name), for messages
};

// Reads a .gltf (external files and data URIs resolved beside it) or a .glb (recognised by its
// first bytes, whatever the name). Every image that had a uri becomes a bufferView of a new
// buffer with its mimeType (taken from the asset, a data URI or the bytes), so afterwards every
// image is a bufferView. Errors, one line starting with `path`: not glTF, unreadable JSON,
// a missing or unreadable buffer or image file, an image of a format glTF cannot embed, a uri
// that leaves the asset's folder (unless `allowOutside`; readGltfUri has the rules).
Result<GltfAsset> readGltf(const std::string& path, bool allowOutside = false);

// The bytes of image `index` (a bufferView after readGltf); an error when the index, its
// bufferView or the view's range is out of bounds.
Result<std::string> gltfImageBytes(const GltfAsset& asset, int index);

// Adds `bytes` as a new image (in a new buffer and bufferView); returns its index.
int addGltfImage(GltfAsset& asset, std::string bytes, const std::string& mimeType,
                 const std::string& name);

// Gives an image that addGltfImage added (its own buffer, one view over all of it) its bytes,
// for an image added before they were ready.
void setGltfImageBytes(GltfAsset& asset, int index, std::string bytes);

// The asset as GLB: every buffer in the one binary chunk (each at a 16-byte boundary, the
// bufferViews' offsets moved with it, buffer 0's other properties kept), JSON padded with
// spaces and the binary chunk with zeros as the GLB format requires.
Result<std::string> glbFile(const GltfAsset& asset);

} // namespace ndfmip
