// The bake directory: manifest.json (what was baked, from what, how to read each channel) and
// one float EXR per plane per level. The whole directory is staged beside its final place
// and swapped in at the end, so a failed bake never leaves a half-written one behind.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "ndfmip/bake.h"
#include "ndfmip/io.h"

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

Image encodeNormals(const Image& directions, bool greenDown) {
    Image out(directions.width, directions.height, 3);
    for (size_t i = 0; i < directions.texelCount(); ++i) {
        float n[3];
        normalizeOrFlat(&directions.pixels[i * directions.channels], n);
        if (greenDown) n[1] = -n[1];
        for (int c = 0; c < 3; ++c) out.pixels[3 * i + c] = 0.5f * (n[c] + 1.f);
    }
    return out;
}

Image perceptual(const Image& alpha) {
    Image out = alpha;
    for (float& v : out.pixels) v = std::sqrt(std::max(v, 0.f));
    return out;
}

// Writes the png16 files into `folder`; returns their names relative to the bake folder.
Result<std::vector<std::string>> writePng16(const fs::path& folder, const Bake& bake,
                                            bool greenDown) {
    std::error_code ec;
    fs::create_directory(folder / "png16", ec);
    std::vector<std::string> names;
    int dirPlane = directionPlane(bake), ggx = findPlane(bake.planes, "roughness_ggx");
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

json manifestJson(const Bake& bake, const BakeSource& source) {
    json planes = json::array();
    for (const PlaneInfo& p : bake.planes)
        planes.push_back({{"name", p.name}, {"channels", p.channels},
                          {"description", p.description}, {"linear", p.linear}});
    json levels = json::array();
    for (size_t k = 0; k < bake.levels.size(); ++k) {
        json files = json::object();
        for (const PlaneInfo& p : bake.planes) files[p.name] = planeFile(p, int(k));
        const Image& first = *bake.levels[k].front();
        levels.push_back({{"level", k}, {"width", first.width}, {"height", first.height},
                          {"files", files}});
    }
    const DecodeOptions& d = source.decode;
    return {
        {"tool", "ndfmip"},
        {"version", NDFMIP_VERSION},
        {"method", methodName(bake.method)},
        {"parameters", bake.parameters},
        {"source", {{"path", source.path}, {"sha256", source.sha256},
                    {"width", source.width}, {"height", source.height},
                    {"gloss", source.gloss}}},
        {"conventions", {{"green_down", d.greenDown}, {"two_channel", d.twoChannel},
                         {"signed", d.signedValues}, {"height", d.height},
                         {"height_scale", d.heightScale},
                         {"address", d.address == AddressMode::Wrap ? "wrap" : "clamp"},
                         {"normals", "tangent space, OpenGL convention (+Y towards the top row)"},
                         {"texel_origin", "x = column, y = row counted from the top row"}}},
        {"pyramid", kPyramidRule},
        {"planes", planes},
        {"levels", levels},
    };
}

// Moves the finished staging folder to `dir`, replacing an earlier bake there but never a
// folder that holds anything else.
Status swapIn(const fs::path& staging, const fs::path& dir) {
    std::error_code ec;
    if (fs::exists(dir, ec)) {
        if (!fs::is_directory(dir, ec))
            return Status::failure(dir.string() + ": exists and is not a directory");
        bool empty = fs::is_empty(dir, ec);
        if (!empty && !fs::exists(dir / "manifest.json", ec))
            return Status::failure(dir.string() +
                                   ": exists and is not an ndfmip bake directory; not replacing it");
        fs::path old = dir.string() + ".old-" + std::to_string(getpid());
        fs::rename(dir, old, ec);
        if (ec) return Status::failure(dir.string() + ": cannot replace (" + ec.message() + ")");
        fs::rename(staging, dir, ec);
        if (ec) {
            fs::rename(old, dir);
            return Status::failure(dir.string() + ": cannot replace (" + ec.message() + ")");
        }
        fs::remove_all(old, ec);
        return Status::success();
    }
    fs::rename(staging, dir, ec);
    if (ec) return Status::failure(dir.string() + ": cannot create (" + ec.message() + ")");
    return Status::success();
}

} // namespace

Status writeBake(const std::string& dirName, const Bake& bake, const BakeSource& source,
                 const BakeWriteOptions& options) {
    fs::path dir = fs::path(dirName).lexically_normal();
    if (dir.filename().empty()) dir = dir.parent_path();
    std::error_code ec;
    fs::path parent = dir.has_parent_path() ? dir.parent_path() : fs::path(".");
    if (!fs::is_directory(parent, ec))
        return Status::failure(dirName + ": parent folder " + parent.string() +
                               (fs::exists(parent, ec) ? " is not a folder" : " does not exist"));
    fs::path staging = dir.string() + ".partial-" + std::to_string(getpid());
    fs::remove_all(staging, ec);
    if (!fs::create_directory(staging, ec))
        return Status::failure(dirName + ": cannot write (" + ec.message() + ")");

    auto fail = [&](const std::string& message) {
        fs::remove_all(staging, ec);
        return Status::failure(message);
    };
    for (size_t k = 0; k < bake.levels.size(); ++k) {
        for (size_t p = 0; p < bake.planes.size(); ++p) {
            Status s = saveExr((staging / planeFile(bake.planes[p], int(k))).string(),
                               *bake.levels[k][p], {}, options.half);
            if (!s) return fail(s.error);
        }
    }
    json manifest = manifestJson(bake, source);
    manifest["storage"] = options.half ? "half" : "float";
    if (options.png16) {
        auto names = writePng16(staging, bake, source.decode.greenDown);
        if (!names) return fail(dirName + ": " + names.error().message);
        manifest["exports"] = {{"png16", names.value()}};
    }
    Status s = writeFileAtomic((staging / "manifest.json").string(), manifest.dump(2) + "\n");
    if (!s) return fail(s.error);
    s = swapIn(staging, dir);
    if (!s) return fail(s.error);
    return Status::success();
}

Result<LoadedBake> readBake(const std::string& dirName, int level) {
    fs::path manifestPath = fs::path(dirName) / "manifest.json";
    std::ifstream in(manifestPath);
    if (!in) return Error{manifestPath.string() + ": cannot open (not a bake directory?)"};
    LoadedBake bake;
    try {
        json m = json::parse(in);
        auto method = methodFromString(m.at("method").get<std::string>());
        if (!method) return Error{manifestPath.string() + ": unknown method " + m.at("method").dump()};
        bake.method = *method;
        for (auto& [key, value] : m.at("parameters").items()) bake.parameters[key] = value.get<double>();
        for (const json& p : m.at("planes"))
            bake.planes.push_back({p.at("name"), p.at("channels"), p.at("description"), p.at("linear")});
        const json& src = m.at("source");
        bake.source.path = src.at("path");
        bake.source.sha256 = src.at("sha256");
        bake.source.width = src.at("width");
        bake.source.height = src.at("height");
        bake.source.gloss = src.value("gloss", "");
        const json& conv = m.at("conventions");
        bake.source.decode.greenDown = conv.at("green_down");
        bake.source.decode.twoChannel = conv.at("two_channel");
        bake.source.decode.signedValues = conv.at("signed");
        bake.source.decode.height = conv.at("height");
        bake.source.decode.heightScale = conv.at("height_scale");
        bake.source.decode.address = conv.at("address") == "clamp" ? AddressMode::Clamp : AddressMode::Wrap;
        const json& levels = m.at("levels");
        for (const json& l : levels) bake.levelSizes.emplace_back(l.at("width"), l.at("height"));
        if (level < 0 || level >= int(levels.size()))
            return Error{dirName + ": level " + std::to_string(level) + " out of range (the bake has " +
                         std::to_string(levels.size()) + " levels, 0 to " +
                         std::to_string(levels.size() - 1) + ")"};
        for (const PlaneInfo& p : bake.planes) {
            std::string file = (fs::path(dirName) / levels[level].at("files").at(p.name).get<std::string>()).string();
            Result<SourceImage> image = loadImage(file);
            if (!image) return image.error();
            bake.level.push_back(std::move(image->image));
        }
    } catch (const json::exception& e) {
        return Error{manifestPath.string() + ": malformed manifest (" + e.what() + ")"};
    }
    return bake;
}

Result<Bake> loadBake(const std::string& dir) {
    Result<LoadedBake> first = readBake(dir, 0);
    if (!first) return first.error();
    Bake bake;
    bake.method = first->method;
    bake.planes = first->planes;
    bake.parameters = first->parameters;
    const int count = int(first->levelSizes.size());
    for (int k = 0; k < count; ++k) {
        Result<LoadedBake> level = k == 0 ? std::move(first) : readBake(dir, k);
        if (!level) return level.error();
        std::vector<SharedImage> planes;
        for (size_t p = 0; p < level->level.size(); ++p) {
            Image& image = level->level[p];
            const auto [w, h] = level->levelSizes[k];
            if (image.width != w || image.height != h || image.channels != int(bake.planes[p].channels.size()))
                return Error{dir + ": level " + std::to_string(k) + " plane '" + bake.planes[p].name +
                             "' does not match the manifest's size or channels"};
            planes.push_back(std::make_shared<const Image>(std::move(image)));
        }
        bake.levels.push_back(std::move(planes));
    }
    return bake;
}

} // namespace ndfmip
