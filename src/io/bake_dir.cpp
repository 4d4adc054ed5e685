// The bake directory: manifest.json (what was baked, from what, how to read each channel) and
// one float EXR per plane per level. The whole directory is staged beside its final place
// and swapped in at the end, so a failed or killed bake never leaves a half-written one behind.
// Reading checks every image against the manifest (bake_manifest.cpp checks the manifest).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <set>

#include <sys/stat.h>

#include <nlohmann/json.hpp>

#include "io/basisu_encoder.h"
#include "io/crash_recovery.h"
#include "io/input_file.h"
#include "methods/lean/engine_anisotropy.h"
#include "ndfmip/bake.h"
#include "ndfmip/engine_presets.h"
#include "ndfmip/io.h"
#include "ndfmip/limits.h"
#include "ndfmip/texture_container.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace ndfmip {
namespace {

const char* kPyramidRule =
    "level k+1 is max(1, floor(w_k/2)) x max(1, floor(h_k/2)); texel i covers children 2i and "
    "2i+1 of level k, and the last texel also takes child 2i+2 when w_k (h_k) is odd";

std::string planeFile(const PlaneInfo& plane, int level) {
    return plane.name + "_L" + std::to_string(level) + ".exr";
}

// The plane holding a direction per texel: the renormalised or the mean normal.
int directionPlane(const Bake& bake) {
    int p = findPlane(bake.planes, "normal");
    return p >= 0 ? p : findPlane(bake.planes, "mean");
}

// Unit normal of one texel of a direction plane encoded (n + 1)/2 in 2 channels (x, y: what the
// two-channel formats keep), 3, or 4 with alpha 1.
void encodeNormal(const float* direction, bool greenDown, int channels, float* texel) {
    float n[3];
    normalizeOrFlat(direction, n);
    if (greenDown) n[1] = -n[1];
    for (int c = 0; c < std::min(channels, 3); ++c) texel[c] = 0.5f * (n[c] + 1.f);
    if (channels == 4) texel[3] = 1.f;
}

Image encodeNormals(const Image& directions, bool greenDown, int channels = 3) {
    Image out(directions.width, directions.height, channels, Image::Uninitialized{});
    const int64_t texels = int64_t(directions.texelCount());
#pragma omp parallel for schedule(static) if (texels >= 65536)
    for (int64_t i = 0; i < texels; ++i)
        encodeNormal(&directions.pixels[size_t(i) * size_t(directions.channels)], greenDown,
                     channels, &out.pixels[size_t(channels) * size_t(i)]);
    return out;
}

// The same a row at a time, for the block encoders (no float copy of the level).
LevelRows normalRows(const Image& directions, bool greenDown, int channels) {
    return {directions.width, directions.height, channels,
            [&directions, greenDown, channels](int y, float* out) {
                for (int x = 0; x < directions.width; ++x)
                    encodeNormal(directions.at(x, y), greenDown, channels,
                                 out + size_t(x) * size_t(channels));
            }};
}

Image perceptual(const Image& alpha) {
    Image out = alpha;
    const int64_t n = int64_t(out.pixels.size());
#pragma omp parallel for schedule(static) if (n >= 65536)
    for (int64_t i = 0; i < n; ++i)
        out.pixels[size_t(i)] = std::sqrt(std::max(out.pixels[size_t(i)], 0.f));
    return out;
}

// Perceptual roughness sqrt(alpha) of a one-channel alpha plane, a row at a time.
LevelRows perceptualRows(const Image& alpha) {
    return {alpha.width, alpha.height, 1, [&alpha](int y, float* out) {
                const float* row = alpha.at(0, y);
                for (int x = 0; x < alpha.width; ++x)
                    out[x] = std::sqrt(std::max(row[size_t(x) * size_t(alpha.channels)], 0.f));
            }};
}

// Writes the png16 files into `folder`; returns their names relative to the bake folder.
Result<std::vector<std::string>> writePng16(const fs::path& folder, const Bake& bake,
                                            bool greenDown, const BakeWriteOptions& options) {
    std::error_code ec;
    fs::create_directory(folder / "png16", ec);
    std::vector<std::string> names;
    const int dirPlane = options.exportNormal ? directionPlane(bake) : -1;
    const int ggx = options.exportRoughness ? findPlane(bake.planes, "roughness_ggx") : -1;
    for (size_t k = 0; k < bake.levels.size(); ++k) {
        std::vector<std::pair<std::string, Image>> files;
        if (dirPlane >= 0)
            files.emplace_back("normal", encodeNormals(*bake.levels[k][dirPlane], greenDown));
        if (ggx >= 0) files.emplace_back("roughness", perceptual(*bake.levels[k][ggx]));
        for (auto& [stem, image] : files) {
            std::string name = "png16/" + stem + "_L" + std::to_string(k) + ".png";
            Status s = savePng((folder / name).string(), image, 16);
            if (!s) return Error{s.error};
            names.push_back(name);
        }
    }
    return names;
}

// An engine's packed material map at one level from its perceptual roughness, metallic (0
// without) and occlusion (1 without), channel by channel as the preset lays them out.
Image packedMaterial(const EnginePreset& engine, const Image& roughness, const Image* metallic,
                     const Image* occlusion) {
    Image packed(roughness.width, roughness.height, 4);
    for (size_t i = 0; i < roughness.texelCount(); ++i)
        for (int c = 0; c < 4; ++c) {
            float v = 0.f;
            switch (engine.packed[c]) {
            case MaterialChannel::Zero:
                v = 0.f;
                break;
            case MaterialChannel::One:
                v = 1.f;
                break;
            case MaterialChannel::Roughness:
                v = roughness.pixels[i];
                break;
            case MaterialChannel::Smoothness:
                v = 1.f - roughness.pixels[i];
                break;
            case MaterialChannel::Metallic:
                v = metallic ? metallic->pixels[i] : 0.f;
                break;
            case MaterialChannel::Occlusion:
                v = occlusion ? occlusion->pixels[i] : 1.f;
                break;
            }
            packed.pixels[4 * i + size_t(c)] = v;
        }
    return packed;
}

// What a KTX2 file holds, for readers that do not know ndfmip: KTXswizzle (what a sampler
// should return) and an "ndfmip" key, JSON naming each channel (KTX2's formats say only "BC5").
std::string aboutText(const json& about) {
    return about.dump(-1, ' ', false, json::error_handler_t::replace);
}

Ktx2KeyValues normalKeyValues(TextureFormat format, bool greenDown) {
    // rgba8 and uastc keep z (glTF's KHR_texture_basisu normal maps are RGB); bc5 and rg16 x and y
    const bool xyz = format == TextureFormat::Rgba8Unorm || format == TextureFormat::Uastc;
    json about = {{"content", "normal"},
                  {"space", "tangent"},
                  {"encoding", "(n+1)/2"},
                  {"green", greenDown ? "down" : "up"},
                  {"convention", greenDown ? "DirectX: -Y, +y towards the bottom row"
                                           : "OpenGL: +Y, +y towards the top row"}};
    if (xyz)
        about["channels"] = {{"r", "x"}, {"g", "y"}, {"b", "z"}, {"a", "1"}};
    else
        about["channels"] = {{"r", "x"}, {"g", "y"}},
        about["z"] = "sqrt(1 - x^2 - y^2) of x, y = 2c - 1";
    if (format == TextureFormat::Uastc)
        about["codec"] = "UASTC (Basis Universal), each level encoded alone";
    return {{"KTXswizzle", xyz ? "rgb1" : "rg01"}, {"ndfmip", aboutText(about)}};
}

Ktx2KeyValues roughnessKeyValues(TextureFormat format) {
    json about = {
        {"content", "roughness"},
        {"encoding", "sqrt(alpha)"},
        {"channels", {{"r", "perceptual roughness sqrt(alpha), GGX alpha = r^2"}}},
        {"layout",
         "one channel: not a glTF metallicRoughness texture (that reads roughness from G)"}};
    if (format == TextureFormat::Uastc) { // UASTC has no one-channel mode: grey, R = G = B
        const char* r = "perceptual roughness sqrt(alpha), GGX alpha = r^2";
        about["channels"] = {{"r", r}, {"g", r}, {"b", r}, {"a", "1"}};
        about["layout"] = "grey: R = G = B, so a reader of R or of glTF's G gets the roughness";
        about["codec"] = "UASTC (Basis Universal), each level encoded alone";
        return {{"KTXswizzle", "rrr1"}, {"ndfmip", aboutText(about)}};
    }
    return {{"ndfmip", aboutText(about)}};
}

const char* channelMeaning(MaterialChannel c) {
    switch (c) {
    case MaterialChannel::Zero:
        return "0";
    case MaterialChannel::One:
        return "1";
    case MaterialChannel::Roughness:
        return "roughness: perceptual, sqrt(alpha)";
    case MaterialChannel::Smoothness:
        return "smoothness: 1 - sqrt(alpha)";
    case MaterialChannel::Metallic:
        return "metallic";
    case MaterialChannel::Occlusion:
        return "occlusion";
    }
    return "";
}

Ktx2KeyValues packedKeyValues(const EnginePreset& engine) {
    json channels = json::object();
    for (int c = 0; c < 4; ++c)
        channels[std::string(1, "rgba"[c])] = channelMeaning(engine.packed[c]);
    return {
        {"ndfmip",
         aboutText({{"content", "material"}, {"engine", engine.name}, {"channels", channels}})}};
}

Ktx2KeyValues planeKeyValues(const PlaneInfo& plane) {
    json channels = json::object();
    for (size_t c = 0; c < plane.channels.size() && c < 4; ++c)
        channels[std::string(1, "rgba"[c])] = plane.channels[c];
    return {{"ndfmip", aboutText({{"content", "plane"},
                                  {"plane", plane.name},
                                  {"description", plane.description},
                                  {"channels", channels}})}};
}

// BC5 and RG16 keep a normal's x and y; RGBA8 and UASTC x, y, z as glTF normal textures do.
int normalChannels(TextureFormat format) {
    return format == TextureFormat::Rgba8Unorm ? 4 : format == TextureFormat::Uastc ? 3 : 2;
}

// writeContainers' writer of a file of levels made row by row.
using WriteMade =
    std::function<Status(const std::string& stem, const std::function<LevelRows(size_t)>& make,
                         TextureFormat format, const Ktx2KeyValues& keyValues)>;

// One anisotropic GGX lobe per texel: level k's texel i (row by row) of a plane `plane` sized.
struct LobeLevels {
    size_t plane = 0;
    std::function<AnisotropicLobe(size_t k, size_t i)> lobe;
};

// The engine files of a bake with one anisotropic GGX lobe per texel (engine_anisotropy.h): the
// roughness in the packed map, and the direction and anisotropy textures.
Status writeEngineAnisotropy(const EnginePreset& engine, const Bake& bake,
                             const LobeLevels& lobesAsFitted, const BakeWriteOptions& options,
                             const WriteMade& writeMade) {
    // The directions chosen so that the sampler's blends of neighbours and of two levels keep
    // them (coherentDirections).
    std::vector<std::pair<int, int>> sizes;
    for (const auto& level : bake.levels)
        sizes.emplace_back(level[lobesAsFitted.plane]->width, level[lobesAsFitted.plane]->height);
    const StoredDirections directions = coherentDirections(sizes, lobesAsFitted.lobe);
    const LobeLevels lobes{lobesAsFitted.plane, [&lobesAsFitted, &directions](size_t k, size_t i) {
                               AnisotropicLobe lobe = lobesAsFitted.lobe(k, i);
                               lobe.direction = directions.at(k, i);
                               return lobe;
                           }};
    const std::string prefix = std::string(engine.name) + "_";
    const AnisotropyInput input = engine.anisotropy;
    const bool down = engine.greenDown;
    // Level k's rows computed as the encoder asks for them: `texel` writes one texel's
    // `channels` values from its lobe.
    auto lobeRows = [&bake, &lobes](size_t k, int channels, auto texel) {
        const Image& m = *bake.levels[k][lobes.plane];
        return LevelRows{m.width, m.height, channels,
                         [&m, &lobes, k, channels, texel](int y, float* out) {
                             for (int x = 0; x < m.width; ++x) {
                                 const size_t i = size_t(y) * size_t(m.width) + size_t(x);
                                 texel(lobes.lobe(k, i), out + size_t(x) * size_t(channels));
                             }
                         }};
    };
    // The engine's perceptual roughness of a lobe, and its direction in the normal map's frame.
    auto roughnessOf = [input](const AnisotropicLobe& lobe) {
        return input == AnisotropyInput::Khr     ? khrAnisotropy(lobe).roughness
               : input == AnisotropyInput::Godot ? burleyAnisotropy(lobe).roughness
                                                 : kullaAnisotropy(lobe).roughness;
    };
    auto direction = [down](const AnisotropicLobe& lobe, float* rg) {
        rg[0] = 0.5f * (lobe.direction.x + 1.f);
        rg[1] = 0.5f * ((down ? -lobe.direction.y : lobe.direction.y) + 1.f);
    };

    auto packed = [&](size_t k) {
        const Image& m = *bake.levels[k][lobes.plane];
        Image roughness(m.width, m.height, 1);
        const LevelRows rows =
            lobeRows(k, 1, [roughnessOf](const AnisotropicLobe& lobe, float* out) {
                out[0] = roughnessOf(lobe);
            });
        for (int y = 0; y < m.height; ++y) rows.row(y, roughness.at(0, y));
        return rowsOf(std::make_shared<const Image>(packedMaterial(
            engine, roughness, k < options.metallic.size() ? options.metallic[k].get() : nullptr,
            k < options.occlusion.size() ? options.occlusion[k].get() : nullptr)));
    };
    if (Status s = writeMade(prefix + engine.packedFile, packed, TextureFormat::Rgba8Unorm,
                             packedKeyValues(engine));
        !s)
        return s;

    auto about = [&](const char* content, const json& channelMeanings) -> Ktx2KeyValues {
        return {{"ndfmip", aboutText({{"content", content},
                                      {"engine", engine.name},
                                      {"channels", channelMeanings}})}};
    };
    const char* directionX = "direction of alpha_t, tangent x, (d + 1)/2";
    const char* directionY = down ? "direction of alpha_t, bitangent y (green down), (d + 1)/2"
                                  : "direction of alpha_t, bitangent y, (d + 1)/2";
    switch (input) {
    case AnisotropyInput::Khr:
        return writeMade(
            prefix + "anisotropy",
            [&](size_t k) {
                return lobeRows(k, 4, [](const AnisotropicLobe& lobe, float* out) {
                    khrAnisotropyTexel(khrAnisotropy(lobe), out);
                });
            },
            TextureFormat::Rgba8Unorm,
            about("KHR_materials_anisotropy anisotropyTexture", {{"r", kKhrAnisotropyChannels[0]},
                                                                 {"g", kKhrAnisotropyChannels[1]},
                                                                 {"b", kKhrAnisotropyChannels[2]},
                                                                 {"a", "1"}}));
    case AnisotropyInput::Unreal:
        return writeMade(
            prefix + "anisotropy",
            [&](size_t k) {
                return lobeRows(k, 4, [direction](const AnisotropicLobe& lobe, float* out) {
                    direction(lobe, out);
                    out[2] = kullaAnisotropy(lobe).anisotropy;
                    out[3] = 1.f;
                });
            },
            TextureFormat::Rgba8Unorm,
            about("Unreal Tangent and Anisotropy inputs",
                  {{"r", directionX},
                   {"g", directionY},
                   {"b", "Anisotropy k: alpha_t,b = alpha (1 +- k), alpha = roughness^2"},
                   {"a", "1"}}));
    case AnisotropyInput::UnityHdrp:
        if (Status s = writeMade(
                prefix + "tangent",
                [&](size_t k) {
                    return lobeRows(k, 4, [direction](const AnisotropicLobe& lobe, float* out) {
                        direction(lobe, out);
                        out[2] = 0.5f;
                        out[3] = 1.f;
                    });
                },
                TextureFormat::Rgba8Unorm,
                about("HDRP tangent map (import as a normal map)",
                      {{"r", directionX}, {"g", directionY}, {"b", "0.5 (z = 0)"}, {"a", "1"}}));
            !s)
            return s;
        return writeMade(
            prefix + "anisotropy",
            [&](size_t k) {
                return lobeRows(k, 4, [](const AnisotropicLobe& lobe, float* out) {
                    out[0] = out[1] = out[2] = kullaAnisotropy(lobe).anisotropy;
                    out[3] = 1.f;
                });
            },
            TextureFormat::Rgba8Unorm,
            about("HDRP anisotropy map",
                  {{"r", "Anisotropy k: alpha_t,b = alpha (1 +- k), alpha = (1 - smoothness)^2"},
                   {"g", "k"},
                   {"b", "k"},
                   {"a", "1"}}));
    case AnisotropyInput::Godot:
        return writeMade(
            prefix + "anisotropy",
            [&](size_t k) {
                return lobeRows(k, 4, [direction](const AnisotropicLobe& lobe, float* out) {
                    direction(lobe, out);
                    out[2] = 0.f;
                    out[3] = burleyAnisotropy(lobe).anisotropy;
                });
            },
            TextureFormat::Rgba8Unorm,
            about("Godot anisotropy flowmap",
                  {{"r", directionX},
                   {"g", directionY},
                   {"b", "0 (unused)"},
                   {"a", "anisotropy k: aspect sqrt(1 - 0.9 k), alpha_t,b = alpha / aspect, "
                         "alpha aspect"}}));
    }
    return Status::success();
}

// Writes the ktx2 or dds files (`container` "ktx2" or "dds") into `folder`; returns their names
// relative to the bake folder.
Result<std::vector<std::string>> writeContainers(const fs::path& folder, const Bake& bake,
                                                 bool greenDown, bool half,
                                                 const std::string& container,
                                                 const BakeWriteOptions& options) {
    std::error_code ec;
    fs::create_directory(folder / container, ec);
    std::vector<std::string> names;
    auto write = [&](const std::string& stem, const auto& levels, TextureFormat format,
                     const Ktx2KeyValues& keyValues) -> Status {
        Result<EncodedTexture> texture = encodeTexture(levels, format);
        if (!texture) return Status::failure(texture.error().message);
        const std::string name = container + "/" + stem + "." + container;
        // UASTC is always supercompressed: its blocks are 8 bits a texel until Zstandard packs
        // them.
        const int zstd = format == TextureFormat::Uastc && options.zstdLevel == 0
                             ? kUastcZstdLevel
                             : options.zstdLevel;
        Result<std::string> bytes = container == "ktx2"
                                        ? ktx2File(texture.value(), zstd, keyValues)
                                        : Result<std::string>(ddsFile(texture.value()));
        if (!bytes) return Status::failure(bytes.error().message);
        if (Status s = writeFileAtomic((folder / name).string(), bytes.value()); !s) return s;
        names.push_back(name);
        return Status::success();
    };
    // A file of levels made from the planes (encoded normals, perceptual roughness, packed maps).
    auto writeMade = [&](const std::string& stem, const std::function<LevelRows(size_t)>& make,
                         TextureFormat format, const Ktx2KeyValues& keyValues) {
        std::vector<LevelRows> levels;
        for (size_t k = 0; k < bake.levels.size(); ++k) levels.push_back(make(k));
        return write(stem, levels, format, keyValues);
    };
    const int dirPlane = directionPlane(bake), ggx = findPlane(bake.planes, "roughness_ggx");
    auto normals = [&](bool down, TextureFormat format) {
        const int channels = normalChannels(format);
        return [&bake, dirPlane, down, channels](size_t k) {
            return normalRows(*bake.levels[k][dirPlane], down, channels);
        };
    };
    if (dirPlane >= 0 && options.exportNormal)
        if (Status s = writeMade(std::string("normal_") + textureFormatName(options.normalFormat),
                                 normals(greenDown, options.normalFormat), options.normalFormat,
                                 normalKeyValues(options.normalFormat, greenDown));
            !s)
            return Error{s.error};
    if (ggx >= 0 && options.exportRoughness)
        if (Status s = writeMade(
                std::string("roughness_") + textureFormatName(options.roughnessFormat),
                [&](size_t k) { return perceptualRows(*bake.levels[k][ggx]); },
                options.roughnessFormat, roughnessKeyValues(options.roughnessFormat));
            !s)
            return Error{s.error};
    for (size_t p = 0; p < bake.planes.size(); ++p) {
        if (!bake.planes[p].linear || !options.exportPlanes) continue;
        std::vector<const Image*> levels;
        for (const auto& level : bake.levels) levels.push_back(level[p].get());
        if (Status s = write(bake.planes[p].name, levels,
                             half ? TextureFormat::Rgba16F : TextureFormat::Rgba32F,
                             planeKeyValues(bake.planes[p]));
            !s)
            return Error{s.error};
    }
    if (const EnginePreset* engine = options.engine; engine && dirPlane >= 0) {
        const std::string prefix = std::string(engine->name) + "_";
        // The engine's green convention, in the format --normal-format asks for.
        if (Status s = writeMade(
                prefix + engine->normalFile, normals(engine->greenDown, options.normalFormat),
                options.normalFormat, normalKeyValues(options.normalFormat, engine->greenDown));
            !s)
            return Error{s.error};
        auto packed = [&](size_t k) {
            return rowsOf(std::make_shared<const Image>(packedMaterial(
                *engine, perceptual(*bake.levels[k][ggx]),
                k < options.metallic.size() ? options.metallic[k].get() : nullptr,
                k < options.occlusion.size() ? options.occlusion[k].get() : nullptr)));
        };
        if (ggx >= 0)
            if (Status s = writeMade(prefix + engine->packedFile, packed, TextureFormat::Rgba8Unorm,
                                     packedKeyValues(*engine));
                !s)
                return Error{s.error};
    }
    const int moments = findPlane(bake.planes, "lean_moments"),
              cross = findPlane(bake.planes, "lean_cross");
    if (const EnginePreset* engine = options.engine; engine && moments >= 0 && cross >= 0) {
        // The lean bake's lobe from the slope moments (sggx.glsl), about the mean slope's normal
        // (E[bx], E[by], 1), which is the engine's normal map.
        const int channels = normalChannels(options.normalFormat);
        const bool down = engine->greenDown;
        auto normal = [&bake, moments, down, channels](size_t k) {
            const Image& m = *bake.levels[k][size_t(moments)];
            return LevelRows{m.width, m.height, channels, [&m, down, channels](int y, float* out) {
                                 for (int x = 0; x < m.width; ++x) {
                                     const float* mi = m.at(x, y);
                                     const float slopeNormal[3] = {mi[0], mi[1], 1.f};
                                     encodeNormal(slopeNormal, down, channels,
                                                  out + size_t(x) * size_t(channels));
                                 }
                             }};
        };
        if (Status s = writeMade(std::string(engine->name) + "_" + engine->normalFile, normal,
                                 options.normalFormat, normalKeyValues(options.normalFormat, down));
            !s)
            return Error{s.error};
        const float alpha2 = options.baseRoughness * options.baseRoughness;
        const LobeLevels lobes{
            size_t(moments), [&bake, moments, cross, alpha2](size_t k, size_t i) {
                return anisotropicLobeOfMoments(&bake.levels[k][size_t(moments)]->pixels[4 * i],
                                                bake.levels[k][size_t(cross)]->pixels[i], alpha2);
            }};
        if (Status s = writeEngineAnisotropy(*engine, bake, lobes, options, writeMade); !s)
            return Error{s.error};
    }
    // ggx-aniso's fitted lobe from its moments (ggx_aniso.glsl), about its normal plane (written
    // above as the engine's normal map).
    const int alphaMoments = findPlane(bake.planes, "alpha_moments"),
              normal = findPlane(bake.planes, "normal");
    if (options.engine && alphaMoments >= 0 && normal >= 0) {
        const LobeLevels lobes{size_t(alphaMoments),
                               [&bake, alphaMoments, normal](size_t k, size_t i) {
                                   return anisotropicLobeOfGgxAniso(
                                       &bake.levels[k][size_t(alphaMoments)]->pixels[3 * i],
                                       &bake.levels[k][size_t(normal)]->pixels[3 * i]);
                               }};
        if (Status s = writeEngineAnisotropy(*options.engine, bake, lobes, options, writeMade); !s)
            return Error{s.error};
    }
    // A container asked for but given nothing (a method without normal or roughness, planes not
    // asked for) is a mistake, not an empty folder.
    if (names.empty())
        return Error{"--export " + container +
                     " has nothing to write: the method stores no normal or roughness; add "
                     "planes to --export-textures for its planes"};
    return names;
}

json manifestJson(const Bake& bake, const BakeSource& source, bool withPlanes) {
    json planes = json::array();
    for (const PlaneInfo& p : bake.planes)
        planes.push_back({{"name", p.name},
                          {"channels", p.channels},
                          {"description", p.description},
                          {"linear", p.linear}});
    json levels = json::array();
    for (size_t k = 0; k < bake.levels.size(); ++k) {
        json files = json::object();
        if (withPlanes)
            for (const PlaneInfo& p : bake.planes) files[p.name] = planeFile(p, int(k));
        const Image& first = *bake.levels[k].front();
        levels.push_back(
            {{"level", k}, {"width", first.width}, {"height", first.height}, {"files", files}});
    }
    const DecodeOptions& d = source.decode;
    return {
        {"tool", "ndfmip"},
        {"version", NDFMIP_VERSION},
        {"method", methodName(bake.method)},
        {"parameters", bake.parameters},
        {"source",
         {{"path", source.path},
          {"sha256", source.sha256},
          {"width", source.width},
          {"height", source.height},
          {"gloss", source.gloss}}},
        {"conventions",
         {{"green_down", d.greenDown},
          {"two_channel", d.twoChannel},
          {"signed", d.signedValues},
          {"height", d.height},
          {"height_scale", d.heightScale},
          {"address", d.address == AddressMode::Wrap ? "wrap" : "clamp"},
          {"normals", "tangent space, OpenGL convention (+Y towards the top row)"},
          {"texel_origin", "x = column, y = row counted from the top row"}}},
        {"pyramid", kPyramidRule},
        {"planes", planes},
        {"levels", levels},
    };
}

// Whether `dir` may be replaced: it is empty, or it holds an earlier bake and nothing else (its
// manifest says ndfmip wrote it, and every file in it is one the manifest lists). Anything more
// means the folder is someone's work, and it is never deleted.
Status checkBakeReplaceable(const fs::path& dir) {
    std::error_code ec;
    if (!fs::is_directory(dir, ec))
        return Status::failure(dir.string() + ": exists and is not a directory");
    if (fs::is_empty(dir, ec)) return Status::success();
    auto refuse = [&](const std::string& why) {
        return Status::failure(dir.string() + ": exists and is not an ndfmip bake (" + why +
                               "); not replacing it");
    };
    const fs::path manifestPath = dir / "manifest.json";
    Result<std::string> text =
        readRegularFile(manifestPath.string(), inputLimits().maxTextFileBytes);
    if (!text) return refuse("no readable manifest.json");
    if (!jsonNestingProblem(text.value(), inputLimits().maxJsonDepth).empty())
        return refuse("its manifest.json is not an ndfmip manifest");
    json m = json::parse(text.value(), nullptr, /*allow_exceptions=*/false);
    const json* tool = m.is_object() && m.contains("tool") ? &m["tool"] : nullptr;
    if (!tool || *tool != "ndfmip" || !m.contains("levels") || !m["levels"].is_array())
        return refuse("its manifest.json is not an ndfmip manifest");
    std::set<std::string> listed{"manifest.json"};
    for (const json& level : m["levels"])
        if (level.is_object() && level.contains("files") && level["files"].is_object())
            for (const auto& item : level["files"].items())
                if (item.value().is_string()) listed.insert(item.value().get<std::string>());
    if (m.contains("exports") && m["exports"].is_object())
        for (const auto& item : m["exports"].items())
            if (item.value().is_array())
                for (const json& name : item.value())
                    if (name.is_string()) listed.insert(name.get<std::string>());
    for (auto it = fs::recursive_directory_iterator(dir, ec);
         !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
        const std::string relative = it->path().lexically_relative(dir).string();
        if (it->is_directory(ec) && !it->is_symlink(ec) &&
            (relative == "png16" || relative == "ktx2" || relative == "dds"))
            continue;
        if (!listed.count(relative))
            return refuse("it holds " + quote(relative) + ", which its manifest does not list");
    }
    if (ec) return refuse("cannot list it: " + ec.message());
    return Status::success();
}

std::string planeName(const LoadedBake& bake, size_t p, int level) {
    return "plane '" + bake.planes[p].name + "' of level " + std::to_string(level);
}

// One plane image of one level, checked against the manifest: a plain file (no link out of the
// folder), the level's size, the plane's channel count, finite values.
Result<Image> readPlane(const fs::path& dir, const LoadedBake& bake, size_t p, int level) {
    const std::string file = (dir / bake.levelFiles[size_t(level)][p]).string();
    struct stat info {};
    if (::lstat(file.c_str(), &info) == 0 && S_ISLNK(info.st_mode))
        return Error{file + ": is a symbolic link; a bake's files are plain files in its folder"};
    Result<SourceImage> image = loadImage(file);
    if (!image) return image.error();
    const Image& got = image->image;
    const auto [w, h] = bake.levelSizes[size_t(level)];
    const int channels = int(bake.planes[p].channels.size());
    if (got.width != w || got.height != h || got.channels != channels)
        return Error{file + ": is " + std::to_string(got.width) + "x" + std::to_string(got.height) +
                     " with " + std::to_string(got.channels) + " channels, but the manifest's " +
                     planeName(bake, p, level) + " is " + std::to_string(w) + "x" +
                     std::to_string(h) + " with " + std::to_string(channels)};
    for (size_t i = 0; i < got.pixels.size(); ++i)
        if (!std::isfinite(got.pixels[i]))
            return Error{file + ": texel (" + std::to_string(i / size_t(channels) % size_t(w)) +
                         ", " + std::to_string(i / size_t(channels) / size_t(w)) +
                         ") is not a finite number"};
    return std::move(image->image);
}

// The manifest of a bake whose planes are to be read: one baked with EXR planes.
Result<LoadedBake> readManifest(const fs::path& dir) {
    const std::string path = (dir / "manifest.json").string();
    Result<std::string> text = readRegularFile(path, inputLimits().maxTextFileBytes);
    if (!text) return text.error();
    Result<LoadedBake> bake = parseBakeManifest(text.value(), path);
    if (bake && bake->storage == "none")
        return Error{dir.string() +
                     ": holds only exported textures (baked with --export without exr); bake "
                     "again with exr in --export to render, inspect or evaluate it"};
    return bake;
}

} // namespace

void recoverInterruptedBake(const std::string& dir) {
    recoverFolderLeftovers(folderPath(dir));
}

Status writeBake(const std::string& dirName, const Bake& bake, const BakeSource& source,
                 const BakeWriteOptions& options) {
    return writeFolderWhole(dirName, checkBakeReplaceable, [&](const fs::path& staging) -> Status {
        for (size_t k = 0; k < bake.levels.size() && options.exr; ++k)
            for (size_t p = 0; p < bake.planes.size(); ++p)
                if (Status s = saveExr((staging / planeFile(bake.planes[p], int(k))).string(),
                                       *bake.levels[k][p], {}, options.half);
                    !s)
                    return s;
        json manifest = manifestJson(bake, source, options.exr);
        if (!source.cacheKey.empty()) manifest["cache_key"] = source.cacheKey;
        manifest["storage"] = !options.exr ? "none" : options.half ? "half" : "float";
        json exports = json::object();
        if (options.png16) {
            auto names = writePng16(staging, bake, source.decode.greenDown, options);
            if (!names) return Status::failure(dirName + ": " + names.error().message);
            exports["png16"] = names.value();
        }
        for (const auto& [container, wanted] :
             {std::pair<std::string, bool>{"ktx2", options.ktx2}, {"dds", options.dds}}) {
            if (!wanted) continue;
            auto names = writeContainers(staging, bake, source.decode.greenDown, options.half,
                                         container, options);
            if (!names) return Status::failure(dirName + ": " + names.error().message);
            exports[container] = names.value();
        }
        if (!exports.empty()) manifest["exports"] = exports;
        // File names need not be UTF-8; JSON must be: invalid bytes are written as U+FFFD.
        const std::string text =
            manifest.dump(2, ' ', false, json::error_handler_t::replace) + "\n";
        return writeFileAtomic((staging / "manifest.json").string(), text);
    });
}

Result<LoadedBake> readBake(const std::string& dirName, int level) {
    const fs::path dir(dirName);
    Result<LoadedBake> bake = readManifest(dir);
    if (!bake) return bake;
    const size_t levels = bake->levelSizes.size();
    if (level < 0 || level >= int(levels))
        return Error{dirName + ": level " + std::to_string(level) + " out of range (the bake has " +
                     std::to_string(levels) + " levels, 0 to " + std::to_string(levels - 1) + ")"};
    for (size_t p = 0; p < bake->planes.size(); ++p) {
        Result<Image> image = readPlane(dir, bake.value(), p, level);
        if (!image) return image.error();
        bake->level.push_back(std::move(image.value()));
    }
    return bake;
}

Result<Bake> loadBake(const std::string& dirName) {
    const fs::path dir(dirName);
    Result<LoadedBake> manifest = readManifest(dir);
    if (!manifest) return manifest.error();
    int64_t bytes = 0;
    for (const auto& [w, h] : manifest->levelSizes)
        for (const PlaneInfo& plane : manifest->planes)
            bytes += int64_t(w) * h * int64_t(plane.channels.size()) * int64_t(sizeof(float));
    if (bytes > inputLimits().maxMemoryBytes)
        return Error{dirName + ": the bake's planes need " + byteSize(bytes) +
                     " in memory, above the limit of " + byteSize(inputLimits().maxMemoryBytes) +
                     "; --max-memory raises it"};
    Bake bake;
    bake.method = manifest->method;
    bake.planes = manifest->planes;
    bake.parameters = manifest->parameters;
    for (int k = 0; k < int(manifest->levelSizes.size()); ++k) {
        std::vector<SharedImage> planes;
        for (size_t p = 0; p < bake.planes.size(); ++p) {
            Result<Image> image = readPlane(dir, manifest.value(), p, k);
            if (!image) return image.error();
            planes.push_back(std::make_shared<const Image>(std::move(image.value())));
        }
        bake.levels.push_back(std::move(planes));
    }
    return bake;
}

} // namespace ndfmip
