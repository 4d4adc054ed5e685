// glTF materials filtered: per material the normal map's pyramid, a Toksvig bake over the
// material's own roughness (metallicRoughnessTexture G times roughnessFactor), and images of
// every level added to the textures: UASTC KTX2 through KHR_texture_basisu, DDS through
// MSFT_texture_dds, or both. The original images stay each texture's core source, so loaders
// without the extensions draw the asset as before.
#include "ndfmip/gltf.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <deque>
#include <functional>
#include <future>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string_view>
#include <tuple>

#include "io/basisu_encoder.h"
#include "io/gltf_asset.h"
#include "methods/lean/engine_anisotropy.h"
#include "ndfmip/bake.h"
#include "ndfmip/io.h"
#include "ndfmip/limits.h"
#include "ndfmip/normal_map.h"
#include "ndfmip/pyramid.h"
#include "ndfmip/render.h"
#include "ndfmip/texture_container.h"

namespace ndfmip {
namespace {

using json = nlohmann::ordered_json;
using Pointer = json::json_pointer;

const char* kDdsExtension = "MSFT_texture_dds";
const char* kDdsMimeType = "image/vnd-ms.dds"; // as MSFT_texture_dds specifies
const char* kBasisuExtension = "KHR_texture_basisu";
const char* kKtx2MimeType = "image/ktx2";
const char* kAnisotropyExtension = "KHR_materials_anisotropy";
// The extras key on every image and texture ndfmip adds: a later pass finds them by it.
const char* kMark = "ndfmip";

// Marks `object` as ndfmip's (extras.ndfmip = role); extras of another type than an object
// are the copied texture's own and give way.
void markOurs(json& object, json role) {
    if (!object["extras"].is_object()) object["extras"] = json::object();
    object["extras"][kMark] = std::move(role);
}

// The mark, or null when `object` is none of ndfmip's.
const json* markOf(const json& object) {
    if (!object.is_object()) return nullptr;
    auto extras = object.find("extras");
    if (extras == object.end() || !extras->is_object()) return nullptr;
    auto mark = extras->find(kMark);
    return mark == extras->end() ? nullptr : &*mark;
}

// The images of one chain of levels ndfmip adds (-1: not written in this --texture-format).
struct AddedLevels {
    int dds = -1, ktx2 = -1;
    bool operator<(const AddedLevels& o) const {
        return std::tie(dds, ktx2) < std::tie(o.dds, o.ktx2);
    }
    bool operator==(const AddedLevels& o) const { return dds == o.dds && ktx2 == o.ktx2; }
};

// Links `texture` to the levels through the extensions that carry them.
void linkLevels(json& texture, const AddedLevels& levels) {
    if (levels.dds >= 0) texture["extensions"][kDdsExtension] = {{"source", levels.dds}};
    if (levels.ktx2 >= 0) texture["extensions"][kBasisuExtension] = {{"source", levels.ktx2}};
}

// Thrown inside this file only, caught by filterGltf: one line, starting with the path.
struct GltfProblem {
    std::string message;
};
[[noreturn]] void refuse(std::string message) {
    throw GltfProblem{std::move(message)};
}

// A texture slot of a material and the texture it reads: the normalTexture object, etc.
struct TextureUse {
    Pointer at;
    int texture = -1;
};

// One material to filter: what it reads, what it gets.
struct MaterialJob {
    size_t material = 0;
    std::string where; // "scene.gltf: material 0 'Wall'"
    std::string name;  // for the report
    int normalTexture = -1, normalImage = -1;
    float scale = 1.f; // normalTexture.scale
    int roughnessTexture = -1, roughnessImage = -1;
    float roughnessFactor = 1.f;
    bool makeMap = false; // no texture can carry the filtered roughness: make one
};

const json* member(const json& object, const char* key) {
    if (!object.is_object()) return nullptr;
    auto it = object.find(key);
    return it == object.end() ? nullptr : &*it;
}

// The index of a textureInfo (-1 when `info` is null), checked against the textures.
int textureIndex(const json* info, const std::string& where, const char* slot, size_t textures) {
    if (!info) return -1;
    const json* index = member(*info, "index");
    if (!index || !index->is_number_integer() || index->get<int64_t>() < 0 ||
        size_t(index->get<int64_t>()) >= textures)
        refuse(where + ": " + slot + " does not name one of the asset's " +
               std::to_string(textures) + " textures");
    return int(index->get<int64_t>());
}

float numberOr(const json* object, const char* key, float fallback, const std::string& where) {
    const json* value = object ? member(*object, key) : nullptr;
    if (!value) return fallback;
    if (!value->is_number() || !std::isfinite(value->get<double>()))
        refuse(where + ": " + key + " is not a number");
    return value->get<float>();
}

// The core source image of texture `t` (the PNG or JPEG every loader reads).
int sourceImage(const json& textures, int t, size_t images, const std::string& where,
                const char* slot) {
    const json* source = member(textures[size_t(t)], "source");
    if (!source || !source->is_number_integer() || source->get<int64_t>() < 0 ||
        size_t(source->get<int64_t>()) >= images)
        refuse(where + ": " + slot + " (texture " + std::to_string(t) +
               ") has no core source image (PNG or JPEG)");
    return int(source->get<int64_t>());
}

json texCoordOf(const json* info) {
    const json* c = info ? member(*info, "texCoord") : nullptr;
    return c ? *c : json(0);
}

json transformOf(const json* info) {
    const json* extensions = info ? member(*info, "extensions") : nullptr;
    const json* transform = extensions ? member(*extensions, "KHR_texture_transform") : nullptr;
    return transform ? *transform : json(nullptr);
}

std::string sizeText(const Image& image) {
    return std::to_string(image.width) + "x" + std::to_string(image.height);
}

std::string percentText(size_t part, size_t whole) {
    char text[32];
    std::snprintf(text, sizeof text, "%.0f%%",
                  100.0 * double(part) / double(std::max<size_t>(whole, 1)));
    return text;
}

double elapsedMs(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
        .count();
}

// Width and height as a PNG's or JPEG's header declares them (the formats glTF embeds), read
// before anything is decoded; nullopt for other formats or a header cut short.
std::optional<std::pair<int64_t, int64_t>> declaredSize(std::string_view b) {
    auto be = [&](size_t at, int bytes) {
        int64_t v = 0;
        for (int k = 0; k < bytes; ++k)
            v = v << 8 | int64_t(static_cast<unsigned char>(b[at + size_t(k)]));
        return v;
    };
    if (b.size() >= 24 && b.substr(0, 8) == "\x89PNG\r\n\x1a\n" && b.substr(12, 4) == "IHDR")
        return std::pair(be(16, 4), be(20, 4));
    if (b.size() < 4 || b.substr(0, 3) != "\xFF\xD8\xFF") return std::nullopt;
    size_t at = 2;
    while (at + 4 <= b.size()) {
        if (static_cast<unsigned char>(b[at]) != 0xFF) return std::nullopt;
        const int marker = static_cast<unsigned char>(b[at + 1]);
        if (marker == 0xFF) { // fill byte
            ++at;
            continue;
        }
        if (marker == 0x01 || (marker >= 0xD0 && marker <= 0xD8)) { // no length
            at += 2;
            continue;
        }
        if (marker == 0xD9 || marker == 0xDA) return std::nullopt; // no frame header before data
        const bool frame =
            marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC;
        if (frame) {
            if (at + 9 > b.size()) return std::nullopt;
            return std::pair(be(at + 7, 2), be(at + 5, 2));
        }
        at += 2 + size_t(be(at + 2, 2));
    }
    return std::nullopt;
}

// Every material of the asset and the texture slot each reads: the core slots and any
// textureInfo inside the material's extensions (KHR_materials_clearcoat and the like).
std::vector<TextureUse> textureUses(const json& materials) {
    std::vector<TextureUse> uses;
    auto visit = [&](auto& self, const json& value, const Pointer& at) -> void {
        if (value.is_object()) {
            const json* index = member(value, "index");
            if (index && index->is_number_integer())
                uses.push_back({at, int(index->get<int64_t>())});
            // extras are the application's: an "index" there names no texture.
            for (auto it = value.begin(); it != value.end(); ++it)
                if (it.key() != "extras") self(self, it.value(), at / it.key());
        }
    };
    for (size_t m = 0; m < materials.size(); ++m) {
        const Pointer at = Pointer("/materials") / m;
        for (const char* slot : {"normalTexture", "occlusionTexture", "emissiveTexture"})
            if (const json* info = member(materials[m], slot)) visit(visit, *info, at / slot);
        if (const json* pbr = member(materials[m], "pbrMetallicRoughness"))
            for (const char* slot : {"baseColorTexture", "metallicRoughnessTexture"})
                if (const json* info = member(*pbr, slot))
                    visit(visit, *info, at / "pbrMetallicRoughness" / slot);
        if (const json* extensions = member(materials[m], "extensions"))
            visit(visit, *extensions, at / "extensions");
    }
    return uses;
}

class Filter {
  public:
    Filter(std::string path, GltfAsset& asset, const GltfOptions& options)
        : path_(std::move(path)), asset_(asset),
          dds_(options.textureFormat != GltfTextureFormat::Basisu),
          basisu_(options.textureFormat != GltfTextureFormat::Dds),
          anisotropy_(options.method == GltfMethod::Sggx || options.method == GltfMethod::GgxAniso),
          roughness_(options.method == GltfMethod::GgxFit     ? Method::GgxFit
                     : options.method == GltfMethod::GgxAniso ? Method::GgxAniso
                                                              : Method::Toksvig) {}

    GltfFiltered run() {
        json& root = asset_.json;
        stripEarlierPass();
        const json empty = json::array();
        const json& materials = root.contains("materials") ? root["materials"] : empty;
        if (!materials.is_array()) refuse(path_ + ": materials is not an array");
        std::vector<MaterialJob> jobs;
        for (size_t m = 0; m < materials.size(); ++m)
            if (member(materials[m], "normalTexture")) jobs.push_back(plan(m));
        if (jobs.empty()) refuse(path_ + ": no material has a normalTexture: nothing to correct");
        originalTextures_ = root["textures"].size();
        // One normal image at a time: its chain is built once, serves every material that reads
        // it, and is dropped before the next (memory does not grow with the material count).
        std::vector<std::optional<GltfMaterialReport>> reports(jobs.size());
        std::set<int> done;
        for (const MaterialJob& job : jobs) {
            if (!done.insert(job.normalImage).second) continue;
            std::vector<size_t> group;
            for (size_t j = 0; j < jobs.size(); ++j)
                if (jobs[j].normalImage == job.normalImage) group.push_back(j);
            filterGroup(jobs, group, reports);
        }
        while (!uastcInFlight_.empty()) finishOldestUastc();
        for (std::optional<GltfMaterialReport>& report : reports)
            result_.materials.push_back(std::move(*report));
        assignTextures();
        // Used, not required: the original images stay the core sources.
        json& used = root["extensionsUsed"];
        if (!used.is_array()) used = json::array();
        for (const char* name : {kDdsExtension, kBasisuExtension})
            if ((name == kDdsExtension ? dds_ : basisu_) &&
                std::find(used.begin(), used.end(), name) == used.end())
                used.push_back(name);
        if (anisotropy_ && std::find(used.begin(), used.end(), kAnisotropyExtension) == used.end())
            used.push_back(kAnisotropyExtension);
        Result<std::string> glb = glbFile(asset_);
        if (!glb) refuse(path_ + ": " + glb.error().message);
        result_.glb = std::move(glb.value());
        return std::move(result_);
    }

  private:
    // An asset that ndfmip gltf wrote is put back as it was: its marked images and textures
    // removed (with their bufferViews and bytes when they are the last ones, as ndfmip wrote
    // them), the DDS links it added to the asset's own textures dropped, the materials it gave a
    // texture of its own given back their roughnessFactor and metallicRoughnessTexture.
    void stripEarlierPass() {
        json& root = asset_.json;
        json& images = root["images"];
        std::vector<bool> ourImage(images.size(), false);
        for (size_t i = 0; i < images.size(); ++i) ourImage[i] = markOf(images[i]) != nullptr;
        if (std::find(ourImage.begin(), ourImage.end(), true) == ourImage.end()) return;
        stripOurAnisotropy();
        if (!root.contains("textures")) root["textures"] = json::array();
        json& textures = root["textures"];
        if (!textures.is_array()) refuse(path_ + ": textures is not an array");

        // Texture by texture: ours go (their uses redirected or restored), the asset's own lose
        // the DDS link to one of our images.
        std::vector<int> newTexture(textures.size());
        const auto ours = [&](const json& index) {
            return index.is_number_integer() && index.get<int64_t>() >= 0 &&
                   size_t(index.get<int64_t>()) < ourImage.size() &&
                   ourImage[size_t(index.get<int64_t>())];
        };
        for (size_t t = 0; t < textures.size(); ++t) {
            json& texture = textures[t];
            newTexture[t] = markOf(texture) ? -1 : int(t);
            if (!texture.is_object() || !texture.contains("extensions")) continue;
            json& extensions = texture["extensions"];
            for (const char* name : {kDdsExtension, kBasisuExtension})
                if (extensions.is_object() && extensions.contains(name)) {
                    const json& link = extensions[name];
                    if (link.is_object() && link.contains("source") && ours(link["source"]))
                        extensions.erase(name);
                }
            if (extensions.is_object() && extensions.empty()) texture.erase("extensions");
        }
        json& materials = root["materials"];
        if (materials.is_null()) materials = json::array();
        for (const TextureUse& use : textureUses(materials)) {
            if (use.texture < 0 || size_t(use.texture) >= textures.size() ||
                newTexture[size_t(use.texture)] >= 0)
                continue;
            const json& mark = *markOf(textures[size_t(use.texture)]);
            json& info = root[use.at];
            if (mark.is_object() && mark.contains("copyOf")) {
                info["index"] = mark["copyOf"];
                continue;
            }
            if (!mark.is_object() || !mark.contains("made")) continue; // refused below
            const int64_t original = mark.value("metallicRoughnessTexture", int64_t(-1));
            const std::string slot = use.at.back();
            if (slot == "metallicRoughnessTexture") {
                json& pbr = root[use.at.parent_pointer()];
                pbr["roughnessFactor"] = mark.value("roughnessFactor", 1.0);
                if (original >= 0)
                    info["index"] = original;
                else
                    pbr.erase("metallicRoughnessTexture");
            } else if (slot == "occlusionTexture" && original >= 0) {
                info["index"] = original;
            }
        }
        // What still reads one of ours cannot be put back.
        for (const TextureUse& use : textureUses(materials))
            if (use.texture >= 0 && size_t(use.texture) < textures.size() &&
                newTexture[size_t(use.texture)] < 0)
                refuse(path_ + ": " + use.at.to_string() + " reads texture " +
                       std::to_string(use.texture) +
                       ", which an earlier ndfmip gltf made and this one would remove");
        // Renumber: textures, then images.
        int next = 0;
        for (int& t : newTexture)
            if (t >= 0) t = next++;
        for (const TextureUse& use : textureUses(materials))
            if (use.texture >= 0 && size_t(use.texture) < newTexture.size())
                root[use.at]["index"] = newTexture[size_t(use.texture)];
        for (size_t t = textures.size(); t-- > 0;)
            if (newTexture[t] < 0) textures.erase(t);
        // The extensions the earlier pass named and no texture uses now (a rerun with another
        // --texture-format) leave extensionsUsed; run() names again those this pass uses.
        if (root.contains("extensionsUsed") && root["extensionsUsed"].is_array())
            for (const char* name : {kDdsExtension, kBasisuExtension}) {
                bool inUse = false;
                for (const json& texture : textures)
                    if (const json* extensions = member(texture, "extensions"))
                        inUse = inUse || (extensions->is_object() && extensions->contains(name));
                json& used = root["extensionsUsed"];
                if (!inUse) used.erase(std::remove(used.begin(), used.end(), name), used.end());
            }

        std::vector<int> newImage(images.size());
        next = 0;
        for (size_t i = 0; i < images.size(); ++i) newImage[i] = ourImage[i] ? -1 : next++;
        auto renumber = [&](json& holder, const std::string& where) {
            if (!holder.is_object() || !holder.contains("source")) return;
            json& source = holder["source"];
            if (!source.is_number_integer() || source.get<int64_t>() < 0 ||
                size_t(source.get<int64_t>()) >= newImage.size())
                return;
            const int to = newImage[size_t(source.get<int64_t>())];
            if (to < 0)
                refuse(path_ + ": " + where + " reads image " + source.dump() +
                       ", which an earlier ndfmip gltf made and this one would remove");
            source = to;
        };
        for (size_t t = 0; t < textures.size(); ++t) {
            const std::string where = "texture " + std::to_string(t);
            renumber(textures[t], where);
            if (textures[t].is_object() && textures[t].contains("extensions") &&
                textures[t]["extensions"].is_object())
                for (auto& [name, extension] : textures[t]["extensions"].items())
                    renumber(extension, where + " (" + name + ")");
        }

        // Their bufferViews, when they are the last ones and nothing else reads them, and
        // their bytes, when they end the buffer.
        json& views = root["bufferViews"];
        std::set<size_t> ourViews;
        for (size_t i = 0; i < images.size(); ++i)
            if (ourImage[i] && images[i].contains("bufferView") &&
                images[i]["bufferView"].is_number_unsigned())
                ourViews.insert(images[i]["bufferView"].get<size_t>());
        for (size_t i = 0; i < images.size(); ++i)
            if (!ourImage[i] && images[i].is_object() && images[i].contains("bufferView") &&
                images[i]["bufferView"].is_number_unsigned())
                ourViews.erase(images[i]["bufferView"].get<size_t>());
        if (root.contains("accessors") && root["accessors"].is_array())
            for (const json& accessor : root["accessors"])
                if (accessor.is_object() && accessor.contains("bufferView") &&
                    accessor["bufferView"].is_number_unsigned())
                    ourViews.erase(accessor["bufferView"].get<size_t>());
        for (size_t i = images.size(); i-- > 0;)
            if (ourImage[i]) images.erase(i);
        result_.replacedImages = int(std::count(ourImage.begin(), ourImage.end(), true));
        const bool suffix = views.is_array() && !ourViews.empty() &&
                            *ourViews.begin() == views.size() - ourViews.size() &&
                            *ourViews.rbegin() == views.size() - 1;
        if (!suffix) {
            if (!ourViews.empty())
                result_.warnings.push_back(path_ + ": the earlier pass's " +
                                           std::to_string(ourViews.size()) +
                                           " bufferViews are no longer the last ones: kept");
            return;
        }
        // Every view ours reads one buffer and nothing kept reads past the first of them.
        int64_t buffer = -1;
        uint64_t cut = std::numeric_limits<uint64_t>::max();
        for (size_t v : ourViews) {
            const json& view = views[v];
            const int64_t b = view.value("buffer", int64_t(-1));
            if (buffer >= 0 && b != buffer) buffer = -2;
            if (buffer != -2) buffer = b;
            cut = std::min(cut, view.value("byteOffset", uint64_t(0)));
        }
        const size_t kept = views.size() - ourViews.size();
        for (size_t v = 0; v < kept; ++v) {
            const json& view = views[v];
            if (view.value("buffer", int64_t(-1)) == buffer &&
                view.value("byteOffset", uint64_t(0)) + view.value("byteLength", uint64_t(0)) > cut)
                buffer = -2;
        }
        while (views.size() > kept) views.erase(views.size() - 1);
        if (buffer >= 0 && size_t(buffer) < asset_.buffers.size() &&
            cut <= asset_.buffers[size_t(buffer)].size()) {
            asset_.buffers[size_t(buffer)].resize(size_t(cut));
            root["buffers"][size_t(buffer)]["byteLength"] = cut;
        }
    }

    // The KHR_materials_anisotropy that an earlier pass gave materials (marked in its extras)
    // removed, and the extension from extensionsUsed when no material has it any more.
    void stripOurAnisotropy() {
        json& root = asset_.json;
        if (!root.contains("materials") || !root["materials"].is_array()) return;
        bool inUse = false;
        for (json& material : root["materials"]) {
            if (!material.is_object() || !material.contains("extensions")) continue;
            json& extensions = material["extensions"];
            if (!extensions.is_object() || !extensions.contains(kAnisotropyExtension)) continue;
            if (markOf(extensions[kAnisotropyExtension])) {
                extensions.erase(kAnisotropyExtension);
                if (extensions.empty()) material.erase("extensions");
            } else {
                inUse = true;
            }
        }
        if (!inUse && root.contains("extensionsUsed") && root["extensionsUsed"].is_array()) {
            json& used = root["extensionsUsed"];
            used.erase(std::remove(used.begin(), used.end(), kAnisotropyExtension), used.end());
        }
    }

    // What material m reads, checked.
    MaterialJob plan(size_t m) {
        const json& root = asset_.json;
        const json& material = root["materials"][m];
        const json* textures = member(root, "textures");
        const size_t textureCount = textures && textures->is_array() ? textures->size() : 0;
        const size_t imageCount = root["images"].size();
        MaterialJob job;
        job.material = m;
        const json* name = member(material, "name");
        job.name =
            name && name->is_string() ? name->get<std::string>() : "material " + std::to_string(m);
        job.where = path_ + ": material " + std::to_string(m);
        if (name && name->is_string()) job.where += ' ' + quote(job.name);
        const json* normal = member(material, "normalTexture");
        job.normalTexture = textureIndex(normal, job.where, "normalTexture", textureCount);
        job.normalImage =
            sourceImage(*textures, job.normalTexture, imageCount, job.where, "normalTexture");
        job.scale = numberOr(normal, "scale", 1.f, job.where + ": normalTexture");
        const json* pbr = member(material, "pbrMetallicRoughness");
        job.roughnessFactor =
            std::clamp(numberOr(pbr, "roughnessFactor", 1.f, job.where), 0.f, 1.f);
        const json* roughness = pbr ? member(*pbr, "metallicRoughnessTexture") : nullptr;
        job.roughnessTexture =
            textureIndex(roughness, job.where, "metallicRoughnessTexture", textureCount);
        if (job.roughnessTexture >= 0) {
            job.roughnessImage = sourceImage(*textures, job.roughnessTexture, imageCount, job.where,
                                             "metallicRoughnessTexture");
            // The two are combined texel by texel: they must be read at the same coordinates.
            if (texCoordOf(normal) != texCoordOf(roughness))
                refuse(job.where + ": normalTexture reads TEXCOORD_" + texCoordOf(normal).dump() +
                       " but metallicRoughnessTexture TEXCOORD_" + texCoordOf(roughness).dump() +
                       ": their texels do not line up");
            if (transformOf(normal) != transformOf(roughness))
                refuse(job.where + ": normalTexture and metallicRoughnessTexture have different "
                                   "KHR_texture_transform: "
                                   "their texels do not line up");
        }
        // roughnessFactor 0 scales any texture to 0: only a factor of 1 and a map of our own can
        // carry the roughness the normals add.
        job.makeMap = job.roughnessTexture < 0 || job.roughnessFactor == 0.f;
        if (anisotropy_)
            if (const json* extensions = member(material, "extensions");
                extensions && member(*extensions, kAnisotropyExtension))
                refuse(job.where + ": has a " + kAnisotropyExtension +
                       " of its own, which --method " +
                       (roughness_ == Method::GgxAniso ? "ggx-aniso" : "sggx") +
                       " would replace: use --method toksvig");
        return job;
    }

    SourceImage decodeOrRefuse(int image, const std::string& name) {
        Result<std::string> bytes = gltfImageBytes(asset_, image);
        if (!bytes) refuse(path_ + ": " + bytes.error().message);
        Result<SourceImage> decoded = decodeImage(bytes.value(), name);
        if (!decoded) refuse(decoded.error().message);
        ++result_.decodedImages;
        return std::move(decoded.value());
    }

    // The unit normals of the normal image, refused when they are no tangent-space normal map.
    Image normalsOrRefuse(const MaterialJob& job) {
        const std::string name =
            job.where + ", normalTexture " + asset_.imageLabels[size_t(job.normalImage)];
        checkMemoryBeforeDecoding(job, name);
        const SourceImage source = decodeOrRefuse(job.normalImage, name);
        if (source.image.channels < 3)
            refuse(name + ": has " + std::to_string(source.image.channels) +
                   " channel(s): not a normal map (glTF stores x, y, z in RGB)");
        DecodeReport report;
        Result<Image> normals = decodeNormalMap(source, DecodeOptions{}, name, &report);
        if (!normals) refuse(normals.error().message);
        if (report.offUnitLength * 2 > report.texels)
            refuse(
                name + ": " + percentText(report.offUnitLength, report.texels) +
                " of its texels decode to vectors more than 10% off unit length: not a normal map "
                "(glTF stores (n + 1)/2 in RGB)");
        if (report.facingDown * 2 > report.texels)
            refuse(
                name + ": " + percentText(report.facingDown, report.texels) +
                " of its normals point into the surface (z < 0): not a tangent-space normal map");
        if (report.offUnitLength * 20 > report.texels)
            result_.warnings.push_back(name + ": " +
                                       percentText(report.offUnitLength, report.texels) +
                                       " of the normals are far from unit length");
        if (report.facingDown)
            result_.warnings.push_back(name + ": " + std::to_string(report.facingDown) +
                                       " normals face away from the surface (z < 0)");
        if (report.degenerate)
            result_.warnings.push_back(name + ": " + std::to_string(report.degenerate) +
                                       " zero-length normals replaced by (0,0,1)");
        return std::move(normals.value());
    }

    // The metallic-roughness image as R, G, B, A in [0, 1] (grey images give R = G = B).
    Image materialMapOrRefuse(const MaterialJob& job, const Image& normals) {
        const std::string name = job.where + ", metallicRoughnessTexture " +
                                 asset_.imageLabels[size_t(job.roughnessImage)];
        const Image map = decodeOrRefuse(job.roughnessImage, name).image;
        if (map.width != normals.width || map.height != normals.height)
            refuse(name + " is " + sizeText(map) + " but the normalTexture " +
                   asset_.imageLabels[size_t(job.normalImage)] + " is " + sizeText(normals) +
                   ": resize one to the other");
        Image rgba(map.width, map.height, 4);
        const size_t c = size_t(map.channels);
        for (size_t i = 0; i < map.texelCount(); ++i) {
            const float* p = &map.pixels[i * c];
            const float v[4] = {p[0], c >= 3 ? p[1] : p[0], c >= 3 ? p[2] : p[0],
                                c == 4   ? p[3]
                                : c == 2 ? p[1]
                                         : 1.f};
            for (int k = 0; k < 4; ++k) {
                if (!std::isfinite(v[k]))
                    refuse(name + ": NaN or infinite value at texel (" +
                           std::to_string(i % size_t(map.width)) + ", " +
                           std::to_string(i / size_t(map.width)) + ")");
                rgba.pixels[4 * i + size_t(k)] = std::clamp(v[k], 0.f, 1.f);
            }
        }
        return rgba;
    }

    // The levels as a DDS in `ddsFormat` and/or a UASTC KTX2 of their first three channels
    // (RGB: the normal's x, y, z; the material map's occlusion, roughness, metallic), as
    // --texture-format asks; `about` says in the KTX2 what the channels hold.
    AddedLevels addLevels(std::vector<Image> levels, TextureFormat ddsFormat,
                          const std::string& name, const std::string& role, const json& about) {
        AddedLevels out;
        if (dds_) {
            std::vector<const Image*> pointers;
            for (const Image& level : levels) pointers.push_back(&level);
            Result<EncodedTexture> texture = encodeTexture(pointers, ddsFormat);
            if (!texture) refuse(path_ + ": " + texture.error().message);
            out.dds = addGltfImage(asset_, ddsFile(texture.value()), kDdsMimeType, name);
            markOurs(asset_.json["images"][size_t(out.dds)], role);
        }
        if (basisu_) {
            std::vector<LevelRows> rows;
            for (Image& level : levels)
                rows.push_back(rowsOf(std::make_shared<const Image>(std::move(level)), 3));
            Ktx2KeyValues keys = {
                {"KTXswizzle", "rgb1"},
                {"ndfmip", about.dump(-1, ' ', false, json::error_handler_t::replace)}};
            out.ktx2 = addGltfImage(asset_, std::string(), kKtx2MimeType, name + " (UASTC KTX2)");
            markOurs(asset_.json["images"][size_t(out.ktx2)], role + " (UASTC)");
            encodeUastcLater(out.ktx2, std::move(rows), std::move(keys));
        }
        return out;
    }

    // The UASTC encoder, most of the run's time, works while the next texture is baked and
    // encoded: one texture's encode leaves a core idle once its small levels are done. At most
    // two textures are in flight, so memory does not grow with the texture count.
    void encodeUastcLater(int image, std::vector<LevelRows> rows, Ktx2KeyValues keys) {
        if (uastcInFlight_.size() >= 2) finishOldestUastc();
        auto encode = [rows = std::move(rows), keys = std::move(keys)]() -> Result<std::string> {
            Result<EncodedTexture> texture = encodeTexture(rows, TextureFormat::Uastc);
            if (!texture) return texture.error();
            return ktx2File(texture.value(), kUastcZstdLevel, keys);
        };
        uastcInFlight_.push_back({image, std::async(std::launch::async, std::move(encode))});
    }

    void finishOldestUastc() {
        PendingUastc oldest = std::move(uastcInFlight_.front());
        uastcInFlight_.pop_front();
        Result<std::string> bytes = oldest.bytes.get();
        if (!bytes) refuse(path_ + ": " + bytes.error().message);
        setGltfImageBytes(asset_, oldest.image, std::move(bytes.value()));
    }

    // --max-memory against the size the normal image's header declares, before it is decoded:
    // the bake, and beside it the material map as RGBA, its alpha, the averaged and encoded
    // levels and, with a normalTexture.scale, the scaled normals' pyramid.
    void checkMemoryBeforeDecoding(const MaterialJob& job, const std::string& name) {
        Result<std::string> bytes = gltfImageBytes(asset_, job.normalImage);
        if (!bytes) return; // decodeOrRefuse names the problem
        const std::optional<std::pair<int64_t, int64_t>> size = declaredSize(bytes.value());
        if (!size) return;
        if (Status s = checkImageSize(name, size->first, size->second); !s) refuse(s.error);
        BakeOptions options;
        options.roughnessMap = std::make_shared<Image>();
        const double texels = double(size->first) * double(size->second);
        const double beside =
            16 + 4 + 16 * 4.0 / 3 * 2 + 12 * 4.0 / 3 + (job.scale != 1.f ? 28 : 0);
        const int64_t need = bakeMemoryEstimate(roughness_, options, size->first, size->second) +
                             int64_t(beside * texels);
        if (need > inputLimits().maxMemoryBytes)
            refuse(name + ": filtering a " + std::to_string(size->first) + "x" +
                   std::to_string(size->second) + " normal map needs about " + byteSize(need) +
                   ", above the limit of " + byteSize(inputLimits().maxMemoryBytes) +
                   "; --max-memory raises it");
    }

    // The materials of `group` (indices into jobs), which all read one normal image: it is
    // decoded and its pyramid built once; each distinct material map and option set is baked
    // once and its DDS shared by the materials that read it.
    void filterGroup(const std::vector<MaterialJob>& jobs, const std::vector<size_t>& group,
                     std::vector<std::optional<GltfMaterialReport>>& reports) {
        const MaterialJob& first = jobs[group.front()];
        const auto start = std::chrono::steady_clock::now();
        auto normals = std::make_shared<Image>(normalsOrRefuse(first));
        const Pyramid pyramid = buildPyramid(SharedImage(normals));
        const int levels = int(pyramid.levels.size());

        // The normal texture's levels: the mean normal's direction, (n + 1)/2 (one file per image).
        std::vector<Image> encoded;
        for (int k = 0; k < levels; ++k) {
            const Image& mean = levelMean(pyramid, k);
            Image e(mean.width, mean.height, 3);
            for (size_t i = 0; i < e.texelCount(); ++i) {
                float n[3];
                normalizeOrFlat(&mean.pixels[3 * i], n);
                for (int c = 0; c < 3; ++c) e.pixels[3 * i + size_t(c)] = 0.5f * (n[c] + 1.f);
            }
            encoded.push_back(std::move(e));
        }
        const AddedLevels normalDds =
            addLevels(std::move(encoded), TextureFormat::Bc5Unorm,
                      "ndfmip BC5 mips of " + asset_.imageLabels[size_t(first.normalImage)],
                      "BC5 normal mips",
                      {{"content", "normal"},
                       {"space", "tangent"},
                       {"encoding", "(n+1)/2"},
                       {"green", "up"},
                       {"channels", {{"r", "x"}, {"g", "y"}, {"b", "z"}}}});
        const double normalMilliseconds = elapsedMs(start);

        std::map<int, std::shared_ptr<const Image>> maps; // material image -> RGBA, for this group
        std::map<std::tuple<int, float, float, bool>, Baked> baked;
        for (size_t j : group) {
            const MaterialJob& job = jobs[j];
            const auto key =
                std::tuple(job.roughnessImage, job.roughnessFactor, job.scale, job.makeMap);
            auto it = baked.find(key);
            if (it == baked.end()) {
                const auto bakeStart = std::chrono::steady_clock::now();
                std::shared_ptr<const Image>& rgba = maps[job.roughnessImage];
                if (!rgba) rgba = materialRgba(job, *normals);
                Baked b = bakeMaterial(job, pyramid, normals, rgba);
                b.milliseconds = elapsedMs(bakeStart);
                it = baked.emplace(key, std::move(b)).first;
            }
            Baked& b = it->second;
            wants_[(Pointer("/materials") / job.material / "normalTexture").to_string()] =
                normalDds;
            if (job.makeMap) {
                madeTexture(job, b);
            } else {
                const Pointer materialAt = Pointer("/materials") / job.material;
                wants_[(materialAt / "pbrMetallicRoughness" / "metallicRoughnessTexture")
                           .to_string()] = b.dds;
                // ORM packing: the occlusion read from the same texture (R) gets the same levels.
                const json* occlusion = member(asset_.json[materialAt], "occlusionTexture");
                const json* index = occlusion ? member(*occlusion, "index") : nullptr;
                if (index && *index == job.roughnessTexture)
                    wants_[(materialAt / "occlusionTexture").to_string()] = b.dds;
            }
            if (anisotropy_) anisotropyFor(job, b);
            reports[j] = GltfMaterialReport{job.name,
                                            normals->width,
                                            normals->height,
                                            levels,
                                            job.makeMap,
                                            b.clampedTexels,
                                            normalMilliseconds + b.milliseconds};
        }
    }

    // R, G, B, A of the material map (all 1 without one).
    std::shared_ptr<const Image> materialRgba(const MaterialJob& job, const Image& normals) {
        auto rgba = std::make_shared<Image>(normals.width, normals.height, 4);
        if (job.roughnessTexture >= 0)
            *rgba = materialMapOrRefuse(job, normals);
        else
            std::fill(rgba->pixels.begin(), rgba->pixels.end(), 1.f);
        return rgba;
    }

    // One material map and option set baked: its RGBA8 DDS of every level and level 0, the
    // PNG core source should a texture of our own be made.
    struct Baked {
        AddedLevels dds;
        Image level0; // with makeMap: the level the core PNG is made of
        int png = -1; // that PNG's image, once made
        std::map<std::pair<int, int>, int> madeTextures; // (roughness texture, normal texture)
        size_t clampedTexels = 0;
        double milliseconds = 0.0;
        // --method sggx: the anisotropy levels, level 0 as the core PNG of the
        // anisotropyTexture (made once: anisotropyTexture).
        AddedLevels anisotropy;
        Image anisotropyLevel0;
        int anisotropyTexture = -1;
    };

    // Every level of KHR_materials_anisotropy from each texel's lobe, `lobeOf(k, i)`, the
    // directions chosen so that the sampler's blends keep them (coherentDirections): returns
    // the material levels (`averaged`'s R, B, A; G = roughnessG(sqrt(alpha_b))) and fills
    // `anisotropy` with the anisotropyTexture's (RGBA: (d + 1)/2, s, 1).
    template <class RoughnessG>
    static std::vector<Image>
    khrAnisotropyLevels(const std::vector<SharedImage>& averaged,
                        const std::function<AnisotropicLobe(size_t k, size_t i)>& lobeOf,
                        RoughnessG roughnessG, std::vector<Image>& anisotropy) {
        std::vector<std::pair<int, int>> sizes;
        for (const SharedImage& level : averaged) sizes.emplace_back(level->width, level->height);
        const StoredDirections directions = coherentDirections(sizes, lobeOf);
        std::vector<Image> material;
        for (size_t k = 0; k < averaged.size(); ++k) {
            Image level = *averaged[k];
            Image texture(level.width, level.height, 4);
            for (size_t i = 0; i < level.texelCount(); ++i) {
                AnisotropicLobe lobe = lobeOf(k, i);
                lobe.direction = directions.at(k, i);
                const KhrAnisotropy khr = khrAnisotropy(lobe);
                level.pixels[4 * i + 1] = roughnessG(khr.roughness);
                khrAnisotropyTexel(khr, &texture.pixels[4 * i]);
            }
            anisotropy.push_back(std::move(texture));
            material.push_back(std::move(level));
        }
        return material;
    }

    // --method sggx: the anisotropic GGX lobe of squared-roughness tensor E[alpha^2] I + 2 Sigma
    // (Sigma the slopes' covariance, the lean bake's moments; sggx.glsl) as
    // KHR_materials_anisotropy stores it (khrAnisotropyLevels).
    template <class RoughnessG>
    std::vector<Image> sggxLevels(const Pyramid& pyramid, const Image& alpha,
                                  const std::vector<SharedImage>& averaged, RoughnessG roughnessG,
                                  std::vector<Image>& anisotropy) {
        const Bake lean = bakeMethod(Method::Lean, pyramid, {});
        ++result_.bakes;
        std::vector<Image> alpha2{Image(alpha.width, alpha.height, 1)};
        for (size_t i = 0; i < alpha.texelCount(); ++i)
            alpha2[0].pixels[i] = alpha.pixels[i] * alpha.pixels[i];
        for (int k = 1; k < int(pyramid.levels.size()); ++k)
            alpha2.push_back(averageToLevel(pyramid, alpha2.back(), k));
        return khrAnisotropyLevels(
            averaged,
            [&](size_t k, size_t i) {
                return anisotropicLobeOfMoments(&lean.levels[k][0]->pixels[4 * i],
                                                lean.levels[k][1]->pixels[i], alpha2[k].pixels[i]);
            },
            roughnessG, anisotropy);
    }

    // --method ggx-aniso: the fitted lobe of each texel (the bake's alpha_moments about its
    // normal, ggx_aniso.glsl) as KHR_materials_anisotropy stores it (khrAnisotropyLevels).
    template <class RoughnessG>
    std::vector<Image>
    fittedAnisotropyLevels(const Bake& bake, const std::vector<SharedImage>& averaged,
                           RoughnessG roughnessG, std::vector<Image>& anisotropy) {
        const size_t moments = size_t(findPlane(bake.planes, "alpha_moments")),
                     normal = size_t(findPlane(bake.planes, "normal"));
        return khrAnisotropyLevels(
            averaged,
            [&](size_t k, size_t i) {
                return anisotropicLobeOfGgxAniso(&bake.levels[k][moments]->pixels[3 * i],
                                                 &bake.levels[k][normal]->pixels[3 * i]);
            },
            roughnessG, anisotropy);
    }

    Baked bakeMaterial(const MaterialJob& job, const Pyramid& pyramid,
                       const std::shared_ptr<Image>& normals,
                       const std::shared_ptr<const Image>& rgba) {
        const int width = normals->width, height = normals->height;
        // alpha_0 = (G roughnessFactor)^2.
        auto alpha = std::make_shared<Image>(width, height, 1);
        for (size_t i = 0; i < alpha->texelCount(); ++i) {
            const float r = rgba->pixels[4 * i + 1] * job.roughnessFactor;
            alpha->pixels[i] = r * r;
        }
        BakeOptions options;
        options.roughnessMap = alpha;
        if (Status s = checkBakeMemory(job.where, roughness_, options, width, height); !s)
            refuse(s.error);

        // normalTexture.scale widens the normals' spread as a loader applies it: n.xy * scale.
        std::optional<Pyramid> scaled;
        if (job.scale != 1.f) {
            auto s = std::make_shared<Image>(*normals);
            for (size_t i = 0; i < s->texelCount(); ++i) {
                float* n = &s->pixels[3 * i];
                n[0] *= job.scale, n[1] *= job.scale;
                normalizeOrFlat(n, n);
            }
            scaled = buildPyramid(SharedImage(s));
        }
        // sggx reads the lean bake's moments (sggxLevels): no roughness bake of its own.
        const bool moments = anisotropy_ && roughness_ != Method::GgxAniso;
        Bake bake;
        if (!moments) {
            bake = bakeMethod(roughness_, scaled ? *scaled : pyramid, options);
            ++result_.bakes;
        }
        const int ggx = findPlane(bake.planes, "roughness_ggx");
        const int levels = int(pyramid.levels.size());

        // The material map's levels: R, B, A averaged, G the filtered roughness.
        Baked out;
        const std::vector<SharedImage> averaged = albedoMips(pyramid, rgba);
        std::vector<Image> material;
        auto roughnessG = [&](float r) {
            const float g = job.makeMap ? r : r / job.roughnessFactor;
            if (g > 1.f + 1e-4f) ++out.clampedTexels;
            return std::min(g, 1.f);
        };
        if (anisotropy_) {
            std::vector<Image> anisotropy;
            material = moments ? sggxLevels(scaled ? *scaled : pyramid, *alpha, averaged,
                                            roughnessG, anisotropy)
                               : fittedAnisotropyLevels(bake, averaged, roughnessG, anisotropy);
            out.anisotropyLevel0 = anisotropy.front();
            out.anisotropy = addLevels(std::move(anisotropy), TextureFormat::Rgba8Unorm,
                                       "ndfmip RGBA8 anisotropy mips of material " +
                                           std::to_string(job.material),
                                       "RGBA8 anisotropy mips",
                                       {{"content", "KHR_materials_anisotropy anisotropyTexture"},
                                        {"channels",
                                         {{"r", kKhrAnisotropyChannels[0]},
                                          {"g", kKhrAnisotropyChannels[1]},
                                          {"b", kKhrAnisotropyChannels[2]}}}});
        } else {
            for (int k = 0; k < levels; ++k) {
                Image level = *averaged[size_t(k)];
                const Image& a = *bake.levels[size_t(k)][size_t(ggx)];
                for (size_t i = 0; i < level.texelCount(); ++i)
                    level.pixels[4 * i + 1] = roughnessG(std::sqrt(std::max(a.pixels[i], 0.f)));
                material.push_back(std::move(level));
            }
        }
        const std::string label =
            job.roughnessImage >= 0 ? asset_.imageLabels[size_t(job.roughnessImage)] : "no image";
        if (job.makeMap) out.level0 = material.front();
        out.dds = addLevels(std::move(material), TextureFormat::Rgba8Unorm,
                            "ndfmip RGBA8 metallicRoughness mips of material " +
                                std::to_string(job.material) + " (" + label + ")",
                            "RGBA8 metallicRoughness mips",
                            {{"content", "metallicRoughness"},
                             {"channels",
                              {{"r", "R averaged (occlusion where packed)"},
                               {"g", roughness_ == Method::GgxFit
                                         ? "perceptual roughness, fitted to the filtered NDF"
                                     : roughness_ == Method::GgxAniso
                                         ? "perceptual roughness sqrt(alpha_b) of the anisotropic "
                                           "lobe fitted to the filtered NDF"
                                     : anisotropy_ ? "perceptual roughness sqrt(alpha_b) of the "
                                                     "slope moments' anisotropic lobe"
                                                   : "perceptual roughness, Toksvig-filtered"},
                               {"b", "metallic averaged"}}}});
        return out;
    }

    // --method sggx: the material's KHR_materials_anisotropy, strength 1 (the texture's B is the
    // strength), read with the normal map's coordinates; its anisotropyTexture is ours, level 0
    // as its PNG core source and the levels through the extensions, made once per bake.
    void anisotropyFor(const MaterialJob& job, Baked& b) {
        json& textures = asset_.json["textures"];
        if (b.anisotropyTexture < 0) {
            Result<std::string> png = encodePng(b.anisotropyLevel0, 8);
            if (!png) refuse(job.where + ": " + png.error().message);
            const int image =
                addGltfImage(asset_, std::move(png.value()), "image/png",
                             "ndfmip anisotropy of material " + std::to_string(job.material));
            markOurs(asset_.json["images"][size_t(image)], "anisotropy level 0");
            b.anisotropyLevel0 = Image();
            json texture = json::object();
            if (const json* sampler = member(textures[size_t(job.normalTexture)], "sampler"))
                texture["sampler"] = *sampler;
            texture["source"] = image;
            linkLevels(texture, b.anisotropy);
            texture["extras"][kMark] = {{"made", "anisotropyTexture"}};
            textures.push_back(texture);
            b.anisotropyTexture = int(textures.size() - 1);
        }
        json& material = asset_.json["materials"][job.material];
        const json& normal = material["normalTexture"];
        json info = {{"index", b.anisotropyTexture}};
        if (const json* c = member(normal, "texCoord")) info["texCoord"] = *c;
        if (const json t = transformOf(&normal); !t.is_null())
            info["extensions"]["KHR_texture_transform"] = t;
        json extension = {
            {"anisotropyStrength", 1.0}, {"anisotropyRotation", 0.0}, {"anisotropyTexture", info}};
        markOurs(extension, "anisotropy");
        material["extensions"][kAnisotropyExtension] = extension;
    }

    // A metallicRoughnessTexture of our own: level 0 as its PNG core source, the DDS as its
    // extension, roughnessFactor 1 (G holds the whole roughness).
    // The texture carries what the material had, so that a later pass can put it back.
    void madeTexture(const MaterialJob& job, Baked& b) {
        if (b.png < 0) {
            Result<std::string> png = encodePng(b.level0, 8);
            if (!png) refuse(job.where + ": " + png.error().message);
            b.png = addGltfImage(asset_, std::move(png.value()), "image/png",
                                 "ndfmip metallicRoughness of material " +
                                     std::to_string(job.material));
            markOurs(asset_.json["images"][size_t(b.png)], "metallicRoughness level 0");
            b.level0 = Image();
        }
        json& textures = asset_.json["textures"];
        const auto madeKey = std::pair(job.roughnessTexture, job.normalTexture);
        auto made = b.madeTextures.find(madeKey);
        if (made == b.madeTextures.end()) {
            json texture = json::object();
            const int samplerFrom =
                job.roughnessTexture >= 0 ? job.roughnessTexture : job.normalTexture;
            if (const json* sampler = member(textures[size_t(samplerFrom)], "sampler"))
                texture["sampler"] = *sampler;
            texture["source"] = b.png;
            linkLevels(texture, b.dds);
            texture["extras"][kMark] = {{"made", "metallicRoughnessTexture"},
                                        {"roughnessFactor", job.roughnessFactor},
                                        {"metallicRoughnessTexture", job.roughnessTexture}};
            textures.push_back(texture);
            made = b.madeTextures.emplace(madeKey, int(textures.size() - 1)).first;
        }
        const int index = made->second;

        json& material = asset_.json["materials"][job.material];
        json& pbr = material["pbrMetallicRoughness"];
        if (!pbr.is_object()) pbr = json::object();
        json& info = pbr["metallicRoughnessTexture"];
        if (!info.is_object()) {
            // Read where the normal map is read, so the texels line up.
            const json& normal = material["normalTexture"];
            info = json::object();
            if (const json* c = member(normal, "texCoord")) info["texCoord"] = *c;
            if (const json t = transformOf(&normal); !t.is_null())
                info["extensions"]["KHR_texture_transform"] = t;
        }
        info["index"] = index;
        pbr["roughnessFactor"] = 1.0;
        json* occlusion =
            material.contains("occlusionTexture") ? &material["occlusionTexture"] : nullptr;
        if (occlusion && job.roughnessTexture >= 0 && member(*occlusion, "index") &&
            (*occlusion)["index"] == job.roughnessTexture)
            (*occlusion)["index"] = index;
    }

    // Each texture read by the filtered slots gets its levels: in place when every use of it
    // wants the same levels, else this use gets a copy of the texture (its sampler, its core
    // source). A KHR_texture_basisu image of the asset's own is not replaced: refused.
    void assignTextures() {
        json& textures = asset_.json["textures"];
        const AddedLevels none;
        std::map<int, std::vector<std::pair<TextureUse, AddedLevels>>> byTexture;
        for (TextureUse& use : textureUses(asset_.json["materials"])) {
            if (use.texture < 0 || size_t(use.texture) >= originalTextures_)
                continue; // ours, or invalid
            auto want = wants_.find(use.at.to_string());
            byTexture[use.texture].emplace_back(use, want == wants_.end() ? none : want->second);
        }
        for (auto& [texture, uses] : byTexture) {
            std::set<AddedLevels> wanted;
            for (const auto& use : uses) wanted.insert(use.second);
            if (basisu_ && !(wanted.size() == 1 && *wanted.begin() == none))
                if (const json* extensions = member(textures[size_t(texture)], "extensions");
                    extensions && extensions->is_object() && extensions->contains(kBasisuExtension))
                    refuse(path_ + ": texture " + std::to_string(texture) + " already has a " +
                           kBasisuExtension +
                           " image of its own, which ndfmip would replace: give the asset with its "
                           "original "
                           "images only, or use --texture-format dds");
            if (wanted.size() == 1 && !(*wanted.begin() == none)) {
                linkLevels(textures[size_t(texture)], *wanted.begin());
                continue;
            }
            for (const AddedLevels& levels : wanted) {
                if (levels == none) continue;
                json copy = textures[size_t(texture)];
                linkLevels(copy, levels);
                markOurs(copy, json{{"copyOf", texture}});
                textures.push_back(copy);
                for (const auto& [use, want] : uses)
                    if (want == levels) asset_.json[use.at]["index"] = textures.size() - 1;
            }
        }
    }

    std::string path_;
    GltfAsset& asset_;
    GltfFiltered result_;
    size_t originalTextures_ = 0;
    std::map<std::string, AddedLevels> wants_; // slot (JSON pointer) -> the levels it should read
    bool dds_ = false, basisu_ = true;
    bool anisotropy_ = false; // --method sggx or ggx-aniso: KHR_materials_anisotropy
    // The bake whose roughness the material maps get: toksvig's roughness_ggx, or with --method
    // ggx-fit (ggx-aniso) the roughness (anisotropic lobe) fitted to each texel's filtered NDF,
    // the material's alpha per texel the lobes it widens (bake --method ggx-fit --roughness-map).
    Method roughness_ = Method::Toksvig;
    struct PendingUastc {
        int image = -1;                         // added with no bytes yet
        std::future<Result<std::string>> bytes; // its KTX2 file
    };
    std::deque<PendingUastc> uastcInFlight_;
};

} // namespace

Result<GltfFiltered> filterGltf(const std::string& path) {
    return filterGltf(path, GltfOptions{});
}

Result<GltfFiltered> filterGltf(const std::string& path, const GltfOptions& options) {
    Result<GltfAsset> asset = readGltf(path, options.allowOutside);
    if (!asset) return asset.error();
    try {
        return Filter(path, asset.value(), options).run();
    } catch (const GltfProblem& p) {
        return Error{p.message};
    } catch (const nlohmann::json::exception& e) { // not expected: every access above is checked
        return Error{path + ": " + shortened(e.what(), 200)};
    } catch (const std::bad_alloc&) {
        return Error{outOfMemoryMessage(path)};
    }
}

} // namespace ndfmip
