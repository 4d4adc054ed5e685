// The environment folder (environment.h): sh.json, ggx_L<k>.exr, dfg.exr, the KTX2 files with
// --ktx2, and environment.json, staged beside the folder and swapped in at the end like a bake
// (bake_dir.cpp).
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>

#include <nlohmann/json.hpp>

#include "io/crash_recovery.h"
#include "io/input_file.h"
#include "ndfmip/environment.h"
#include "ndfmip/io.h"
#include "ndfmip/limits.h"
#include "ndfmip/spherical_harmonics.h"
#include "ndfmip/texture_container.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace ndfmip {
namespace {

const char* kManifest = "environment.json";
const char* kFrame =
    "right-handed, +Y up; texel (u, v) (u to the right, v down from the top row, in [0, 1]) "
    "looks along d = (-cos(lat) sin(phi), sin(lat), cos(lat) cos(phi)), phi = 2 pi (u - 1/2), "
    "lat = pi (1/2 - v): the image centre is +Z, u = 1/4 is +X (Filament cmgen's frame)";

std::string levelFile(size_t k) {
    return "ggx_L" + std::to_string(k) + ".exr";
}

std::string faceFile(size_t k, int face) {
    return "ggx_L" + std::to_string(k) + "_" + cubeFaceName(face) + ".exr";
}

// A level's cube faces are a quarter of its width: the same texels per radian at the equator.
int faceSize(const Image& level) {
    return std::max(level.width / 4, 1);
}

// Coefficients per band: band l is 2l + 1 RGB triples, m = -l ... l.
json bands(const std::vector<glm::dvec3>& c, int order) {
    json out = json::array();
    for (int l = 0; l <= order; ++l) {
        json band = json::array();
        for (int m = -l; m <= l; ++m) {
            const glm::dvec3& v = c[size_t(shIndex(l, m))];
            band.push_back({v.x, v.y, v.z});
        }
        out.push_back(band);
    }
    return out;
}

json shJson(const EnvironmentSh& sh) {
    return {
        {"tool", "ndfmip"},
        {"version", NDFMIP_VERSION},
        {"order", sh.order},
        {"basis",
         "real orthonormal Y_lm without the Condon-Shortley phase (Y_1,-1 = c y, Y_1,0 = c z, "
         "Y_1,1 = c x, c = sqrt(3 / (4 pi))); ndfmip/spherical_harmonics.h"},
        {"frame", kFrame},
        {"layout", "band l is a list of 2l + 1 [r, g, b] for m = -l ... l"},
        {"radiance", bands(sh.radiance, sh.order)},
        {"irradiance_description",
         "E_lm = lambert[l] * radiance_lm: irradiance E(n) = sum E_lm Y_lm(n); a "
         "Lambertian surface of albedo a reflects a E(n) / pi"},
        {"irradiance", bands(sh.irradiance, sh.order)},
        {"lambert", sh.lambert},
    };
}

// The textures --ktx2 and --dds write, by the key the manifest names them under (the file's
// stem as well).
constexpr const char* kCubeTexture = "ggx_cube";
constexpr const char* kEquirectTexture = "ggx_equirect";
constexpr const char* kDfgTexture = "dfg";

// The names of the files in one container (an empty object when it is not written).
json textureFilesJson(const EnvironmentBake& bake, bool written, const std::string& extension,
                      const char* format) {
    json files = json::object();
    if (!written) return files;
    if (bake.cube) files[kCubeTexture] = kCubeTexture + extension;
    if (bake.equirect) files[kEquirectTexture] = kEquirectTexture + extension;
    files[kDfgTexture] = kDfgTexture + extension;
    files["format"] = std::string(format) + ", alpha 1; the GGX levels as the mips";
    return files;
}

// What a texture holds, as the "ndfmip" key of its KTX2 key/value data (JSON).
std::string aboutTexture(const EnvironmentBake& bake, const char* stem) {
    json about;
    if (std::string(stem) == kDfgTexture) {
        about = {{"content", "dfg"},
                 {"x", "n.v = (x + 0.5) / size"},
                 {"y", "perceptual roughness = (y + 0.5) / size, top row first"},
                 {"channels",
                  {{"r", "scale: multiplies f0"},
                   {"g", "bias: multiplies f90"},
                   {"b", "scale + bias: directional albedo with F = 1"},
                   {"a", "1"}}}};
    } else {
        json roughness = json::array();
        for (const PrefilteredLevel& level : bake.levels)
            roughness.push_back(level.perceptualRoughness);
        about = {{"content", "radiance"},
                 {"filter", "GGX-prefiltered (split sum), level k at perceptual_roughness[k]"},
                 {"perceptual_roughness", roughness},
                 {"channels", {{"r", "red"}, {"g", "green"}, {"b", "blue"}, {"a", "1"}}},
                 {"transfer", "linear"}};
    }
    return about.dump(-1, ' ', false, json::error_handler_t::replace);
}

// One texture in each container asked for.
Status writeTexture(const fs::path& staging, const EnvironmentBake& bake, const char* stem,
                    const Result<EncodedTexture>& texture) {
    for (const bool ktx2 : {true, false}) {
        if (!(ktx2 ? bake.ktx2 : bake.dds)) continue;
        const fs::path file = staging / (std::string(stem) + (ktx2 ? ".ktx2" : ".dds"));
        if (!texture) return Status::failure(file.string() + ": " + texture.error().message);
        Result<std::string> bytes =
            ktx2 ? ktx2File(texture.value(), 0, {{"ndfmip", aboutTexture(bake, stem)}})
                 : Result<std::string>(ddsFile(texture.value()));
        if (!bytes) return Status::failure(file.string() + ": " + bytes.error().message);
        if (Status s = writeFileAtomic(file.string(), bytes.value()); !s) return s;
    }
    return Status::success();
}

// Every level's six cube faces (cubeFaceFromEquirect), made once for the EXR faces and the
// containers' cube map.
using LevelFaces = std::array<Image, kCubeFaces>;
std::vector<LevelFaces> cubeFaces(const EnvironmentBake& bake) {
    std::vector<LevelFaces> faces(bake.levels.size());
    for (size_t k = 0; k < bake.levels.size(); ++k) {
        const Image& level = bake.levels[k].radiance;
        for (int face = 0; face < kCubeFaces; ++face)
            faces[k][size_t(face)] = cubeFaceFromEquirect(level, face, faceSize(level));
    }
    return faces;
}

// The textures of textureFilesJson, RGBA16F: each encoded once, written as KTX2 and/or DDS.
Status writeTextureFiles(const fs::path& staging, const EnvironmentBake& bake,
                         const std::vector<LevelFaces>& faces) {
    if (bake.cube) {
        std::vector<std::vector<LevelRows>> rows;
        for (const LevelFaces& level : faces) {
            rows.emplace_back();
            for (const Image& face : level) rows.back().push_back(rowsOf(face, 4, 1.f));
        }
        if (Status s = writeTexture(staging, bake, kCubeTexture,
                                    encodeCubeTexture(rows, TextureFormat::Rgba16F));
            !s)
            return s;
    }
    if (bake.equirect) {
        std::vector<LevelRows> rows;
        for (const PrefilteredLevel& level : bake.levels)
            rows.push_back(rowsOf(level.radiance, 4, 1.f));
        if (Status s = writeTexture(staging, bake, kEquirectTexture,
                                    encodeTexture(rows, TextureFormat::Rgba16F));
            !s)
            return s;
    }
    return writeTexture(
        staging, bake, kDfgTexture,
        encodeTexture(std::vector<LevelRows>{rowsOf(bake.dfg, 4, 1.f)}, TextureFormat::Rgba16F));
}

json manifestJson(const EnvironmentBake& bake, const EnvironmentSource& source, bool half) {
    json levels = json::array();
    for (size_t k = 0; k < bake.levels.size(); ++k) {
        const PrefilteredLevel& level = bake.levels[k];
        const double r = level.perceptualRoughness;
        json entry = {{"level", k},
                      {"width", level.radiance.width},
                      {"height", level.radiance.height},
                      {"perceptual_roughness", r},
                      {"alpha", r * r},
                      {"samples", level.samples}};
        if (bake.equirect) entry["file"] = levelFile(k);
        if (bake.cube) {
            json faces = json::object();
            for (int face = 0; face < kCubeFaces; ++face)
                faces[cubeFaceName(face)] = faceFile(k, face);
            entry["faces"] = faces;
            entry["face_size"] = faceSize(level.radiance);
        }
        levels.push_back(entry);
    }
    const bool filament = bake.mapping == LodMapping::Filament;
    return {
        {"tool", "ndfmip"},
        {"version", NDFMIP_VERSION},
        {"kind", "environment"},
        {"source",
         {{"path", source.path},
          {"sha256", source.sha256},
          {"width", source.width},
          {"height", source.height},
          {"intensity", source.options.intensity},
          {"rotation_degrees", source.options.rotationDegrees}}},
        {"frame", kFrame},
        {"storage", half ? "half" : "float"},
        {"sh", "sh.json"},
        {"ggx",
         {{"description", "radiance convolved with GGX D(h) <n.l> about r (split sum, n = v = r), "
                          "RGB per level: `file` equirectangular, `faces` the cube faces"},
          {"cube_faces",
           "order and orientation of OpenGL/Vulkan/KTX2 cube maps: +X, -X, +Y, -Y, +Z, "
           "-Z; texel (s, t) (s right, t down from the top row) of +X looks along "
           "(1, 1 - 2t, 1 - 2s), and so on (ndfmip/environment.h cubeFaceDirection)"},
          {"lod_mapping", lodMappingName(bake.mapping)},
          {"lod_to_roughness", filament
                                   ? "r = 1 - sqrt(1 - lod), lod = r (2 - r) = k / (levels - 1)"
                                   : "r = lod = k / (levels - 1)"},
          {"levels", levels}}},
        {"ktx2", textureFilesJson(bake, bake.ktx2, ".ktx2", "VK_FORMAT_R16G16B16A16_SFLOAT")},
        {"dds", textureFilesJson(bake, bake.dds, ".dds", "DXGI_FORMAT_R16G16B16A16_FLOAT")},
        {"dfg",
         {{"file", "dfg.exr"},
          {"size", bake.dfg.width},
          {"samples", bake.dfgSamples},
          {"x", "n.v = (x + 0.5) / size"},
          {"y", "perceptual roughness = (y + 0.5) / size, top row first"},
          {"channels",
           {{"R", "scale: multiplies f0"},
            {"G", "bias: multiplies f90"},
            {"B", "scale + bias: directional albedo with F = 1"}}},
          {"brdf", "GGX, height-correlated Smith masking, Schlick Fresnel"}}},
    };
}

// Whether `dir` may be replaced: empty, or an earlier environment folder holding only the files
// its manifest lists. Anything else is someone's work and is never deleted.
Status checkEnvironmentReplaceable(const fs::path& dir) {
    std::error_code ec;
    if (!fs::is_directory(dir, ec))
        return Status::failure(dir.string() + ": exists and is not a directory");
    if (fs::is_empty(dir, ec)) return Status::success();
    auto refuse = [&](const std::string& why) {
        return Status::failure(dir.string() + ": exists and is not an ndfmip environment folder (" +
                               why + "); not replacing it");
    };
    Result<std::string> text =
        readRegularFile((dir / kManifest).string(), inputLimits().maxTextFileBytes);
    if (!text) return refuse(std::string("no readable ") + kManifest);
    json m = json::parse(text.value(), nullptr, /*allow_exceptions=*/false);
    if (!m.is_object() || m.value("tool", "") != "ndfmip" || m.value("kind", "") != "environment")
        return refuse(std::string("its ") + kManifest + " is not an ndfmip environment manifest");
    std::set<std::string> listed{kManifest, "sh.json", "dfg.exr"};
    for (const char* container : {"ktx2", "dds"})
        if (m.contains(container) && m[container].is_object())
            for (const auto& [key, file] : m[container].items())
                if (key != "format" && file.is_string()) listed.insert(file.get<std::string>());
    if (m.contains("ggx") && m["ggx"].is_object() && m["ggx"].contains("levels") &&
        m["ggx"]["levels"].is_array())
        for (const json& level : m["ggx"]["levels"])
            if (level.is_object()) {
                if (level.contains("file") && level["file"].is_string())
                    listed.insert(level["file"].get<std::string>());
                if (level.contains("faces") && level["faces"].is_object())
                    for (const json& face : level["faces"])
                        if (face.is_string()) listed.insert(face.get<std::string>());
            }
    for (auto it = fs::directory_iterator(dir, ec); !ec && it != fs::directory_iterator();
         it.increment(ec)) {
        const std::string name = it->path().filename().string();
        if (!listed.count(name) || !it->is_regular_file(ec))
            return refuse("it holds " + quote(name) + ", which its manifest does not list");
    }
    if (ec) return refuse("cannot list it: " + ec.message());
    return Status::success();
}

// Every value written finite, and within the half-float range where it is stored as one (--half,
// and the RGBA16F KTX2/DDS textures), where 1e5 would become inf. Refused rather than clamped:
// a clamped sun is a different light, and the caller can lower the intensity or drop --half.
Status checkStorable(const EnvironmentBake& bake, const EnvironmentSource& source, bool half) {
    // 65504 is the largest half float; below 65520 a value still rounds to it, not to inf.
    constexpr float kHalfRoundsToInf = 65520.f;
    const bool toHalf = half || bake.ktx2 || bake.dds;
    for (size_t k = 0; k < bake.levels.size(); ++k) {
        const Image& level = bake.levels[k].radiance;
        for (size_t i = 0; i < level.pixels.size(); ++i) {
            const float v = level.pixels[i];
            if (std::isfinite(v) && (!toHalf || std::abs(v) < kHalfRoundsToInf)) continue;
            const size_t texel = i / size_t(level.channels);
            char text[160];
            std::snprintf(text, sizeof text, ": GGX level %zu texel (%zu, %zu) has radiance %g, ",
                          k, texel % size_t(level.width), texel / size_t(level.width), double(v));
            const std::string why =
                !std::isfinite(v)
                    ? "not a finite number"
                    : std::string("above 65504, the largest half float, which ") +
                          (half ? "--half" : "the KTX2/DDS textures (RGBA16F)") +
                          " cannot store; lower --intensity" + (half ? " or drop --half" : "");
            return Status::failure(source.path + text + why);
        }
    }
    for (const auto* coefficients : {&bake.sh.radiance, &bake.sh.irradiance})
        for (const glm::dvec3& c : *coefficients)
            if (!std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z))
                return Status::failure(source.path +
                                       ": its SH coefficients are not finite numbers");
    return Status::success();
}

} // namespace

Status writeEnvironment(const std::string& dirName, const EnvironmentBake& bake,
                        const EnvironmentSource& source, bool half) {
    if (Status s = checkStorable(bake, source, half); !s) return s;
    return writeFolderWhole(
        dirName, checkEnvironmentReplaceable, [&](const fs::path& staging) -> Status {
            const std::vector<LevelFaces> faces =
                bake.cube ? cubeFaces(bake) : std::vector<LevelFaces>{};
            for (size_t k = 0; k < bake.levels.size(); ++k) {
                if (bake.equirect)
                    if (Status s = saveExr((staging / levelFile(k)).string(),
                                           bake.levels[k].radiance, {}, half);
                        !s)
                        return s;
                if (bake.cube)
                    for (int face = 0; face < kCubeFaces; ++face)
                        if (Status s = saveExr((staging / faceFile(k, face)).string(),
                                               faces[k][size_t(face)], {}, half);
                            !s)
                            return s;
            }
            if (Status s = saveExr((staging / "dfg.exr").string(), bake.dfg, {}, half); !s)
                return s;
            if (bake.ktx2 || bake.dds)
                if (Status s = writeTextureFiles(staging, bake, faces); !s) return s;
            if (Status s =
                    writeFileAtomic((staging / "sh.json").string(), shJson(bake.sh).dump(2) + "\n");
                !s)
                return s;
            const std::string manifest = manifestJson(bake, source, half)
                                             .dump(2, ' ', false, json::error_handler_t::replace) +
                                         "\n";
            return writeFileAtomic((staging / kManifest).string(), manifest);
        });
}

} // namespace ndfmip
