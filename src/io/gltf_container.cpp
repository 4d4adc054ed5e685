// The glTF container: GLB chunks, the JSON parsed once (nlohmann's ordered_json, so every
// property is written back as it was), buffers and images from data URIs and from files inside
// the asset's folder through ndfmip's bounded reader. Images are kept as bytes.
#include "io/gltf_container.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>
#include <string_view>

#include <openssl/evp.h>

#include "io/input_file.h"
#include "ndfmip/limits.h"

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

namespace ndfmip {

namespace {

uint32_t readU32(std::string_view bytes, size_t at) {
    uint32_t v = 0;
    std::memcpy(&v, bytes.data() + at, sizeof v);
    return v;
}

// Bytes of the JSON text outside data URIs: what the parser turns into values. Embedded
// images and buffers are one string each however long, so only the rest is held to the text
// limit.
size_t structureBytes(std::string_view text) {
    size_t n = text.size();
    for (size_t i = 0; i < text.size(); ++i) {
        if (text[i] != '"') continue;
        size_t j = i + 1;
        while (j < text.size() && text[j] != '"') j += text[j] == '\\' ? 2 : 1;
        j = std::min(j, text.size());
        if (text.substr(i + 1, 5) == "data:") n -= j - i - 1;
        i = j;
    }
    return n;
}

// Standard base64 (RFC 4648), as data URIs carry it, decoded by OpenSSL; missing padding is
// added, as some writers leave it out.
std::optional<std::string> base64Decoded(std::string_view text) {
    if (text.size() % 4 == 1 || text.size() > size_t(std::numeric_limits<int>::max()) - 3)
        return std::nullopt;
    std::string padded(text);
    while (padded.size() % 4 != 0) padded += '=';
    size_t pads = 0;
    while (pads < 2 && pads < padded.size() && padded[padded.size() - 1 - pads] == '=') ++pads;
    std::string out(padded.size() / 4 * 3, '\0');
    const int n =
        EVP_DecodeBlock(reinterpret_cast<unsigned char*>(out.data()),
                        reinterpret_cast<const unsigned char*>(padded.data()), int(padded.size()));
    if (n < 0 || size_t(n) < pads) return std::nullopt;
    out.resize(size_t(n) - pads); // EVP_DecodeBlock counts the padding's zero bytes
    return out;
}

// "%20" and friends, as a uri names a file.
std::string percentDecoded(std::string_view uri) {
    auto hex = [](char c) { return std::isxdigit(static_cast<unsigned char>(c)) != 0; };
    std::string out;
    for (size_t i = 0; i < uri.size(); ++i) {
        if (uri[i] == '%' && i + 2 < uri.size() && hex(uri[i + 1]) && hex(uri[i + 2])) {
            out += char(std::stoi(std::string(uri.substr(i + 1, 2)), nullptr, 16));
            i += 2;
        } else {
            out += uri[i];
        }
    }
    return out;
}

bool hasControl(std::string_view text) {
    return std::any_of(text.begin(), text.end(), [](char c) {
        return static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) == 0x7F;
    });
}

// "file:" of "file:///x", "" when the uri has no scheme.
std::string schemeOf(std::string_view uri) {
    const size_t colon = uri.find(':');
    if (colon == std::string_view::npos || colon == 0) return "";
    for (size_t i = 0; i < colon; ++i) {
        const char c = uri[i];
        const bool letter = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z');
        if (!letter && (i == 0 || !((c >= '0' && c <= '9') || c == '+' || c == '-' || c == '.')))
            return "";
    }
    return std::string(uri.substr(0, colon + 1));
}

// Whether the relative path `decoded` leaves its folder by '..' (more ups than downs).
bool climbsOut(const std::string& decoded) {
    int depth = 0;
    size_t start = 0;
    while (start <= decoded.size()) {
        size_t end = decoded.find('/', start);
        if (end == std::string::npos) end = decoded.size();
        const std::string_view part(decoded.data() + start, end - start);
        if (part == "..") {
            if (--depth < 0) return true;
        } else if (!part.empty() && part != ".") {
            ++depth;
        }
        start = end + 1;
    }
    return false;
}

Result<UriBytes> dataUri(const std::string& uri) {
    const size_t comma = uri.find(',');
    if (comma == std::string::npos) return Error{"its data URI has no ','"};
    const std::string_view header = std::string_view(uri).substr(5, comma - 5);
    const size_t base64 = header.rfind(";base64");
    if (base64 == std::string_view::npos || base64 + 7 != header.size())
        return Error{"its data URI is not base64 (glTF embeds data as base64)"};
    std::optional<std::string> bytes = base64Decoded(std::string_view(uri).substr(comma + 1));
    if (!bytes) return Error{"its data URI is not valid base64"};
    UriBytes out;
    out.bytes = std::move(*bytes);
    out.mimeType = std::string(header.substr(0, std::min(header.find(';'), header.size())));
    return out;
}

// The file a uri names, or why it may not be read.
Result<fs::path> uriFile(const std::string& uri, const fs::path& folder, bool allowOutside) {
    const std::string decoded = percentDecoded(uri);
    if (hasControl(uri) || hasControl(decoded))
        return Error{"a NUL or control character in the uri"};
    const std::string outside = ", outside the asset's folder (--allow-outside reads it)";
    const std::string scheme = schemeOf(uri);
    if (!scheme.empty() && scheme != "file:")
        return Error{"a " + scheme + " uri: ndfmip reads files only"};
    if (!allowOutside) {
        if (!scheme.empty()) return Error{"a file: uri" + outside};
        if (decoded.front() == '/' || decoded.front() == '\\')
            return Error{"an absolute path" + outside};
        for (const char* separator : {"%2f", "%2F", "%5c", "%5C"})
            if (uri.find(separator) != std::string::npos)
                return Error{"a percent-encoded separator" + outside};
        if (decoded.find('\\') != std::string::npos) return Error{"a backslash" + outside};
        if (climbsOut(decoded)) return Error{"'..' climbs" + outside};
    }
    fs::path file;
    if (scheme == "file:") {
        // file:///x or file://localhost/x: the path after the authority.
        std::string rest = percentDecoded(std::string_view(uri).substr(5));
        if (rest.rfind("//localhost/", 0) == 0)
            rest = rest.substr(11);
        else if (rest.rfind("///", 0) == 0)
            rest = rest.substr(2);
        else if (rest.rfind("//", 0) == 0)
            return Error{"a file: uri naming another host"};
        file = rest;
    } else {
        file = fs::path(decoded).is_absolute() ? fs::path(decoded) : folder / decoded;
    }
    if (!allowOutside) {
        // A link inside the folder may still point out of it: compare the real paths.
        std::error_code fileCode, folderCode;
        const fs::path real = fs::weakly_canonical(file, fileCode);
        const fs::path root = fs::weakly_canonical(folder.empty() ? "." : folder, folderCode);
        if (!fileCode && !folderCode) {
            const auto [r, f] = std::mismatch(root.begin(), root.end(), real.begin(), real.end());
            if (r != root.end())
                return Error{"a file whose real path " + quote(real.string()) + " lies" + outside};
        }
    }
    return file;
}

// The GLB's JSON and BIN chunks, or the first thing wrong with its container.
struct GlbChunks {
    std::string_view json, bin;
    bool hasBin = false;
};

Result<GlbChunks> glbChunks(std::string_view bytes) {
    if (bytes.size() < 12) return Error{"a GLB shorter than its 12-byte header"};
    if (const uint32_t version = readU32(bytes, 4); version != 2)
        return Error{"GLB version " + std::to_string(version) + ": ndfmip reads version 2"};
    const uint64_t length = readU32(bytes, 8);
    if (length < bytes.size())
        return Error{std::to_string(bytes.size() - length) +
                     " bytes after the end of the GLB its header declares (" +
                     std::to_string(length) + " bytes)"};
    GlbChunks out;
    size_t at = 12;
    for (int index = 0; at < bytes.size(); ++index) {
        if (bytes.size() - at < 8)
            return Error{"GLB chunk " + std::to_string(index) + " has a cut header"};
        const uint32_t size = readU32(bytes, at), type = readU32(bytes, at + 4);
        const std::string name = type == kJsonChunk  ? "JSON chunk"
                                 : type == kBinChunk ? "BIN chunk"
                                                     : "chunk " + std::to_string(index);
        if (index == 0 && type != kJsonChunk) return Error{"the GLB's first chunk is not JSON"};
        if (size > bytes.size() - at - 8)
            return Error{"the GLB's " + name + " runs past the end of the file"};
        if (size % 4)
            return Error{"the GLB's " + name + " is " + std::to_string(size) +
                         " bytes, not a multiple of 4"};
        const std::string_view data = bytes.substr(at + 8, size);
        if (index == 0) {
            out.json = data;
        } else if (type == kJsonChunk) {
            return Error{"a second JSON chunk in the GLB"};
        } else if (type == kBinChunk) {
            if (index != 1)
                return Error{"a second BIN chunk in the GLB, or one not right after JSON"};
            out.bin = data, out.hasBin = true;
        } // chunks of other types are skipped, as the GLB format says
        at += 8 + size_t(size);
    }
    if (length != bytes.size())
        return Error{"the GLB header declares " + std::to_string(length) +
                     " bytes but the file has " + std::to_string(bytes.size())};
    return out;
}

// The asset's glTF version: 2.x only (a major version 3 would mean another format).
std::string versionProblem(const json& root) {
    const auto asset = root.find("asset");
    if (asset == root.end() || !asset->is_object() || !asset->contains("version") ||
        !(*asset)["version"].is_string())
        return "no asset.version: not a glTF 2.0 asset";
    const std::string& version = (*asset)["version"].get_ref<const std::string&>();
    if (version.rfind("2.", 0) != 0 || version.size() < 3 ||
        !std::all_of(version.begin() + 2, version.end(),
                     [](char c) { return c >= '0' && c <= '9'; }))
        return "asset.version " + quote(version) + ": ndfmip reads glTF 2.x";
    return "";
}

Result<GltfContainer> readContainer(const std::string& path, bool allowOutside) {
    Result<std::string> file = readRegularFile(path, inputLimits().maxImageFileBytes);
    if (!file) return file.error();
    const std::string& bytes = file.value();
    if (bytes.size() >= std::numeric_limits<uint32_t>::max())
        return Error{path + ": larger than 4 GiB, more than glTF readers take"};
    const bool binary = bytes.size() >= 4 && readU32(bytes, 0) == kGlbMagic;

    // The JSON text: the whole file, or a GLB's first chunk; its size and nesting bounded
    // before the parser allocates or recurses.
    GlbChunks chunks;
    if (binary) {
        Result<GlbChunks> c = glbChunks(bytes);
        if (!c) return Error{path + ": " + c.error().message};
        chunks = c.value();
    } else {
        chunks.json = bytes;
    }
    const int64_t textLimit = inputLimits().maxTextFileBytes;
    if (const size_t structure = structureBytes(chunks.json); int64_t(structure) > textLimit)
        return Error{path + ": " + byteSize(int64_t(structure)) +
                     " of glTF JSON (data URIs aside), above the limit of " + byteSize(textLimit)};
    if (std::string problem = jsonNestingProblem(chunks.json, inputLimits().maxJsonDepth);
        !problem.empty())
        return Error{path + ": JSON " + problem};

    GltfContainer c;
    try {
        c.json = json::parse(chunks.json);
    } catch (const std::exception& e) {
        return Error{path + ": not glTF JSON (" + oneLine(e.what()) + ")"};
    }
    if (!c.json.is_object()) return Error{path + ": the glTF JSON is not an object"};
    if (std::string problem = versionProblem(c.json); !problem.empty())
        return Error{path + ": " + problem};

    const fs::path folder = fs::path(path).parent_path();
    const json none = json::array();
    const json& buffers = c.json.contains("buffers") ? c.json["buffers"] : none;
    if (!buffers.is_array()) return Error{path + ": buffers is not an array"};
    for (size_t i = 0; i < buffers.size(); ++i) {
        const json& buffer = buffers[i];
        std::string label = "buffer " + std::to_string(i);
        const json* length =
            buffer.is_object() && buffer.contains("byteLength") ? &buffer["byteLength"] : nullptr;
        if (!length || !length->is_number_integer() || length->get<int64_t>() < 0)
            return Error{path + ": " + label + " has no byteLength"};
        const uint64_t declared = length->get<uint64_t>();
        std::string data;
        if (buffer.contains("uri")) {
            if (!buffer["uri"].is_string())
                return Error{path + ": " + label + ": uri is no string"};
            const std::string& uri = buffer["uri"].get_ref<const std::string&>();
            if (uri.rfind("data:", 0) != 0) label += " " + quote(uri);
            Result<UriBytes> read = readGltfUri(uri, folder, allowOutside);
            if (!read) return Error{path + ": " + label + ": " + read.error().message};
            data = std::move(read->bytes);
        } else if (binary && i == 0 && chunks.hasBin) {
            data = std::string(chunks.bin);
        } else {
            return Error{path + ": " + label + " has no uri" +
                         (binary && i == 0 ? " and the GLB no BIN chunk" : "")};
        }
        if (data.size() < declared)
            return Error{path + ": " + label + " has " + std::to_string(data.size()) +
                         " bytes, fewer than its byteLength of " + std::to_string(declared)};
        data.resize(size_t(declared)); // a BIN chunk's padding is no part of the buffer
        c.buffers.push_back(std::move(data));
    }
    return c;
}

} // namespace

Result<UriBytes> readGltfUri(const std::string& uri, const fs::path& folder, bool allowOutside) {
    if (uri.rfind("data:", 0) == 0) return dataUri(uri);
    if (uri.empty()) return Error{"an empty uri"};
    Result<fs::path> file = uriFile(uri, folder, allowOutside);
    if (!file) return file.error();
    Result<std::string> bytes = readRegularFile(file->string(), inputLimits().maxImageFileBytes);
    if (!bytes) return bytes.error();
    return UriBytes{std::move(bytes.value()), ""};
}

Result<GltfContainer> readGltfContainer(const std::string& path, bool allowOutside) {
    try {
        return readContainer(path, allowOutside);
    } catch (const json::exception& e) { // a property of an unexpected type
        return fileError(path, e.what());
    }
}

} // namespace ndfmip
