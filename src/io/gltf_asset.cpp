// glTF in and GLB out. The container comes from gltf_container.cpp; the JSON is kept
// as nlohmann's ordered_json so that every property, known to ndfmip or not, is written back
// as it was, and no image or buffer is decoded or re-encoded.
#include "io/gltf_asset.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <string_view>

#include "io/gltf_container.h"
#include "io/input_file.h"
#include "ndfmip/io.h"
#include "ndfmip/limits.h"

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

namespace ndfmip {
namespace {

void appendU32(std::string& out, uint32_t v) {
    char b[4];
    std::memcpy(b, &v, sizeof b);
    out.append(b, sizeof b);
}

std::string sniffMimeType(std::string_view b) {
    auto starts = [&](std::string_view magic) { return b.substr(0, magic.size()) == magic; };
    if (starts("\x89PNG\r\n\x1a\n")) return "image/png";
    if (starts("\xFF\xD8\xFF")) return "image/jpeg";
    if (starts("RIFF") && b.size() >= 12 && b.substr(8, 4) == "WEBP") return "image/webp";
    if (starts("\xABKTX 20\xBB\r\n\x1A\n")) return "image/ktx2";
    if (starts("DDS ")) return "image/vnd-ms.dds";
    return "";
}

std::string imageLabel(const json& image, int index) {
    std::string label = "image " + std::to_string(index);
    if (!image.is_object()) return label;
    if (auto uri = image.find("uri"); uri != image.end() && uri->is_string() &&
                                      uri->get_ref<const std::string&>().rfind("data:", 0) != 0)
        return label + " " + quote(uri->get_ref<const std::string&>());
    if (auto name = image.find("name"); name != image.end() && name->is_string())
        return label + " " + quote(name->get_ref<const std::string&>());
    return label;
}

// A non-negative integer property, or -1 when it is missing or of another type.
int64_t indexOf(const json& object, const char* key) {
    if (!object.is_object()) return -1;
    auto it = object.find(key);
    if (it == object.end() || !it->is_number_integer()) return -1;
    const int64_t v = it->get<int64_t>();
    return v >= 0 ? v : -1;
}

int appendBufferView(GltfAsset& asset, std::string bytes) {
    json& buffers = asset.json["buffers"];
    json& views = asset.json["bufferViews"];
    const int64_t size = int64_t(bytes.size());
    buffers.push_back({{"byteLength", size}});
    asset.buffers.push_back(std::move(bytes));
    views.push_back({{"buffer", buffers.size() - 1}, {"byteLength", size}});
    return int(views.size() - 1);
}

Result<GltfAsset> readAsset(const std::string& path, bool allowOutside) {
    Result<GltfContainer> container = readGltfContainer(path, allowOutside);
    if (!container) return container.error();
    GltfContainer& c = container.value();
    const fs::path folder = fs::path(path).parent_path();

    GltfAsset asset;
    asset.json = std::move(c.json);
    asset.buffers = std::move(c.buffers);
    if (!asset.json.contains("buffers")) asset.json["buffers"] = json::array();
    if (!asset.json.contains("bufferViews")) asset.json["bufferViews"] = json::array();
    if (asset.buffers.size() != asset.json["buffers"].size() ||
        !asset.json["bufferViews"].is_array())
        return Error{path + ": buffers do not match the asset's JSON"};

    // Images given by a uri become bufferViews: a GLB holds everything.
    json& images = asset.json["images"];
    if (images.is_null()) images = json::array();
    if (!images.is_array()) return Error{path + ": images is not an array"};
    for (size_t i = 0; i < images.size(); ++i) {
        json& image = images[i];
        asset.imageLabels.push_back(imageLabel(image, int(i)));
        if (!image.is_object() || !image.contains("uri")) continue;
        if (!image["uri"].is_string())
            return Error{path + ": " + asset.imageLabels[i] + ": uri is no string"};
        Result<UriBytes> read = readGltfUri(image["uri"].get<std::string>(), folder, allowOutside);
        if (!read) return Error{path + ": " + asset.imageLabels[i] + ": " + read.error().message};
        std::string data = std::move(read->bytes);
        // Only image files are embedded, whatever the asset declares: a uri may name any file.
        const std::string sniffed = sniffMimeType(data);
        if (sniffed.empty())
            return Error{path + ": " + asset.imageLabels[i] +
                         (data.empty() ? ": the file is empty"
                                       : ": not an image file (glTF embeds PNG or JPEG)")};
        std::string mime = image.value("mimeType", read->mimeType);
        if (mime.empty()) mime = sniffed;
        image.erase("uri");
        image["bufferView"] = appendBufferView(asset, std::move(data));
        image["mimeType"] = mime;
    }
    return asset;
}

} // namespace

Result<GltfAsset> readGltf(const std::string& path, bool allowOutside) {
    try {
        return readAsset(path, allowOutside);
    } catch (const json::exception& e) { // a property of an unexpected type
        return fileError(path, e.what());
    }
}

Result<std::string> gltfImageBytes(const GltfAsset& asset, int index) {
    const json& images = asset.json["images"];
    const std::string label = index >= 0 && size_t(index) < asset.imageLabels.size()
                                  ? asset.imageLabels[size_t(index)]
                                  : "image " + std::to_string(index);
    if (index < 0 || size_t(index) >= images.size()) return Error{label + " does not exist"};
    const int64_t view = indexOf(images[size_t(index)], "bufferView");
    const json& views = asset.json["bufferViews"];
    if (view < 0 || size_t(view) >= views.size()) return Error{label + ": no bufferView holds it"};
    const json& v = views[size_t(view)];
    const int64_t buffer = indexOf(v, "buffer");
    const int64_t length = indexOf(v, "byteLength");
    const int64_t offset = v.contains("byteOffset") ? indexOf(v, "byteOffset") : 0;
    if (buffer < 0 || size_t(buffer) >= asset.buffers.size() || length < 0 || offset < 0 ||
        uint64_t(offset) + uint64_t(length) > asset.buffers[size_t(buffer)].size())
        return Error{label + ": bufferView " + std::to_string(view) + " lies outside its buffer"};
    return asset.buffers[size_t(buffer)].substr(size_t(offset), size_t(length));
}

int addGltfImage(GltfAsset& asset, std::string bytes, const std::string& mimeType,
                 const std::string& name) {
    const int view = appendBufferView(asset, std::move(bytes));
    json& images = asset.json["images"];
    images.push_back({{"name", name}, {"bufferView", view}, {"mimeType", mimeType}});
    asset.imageLabels.push_back("image " + std::to_string(images.size() - 1) + " " + quote(name));
    return int(images.size() - 1);
}

void setGltfImageBytes(GltfAsset& asset, int index, std::string bytes) {
    json& view =
        asset.json["bufferViews"][asset.json["images"][size_t(index)]["bufferView"].get<size_t>()];
    const size_t buffer = view["buffer"].get<size_t>();
    view["byteLength"] = bytes.size();
    asset.json["buffers"][buffer]["byteLength"] = bytes.size();
    asset.buffers[buffer] = std::move(bytes);
}

Result<std::string> glbFile(const GltfAsset& asset) {
    json out = asset.json;
    // Every buffer into one, each at a 16-byte boundary (accessors need at most 4).
    std::string bin;
    std::vector<uint64_t> base;
    for (const std::string& buffer : asset.buffers) {
        bin.resize((bin.size() + 15) / 16 * 16, '\0');
        base.push_back(bin.size());
        bin += buffer;
    }
    auto move = [&](json& object, size_t view) -> Status {
        const int64_t b = indexOf(object, "buffer");
        if (b < 0 || size_t(b) >= base.size())
            return Status::failure("bufferView " + std::to_string(view) +
                                   " names no buffer of the asset");
        const int64_t offset = object.contains("byteOffset") ? indexOf(object, "byteOffset") : 0;
        if (offset < 0)
            return Status::failure("bufferView " + std::to_string(view) + " has a bad byteOffset");
        object["buffer"] = 0;
        object["byteOffset"] = base[size_t(b)] + uint64_t(offset);
        return Status::success();
    };
    json& views = out["bufferViews"];
    for (size_t v = 0; v < views.size(); ++v) {
        if (Status s = move(views[v], v); !s) return Error{s.error};
        // EXT_meshopt_compression keeps its compressed bytes in a buffer of its own naming.
        if (views[v].contains("extensions") &&
            views[v]["extensions"].contains("EXT_meshopt_compression"))
            if (Status s = move(views[v]["extensions"]["EXT_meshopt_compression"], v); !s)
                return Error{s.error};
    }
    if (views.empty()) out.erase("bufferViews");
    if (bin.empty()) {
        out.erase("buffers");
    } else {
        json merged = out["buffers"][0];
        merged.erase("uri");
        merged["byteLength"] = bin.size();
        out["buffers"] = json::array({merged});
    }
    if (out["images"].empty()) out.erase("images");

    std::string text = out.dump(-1, ' ', false, json::error_handler_t::replace);
    text.resize((text.size() + 3) / 4 * 4, ' ');
    bin.resize((bin.size() + 3) / 4 * 4, '\0');
    const uint64_t total = 12 + 8 + text.size() + (bin.empty() ? 0 : 8 + bin.size());
    if (total > std::numeric_limits<uint32_t>::max())
        return Error{"the GLB would hold " + byteSize(int64_t(total)) +
                     ", above its limit of 4 GiB"};
    std::string glb;
    glb.reserve(size_t(total));
    appendU32(glb, kGlbMagic);
    appendU32(glb, 2);
    appendU32(glb, uint32_t(total));
    appendU32(glb, uint32_t(text.size()));
    appendU32(glb, kJsonChunk);
    glb += text;
    if (!bin.empty()) {
        appendU32(glb, uint32_t(bin.size()));
        appendU32(glb, kBinChunk);
        glb += bin;
    }
    return glb;
}

} // namespace ndfmip
