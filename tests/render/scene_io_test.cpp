// Scene files: the bundled examples, defaults, normalisation, paths and one error per mistake.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>

#include <nlohmann/json.hpp>

#include "ndfmip/io.h"
#include "ndfmip/scene.h"
#include "test_support.h"

namespace fs = std::filesystem;
using ndfmip::Scene;
using ndfmip::test::TempDir;
using nlohmann::json;

namespace {

constexpr double kPi = 3.14159265358979323846;

fs::path scenesDir() {
    return fs::path(NDFMIP_SOURCE_DIR) / "scenes";
}

void expectVec(const glm::vec3& v, double x, double y, double z, double tolerance = 1e-6) {
    EXPECT_NEAR(v.x, x, tolerance);
    EXPECT_NEAR(v.y, y, tolerance);
    EXPECT_NEAR(v.z, z, tolerance);
}

void writeText(const std::string& path, const std::string& text) {
    std::ofstream(path, std::ios::binary) << text;
}

// A valid scene every error case below starts from.
json baseScene() {
    return json::parse(R"({
        "camera": {"type": "perspective", "eye": [0, -3, 1], "target": [0, 0, 0],
                   "up": [0, 0, 1], "fov": 45, "width": 32, "height": 24},
        "object": {"type": "plane", "center": [0, 0, 0], "normal": [0, 0, 1],
                   "tangent": [1, 0, 0], "size": [2, 2], "tiling": [1, 1]},
        "lights": [{"type": "directional", "direction": [0, 0, 1]},
                   {"type": "point", "position": [0, 0, 2]}],
        "material": {"brdf": "blinnphong", "exponent": 32, "albedo": 0.1, "specular": 1},
        "normal_map": {"path": "n.png", "green_down": true},
        "method": "toksvig",
        "bake": "n.bake",
        "background": 0
    })");
}

ndfmip::Result<Scene> parse(const json& document, const std::string& baseDir = "/scenes") {
    return ndfmip::parseScene(document.dump(), "scene.json", baseDir);
}

// Where the ray through the centre of pixel (px, py) meets the plane of `scene` (pinhole
// camera: vertical fov, square pixels, row 0 at the top). False when it misses the plane.
bool hitPlane(const Scene& scene, double px, double py, glm::dvec3& hit) {
    const ndfmip::Camera& c = scene.camera;
    glm::dvec3 eye(c.eye), forward = glm::normalize(glm::dvec3(c.target) - eye);
    glm::dvec3 right = glm::normalize(glm::cross(forward, glm::dvec3(c.up)));
    glm::dvec3 up = glm::cross(right, forward);
    double t = std::tan(c.fovY * kPi / 360.0);
    double x = (2.0 * (px + 0.5) / c.width - 1.0) * t * c.width / c.height;
    double y = (1.0 - 2.0 * (py + 0.5) / c.height) * t;
    glm::dvec3 d = forward + x * right + y * up;
    const ndfmip::Geometry& g = scene.geometry;
    glm::dvec3 n(g.normal), tangent(g.tangent), bitangent = glm::cross(n, tangent);
    double denominator = glm::dot(d, n);
    if (denominator >= 0) return false;
    hit = eye + d * (glm::dot(glm::dvec3(g.center) - eye, n) / denominator);
    glm::dvec3 local = hit - glm::dvec3(g.center);
    return std::abs(glm::dot(local, tangent)) <= g.size.x / 2 &&
           std::abs(glm::dot(local, bitangent)) <= g.size.y / 2;
}

} // namespace

// ---- the bundled examples
// ------------------------------------------------------------------------

TEST(SceneExamples, EveryExampleParsesAndItsMapExists) {
    std::set<std::string> names;
    for (const auto& entry : fs::directory_iterator(scenesDir())) {
        if (entry.path().extension() != ".json") continue;
        names.insert(entry.path().filename().string());
        std::string path = entry.path().string();
        auto scene = ndfmip::loadScene(path);
        ASSERT_TRUE(scene) << scene.error().message;
        EXPECT_EQ(scene->path, path);
        EXPECT_TRUE(fs::is_regular_file(scene->normalMap.path))
            << path << ": " << scene->normalMap.path;
    }
    for (const char* expected : {"plane_grazing.json", "sphere.json", "aligned_ortho.json"})
        EXPECT_TRUE(names.count(expected)) << expected;
}

// Every pixel covers an exact 4x4 block of the 256x256 map, rows and columns aligned.
TEST(SceneExamples, AlignedOrthoPixelCoversFourByFourTexels) {
    auto scene = ndfmip::loadScene((scenesDir() / "aligned_ortho.json").string());
    ASSERT_TRUE(scene) << scene.error().message;
    auto map = ndfmip::loadImage(scene->normalMap.path);
    ASSERT_TRUE(map) << map.error().message;
    const ndfmip::Camera& c = scene->camera;
    const ndfmip::Geometry& g = scene->geometry;
    ASSERT_EQ(c.type, ndfmip::CameraType::Orthographic);
    ASSERT_EQ(g.type, ndfmip::GeometryType::Plane);
    double pixel = c.orthoHeight / c.height;
    EXPECT_DOUBLE_EQ(pixel * c.width, g.size.x); // the view is the plane, edge to edge
    EXPECT_DOUBLE_EQ(pixel * c.height, g.size.y);
    EXPECT_DOUBLE_EQ(pixel / (g.size.x / (g.tiling.x * map->image.width)), 4.0);
    EXPECT_DOUBLE_EQ(pixel / (g.size.y / (g.tiling.y * map->image.height)), 4.0);
    // Looking straight down the normal, image up = bitangent (the map's top row), and the
    // view centred on the plane.
    expectVec(glm::normalize(c.eye - c.target), g.normal.x, g.normal.y, g.normal.z);
    glm::vec3 bitangent = glm::cross(g.normal, g.tangent);
    expectVec(c.up, bitangent.x, bitangent.y, bitangent.z);
    expectVec(c.target, g.center.x, g.center.y, g.center.z);
}

// Down the middle column, the pixel footprint (along the view, in texels) runs from at most
// one texel at the bottom row to a whole 256-texel tile near the top: every mip level shows.
TEST(SceneExamples, PlaneGrazingSpansEveryMipLevel) {
    auto scene = ndfmip::loadScene((scenesDir() / "plane_grazing.json").string());
    ASSERT_TRUE(scene) << scene.error().message;
    auto map = ndfmip::loadImage(scene->normalMap.path);
    ASSERT_TRUE(map) << map.error().message;
    const ndfmip::Geometry& g = scene->geometry;
    double texel = g.size.y / (g.tiling.y * map->image.height);
    double column = scene->camera.width / 2;
    double smallest = 1e30, largest = 0;
    for (int row = 0; row + 1 < scene->camera.height; ++row) {
        glm::dvec3 a, b;
        if (!hitPlane(scene.value(), column, row, a) ||
            !hitPlane(scene.value(), column, row + 1, b))
            continue;
        double footprint = glm::length(a - b) / texel;
        smallest = std::min(smallest, footprint);
        largest = std::max(largest, footprint);
    }
    glm::dvec3 bottom;
    EXPECT_TRUE(hitPlane(scene.value(), column, scene->camera.height - 1, bottom));
    EXPECT_LE(smallest, 1.0);
    EXPECT_GE(largest, map->image.height / 2.0); // coarser than the next-to-last level
}

// ---- what a scene holds ------------------------------------------------------------------------

TEST(SceneRead, EnvironmentLightsASceneWithoutLights) {
    auto scene = ndfmip::parseScene(
        R"({"camera": {}, "object": {}, "normal_map": "n.png",
            "environment": {"path": "maps/sky.hdr", "intensity": 2.5, "rotation": -90, "visible": true}})",
        "s", "/scenes");
    ASSERT_TRUE(scene) << scene.error().message;
    EXPECT_TRUE(scene->lights.empty());
    EXPECT_EQ(scene->environment.path, "/scenes/maps/sky.hdr"); // against the scene's folder
    EXPECT_EQ(scene->environment.options.intensity, 2.5f);
    EXPECT_EQ(scene->environment.options.rotationDegrees, -90.f);
    EXPECT_TRUE(scene->environment.visible);
    // A bare file name, beside lights and with an empty light list.
    auto plain = ndfmip::parseScene(
        R"({"camera": {}, "object": {}, "normal_map": "n.png", "lights": [], "environment": "sky.hdr"})",
        "s", "/scenes");
    ASSERT_TRUE(plain) << plain.error().message;
    EXPECT_EQ(plain->environment.path, "/scenes/sky.hdr");
    EXPECT_EQ(plain->environment.options.intensity, 1.f);
    EXPECT_FALSE(plain->environment.visible);
    // Without one, no environment.
    auto none = ndfmip::parseScene(
        R"({"camera": {}, "object": {}, "lights": [{}], "normal_map": "n.png"})", "s", "");
    ASSERT_TRUE(none);
    EXPECT_TRUE(none->environment.path.empty());
}

TEST(SceneRead, DefaultsFillWhatIsLeftOut) {
    auto scene = ndfmip::parseScene(
        R"({"camera": {}, "object": {}, "lights": [{}], "normal_map": "n.png"})", "s", "");
    ASSERT_TRUE(scene) << scene.error().message;
    const Scene expected;
    const ndfmip::Camera camera;
    EXPECT_EQ(scene->camera.type, camera.type);
    EXPECT_EQ(scene->camera.eye, camera.eye);
    EXPECT_EQ(scene->camera.target, camera.target);
    EXPECT_EQ(scene->camera.up, camera.up);
    EXPECT_EQ(scene->camera.fovY, camera.fovY);
    EXPECT_EQ(scene->camera.orthoHeight, camera.orthoHeight);
    EXPECT_EQ(scene->camera.width, camera.width);
    EXPECT_EQ(scene->camera.height, camera.height);
    const ndfmip::Geometry geometry;
    EXPECT_EQ(scene->geometry.type, ndfmip::GeometryType::Plane);
    EXPECT_EQ(scene->geometry.center, geometry.center);
    EXPECT_EQ(scene->geometry.normal, geometry.normal);
    EXPECT_EQ(scene->geometry.tangent, geometry.tangent);
    EXPECT_EQ(scene->geometry.size, geometry.size);
    EXPECT_EQ(scene->geometry.tiling, geometry.tiling);
    ASSERT_EQ(scene->lights.size(), 1u);
    EXPECT_EQ(scene->lights[0].type, ndfmip::LightType::Directional);
    EXPECT_EQ(scene->lights[0].direction, ndfmip::Light{}.direction);
    EXPECT_EQ(scene->lights[0].color, glm::vec3(1.f));
    const ndfmip::Material material;
    EXPECT_EQ(scene->material.brdf, material.brdf);
    EXPECT_EQ(scene->material.exponent, material.exponent);
    EXPECT_EQ(scene->material.roughness, material.roughness);
    EXPECT_EQ(scene->material.albedo, material.albedo);
    EXPECT_EQ(scene->material.specular, material.specular);
    EXPECT_EQ(scene->normalMap.path, "n.png"); // no base folder: left as given
    const ndfmip::DecodeOptions decode;
    EXPECT_EQ(scene->normalMap.decode.greenDown, decode.greenDown);
    EXPECT_EQ(scene->normalMap.decode.twoChannel, decode.twoChannel);
    EXPECT_EQ(scene->normalMap.decode.signedValues, decode.signedValues);
    EXPECT_EQ(scene->normalMap.decode.height, decode.height);
    EXPECT_EQ(scene->normalMap.decode.address, decode.address);
    EXPECT_EQ(scene->method, expected.method);
    EXPECT_EQ(scene->bakeDir, "");
    EXPECT_EQ(scene->background, expected.background);
    EXPECT_EQ(scene->path, ""); // parsed from text, not read from a file
}

TEST(SceneRead, EveryFieldIsRead) {
    auto scene = ndfmip::parseScene(R"({
        "camera": {"type": "orthographic", "eye": [1, 2, 3], "target": [1, 2, 0],
                   "up": [0, 1, 0], "fov": 30, "ortho_height": 4.5, "width": 640, "height": 480},
        "object": {"type": "sphere", "center": [0.5, 0, -1], "radius": 2.5, "tiling": [4, 2]},
        "lights": [{"type": "point", "position": [3, -2, 1]}],
        "material": {"brdf": "ggx", "exponent": 100, "roughness": 0.3,
                     "albedo": [0.1, 0.2, 0.3], "specular": 0.5},
        "normal_map": {"path": "/maps/h.exr", "two_channel": true, "signed": true,
                       "height_scale": 2.5, "address": "clamp"},
        "method": "groundtruth",
        "background": [0.25, 0.5, 1]
    })",
                                    "s", "/base");
    ASSERT_TRUE(scene) << scene.error().message;
    const Scene& s = scene.value();
    EXPECT_EQ(s.camera.type, ndfmip::CameraType::Orthographic);
    expectVec(s.camera.eye, 1, 2, 3);
    expectVec(s.camera.target, 1, 2, 0);
    expectVec(s.camera.up, 0, 1, 0);
    EXPECT_EQ(s.camera.fovY, 30.f);
    EXPECT_EQ(s.camera.orthoHeight, 4.5f);
    EXPECT_EQ(s.camera.width, 640);
    EXPECT_EQ(s.camera.height, 480);
    EXPECT_EQ(s.geometry.type, ndfmip::GeometryType::Sphere);
    expectVec(s.geometry.center, 0.5, 0, -1);
    EXPECT_EQ(s.geometry.radius, 2.5f);
    EXPECT_EQ(s.geometry.tiling, glm::vec2(4.f, 2.f));
    ASSERT_EQ(s.lights.size(), 1u);
    EXPECT_EQ(s.lights[0].type, ndfmip::LightType::Point);
    expectVec(s.lights[0].position, 3, -2, 1);
    EXPECT_EQ(s.material.brdf, ndfmip::Brdf::Ggx);
    EXPECT_EQ(s.material.exponent, 100.f);
    EXPECT_EQ(s.material.roughness, 0.3f);
    expectVec(s.material.albedo, 0.1, 0.2, 0.3);
    expectVec(s.material.specular, 0.5, 0.5, 0.5);
    EXPECT_EQ(s.normalMap.path, "/maps/h.exr");
    EXPECT_FALSE(s.normalMap.decode.greenDown);
    EXPECT_TRUE(s.normalMap.decode.twoChannel);
    EXPECT_TRUE(s.normalMap.decode.signedValues);
    EXPECT_TRUE(s.normalMap.decode.height);
    EXPECT_EQ(s.normalMap.decode.heightScale, 2.5f);
    EXPECT_EQ(s.normalMap.decode.address, ndfmip::AddressMode::Clamp);
    EXPECT_EQ(s.method, "groundtruth");
    expectVec(s.background, 0.25, 0.5, 1);
}

TEST(SceneRead, BrdfNamesRoundTrip) {
    for (ndfmip::Brdf brdf : {ndfmip::Brdf::Lambert, ndfmip::Brdf::BlinnPhong,
                              ndfmip::Brdf::Beckmann, ndfmip::Brdf::Ggx}) {
        ndfmip::Brdf parsed = ndfmip::Brdf::Lambert;
        if (brdf == ndfmip::Brdf::Lambert) parsed = ndfmip::Brdf::Ggx;
        ASSERT_TRUE(ndfmip::brdfFromString(ndfmip::brdfName(brdf), parsed))
            << ndfmip::brdfName(brdf);
        EXPECT_EQ(parsed, brdf);
    }
    EXPECT_STREQ(ndfmip::brdfName(ndfmip::Brdf::BlinnPhong), "blinnphong");
    ndfmip::Brdf parsed = ndfmip::Brdf::Lambert;
    EXPECT_TRUE(ndfmip::brdfFromString("torrance-sparrow", parsed));
    EXPECT_EQ(parsed, ndfmip::Brdf::Beckmann);
    for (const char* wrong : {"phong", "GGX", "", "ggx "}) {
        parsed = ndfmip::Brdf::Lambert;
        EXPECT_FALSE(ndfmip::brdfFromString(wrong, parsed)) << wrong;
        EXPECT_EQ(parsed, ndfmip::Brdf::Lambert) << "unchanged on failure";
    }
}

TEST(SceneRead, VectorsAreNormalisedAndTangentOrthogonalised) {
    json doc = baseScene();
    doc["camera"]["up"] = {0, 0, 5};
    doc["object"]["normal"] = {0, 2, 2};
    doc["object"]["tangent"] = {3, 3, 0};
    doc["lights"][0]["direction"] = {3, 0, 4};
    auto scene = parse(doc);
    ASSERT_TRUE(scene) << scene.error().message;
    expectVec(scene->camera.up, 0, 0, 1);
    const double h = std::sqrt(0.5);
    expectVec(scene->geometry.normal, 0, h, h);
    // t - (t.n) n for t = (1,1,0)/sqrt2, n = (0,1,1)/sqrt2 is (1, 1/2, -1/2)/sqrt2, length
    // sqrt(3/4)
    const double k = 1.0 / std::sqrt(1.5);
    expectVec(scene->geometry.tangent, k, k / 2, -k / 2);
    EXPECT_NEAR(glm::dot(scene->geometry.tangent, scene->geometry.normal), 0.0, 1e-7);
    expectVec(scene->lights[0].direction, 0.6, 0, 0.8);
    expectVec(scene->lights[1].position, 0, 0, 2); // positions are not directions
}

TEST(SceneRead, LightColourIsColourTimesIntensity) {
    json doc = baseScene();
    doc["lights"] = json::parse(R"([
        {"color": [0.5, 1, 2], "intensity": 3},
        {"type": "point", "color": 0.25, "intensity": 4},
        {"intensity": 2.5},
        {"color": [0.1, 0.2, 0.3]},
        {"color": [1, 1, 1], "intensity": 0}
    ])");
    auto scene = parse(doc);
    ASSERT_TRUE(scene) << scene.error().message;
    ASSERT_EQ(scene->lights.size(), 5u);
    expectVec(scene->lights[0].color, 1.5, 3, 6);
    expectVec(scene->lights[1].color, 1, 1, 1);
    expectVec(scene->lights[2].color, 2.5, 2.5, 2.5);
    expectVec(scene->lights[3].color, 0.1, 0.2, 0.3);
    expectVec(scene->lights[4].color, 0, 0, 0);
}

TEST(SceneRead, RelativePathsResolveAgainstTheSceneFolder) {
    json doc = baseScene();
    doc["normal_map"]["path"] = "maps/n.png";
    doc["bake"] = "../bakes/n.bake";
    auto scene = parse(doc, "/data/scenes");
    ASSERT_TRUE(scene) << scene.error().message;
    EXPECT_EQ(fs::path(scene->normalMap.path), fs::path("/data/scenes/maps/n.png"));
    EXPECT_EQ(fs::path(scene->bakeDir), fs::path("/data/scenes/../bakes/n.bake"));

    doc["normal_map"] = "/abs/n.png"; // the plain-string form; absolute stays as it is
    doc["bake"] = "/abs/n.bake";
    scene = parse(doc, "/data/scenes");
    ASSERT_TRUE(scene) << scene.error().message;
    EXPECT_EQ(scene->normalMap.path, "/abs/n.png");
    EXPECT_EQ(scene->bakeDir, "/abs/n.bake");
}

TEST(SceneRead, LoadSceneResolvesAgainstTheFilesFolder) {
    TempDir dir("scene");
    fs::create_directories(dir.path / "scenes");
    json doc = baseScene();
    doc["normal_map"] = "n.png";
    std::string path = (dir.path / "scenes" / "s.json").string();
    writeText(path, doc.dump(2));
    auto scene = ndfmip::loadScene(path);
    ASSERT_TRUE(scene) << scene.error().message;
    EXPECT_EQ(scene->path, path);
    EXPECT_EQ(fs::path(scene->normalMap.path), dir.path / "scenes" / "n.png");
    EXPECT_EQ(fs::path(scene->bakeDir), dir.path / "scenes" / "n.bake");
}

// ---- file-level errors
// ---------------------------------------------------------------------------

TEST(SceneErrors, UnreadableFile) {
    TempDir dir("scene");
    std::string missing = dir.file("none.json");
    auto scene = ndfmip::loadScene(missing);
    ASSERT_FALSE(scene);
    EXPECT_EQ(scene.error().message, missing + ": cannot read: No such file or directory");
    scene = ndfmip::loadScene(dir.path.string());
    ASSERT_FALSE(scene);
    EXPECT_EQ(scene.error().message, dir.path.string() + ": cannot read: is a directory");
}

TEST(SceneErrors, InvalidJsonNamesLineAndColumn) {
    TempDir dir("scene");
    std::string path = dir.file("bad.json");
    writeText(path, "{\n  \"camera\": {},\n  \"object\": {,\n}\n");
    auto scene = ndfmip::loadScene(path);
    ASSERT_FALSE(scene);
    const std::string& m = scene.error().message;
    EXPECT_EQ(m.rfind(path + ": invalid JSON at line 3, column 14: ", 0), 0u) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;

    scene = ndfmip::parseScene("", "empty.json", "");
    ASSERT_FALSE(scene);
    EXPECT_EQ(scene.error().message.rfind("empty.json: invalid JSON at line 1, column 1: ", 0), 0u)
        << scene.error().message;

    scene = ndfmip::parseScene(R"({"background": 1e999})", "big.json", "");
    ASSERT_FALSE(scene);
    EXPECT_EQ(scene.error().message, "big.json: invalid JSON: number overflow parsing '1e999'");
}

TEST(SceneErrors, KeyGivenTwiceIsNamed) {
    json doc = baseScene();
    std::string text = doc.dump();
    auto withDuplicate = [&](const std::string& from, const std::string& to) {
        std::string t = text;
        size_t at = t.find(from);
        EXPECT_NE(at, std::string::npos) << from;
        return t.replace(at, from.size(), to);
    };
    auto scene =
        ndfmip::parseScene(withDuplicate(R"("fov":45)", R"("fov":45,"fov":50)"), "scene.json", "");
    ASSERT_FALSE(scene);
    EXPECT_EQ(scene.error().message, "scene.json: camera.fov: given twice");
    scene = ndfmip::parseScene(
        withDuplicate(R"("position":[0,0,2])", R"("position":[0,0,2],"position":[0,0,3])"),
        "scene.json", "");
    ASSERT_FALSE(scene);
    EXPECT_EQ(scene.error().message, "scene.json: lights[1].position: given twice");
    scene = ndfmip::parseScene(
        withDuplicate(R"("method":"toksvig")", R"("method":"toksvig","method":"naive")"),
        "scene.json", "");
    ASSERT_FALSE(scene);
    EXPECT_EQ(scene.error().message, "scene.json: method: given twice");
}

// ---- one bad field at a time
// ---------------------------------------------------------------------

struct BadScene {
    const char* patch;    // JSON merge patch (RFC 7386) applied to baseScene(); null deletes
    const char* expected; // the error message, or its start when it ends with "..."
};

void PrintTo(const BadScene& c, std::ostream* os) {
    *os << c.patch;
}

class SceneFieldErrors : public testing::TestWithParam<BadScene> {};

TEST(SceneFieldErrorsBase, BaseSceneIsValid) {
    auto scene = parse(baseScene());
    EXPECT_TRUE(scene) << scene.error().message;
}

TEST_P(SceneFieldErrors, MessageNamesTheField) {
    const BadScene& c = GetParam();
    json doc = baseScene();
    doc.merge_patch(json::parse(c.patch));
    auto scene = parse(doc);
    ASSERT_FALSE(scene) << c.patch;
    const std::string& message = scene.error().message;
    std::string expected = c.expected;
    if (expected.size() > 3 && expected.compare(expected.size() - 3, 3, "...") == 0)
        EXPECT_EQ(message.substr(0, expected.size() - 3), expected.substr(0, expected.size() - 3));
    else
        EXPECT_EQ(message, expected);
    EXPECT_EQ(message.find('\n'), std::string::npos);
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, SceneFieldErrors,
    testing::Values(
        // required sections and the document itself
        BadScene{R"({"camera": null})", "scene.json: camera: missing"},
        BadScene{R"({"object": null})", "scene.json: object: missing"},
        BadScene{R"({"lights": null})",
                 "scene.json: lights: missing (a scene needs lights or an environment)"},
        BadScene{R"({"normal_map": null})", "scene.json: normal_map: missing"},
        BadScene{R"([1, 2])", "scene.json: expected a JSON object at the top level, got [1,2]"},
        BadScene{R"({"camera": [1]})", "scene.json: camera: expected an object, got [1]"},
        // unknown keys
        BadScene{R"({"camra": {}})", "scene.json: camra: unknown key (did you mean 'camera'?)"},
        BadScene{R"({"material": {"exponnet": 64}})",
                 "scene.json: material.exponnet: unknown key (did you mean 'exponent'?)"},
        BadScene{R"({"material": {"shininess": 64}})",
                 "scene.json: material.shininess: unknown key (material takes brdf, exponent, "
                 "roughness, albedo, specular, table, g_table)"},
        BadScene{R"({"object": {"radius": 2}})", "scene.json: object.radius: unknown key (..."},
        BadScene{R"({"lights": [{"type": "point", "direction": [0, 0, 1]}]})",
                 "scene.json: lights[0].direction: unknown key (..."},
        BadScene{R"({"normal_map": {"green-down": true}})",
                 "scene.json: normal_map.green-down: unknown key (did you mean 'green_down'?)"},
        // names of things
        BadScene{R"({"material": {"brdf": "foo"}})",
                 "scene.json: material.brdf: unknown BRDF 'foo' (expected lambert, blinnphong, "
                 "beckmann, ggx, tabulated)"},
        BadScene{
            R"({"material": {"brdf": "tabulated"}})",
            "scene.json: material.table: missing (brdf \"tabulated\" needs a theta_h table file)"},
        BadScene{R"({"material": {"brdf": "tabulated", "table": "no_such_table.txt"}})",
                 "scene.json: material.table: ..."},
        BadScene{R"({"material": {"brdf": "ggx", "g_table": "x.txt"}})",
                 "scene.json: material.g_table: ..."},
        BadScene{R"({"camera": {"type": "fisheye"}})",
                 "scene.json: camera.type: unknown camera type 'fisheye' (expected perspective, "
                 "orthographic)"},
        BadScene{R"({"object": {"type": "cube"}})",
                 "scene.json: object.type: unknown object type 'cube' (expected plane, sphere, "
                 "faceted-sphere)"},
        BadScene{R"({"lights": [{}, {"type": "spot"}]})",
                 "scene.json: lights[1].type: unknown light type 'spot' (expected directional, "
                 "point)"},
        BadScene{R"({"normal_map": {"address": "mirror"}})",
                 "scene.json: normal_map.address: unknown address mode 'mirror' (expected wrap, "
                 "clamp)"},
        // wrong types
        BadScene{R"({"camera": {"width": "abc"}})",
                 R"(scene.json: camera.width: expected a positive integer, got "abc")"},
        BadScene{R"({"camera": {"eye": [1, 2]}})",
                 "scene.json: camera.eye: expected an array of 3 numbers, got [1,2]"},
        BadScene{R"({"camera": {"eye": ["a", 0, 0]}})",
                 R"(scene.json: camera.eye[0]: expected a number, got "a")"},
        BadScene{R"({"camera": {"fov": true}})",
                 "scene.json: camera.fov: expected a number, got true"},
        BadScene{R"({"camera": {"type": 1}})", "scene.json: camera.type: expected a string, got 1"},
        BadScene{R"({"object": {"size": [1]}})",
                 "scene.json: object.size: expected an array of 2 numbers, got [1]"},
        BadScene{R"({"lights": []})",
                 "scene.json: lights: empty (a scene needs at least one light or an environment)"},
        BadScene{
            R"({"environment": 3})",
            R"(scene.json: environment: expected a file name or an object with "path", got 3)"},
        BadScene{R"({"environment": {"intensity": 2}})", "scene.json: environment.path: missing"},
        BadScene{R"({"environment": {"path": "e.hdr", "intensity": 0}})",
                 "scene.json: environment.intensity: must be > 0, got 0"},
        BadScene{R"({"environment": {"path": "e.hdr", "rotation": 400}})",
                 "scene.json: environment.rotation: must be within -360 .. 360 degrees, got 400"},
        BadScene{R"({"environment": {"path": "e.hdr", "visible": 1}})",
                 "scene.json: environment.visible: expected true or false, got 1"},
        BadScene{R"({"environment": {"path": "e.hdr", "rotaton": 1}})",
                 "scene.json: environment.rotaton: unknown key (did you mean 'rotation'?)"},
        BadScene{R"({"lights": {"type": "point"}})",
                 R"(scene.json: lights: expected an array of lights, got {"type":"point"})"},
        BadScene{R"({"lights": [3]})", "scene.json: lights[0]: expected an object, got 3"},
        BadScene{R"({"normal_map": 5})",
                 R"(scene.json: normal_map: expected a file name or an object with "path", got 5)"},
        BadScene{R"({"normal_map": {"path": null}})", "scene.json: normal_map.path: missing"},
        BadScene{R"({"normal_map": {"path": ""}})", "scene.json: normal_map.path: empty"},
        BadScene{R"({"normal_map": {"green_down": "yes"}})",
                 R"(scene.json: normal_map.green_down: expected true or false, got "yes")"},
        BadScene{R"({"method": 3})", "scene.json: method: expected a string, got 3"},
        BadScene{R"({"bake": ""})", "scene.json: bake: empty"},
        BadScene{R"({"background": [1, 1]})",
                 "scene.json: background: expected a colour ([r, g, b] or one number), got [1,1]"},
        BadScene{R"({"camera": {"eye": [1e39, 0, 0]}})",
                 "scene.json: camera.eye[0]: out of range (a float holds up to 3.4e38), got ..."},
        // ranges
        BadScene{R"({"camera": {"width": 0}})",
                 "scene.json: camera.width: expected a positive integer, got 0"},
        BadScene{R"({"camera": {"height": 12.5}})",
                 "scene.json: camera.height: expected a positive integer, got 12.5"},
        BadScene{R"({"camera": {"width": 16385}})",
                 "scene.json: camera.width: must be at most 16384, got 16385"},
        BadScene{R"({"camera": {"fov": 180}})",
                 "scene.json: camera.fov: must be in (0, 180) degrees, got 180"},
        BadScene{R"({"camera": {"fov": 0}})",
                 "scene.json: camera.fov: must be in (0, 180) degrees, got 0"},
        BadScene{R"({"camera": {"ortho_height": -1}})",
                 "scene.json: camera.ortho_height: must be > 0, got -1"},
        BadScene{R"({"object": {"type": "sphere", "normal": null, "tangent": null, "size": null,
                                "radius": 0}})",
                 "scene.json: object.radius: must be > 0, got 0"},
        BadScene{R"({"object": {"size": [1, 0]}})",
                 "scene.json: object.size[1]: must be > 0, got 0"},
        BadScene{R"({"object": {"tiling": [-1, 1]}})",
                 "scene.json: object.tiling[0]: must be > 0, got -1"},
        BadScene{R"({"material": {"exponent": 0}})",
                 "scene.json: material.exponent: must be in (0, 1e6], got 0"},
        BadScene{R"({"material": {"exponent": 1000001}})",
                 "scene.json: material.exponent: must be in (0, 1e6], got 1000001"},
        BadScene{R"({"material": {"roughness": 1.5}})",
                 "scene.json: material.roughness: must be in (0, 1], got 1.5"},
        BadScene{R"({"material": {"albedo": [0.1, -0.5, 0]}})",
                 "scene.json: material.albedo[1]: must be >= 0, got -0.5"},
        BadScene{R"({"material": {"specular": -1}})",
                 "scene.json: material.specular: must be >= 0, got -1"},
        BadScene{R"({"lights": [{"color": [1, 1, -1]}]})",
                 "scene.json: lights[0].color[2]: must be >= 0, got -1"},
        BadScene{R"({"lights": [{"intensity": -2}]})",
                 "scene.json: lights[0].intensity: must be >= 0, got -2"},
        BadScene{R"({"background": -0.5})", "scene.json: background: must be >= 0, got -0.5"},
        BadScene{R"({"normal_map": {"height_scale": 0}})",
                 "scene.json: normal_map.height_scale: must be > 0, got 0"},
        // geometry that gives no frame
        BadScene{R"({"lights": [{"direction": [0, 0, 0]}]})",
                 "scene.json: lights[0].direction: zero-length vector"},
        BadScene{R"({"object": {"normal": [0, 0, 0]}})",
                 "scene.json: object.normal: zero-length vector"},
        BadScene{R"({"object": {"tangent": [0, 0, 0]}})",
                 "scene.json: object.tangent: zero-length vector"},
        BadScene{R"({"object": {"tangent": [0, 0, -2]}})",
                 "scene.json: object.tangent: parallel to object.normal"},
        BadScene{R"({"object": {"normal": [1, 0, 0], "tangent": null}})",
                 "scene.json: object.tangent: the default [1, 0, 0] is parallel to object.normal; "
                 "give a tangent across it"},
        BadScene{R"({"camera": {"eye": [1, 2, 3], "target": [1, 2, 3]}})",
                 "scene.json: camera.target: same point as camera.eye (no view direction)"},
        BadScene{R"({"camera": {"up": [0, 3, -1]}})",
                 "scene.json: camera.up: parallel to the view direction (target - eye)"},
        BadScene{R"({"camera": {"up": [0, 0, 0]}})", "scene.json: camera.up: zero-length vector"}));
