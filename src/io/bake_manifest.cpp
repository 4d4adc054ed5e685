// Reading a bake's manifest.json: every fact a command will rely on is checked here, once, so
// inspect and render can trust a LoadedBake. A manifest may have been edited by hand or by an
// attacker: sizes must follow the GPU mip rule from the source size, planes must be exactly the
// method's, parameters in range, and level files plain names inside the folder.
#include <cmath>
#include <set>

#include <nlohmann/json.hpp>

#include "io/input_file.h"
#include "methods/method_unit.h"
#include "ndfmip/bake.h"
#include "ndfmip/limits.h"
#include "ndfmip/spherical_harmonics.h"

using nlohmann::json;

namespace ndfmip {
namespace {

// Thrown by the readers below and caught in parseBakeManifest, never outside this file.
struct ManifestProblem {
    std::string problem;
};

[[noreturn]] void failManifest(const std::string& problem) {
    throw ManifestProblem{problem};
}

std::string at(const std::string& path, const std::string& key) {
    return path.empty() ? key : path + "." + key;
}

std::string at(const std::string& path, size_t index) {
    return path + "[" + std::to_string(index) + "]";
}

// A value as a message shows it, never the whole of a large array or object.
std::string shown(const json& value) {
    if (value.is_array()) return "an array of " + std::to_string(value.size());
    if (value.is_object()) return "an object";
    if (value.is_string()) return quote(value.get_ref<const std::string&>());
    return shortened(value.dump(-1, ' ', false, json::error_handler_t::replace), 40);
}

std::string plainNumber(double x) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", x);
    return text;
}

const json& member(const json& object, const std::string& path, const char* key) {
    auto it = object.find(key);
    if (it == object.end()) failManifest("missing key " + quote(at(path, key)));
    return *it;
}

const json& objectAt(const json& object, const std::string& path, const char* key) {
    const json& v = member(object, path, key);
    if (!v.is_object()) failManifest(quote(at(path, key)) + " must be an object, not " + shown(v));
    return v;
}

const json& arrayAt(const json& object, const std::string& path, const char* key) {
    const json& v = member(object, path, key);
    if (!v.is_array()) failManifest(quote(at(path, key)) + " must be an array, not " + shown(v));
    return v;
}

std::string textAt(const json& object, const std::string& path, const char* key) {
    const json& v = member(object, path, key);
    if (!v.is_string()) failManifest(quote(at(path, key)) + " must be a string, not " + shown(v));
    return v.get<std::string>();
}

bool flagAt(const json& object, const std::string& path, const char* key) {
    const json& v = member(object, path, key);
    if (!v.is_boolean())
        failManifest(quote(at(path, key)) + " must be true or false, not " + shown(v));
    return v.get<bool>();
}

double numberAt(const json& object, const std::string& path, const char* key) {
    const json& v = member(object, path, key);
    if (!v.is_number()) failManifest(quote(at(path, key)) + " must be a number, not " + shown(v));
    return v.get<double>();
}

// An integer in [lo, hi]; 7.0 counts, 7.5 and 1e300 do not.
int64_t integerAt(const json& object, const std::string& path, const char* key, int64_t lo,
                  int64_t hi) {
    const double x = numberAt(object, path, key);
    if (!(x == std::floor(x) && x >= double(lo) && x <= double(hi)))
        failManifest(quote(at(path, key)) + " must be an integer from " + std::to_string(lo) +
                     " to " + std::to_string(hi) + ", not " + shown(member(object, path, key)));
    return int64_t(x);
}

// A file of the bake: a plain name inside its folder (or png16/, ktx2/, dds/NAME for exports),
// never a path that leads elsewhere.
bool plainName(const std::string& name) {
    return !name.empty() && name.size() <= 255 && name != "." && name != ".." &&
           name.find_first_of(std::string("/\\\0", 3)) == std::string::npos;
}

std::string fileAt(const json& object, const std::string& path, const char* key) {
    std::string name = textAt(object, path, key);
    if (!plainName(name))
        failManifest(quote(at(path, key)) + " is " + quote(name) +
                     ", not a plain file name inside the bake folder");
    return name;
}

std::string planeList(const std::vector<PlaneInfo>& planes) {
    std::string text;
    for (const PlaneInfo& p : planes)
        text += (text.empty() ? "" : ", ") + p.name + " (" + std::to_string(p.channels.size()) +
                (p.linear ? "" : ", not linear") + ")";
    return shortened(text, 160);
}

void readParameters(const json& m, LoadedBake& bake) {
    const json& parameters = objectAt(m, "", "parameters");
    for (const auto& [key, value] : parameters.items()) {
        if (!value.is_number())
            failManifest(quote(at("parameters", key)) + " must be a number, not " + shown(value));
        bake.parameters[key] = value.get<double>();
    }
    // Those the method's commands use, in the ranges a bake writes.
    for (const MethodParameter& r : methodUnit(bake.method).parameters) {
        if (!r.recorded) continue;
        if (r.type == ParameterType::Integer) {
            integerAt(parameters, "parameters", r.key, int64_t(r.min), int64_t(r.max));
            continue;
        }
        const double x = numberAt(parameters, "parameters", r.key);
        if (!(x >= r.min && x <= r.max))
            failManifest(quote(at("parameters", r.key)) + " must be in [" + plainNumber(r.min) +
                         ", " + plainNumber(r.max) + "], not " + shown(x));
    }
    if (parameters.contains("max_exponent")) {
        const double s = numberAt(parameters, "parameters", "max_exponent");
        if (!(s > 0.0 && s <= 1e6)) failManifest("'parameters.max_exponent' must be in (0, 1e6]");
    }
}

void readPlanes(const json& m, LoadedBake& bake) {
    const json& planes = arrayAt(m, "", "planes");
    for (size_t i = 0; i < planes.size() && i < 256; ++i) { // sh order 30 has 241
        const std::string path = at("planes", i);
        if (!planes[i].is_object())
            failManifest(quote(path) + " must be an object, not " + shown(planes[i]));
        PlaneInfo plane;
        plane.name = textAt(planes[i], path, "name");
        const json& channels = arrayAt(planes[i], path, "channels");
        for (size_t c = 0; c < channels.size() && c < 8; ++c) {
            if (!channels[c].is_string())
                failManifest(quote(at(at(path, "channels"), c)) + " must be a string, not " +
                             shown(channels[c]));
            plane.channels.push_back(channels[c].get<std::string>());
        }
        if (channels.size() > 8) plane.channels.resize(9); // never a valid count, caught below
        plane.description = textAt(planes[i], path, "description");
        plane.linear = flagAt(planes[i], path, "linear");
        bake.planes.push_back(std::move(plane));
    }
    const MethodUnit& unit = methodUnit(bake.method);
    const std::vector<PlaneInfo> expected =
        unit.planes(bake.parameters, findPlane(bake.planes, "color0") >= 0);
    bool same = planes.size() == expected.size();
    for (size_t p = 0; same && p < expected.size(); ++p)
        same = bake.planes[p].name == expected[p].name &&
               bake.planes[p].channels.size() == expected[p].channels.size() &&
               bake.planes[p].linear == expected[p].linear;
    if (!same) {
        const std::string what = unit.describe(bake.parameters);
        failManifest("'planes' do not match a " + what + ": expected " + planeList(expected) +
                     "; found " + (planes.empty() ? std::string("none") : planeList(bake.planes)) +
                     " (a bake made by another version of ndfmip: bake it again)");
    }
}

void readSource(const json& m, LoadedBake& bake) {
    const json& src = objectAt(m, "", "source");
    bake.source.path = textAt(src, "source", "path");
    bake.source.sha256 = textAt(src, "source", "sha256");
    const InputLimits& limits = inputLimits();
    bake.source.width = int(integerAt(src, "source", "width", 1, limits.maxSide));
    bake.source.height = int(integerAt(src, "source", "height", 1, limits.maxSide));
    if (Status size = checkImageSize("'source'", bake.source.width, bake.source.height); !size)
        failManifest(size.error);
    if (src.contains("gloss")) bake.source.gloss = textAt(src, "source", "gloss");

    const json& conv = objectAt(m, "", "conventions");
    DecodeOptions& d = bake.source.decode;
    d.greenDown = flagAt(conv, "conventions", "green_down");
    d.twoChannel = flagAt(conv, "conventions", "two_channel");
    d.signedValues = flagAt(conv, "conventions", "signed");
    d.height = flagAt(conv, "conventions", "height");
    const double scale = numberAt(conv, "conventions", "height_scale");
    if (!(scale > 0.0 && scale <= 1e6))
        failManifest("'conventions.height_scale' must be in (0, 1e6], not " + shown(scale));
    d.heightScale = float(scale);
    const std::string address = textAt(conv, "conventions", "address");
    if (address != "wrap" && address != "clamp")
        failManifest("'conventions.address' must be \"wrap\" or \"clamp\", not " + quote(address));
    d.address = address == "clamp" ? AddressMode::Clamp : AddressMode::Wrap;
}

// Levels down to 1x1 by the GPU rule, each listing one plain file per plane.
void readLevels(const json& m, LoadedBake& bake) {
    const json& levels = arrayAt(m, "", "levels");
    int w = bake.source.width, h = bake.source.height;
    const size_t count = size_t(levelCount(w, h));
    if (levels.size() != count)
        failManifest("'levels' has " + std::to_string(levels.size()) + " entries; a " +
                     std::to_string(w) + "x" + std::to_string(h) + " source has " +
                     std::to_string(count) + " levels down to 1x1");
    for (size_t k = 0; k < count; ++k) {
        const std::string path = at("levels", k);
        if (!levels[k].is_object())
            failManifest(quote(path) + " must be an object, not " + shown(levels[k]));
        integerAt(levels[k], path, "level", int64_t(k), int64_t(k));
        integerAt(levels[k], path, "width", w, w);
        integerAt(levels[k], path, "height", h, h);
        bake.levelSizes.emplace_back(w, h);
        const json& files = objectAt(levels[k], path, "files");
        std::vector<std::string> names;
        if (bake.storage == "none" && !files.empty())
            failManifest(quote(at(path, "files")) +
                         " must be empty: the manifest's storage is \"none\"");
        for (const PlaneInfo& plane : bake.planes)
            if (bake.storage != "none")
                names.push_back(fileAt(files, at(path, "files"), plane.name.c_str()));
        for (const auto& item : files.items())
            if (findPlane(bake.planes, item.key()) < 0)
                failManifest(quote(at(at(path, "files"), item.key())) +
                             " names no plane of the bake");
        bake.levelFiles.push_back(std::move(names));
        w = std::max(1, w / 2);
        h = std::max(1, h / 2);
    }
}

void readStorage(const json& m, LoadedBake& bake) {
    bake.storage = m.contains("storage") ? textAt(m, "", "storage") : "float";
    if (bake.storage != "float" && bake.storage != "half" && bake.storage != "none")
        failManifest("'storage' must be \"float\", \"half\" or \"none\", not " +
                     quote(bake.storage));
}

void readExports(const json& m, LoadedBake& bake) {
    if (!m.contains("exports")) return;
    const json& exports = objectAt(m, "", "exports");
    for (const auto& [format, list] : exports.items()) {
        if (format != "png16" && format != "ktx2" && format != "dds")
            failManifest("unknown export " + quote(at("exports", format)));
        const std::string key = "exports." + format;
        if (!list.is_array()) failManifest(quote(key) + " must be an array, not " + shown(list));
        const std::string folder = format + "/";
        for (size_t i = 0; i < list.size(); ++i) {
            const std::string path = at(key, i);
            if (!list[i].is_string())
                failManifest(quote(path) + " must be a string, not " + shown(list[i]));
            const std::string name = list[i].get<std::string>();
            if (name.rfind(folder, 0) != 0 || !plainName(name.substr(folder.size())))
                failManifest(quote(path) + " is " + quote(name) + ", not " + folder +
                             " and a plain file name");
            bake.exports.push_back(name);
        }
    }
}

} // namespace

Result<LoadedBake> parseBakeManifest(const std::string& text, const std::string& name) {
    auto malformed = [&](const std::string& why) {
        return Error{name + ": malformed manifest (" + why + ")"};
    };
    if (std::string deep = jsonNestingProblem(text, inputLimits().maxJsonDepth); !deep.empty())
        return malformed(deep);
    json m;
    try {
        m = json::parse(text);
    } catch (const json::exception& e) {
        return malformed(shortened(e.what(), 200));
    }
    LoadedBake bake;
    try {
        if (!m.is_object()) failManifest("expected a JSON object, not " + shown(m));
        const std::string method = textAt(m, "", "method");
        std::optional<Method> known = methodFromString(method);
        if (!known) failManifest("unknown method " + quote(method) + " (naive, toksvig, sh, vmf)");
        bake.method = *known;
        const std::string tool = textAt(m, "", "tool");
        if (tool != "ndfmip") failManifest("written by " + quote(tool) + ", not ndfmip");
        readParameters(m, bake);
        readPlanes(m, bake);
        readSource(m, bake);
        readStorage(m, bake);
        if (m.contains("cache_key")) bake.source.cacheKey = textAt(m, "", "cache_key");
        readLevels(m, bake);
        readExports(m, bake);
    } catch (const ManifestProblem& p) {
        return Error{name + ": " + p.problem};
    } catch (const json::exception& e) { // not expected: every access above is checked
        return malformed(shortened(e.what(), 200));
    }
    return bake;
}

} // namespace ndfmip
