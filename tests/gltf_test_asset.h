// A small glTF asset built in the tests: one quad (POSITION, NORMAL, TEXCOORD_0, TANGENT,
// indices) drawn with three materials, a sampler, named nodes and extras; written as .gltf with
// external files or as .glb, and GLB files taken apart again.
#pragma once

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "test_support.h"

namespace ndfmip::test {

using OrderedJson = nlohmann::ordered_json;

inline std::string base64(const std::string& bytes) {
    static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (size_t i = 0; i < bytes.size(); i += 3) {
        uint32_t v = uint32_t((unsigned char)bytes[i]) << 16;
        if (i + 1 < bytes.size()) v |= uint32_t((unsigned char)bytes[i + 1]) << 8;
        if (i + 2 < bytes.size()) v |= uint32_t((unsigned char)bytes[i + 2]);
        out += table[(v >> 18) & 63];
        out += table[(v >> 12) & 63];
        out += i + 1 < bytes.size() ? table[(v >> 6) & 63] : '=';
        out += i + 2 < bytes.size() ? table[v & 63] : '=';
    }
    return out;
}

// The asset's JSON and its one buffer (the quad's vertices and indices). Images 0 and 1 are
// the normal map and the metallic-roughness map; their uri or bufferView is set by the writers.
//  material 0 'Wall':    normalTexture 0 (image 0), metallicRoughnessTexture 1 (image 1) with
//                        roughnessFactor 0.9, occlusionTexture 1 (ORM packing)
//  material 1 'Painted': no textures
//  material 2 'Plain':   normalTexture 0 again, no metallicRoughnessTexture, roughnessFactor 0.5
struct TestAsset {
    OrderedJson json;
    std::string bin;
};

inline TestAsset quadAsset() {
    const float positions[] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
    const float normals[] = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
    const float uvs[] = {0, 1, 1, 1, 1, 0, 0, 0};
    const float tangents[] = {1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1};
    const uint16_t indices[] = {0, 1, 2, 0, 2, 3};
    TestAsset a;
    auto add = [&](const void* data, size_t size) {
        const size_t offset = a.bin.size();
        a.bin.append(static_cast<const char*>(data), size);
        a.bin.resize((a.bin.size() + 3) / 4 * 4, '\0');
        return offset;
    };
    const size_t p = add(positions, sizeof positions), n = add(normals, sizeof normals),
                 t = add(uvs, sizeof uvs), g = add(tangents, sizeof tangents),
                 i = add(indices, sizeof indices);
    a.json = OrderedJson::parse(R"({
      "asset": {"version": "2.0", "generator": "ndfmip tests", "extras": {"kept": true}},
      "scene": 0,
      "scenes": [{"name": "Scene", "nodes": [0]}],
      "nodes": [{"name": "Quad", "mesh": 0, "translation": [0.5, 0, -2], "extras": {"tag": "quad node"}},
                {"name": "Empty", "extras": {"list": [1, 2, 3]}}],
      "meshes": [{"name": "QuadMesh", "primitives": [
          {"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2, "TANGENT": 3}, "indices": 4, "material": 0},
          {"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2, "TANGENT": 3}, "indices": 4, "material": 1},
          {"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2, "TANGENT": 3}, "indices": 4, "material": 2}]}],
      "materials": [
        {"name": "Wall", "normalTexture": {"index": 0},
         "occlusionTexture": {"index": 1, "strength": 0.8},
         "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.7, 0.6, 1], "metallicFactor": 1,
                                  "roughnessFactor": 0.9, "metallicRoughnessTexture": {"index": 1}},
         "extras": {"material": "wall"}},
        {"name": "Painted", "pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.3, 0.9, 1], "roughnessFactor": 0.4},
         "doubleSided": true},
        {"name": "Plain", "normalTexture": {"index": 0, "scale": 1},
         "pbrMetallicRoughness": {"metallicFactor": 0, "roughnessFactor": 0.5}}],
      "samplers": [{"magFilter": 9729, "minFilter": 9987, "wrapS": 10497, "wrapT": 33648, "name": "Repeat"}],
      "textures": [{"sampler": 0, "source": 0, "name": "normal"}, {"sampler": 0, "source": 1, "name": "orm"}],
      "images": [{"name": "normal image"}, {"name": "orm image"}],
      "extras": {"root": "kept"}
    })");
    OrderedJson views = OrderedJson::array(), accessors = OrderedJson::array();
    auto view = [&](size_t offset, size_t length, int target) {
        views.push_back(
            {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", length}, {"target", target}});
        return views.size() - 1;
    };
    accessors.push_back({{"bufferView", view(p, sizeof positions, 34962)},
                         {"componentType", 5126},
                         {"count", 4},
                         {"type", "VEC3"},
                         {"min", {-1, -1, 0}},
                         {"max", {1, 1, 0}}});
    accessors.push_back({{"bufferView", view(n, sizeof normals, 34962)},
                         {"componentType", 5126},
                         {"count", 4},
                         {"type", "VEC3"}});
    accessors.push_back({{"bufferView", view(t, sizeof uvs, 34962)},
                         {"componentType", 5126},
                         {"count", 4},
                         {"type", "VEC2"}});
    accessors.push_back({{"bufferView", view(g, sizeof tangents, 34962)},
                         {"componentType", 5126},
                         {"count", 4},
                         {"type", "VEC4"}});
    accessors.push_back({{"bufferView", view(i, sizeof indices, 34963)},
                         {"componentType", 5123},
                         {"count", 6},
                         {"type", "SCALAR"}});
    a.json["accessors"] = accessors;
    a.json["bufferViews"] = views;
    a.json["buffers"] = OrderedJson::array({{{"byteLength", a.bin.size()}}});
    return a;
}

// As .gltf in `dir`: the buffer in quad.bin, image k in the file images[k].first with the bytes
// images[k].second.
inline std::string writeGltf(const std::filesystem::path& dir, TestAsset a,
                             const std::vector<std::pair<std::string, std::string>>& images) {
    writeBytes(dir / "quad.bin", a.bin);
    a.json["buffers"][0]["uri"] = "quad.bin";
    for (size_t k = 0; k < images.size(); ++k) {
        writeBytes(dir / images[k].first, images[k].second);
        a.json["images"][k]["uri"] = images[k].first;
    }
    const std::filesystem::path path = dir / "quad.gltf";
    writeBytes(path, a.json.dump(2));
    return path.string();
}

inline void appendU32(std::string& out, uint32_t v) {
    char b[4];
    std::memcpy(b, &v, 4);
    out.append(b, 4);
}

inline std::string glbBytes(const OrderedJson& json, std::string bin) {
    std::string text = json.dump();
    text.resize((text.size() + 3) / 4 * 4, ' ');
    bin.resize((bin.size() + 3) / 4 * 4, '\0');
    std::string out;
    appendU32(out, 0x46546C67);
    appendU32(out, 2);
    appendU32(out, uint32_t(12 + 8 + text.size() + 8 + bin.size()));
    appendU32(out, uint32_t(text.size()));
    appendU32(out, 0x4E4F534A);
    out += text;
    appendU32(out, uint32_t(bin.size()));
    appendU32(out, 0x004E4942);
    out += bin;
    return out;
}

// As .glb: the images appended to the buffer as bufferViews with their mimeType.
inline std::string writeGlb(const std::filesystem::path& path, TestAsset a,
                            const std::vector<std::pair<std::string, std::string>>& images) {
    for (size_t k = 0; k < images.size(); ++k) {
        a.bin.resize((a.bin.size() + 3) / 4 * 4, '\0');
        a.json["bufferViews"].push_back(
            {{"buffer", 0}, {"byteOffset", a.bin.size()}, {"byteLength", images[k].second.size()}});
        a.bin += images[k].second;
        a.json["images"][k]["bufferView"] = a.json["bufferViews"].size() - 1;
        a.json["images"][k]["mimeType"] = images[k].first;
    }
    a.json["buffers"][0]["byteLength"] = a.bin.size();
    writeBytes(path, glbBytes(a.json, a.bin));
    return path.string();
}

// A GLB taken apart: its JSON and binary chunk (empty when it has none).
struct Glb {
    OrderedJson json;
    std::string bin;
    bool ok = false;
};

inline Glb parseGlb(const std::string& bytes) {
    Glb g;
    auto u32 = [&](size_t at) {
        uint32_t v = 0;
        std::memcpy(&v, bytes.data() + at, 4);
        return v;
    };
    if (bytes.size() < 20 || u32(0) != 0x46546C67 || u32(4) != 2 || u32(8) != bytes.size() ||
        u32(16) != 0x4E4F534A)
        return g;
    const size_t jsonLength = u32(12);
    if (jsonLength % 4 || 20 + jsonLength > bytes.size()) return g;
    g.json = OrderedJson::parse(bytes.substr(20, jsonLength));
    const size_t at = 20 + jsonLength;
    if (at + 8 <= bytes.size()) {
        if (u32(at + 4) != 0x004E4942 || at + 8 + u32(at) != bytes.size()) return g;
        g.bin = bytes.substr(at + 8, u32(at));
    }
    g.ok = true;
    return g;
}

// The bytes of image `index` of a parsed GLB (every image a bufferView of buffer 0).
inline std::string glbImage(const Glb& g, size_t index) {
    const OrderedJson& view =
        g.json["bufferViews"][g.json["images"][index]["bufferView"].get<size_t>()];
    return g.bin.substr(view.value("byteOffset", size_t(0)), view["byteLength"].get<size_t>());
}

} // namespace ndfmip::test
