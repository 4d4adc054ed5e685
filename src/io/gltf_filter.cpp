// glTF materials filtered: per material the normal map's pyramid, a Toksvig bake over the
// material's own roughness (metallicRoughnessTexture G times roughnessFactor), and DDS images
// of every level added to the textures through MSFT_texture_dds. The original images stay each
// texture's core source, so loaders without the extension draw the asset as before.
#include "ndfmip/gltf.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <optional>
#include <set>

#include "io/gltf_asset.h"
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
    Filter(std::string path, GltfAsset& asset) : path_(std::move(path)), asset_(asset) {}

    GltfFiltered run() {
        json& root = asset_.json;
        const json empty = json::array();
        const json& materials = root.contains("materials") ? root["materials"] : empty;
        if (!materials.is_array()) refuse(path_ + ": materials is not an array");
        std::vector<MaterialJob> jobs;
        for (size_t m = 0; m < materials.size(); ++m)
            if (member(materials[m], "normalTexture")) jobs.push_back(plan(m));
        if (jobs.empty()) refuse(path_ + ": no material has a normalTexture: nothing to correct");
        originalTextures_ = root["textures"].size();
        for (const MaterialJob& job : jobs) filter(job);
        assignTextures();
        json& used = root["extensionsUsed"];
        if (!used.is_array()) used = json::array();
        if (std::find(used.begin(), used.end(), kDdsExtension) == used.end())
            used.push_back(kDdsExtension);
        Result<std::string> glb = glbFile(asset_);
        if (!glb) refuse(path_ + ": " + glb.error().message);
        result_.glb = std::move(glb.value());
        return std::move(result_);
    }

  private:
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
        return job;
    }

    SourceImage decodeOrRefuse(int image, const std::string& name) {
        Result<std::string> bytes = gltfImageBytes(asset_, image);
        if (!bytes) refuse(path_ + ": " + bytes.error().message);
        Result<SourceImage> decoded = decodeImage(bytes.value(), name);
        if (!decoded) refuse(decoded.error().message);
        return std::move(decoded.value());
    }

    // The unit normals of the normal image, refused when they are no tangent-space normal map.
    Image normalsOrRefuse(const MaterialJob& job) {
        const std::string name =
            job.where + ", normalTexture " + asset_.imageLabels[size_t(job.normalImage)];
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

    int addDds(const std::vector<Image>& levels, TextureFormat format, const std::string& name) {
        std::vector<const Image*> pointers;
        for (const Image& level : levels) pointers.push_back(&level);
        Result<EncodedTexture> texture = encodeTexture(pointers, format);
        if (!texture) refuse(path_ + ": " + texture.error().message);
        return addGltfImage(asset_, ddsFile(texture.value()), kDdsMimeType, name);
    }

    void filter(const MaterialJob& job) {
        const auto start = std::chrono::steady_clock::now();
        auto normals = std::make_shared<Image>(normalsOrRefuse(job));
        const int width = normals->width, height = normals->height;
        // R, G, B, A of the material map (all 1 without one), and alpha_0 = (G roughnessFactor)^2.
        auto rgba = std::make_shared<Image>(width, height, 4);
        if (job.roughnessTexture >= 0)
            *rgba = materialMapOrRefuse(job, *normals);
        else
            std::fill(rgba->pixels.begin(), rgba->pixels.end(), 1.f);
        auto alpha = std::make_shared<Image>(width, height, 1);
        for (size_t i = 0; i < alpha->texelCount(); ++i) {
            const float r = rgba->pixels[4 * i + 1] * job.roughnessFactor;
            alpha->pixels[i] = r * r;
        }
        BakeOptions options;
        options.roughnessMap = alpha;
        if (Status s = checkBakeMemory(job.where, Method::Toksvig, options, width, height); !s)
            refuse(s.error);

        const Pyramid pyramid = buildPyramid(SharedImage(normals));
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
        const Bake bake = bakeToksvig(scaled ? *scaled : pyramid, options);
        const int ggx = findPlane(bake.planes, "roughness_ggx");
        const int levels = int(pyramid.levels.size());

        // The normal texture's levels: the mean normal's direction, (n + 1)/2 (one file per image).
        if (!normalDds_.count(job.normalImage)) {
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
            normalDds_[job.normalImage] =
                addDds(encoded, TextureFormat::Bc5Unorm,
                       "ndfmip BC5 mips of " + asset_.imageLabels[size_t(job.normalImage)]);
        }
        wants_[(Pointer("/materials") / job.material / "normalTexture").to_string()] =
            normalDds_[job.normalImage];

        // The material map's levels: R, B, A averaged, G the filtered roughness.
        GltfMaterialReport report{job.name, width, height, levels, job.makeMap, 0, 0.0};
        const std::vector<SharedImage> averaged = albedoMips(pyramid, rgba);
        std::vector<Image> material;
        for (int k = 0; k < levels; ++k) {
            Image level = *averaged[size_t(k)];
            const Image& a = *bake.levels[size_t(k)][size_t(ggx)];
            for (size_t i = 0; i < level.texelCount(); ++i) {
                const float r = std::sqrt(std::max(a.pixels[i], 0.f));
                float g = job.makeMap ? r : r / job.roughnessFactor;
                if (g > 1.f + 1e-4f) ++report.clampedTexels;
                level.pixels[4 * i + 1] = std::min(g, 1.f);
            }
            material.push_back(std::move(level));
        }
        const std::string label =
            job.roughnessImage >= 0 ? asset_.imageLabels[size_t(job.roughnessImage)] : "no image";
        const int dds = addDds(material, TextureFormat::Rgba8Unorm,
                               "ndfmip RGBA8 metallicRoughness mips of material " +
                                   std::to_string(job.material) + " (" + label + ")");
        if (job.makeMap)
            madeTexture(job, material.front(), dds);
        else {
            const Pointer materialAt = Pointer("/materials") / job.material;
            wants_[(materialAt / "pbrMetallicRoughness" / "metallicRoughnessTexture").to_string()] =
                dds;
            // ORM packing: the occlusion read from the same texture (R) gets the same levels.
            const json* occlusion = member(asset_.json[materialAt], "occlusionTexture");
            const json* index = occlusion ? member(*occlusion, "index") : nullptr;
            if (index && *index == job.roughnessTexture)
                wants_[(materialAt / "occlusionTexture").to_string()] = dds;
        }
        report.milliseconds =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                .count();
        result_.materials.push_back(std::move(report));
    }

    // A metallicRoughnessTexture of our own: level 0 as its PNG core source, the DDS as its
    // extension, roughnessFactor 1 (G holds the whole roughness).
    void madeTexture(const MaterialJob& job, const Image& level0, int dds) {
        Result<std::string> png = encodePng(level0, 8);
        if (!png) refuse(job.where + ": " + png.error().message);
        const int source =
            addGltfImage(asset_, std::move(png.value()), "image/png",
                         "ndfmip metallicRoughness of material " + std::to_string(job.material));
        json& textures = asset_.json["textures"];
        json texture = json::object();
        const int samplerFrom =
            job.roughnessTexture >= 0 ? job.roughnessTexture : job.normalTexture;
        if (const json* sampler = member(textures[size_t(samplerFrom)], "sampler"))
            texture["sampler"] = *sampler;
        texture["source"] = source;
        texture["extensions"][kDdsExtension]["source"] = dds;
        textures.push_back(texture);
        const int index = int(textures.size() - 1);

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

    // Each texture read by the filtered slots gets its DDS: in place when every use of it wants
    // the same levels, else this use gets a copy of the texture (its sampler, its core source).
    void assignTextures() {
        json& textures = asset_.json["textures"];
        std::map<int, std::vector<std::pair<TextureUse, int>>> byTexture;
        for (TextureUse& use : textureUses(asset_.json["materials"])) {
            if (use.texture < 0 || size_t(use.texture) >= originalTextures_)
                continue; // ours, or invalid
            auto want = wants_.find(use.at.to_string());
            byTexture[use.texture].emplace_back(use, want == wants_.end() ? -1 : want->second);
        }
        for (auto& [texture, uses] : byTexture) {
            std::set<int> wanted;
            for (const auto& use : uses) wanted.insert(use.second);
            if (wanted.size() == 1 && *wanted.begin() >= 0) {
                textures[size_t(texture)]["extensions"][kDdsExtension] = {
                    {"source", *wanted.begin()}};
                continue;
            }
            for (int dds : wanted) {
                if (dds < 0) continue;
                json copy = textures[size_t(texture)];
                copy["extensions"][kDdsExtension] = {{"source", dds}};
                textures.push_back(copy);
                for (const auto& [use, want] : uses)
                    if (want == dds) asset_.json[use.at]["index"] = textures.size() - 1;
            }
        }
    }

    std::string path_;
    GltfAsset& asset_;
    GltfFiltered result_;
    size_t originalTextures_ = 0;
    std::map<int, int> normalDds_;     // normal image -> its DDS image
    std::map<std::string, int> wants_; // slot (JSON pointer) -> the DDS image it should read
};

} // namespace

Result<GltfFiltered> filterGltf(const std::string& path) {
    Result<GltfAsset> asset = readGltf(path);
    if (!asset) return asset.error();
    try {
        return Filter(path, asset.value()).run();
    } catch (const GltfProblem& p) {
        return Error{p.message};
    } catch (const nlohmann::json::exception& e) { // not expected: every access above is checked
        return Error{path + ": " + shortened(e.what(), 200)};
    } catch (const std::bad_alloc&) {
        return Error{path + ": out of memory"};
    }
}

} // namespace ndfmip
