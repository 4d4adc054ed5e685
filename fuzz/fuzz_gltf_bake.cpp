// Fuzzes glTF JSON on its way to a bake: each input is a .gltf's text in which every string
// "@NORMAL_PNG@" stands for a data uri of a small, valid normal map, so that mutations of the
// JSON (materials, textures, samplers, scales, indices) reach the decode, the Toksvig bake and
// the GLB assembly rather than stopping at a broken image. The output GLB stays in memory.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include "fuzz_limits.h"
#include "ndfmip/gltf.h"
#include "ndfmip/io.h"

namespace fs = std::filesystem;

namespace {

fs::path gRoot;
std::string gNormalUri; // data:image/png;base64,... of an 8 x 8 bump

void removeRoot() {
    std::error_code ec;
    fs::remove_all(gRoot, ec);
}

std::string base64(const std::string& bytes) {
    static const char digits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (size_t i = 0; i < bytes.size(); i += 3) {
        uint32_t n = uint32_t(uint8_t(bytes[i])) << 16;
        if (i + 1 < bytes.size()) n |= uint32_t(uint8_t(bytes[i + 1])) << 8;
        if (i + 2 < bytes.size()) n |= uint32_t(uint8_t(bytes[i + 2]));
        out += digits[(n >> 18) & 63];
        out += digits[(n >> 12) & 63];
        out += i + 1 < bytes.size() ? digits[(n >> 6) & 63] : '=';
        out += i + 2 < bytes.size() ? digits[n & 63] : '=';
    }
    return out;
}

uint32_t le32(const std::string& b, size_t at) {
    return uint32_t(uint8_t(b[at])) | uint32_t(uint8_t(b[at + 1])) << 8 |
           uint32_t(uint8_t(b[at + 2])) << 16 | uint32_t(uint8_t(b[at + 3])) << 24;
}

} // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    ndfmip::setFuzzLimits();
    char pattern[] = "/tmp/ndfmip-fuzz-gltf-bake-XXXXXX";
    if (!::mkdtemp(pattern)) std::abort();
    gRoot = pattern;
    std::atexit(removeRoot);
    ndfmip::Image normals(8, 8, 3);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) {
            float* n = normals.at(x, y);
            n[0] = 0.5f + 0.04f * float(x - 4), n[1] = 0.5f + 0.04f * float(y - 4), n[2] = 0.95f;
        }
    ndfmip::Result<std::string> png = ndfmip::encodePng(normals, 8);
    if (!png) std::abort();
    gNormalUri = "data:image/png;base64," + base64(png.value());
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    std::string text(reinterpret_cast<const char*>(data), size);
    const std::string token = "@NORMAL_PNG@";
    for (size_t at = 0; (at = text.find(token, at)) != std::string::npos; at += gNormalUri.size())
        text.replace(at, token.size(), gNormalUri);
    const fs::path path = gRoot / "asset.gltf";
    {
        std::ofstream out(path, std::ios::binary | std::ios::trunc);
        out.write(text.data(), std::streamsize(text.size()));
    }
    ndfmip::GltfOptions options;
    options.textureFormat = ndfmip::GltfTextureFormat::Dds; // no encoder processes per input
    ndfmip::Result<ndfmip::GltfFiltered> filtered = ndfmip::filterGltf(path.string(), options);
    if (!filtered) {
        const std::string& message = filtered.error().message;
        FUZZ_CHECK(!message.empty() && message.find('\n') == std::string::npos);
        return 0;
    }
    // A GLB: the header's magic, version 2 and its length exactly, then the JSON chunk.
    const std::string& glb = filtered->glb;
    FUZZ_CHECK(glb.size() >= 20 && glb.compare(0, 4, "glTF") == 0);
    FUZZ_CHECK(le32(glb, 4) == 2 && le32(glb, 8) == glb.size());
    FUZZ_CHECK(glb.compare(16, 4, "JSON") == 0);
    // One bake per distinct image and options, each from a decoded image.
    FUZZ_CHECK(filtered->bakes <= int(filtered->materials.size()) &&
               filtered->decodedImages >= (filtered->bakes > 0));
    return 0;
}
