// tinygltf's part of reading glTF: GLB chunks, buffers and images from external files (through
// ndfmip's bounded reader) and data URIs, checked by tinygltf. Images are kept as bytes.
#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE       // images are kept as bytes, never decoded here
#define TINYGLTF_NO_STB_IMAGE_WRITE // and never written by tinygltf
#include <tiny_gltf.h>

#include "io/gltf_container.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <string_view>

#include "io/input_file.h"
#include "ndfmip/limits.h"

namespace fs = std::filesystem;

namespace ndfmip {
namespace {

constexpr uint32_t kGlbMagic = 0x46546C67;  // "glTF"
constexpr uint32_t kJsonChunk = 0x4E4F534A; // "JSON"

std::string oneLine(std::string text) {
    std::replace(text.begin(), text.end(), '\n', ' ');
    std::replace(text.begin(), text.end(), '\r', ' ');
    while (!text.empty() && (text.back() == ' ' || text.back() == '.')) text.pop_back();
    return text;
}

uint32_t readU32(std::string_view bytes, size_t at) {
    uint32_t v = 0;
    std::memcpy(&v, bytes.data() + at, sizeof v);
    return v;
}

// External files go through readRegularFile (no FIFOs, no devices, bounded size).
struct FileAccess {
    static bool exists(const std::string& path, void*) {
        std::error_code ec;
        return fs::exists(path, ec);
    }
    static std::string expand(const std::string& path, void*) { return path; }
    static bool read(std::vector<unsigned char>* out, std::string* err, const std::string& path,
                     void*) {
        Result<std::string> bytes = readRegularFile(path, inputLimits().maxImageFileBytes);
        if (!bytes) {
            if (err) *err = bytes.error().message;
            return false;
        }
        out->assign(bytes->begin(), bytes->end());
        return true;
    }
    static bool write(std::string*, const std::string&, const std::vector<unsigned char>&, void*) {
        return false;
    }
};

// The image loader: keeps the bytes of images given by a uri (the others already sit in a
// bufferView), decodes nothing.
bool keepImageBytes(tinygltf::Image* image, const int, std::string*, std::string*, int, int,
                    const unsigned char* bytes, int size, void*) {
    if (image->bufferView < 0) image->image.assign(bytes, bytes + size);
    return true;
}

} // namespace

Result<GltfContainer> readGltfContainer(const std::string& path) {
    Result<std::string> file = readRegularFile(path, inputLimits().maxImageFileBytes);
    if (!file) return file.error();
    const std::string& bytes = file.value();
    if (bytes.size() >= std::numeric_limits<uint32_t>::max())
        return Error{path + ": larger than 4 GiB, more than glTF readers take"};
    const bool binary = bytes.size() >= 4 && readU32(bytes, 0) == kGlbMagic;

    // The JSON text: the whole file, or a GLB's first chunk; its nesting bounded before any
    // parser recurses into it.
    std::string_view text = bytes;
    if (binary) {
        if (bytes.size() < 20 || readU32(bytes, 16) != kJsonChunk ||
            size_t(readU32(bytes, 12)) > bytes.size() - 20)
            return Error{path + ": GLB without a complete JSON chunk"};
        text = std::string_view(bytes).substr(20, readU32(bytes, 12));
    }
    if (std::string problem = jsonNestingProblem(text, inputLimits().maxJsonDepth);
        !problem.empty())
        return Error{path + ": JSON " + problem};

    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(keepImageBytes, nullptr);
    loader.SetFsCallbacks(
        {FileAccess::exists, FileAccess::expand, FileAccess::read, FileAccess::write, nullptr});
    tinygltf::Model model;
    std::string err, warn;
    const std::string base = fs::path(path).parent_path().string();
    bool loaded = false;
    try {
        loaded =
            binary
                ? loader.LoadBinaryFromMemory(&model, &err, &warn,
                                              reinterpret_cast<const unsigned char*>(bytes.data()),
                                              unsigned(bytes.size()), base)
                : loader.LoadASCIIFromString(&model, &err, &warn, bytes.data(),
                                             unsigned(bytes.size()), base);
    } catch (const std::exception& e) {
        return Error{path + ": not a glTF asset (" + oneLine(e.what()) + ")"};
    }
    if (!loaded)
        return Error{path + ": not a readable glTF asset: " + oneLine(err.empty() ? warn : err)};

    GltfContainer c;
    c.json = std::string(text);
    for (const tinygltf::Buffer& buffer : model.buffers)
        c.buffers.emplace_back(buffer.data.begin(), buffer.data.end());
    for (const tinygltf::Image& image : model.images) {
        c.imageBytes.emplace_back(image.image.begin(), image.image.end());
        c.imageMimeTypes.push_back(image.mimeType);
    }
    return c;
}

} // namespace ndfmip
