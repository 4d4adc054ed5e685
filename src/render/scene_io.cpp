// Reading scene files: JSON text in, a checked Scene out. Scenes are written by hand, so every
// problem comes back as one line "NAME: field.path: problem" that points at the mistake, and
// unknown or repeated keys are errors rather than silently ignored.
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <set>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/input_file.h"
#include "ndfmip/interpolated.h"
#include "ndfmip/limits.h"
#include "ndfmip/scene.h"
#include "ndfmip/sh_brdf.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace ndfmip {

const char* brdfName(Brdf brdf) {
    switch (brdf) {
    case Brdf::Lambert:
        return "lambert";
    case Brdf::BlinnPhong:
        return "blinnphong";
    case Brdf::Beckmann:
        return "beckmann";
    case Brdf::Ggx:
        return "ggx";
    case Brdf::Tabulated:
        return "tabulated";
    }
    return "?";
}

bool brdfFromString(const std::string& name, Brdf& out) {
    for (Brdf brdf :
         {Brdf::Lambert, Brdf::BlinnPhong, Brdf::Beckmann, Brdf::Ggx, Brdf::Tabulated}) {
        if (name == brdfName(brdf)) {
            out = brdf;
            return true;
        }
    }
    // Han et al. 2007 call the Beckmann microfacet model Torrance-Sparrow.
    if (name == "torrance-sparrow") {
        out = Brdf::Beckmann;
        return true;
    }
    return false;
}

namespace {

// Thrown by the field readers below and caught in parseScene, never outside this file: it
// keeps each reader a single line at its call site.
struct SceneProblem {
    std::string where; // field path, "" for the whole document
    std::string problem;
};

[[noreturn]] void fail(const std::string& where, const std::string& problem) {
    throw SceneProblem{where, problem};
}

std::string at(const std::string& path, const std::string& key) {
    return path.empty() ? key : path + "." + key;
}

std::string at(const std::string& path, size_t index) {
    return path + "[" + std::to_string(index) + "]";
}

// A value as the message shows it: JSON text, ASCII only, cut short. Only scalars and small flat
// arrays and objects are printed; a large or nested value (a 10 MB array) is only described.
std::string shown(const json& value) {
    if (value.is_string()) {
        const std::string& s = value.get_ref<const std::string&>();
        // Cut at 40 bytes, maybe inside a UTF-8 sequence: the broken end is shown as U+FFFD.
        const auto replace = json::error_handler_t::replace;
        return json(s.substr(0, 40)).dump(-1, ' ', true, replace) +
               (s.size() > 40 ? "\xE2\x80\xA6" : "");
    }
    if (value.is_structured()) {
        const bool flat =
            value.size() <= 8 && std::none_of(value.begin(), value.end(), [](const json& v) {
                return v.is_structured() ||
                       (v.is_string() && v.get_ref<const std::string&>().size() > 40);
            });
        if (!flat)
            return (value.is_array() ? "an array of " : "an object of ") +
                   std::to_string(value.size());
    }
    return shortened(value.dump(-1, ' ', true, json::error_handler_t::replace), 40);
}

const json* find(const json& object, const char* key) {
    auto it = object.find(key);
    return it == object.end() ? nullptr : &*it;
}

const json& required(const json& object, const std::string& path, const char* key) {
    const json* value = find(object, key);
    if (!value) fail(at(path, key), "missing");
    return *value;
}

size_t editDistance(std::string_view a, std::string_view b) {
    std::vector<size_t> row(b.size() + 1);
    for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (size_t i = 1; i <= a.size(); ++i) {
        size_t diagonal = row[0];
        row[0] = i;
        for (size_t j = 1; j <= b.size(); ++j) {
            size_t above = row[j];
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1])});
            diagonal = above;
        }
    }
    return row[b.size()];
}

// Rejects keys outside `allowed`, suggesting the nearest one, since a misspelt optional key
// would otherwise leave its default in place without a word.
void checkKeys(const json& object, const std::string& path,
               std::initializer_list<std::string_view> allowed, const std::string& what) {
    for (const auto& item : object.items()) {
        const std::string& key = item.key();
        if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
        std::string_view nearest;
        size_t distance = 3;
        for (std::string_view candidate : allowed) {
            if (key.size() > 2 * candidate.size() + 3) continue; // too far to be a misspelling
            size_t d = editDistance(key, candidate);
            if (d < distance) distance = d, nearest = candidate;
        }
        std::string problem = "unknown key";
        if (!nearest.empty()) {
            problem += " (did you mean '" + std::string(nearest) + "'?)";
        } else {
            problem += " (" + what + " takes";
            for (std::string_view candidate : allowed)
                problem += (candidate == *allowed.begin() ? " " : ", ") + std::string(candidate);
            problem += ")";
        }
        fail(at(path, shortened(key)), problem);
    }
}

// ---- typed readers -----------------------------------------------------------------------------

const json& object(const json& value, const std::string& path) {
    if (!value.is_object()) fail(path, "expected an object, got " + shown(value));
    return value;
}

std::string text(const json& value, const std::string& path) {
    if (!value.is_string()) fail(path, "expected a string, got " + shown(value));
    return value.get<std::string>();
}

std::string nonEmptyText(const json& value, const std::string& path) {
    std::string s = text(value, path);
    if (s.empty()) fail(path, "empty");
    return s;
}

bool flag(const json& value, const std::string& path) {
    if (!value.is_boolean()) fail(path, "expected true or false, got " + shown(value));
    return value.get<bool>();
}

// Any number that fits a float (JSON has no NaN or infinity; 1e999 fails to parse).
float number(const json& value, const std::string& path) {
    if (!value.is_number()) fail(path, "expected a number, got " + shown(value));
    double x = value.get<double>();
    if (!std::isfinite(x) || std::fabs(x) > double(std::numeric_limits<float>::max()))
        fail(path, "out of range (a float holds up to 3.4e38), got " + shown(value));
    return float(x);
}

float positive(const json& value, const std::string& path) {
    float x = number(value, path);
    if (!(x > 0.f)) fail(path, "must be > 0, got " + shown(value));
    return x;
}

float nonNegative(const json& value, const std::string& path) {
    float x = number(value, path);
    if (x < 0.f) fail(path, "must be >= 0, got " + shown(value));
    return x;
}

// x in (0, hi) or (0, hi]; `interval` spells the range for the message.
float inInterval(const json& value, const std::string& path, float hi, bool closedAbove,
                 const char* interval) {
    float x = number(value, path);
    if (!(x > 0.f) || x > hi || (!closedAbove && x == hi))
        fail(path, std::string("must be in ") + interval + ", got " + shown(value));
    return x;
}

constexpr int kMaxPixels = 16384;
constexpr size_t kMaxLights = 256;

int pixels(const json& value, const std::string& path) {
    bool ok = value.is_number();
    double x = ok ? value.get<double>() : 0.0;
    if (!ok || !std::isfinite(x) || x != std::floor(x) || x < 1.0)
        fail(path, "expected a positive integer, got " + shown(value));
    if (x > kMaxPixels)
        fail(path, "must be at most " + std::to_string(kMaxPixels) + ", got " + shown(value));
    return int(x);
}

int integerIn(const json& value, const std::string& path, int lo, int hi) {
    bool ok = value.is_number();
    double x = ok ? value.get<double>() : 0.0;
    if (!ok || !std::isfinite(x) || x != std::floor(x) || x < lo || x > hi)
        fail(path, "expected an integer in " + std::to_string(lo) + " .. " + std::to_string(hi) +
                       ", got " + shown(value));
    return int(x);
}

const json& array(const json& value, const std::string& path, size_t size, const char* what) {
    if (!value.is_array() || value.size() != size)
        fail(path, std::string("expected ") + what + ", got " + shown(value));
    return value;
}

glm::vec3 vec3(const json& value, const std::string& path) {
    const json& a = array(value, path, 3, "an array of 3 numbers");
    return {number(a[0], at(path, 0)), number(a[1], at(path, 1)), number(a[2], at(path, 2))};
}

glm::vec2 positivePair(const json& value, const std::string& path) {
    const json& a = array(value, path, 2, "an array of 2 numbers");
    return {positive(a[0], at(path, 0)), positive(a[1], at(path, 1))};
}

// [r, g, b] or one number for grey.
glm::vec3 colour(const json& value, const std::string& path) {
    if (value.is_number()) return glm::vec3(nonNegative(value, path));
    const json& a = array(value, path, 3, "a colour ([r, g, b] or one number)");
    return {nonNegative(a[0], at(path, 0)), nonNegative(a[1], at(path, 1)),
            nonNegative(a[2], at(path, 2))};
}

glm::vec3 unitVector(const json& value, const std::string& path) {
    glm::dvec3 v = vec3(value, path);
    double length = glm::length(v);
    if (!(length > 1e-12)) fail(path, "zero-length vector");
    return glm::vec3(v / length);
}

// Unit vectors closer than about 0.006 degrees to (anti)parallel give no usable frame.
bool parallel(const glm::vec3& a, const glm::vec3& b) {
    return glm::length(glm::cross(glm::dvec3(a), glm::dvec3(b))) < 1e-4;
}

// Which of `names` the string `value` is; `what` names the kind in the message. Callers list
// the names in their enum's order and cast the index (a test reads every non-default value).
size_t oneOf(const json& value, const std::string& path,
             std::initializer_list<std::string_view> names, const std::string& what) {
    std::string name = text(value, path);
    auto it = std::find(names.begin(), names.end(), name);
    if (it != names.end()) return size_t(it - names.begin());
    std::string expected;
    for (std::string_view n : names) expected += (expected.empty() ? "" : ", ") + std::string(n);
    fail(path, "unknown " + what + " " + quote(name) + " (expected " + expected + ")");
}

// A file name from the scene: no NUL (the C library would cut the name there) and no longer
// than a path can be.
std::string pathText(const json& value, const std::string& path) {
    std::string s = nonEmptyText(value, path);
    if (s.find('\0') != std::string::npos)
        fail(path, "file name " + quote(s) + " holds a NUL character");
    if (s.size() > 4096) fail(path, "file name " + quote(s) + " is longer than 4096 bytes");
    return s;
}

std::string resolvePath(const std::string& path, const std::string& baseDir) {
    fs::path p(path);
    if (p.is_absolute() || baseDir.empty()) return path;
    return (fs::path(baseDir) / p).string();
}

// ---- sections ----------------------------------------------------------------------------------

Camera readCamera(const json& value, const std::string& path) {
    const json& o = object(value, path);
    checkKeys(o, path, {"type", "eye", "target", "up", "fov", "ortho_height", "width", "height"},
              "camera");
    Camera camera;
    if (const json* v = find(o, "type"))
        camera.type =
            CameraType(oneOf(*v, at(path, "type"), {"perspective", "orthographic"}, "camera type"));
    if (const json* v = find(o, "eye")) camera.eye = vec3(*v, at(path, "eye"));
    if (const json* v = find(o, "target")) camera.target = vec3(*v, at(path, "target"));
    if (const json* v = find(o, "up")) camera.up = unitVector(*v, at(path, "up"));
    if (const json* v = find(o, "fov"))
        camera.fovY = inInterval(*v, at(path, "fov"), 180.f, false, "(0, 180) degrees");
    if (const json* v = find(o, "ortho_height"))
        camera.orthoHeight = positive(*v, at(path, "ortho_height"));
    if (const json* v = find(o, "width")) camera.width = pixels(*v, at(path, "width"));
    if (const json* v = find(o, "height")) camera.height = pixels(*v, at(path, "height"));
    if (Status size = checkCameraSize(path, camera.width, camera.height); !size)
        fail("", size.error);

    glm::dvec3 view = glm::dvec3(camera.target) - glm::dvec3(camera.eye);
    double scale =
        1.0 + glm::length(glm::dvec3(camera.eye)) + glm::length(glm::dvec3(camera.target));
    if (glm::length(view) <= 1e-6 * scale)
        fail(at(path, "target"), "same point as " + at(path, "eye") + " (no view direction)");
    if (parallel(camera.up, glm::vec3(glm::normalize(view))))
        fail(at(path, "up"), "parallel to the view direction (target - eye)");
    return camera;
}

Geometry readObject(const json& value, const std::string& path) {
    const json& o = object(value, path);
    Geometry g;
    if (const json* v = find(o, "type"))
        g.type = GeometryType(
            oneOf(*v, at(path, "type"), {"plane", "sphere", "faceted-sphere"}, "object type"));
    if (g.type == GeometryType::Plane)
        checkKeys(o, path, {"type", "center", "normal", "tangent", "size", "tiling"}, "a plane");
    else if (g.type == GeometryType::Sphere)
        checkKeys(o, path, {"type", "center", "radius", "tiling"}, "a sphere");
    else
        checkKeys(o, path, {"type", "center", "radius", "segments", "rings"}, "a faceted-sphere");
    if (g.type == GeometryType::FacetedSphere) {
        if (const json* v = find(o, "center")) g.center = vec3(*v, at(path, "center"));
        if (const json* v = find(o, "radius")) g.radius = positive(*v, at(path, "radius"));
        if (const json* v = find(o, "segments"))
            g.segments =
                integerIn(*v, at(path, "segments"), kMinSphereSegments, kMaxSphereSegments);
        if (const json* v = find(o, "rings"))
            g.rings = integerIn(*v, at(path, "rings"), kMinSphereRings, kMaxSphereRings);
        return g;
    }

    if (const json* v = find(o, "center")) g.center = vec3(*v, at(path, "center"));
    if (const json* v = find(o, "tiling")) g.tiling = positivePair(*v, at(path, "tiling"));
    if (g.type == GeometryType::Sphere) {
        if (const json* v = find(o, "radius")) g.radius = positive(*v, at(path, "radius"));
        return g;
    }
    if (const json* v = find(o, "normal")) g.normal = unitVector(*v, at(path, "normal"));
    const json* tangent = find(o, "tangent");
    if (tangent) g.tangent = unitVector(*tangent, at(path, "tangent"));
    if (const json* v = find(o, "size")) g.size = positivePair(*v, at(path, "size"));
    // Keep the tangent's direction within the plane, so uv axes are exactly perpendicular.
    glm::dvec3 n = g.normal, t = g.tangent;
    glm::dvec3 inPlane = t - glm::dot(t, n) * n;
    if (glm::length(inPlane) < 1e-4)
        fail(at(path, "tangent"), tangent ? "parallel to " + at(path, "normal")
                                          : "the default [1, 0, 0] is parallel to " +
                                                at(path, "normal") + "; give a tangent across it");
    g.tangent = glm::vec3(glm::normalize(inPlane));
    return g;
}

Light readLight(const json& value, const std::string& path) {
    const json& o = object(value, path);
    Light light;
    if (const json* v = find(o, "type"))
        light.type = LightType(oneOf(*v, at(path, "type"), {"directional", "point"}, "light type"));
    if (light.type == LightType::Directional) {
        checkKeys(o, path, {"type", "direction", "color", "intensity"}, "a directional light");
        if (const json* v = find(o, "direction"))
            light.direction = unitVector(*v, at(path, "direction"));
    } else {
        checkKeys(o, path, {"type", "position", "color", "intensity"}, "a point light");
        if (const json* v = find(o, "position")) light.position = vec3(*v, at(path, "position"));
    }
    glm::vec3 color(1.f);
    float intensity = 1.f;
    if (const json* v = find(o, "color")) color = colour(*v, at(path, "color"));
    if (const json* v = find(o, "intensity")) intensity = nonNegative(*v, at(path, "intensity"));
    light.color = color * intensity;
    return light;
}

// `optional`: the scene has an environment, so no light at all is fine.
std::vector<Light> readLights(const json& value, const std::string& path, bool optional) {
    if (!value.is_array()) fail(path, "expected an array of lights, got " + shown(value));
    if (value.empty() && !optional)
        fail(path, "empty (a scene needs at least one light or an environment)");
    // Every light is shaded at every sample: thousands would only make a render crawl.
    if (value.size() > kMaxLights)
        fail(path, std::to_string(value.size()) + " lights; a scene has at most " +
                       std::to_string(kMaxLights));
    std::vector<Light> lights;
    for (size_t i = 0; i < value.size(); ++i) lights.push_back(readLight(value[i], at(path, i)));
    return lights;
}

// A BRDF table named by `key`, read and checked; its angle must be `angle`.
std::shared_ptr<const TabulatedTransfer> readTable(const json& value, const std::string& path,
                                                   const std::string& baseDir, const char* angle) {
    const std::string file = resolvePath(pathText(value, path), baseDir);
    Result<TabulatedTransfer> table = loadTabulatedTransfer(file);
    if (!table) fail(path, table.error().message);
    if (table->angle != angle)
        fail(path, file + ": a " + table->angle + " table where a " + angle + " table belongs");
    return std::make_shared<const TabulatedTransfer>(std::move(table.value()));
}

Material readMaterial(const json& value, const std::string& path, const std::string& baseDir) {
    const json& o = object(value, path);
    checkKeys(o, path, {"brdf", "exponent", "roughness", "albedo", "specular", "table", "g_table"},
              "material");
    Material m;
    if (const json* v = find(o, "brdf")) {
        std::string name = text(*v, at(path, "brdf"));
        if (!brdfFromString(name, m.brdf))
            fail(at(path, "brdf"), "unknown BRDF " + quote(name) +
                                       " (expected lambert, blinnphong, beckmann, ggx, tabulated)");
    }
    if (const json* v = find(o, "table"))
        m.table = readTable(*v, at(path, "table"), baseDir, "theta_h");
    if (const json* v = find(o, "g_table"))
        m.factor = readTable(*v, at(path, "g_table"), baseDir, "theta_d");
    if (m.brdf == Brdf::Tabulated && !m.table)
        fail(at(path, "table"), "missing (brdf \"tabulated\" needs a theta_h table file)");
    if (m.brdf != Brdf::Tabulated && (m.table || m.factor))
        fail(at(path, m.table ? "table" : "g_table"), "only brdf \"tabulated\" takes tables");
    if (const json* v = find(o, "exponent"))
        m.exponent = inInterval(*v, at(path, "exponent"), 1e6f, true, "(0, 1e6]");
    if (const json* v = find(o, "roughness"))
        m.roughness = inInterval(*v, at(path, "roughness"), 1.f, true, "(0, 1]");
    if (const json* v = find(o, "albedo")) m.albedo = colour(*v, at(path, "albedo"));
    if (const json* v = find(o, "specular")) m.specular = colour(*v, at(path, "specular"));
    return m;
}

// A file reference, a file name or an object with "path" and the `allowed` keys: sets `file`
// (resolved against the scene's folder) and returns the object to read the other keys from,
// or nullptr for a plain name.
const json* readFileRef(const json& value, const std::string& path, const std::string& baseDir,
                        std::initializer_list<std::string_view> allowed, const std::string& what,
                        std::string& file) {
    if (value.is_string()) {
        file = resolvePath(pathText(value, path), baseDir);
        return nullptr;
    }
    if (!value.is_object())
        fail(path, "expected a file name or an object with \"path\", got " + shown(value));
    checkKeys(value, path, allowed, what);
    file = resolvePath(pathText(required(value, path, "path"), at(path, "path")), baseDir);
    return &value;
}

EnvironmentRef readEnvironment(const json& file, const std::string& path,
                               const std::string& baseDir) {
    EnvironmentRef ref;
    const json* object = readFileRef(
        file, path, baseDir, {"path", "intensity", "rotation", "visible"}, "environment", ref.path);
    if (!object) return ref;
    const json& value = *object;
    if (const json* v = find(value, "intensity"))
        ref.options.intensity = positive(*v, at(path, "intensity"));
    if (const json* v = find(value, "rotation")) {
        ref.options.rotationDegrees = number(*v, at(path, "rotation"));
        if (std::fabs(ref.options.rotationDegrees) > 360.f)
            fail(at(path, "rotation"), "must be within -360 .. 360 degrees, got " + shown(*v));
    }
    if (const json* v = find(value, "visible")) ref.visible = flag(*v, at(path, "visible"));
    return ref;
}

NormalMapRef readNormalMap(const json& file, const std::string& path, const std::string& baseDir) {
    NormalMapRef ref;
    const json* object =
        readFileRef(file, path, baseDir,
                    {"path", "green_down", "two_channel", "signed", "height_scale", "address"},
                    "normal_map", ref.path);
    if (!object) return ref;
    const json& value = *object;
    DecodeOptions& d = ref.decode;
    if (const json* v = find(value, "green_down")) d.greenDown = flag(*v, at(path, "green_down"));
    if (const json* v = find(value, "two_channel"))
        d.twoChannel = flag(*v, at(path, "two_channel"));
    if (const json* v = find(value, "signed")) d.signedValues = flag(*v, at(path, "signed"));
    if (const json* v = find(value, "height_scale")) {
        d.height = true;
        d.heightScale = positive(*v, at(path, "height_scale"));
    }
    if (const json* v = find(value, "address"))
        d.address = AddressMode(oneOf(*v, at(path, "address"), {"wrap", "clamp"}, "address mode"));
    return ref;
}

Scene readScene(const json& root, const std::string& baseDir) {
    if (!root.is_object()) fail("", "expected a JSON object at the top level, got " + shown(root));
    checkKeys(root, "",
              {"camera", "object", "lights", "material", "normal_map", "method", "bake",
               "background", "albedo_map", "environment"},
              "a scene");
    Scene scene;
    scene.camera = readCamera(required(root, "", "camera"), "camera");
    scene.geometry = readObject(required(root, "", "object"), "object");
    if (const json* v = find(root, "environment"))
        scene.environment = readEnvironment(*v, "environment", baseDir);
    const bool lit = !scene.environment.path.empty();
    if (const json* v = find(root, "lights"))
        scene.lights = readLights(*v, "lights", lit);
    else if (!lit)
        fail("lights", "missing (a scene needs lights or an environment)");
    if (const json* v = find(root, "material"))
        scene.material = readMaterial(*v, "material", baseDir);
    if (scene.geometry.type == GeometryType::FacetedSphere) {
        // Interpolated vertex normals (interpolated.h): nothing to texture with.
        for (const char* key : {"normal_map", "bake", "albedo_map"})
            if (find(root, key))
                fail(key, "a faceted-sphere scene takes none (its normals are interpolated)");
        scene.method = kGroundTruth;
    } else {
        scene.normalMap = readNormalMap(required(root, "", "normal_map"), "normal_map", baseDir);
    }
    if (const json* v = find(root, "method")) {
        scene.method = nonEmptyText(*v, "method");
        if (scene.method.size() > 64) fail("method", "unknown method " + quote(scene.method));
    }
    if (const json* v = find(root, "bake"))
        scene.bakeDir = resolvePath(pathText(*v, "bake"), baseDir);
    if (const json* v = find(root, "background")) scene.background = colour(*v, "background");
    if (const json* v = find(root, "albedo_map"))
        scene.albedoMap = resolvePath(pathText(*v, "albedo_map"), baseDir);
    return scene;
}

// nlohmann::json keeps the last of two equal keys without a word; a scene that sets "exponent"
// twice is a mistake worth naming. Follows the parse to know the path of each key.
class DuplicateKeys {
  public:
    std::string first; // path of the first key given twice, "" if none

    bool operator()(int, json::parse_event_t event, json& parsed) {
        switch (event) {
        case json::parse_event_t::object_start:
            enterValue();
            stack_.push_back({true, {}, {}, 0});
            break;
        case json::parse_event_t::array_start:
            enterValue();
            stack_.push_back({false, {}, {}, 0});
            break;
        case json::parse_event_t::object_end:
        case json::parse_event_t::array_end:
            stack_.pop_back();
            break;
        case json::parse_event_t::key: {
            Level& level = stack_.back();
            level.key = parsed.get<std::string>();
            if (!level.keys.insert(level.key).second && first.empty()) first = path();
            break;
        }
        case json::parse_event_t::value:
            enterValue();
            break;
        }
        return true;
    }

  private:
    struct Level {
        bool object;
        std::set<std::string> keys;
        std::string key; // object: the key being read
        size_t count;    // array: elements begun so far
    };
    std::vector<Level> stack_;

    void enterValue() {
        if (!stack_.empty() && !stack_.back().object) ++stack_.back().count;
    }

    std::string path() const {
        std::string p;
        for (const Level& level : stack_)
            p = level.object ? at(p, level.key) : at(p, level.count - 1);
        return p;
    }
};

} // namespace

Result<Scene> parseScene(const std::string& jsonText, const std::string& name,
                         const std::string& baseDir) {
    // The parser itself does not recurse, but dumping or copying a value does: refuse deep
    // nesting before anything else sees it.
    if (std::string deep = jsonNestingProblem(jsonText, inputLimits().maxJsonDepth); !deep.empty())
        return Error{oneLine(name + ": invalid JSON (" + deep + ")")};
    json root;
    DuplicateKeys duplicates;
    try {
        root = json::parse(jsonText,
                           [&duplicates](int depth, json::parse_event_t event, json& parsed) {
                               return duplicates(depth, event, parsed);
                           });
    } catch (const json::exception& e) {
        // "[json.exception.parse_error.101] parse error at line 2, column 9: ..." keeps its
        // position; errors without one ("number overflow parsing '1e999'") keep their text.
        std::string what = e.what();
        size_t position = what.find("at line ");
        size_t prefixEnd = what.find("] ");
        std::string detail = position != std::string::npos    ? " " + what.substr(position)
                             : prefixEnd != std::string::npos ? ": " + what.substr(prefixEnd + 2)
                                                              : ": " + what;
        return Error{oneLine(name + ": invalid JSON" + shortened(detail, 200))};
    }
    if (!duplicates.first.empty())
        return Error{oneLine(name + ": " + shortened(duplicates.first, 160) + ": given twice")};
    try {
        return readScene(root, baseDir);
    } catch (const SceneProblem& p) {
        return Error{oneLine(name + ": " + (p.where.empty() ? "" : p.where + ": ") + p.problem)};
    }
}

Result<Scene> loadScene(const std::string& path) {
    Result<std::string> text = readRegularFile(path, inputLimits().maxTextFileBytes);
    if (!text) return text.error();
    Result<Scene> scene = parseScene(text.value(), path, fs::path(path).parent_path().string());
    if (scene) scene->path = path;
    return scene;
}

} // namespace ndfmip
