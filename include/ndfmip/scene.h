// A scene for the reference renderer: one normal-mapped object (a tiled plane or a UV sphere),
// a camera, lights and a material. Read from JSON (docs/SCENES.md has the schema); every field
// that may be left out has the default written here.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "ndfmip/environment.h"
#include "ndfmip/normal_map.h"
#include "ndfmip/result.h"

namespace ndfmip {

// The specular lobe of the material (Lambert: diffuse only; Tabulated: a measured f(theta_h)
// read from a file, sh_brdf.h).
enum class Brdf { Lambert, BlinnPhong, Beckmann, Ggx, Tabulated };

const char* brdfName(Brdf brdf); // "lambert", "blinnphong", "beckmann", "ggx", "tabulated"
bool brdfFromString(const std::string& name, Brdf& out);

struct TabulatedTransfer; // sh_brdf.h

struct Material {
    Brdf brdf = Brdf::BlinnPhong;
    float exponent = 32.f;   // Blinn-Phong s
    float roughness = 0.2f;  // Beckmann / GGX alpha (not perceptual)
    glm::vec3 albedo{0.f};   // diffuse reflectance (Lambertian term, always on)
    glm::vec3 specular{1.f}; // specular colour (scales the lobe)
    // Tabulated: the lobe f(theta_h), and optionally the factor g(theta_d) of a factored
    // measured BRDF f g (Han et al. eq. 6), which multiplies the specular term unfiltered.
    std::shared_ptr<const TabulatedTransfer> table;
    std::shared_ptr<const TabulatedTransfer> factor;
};

enum class CameraType { Perspective, Orthographic };

struct Camera {
    CameraType type = CameraType::Perspective;
    glm::vec3 eye{0.f, -3.f, 1.f};
    glm::vec3 target{0.f, 0.f, 0.f};
    glm::vec3 up{0.f, 0.f, 1.f};
    float fovY = 45.f;             // perspective: vertical field of view, degrees
    float orthoHeight = 2.f;       // orthographic: world-space height of the view
    int width = 512, height = 512; // image size in pixels
};

enum class LightType { Directional, Point };

struct Light {
    LightType type = LightType::Directional;
    glm::vec3 direction{0.f, 0.f, 1.f}; // directional: towards the light (normalised on read)
    glm::vec3 position{0.f, 0.f, 2.f};  // point light position; radiance falls off as 1/d^2
    glm::vec3 color{1.f};               // colour times intensity (irradiance at normal incidence)
};

enum class GeometryType { Plane, Sphere, FacetedSphere };

struct Geometry {
    GeometryType type = GeometryType::Plane;
    // Plane: centred at `center`, spanning size.x along `tangent` and size.y along
    // normal x tangent; uv runs over [0, tiling.x] x [0, tiling.y], v = 0 at the edge the
    // bitangent points to (the top row of the map).
    glm::vec3 center{0.f};
    glm::vec3 normal{0.f, 0.f, 1.f};
    glm::vec3 tangent{1.f, 0.f, 0.f};
    glm::vec2 size{2.f, 2.f};
    // Sphere: radius about `center`; u = azimuth about +z / 2 pi, v = polar angle / pi from +z.
    float radius = 1.f;
    glm::vec2 tiling{1.f, 1.f}; // texture repeats along u and v
    // FacetedSphere: `radius` about `center` as a triangle mesh with interpolated vertex
    // normals and no normal map (interpolated.h).
    int segments = 12; // longitude
    int rings = 6;     // latitude
};

struct NormalMapRef {
    std::string path; // resolved against the scene file's folder
    DecodeOptions decode;
};

// Light from every direction: an equirectangular map (environment.h) about the scene, in the
// frame mapping of environment_lighting.h (world +Z up is the map's top row).
struct EnvironmentRef {
    std::string path;           // resolved against the scene file's folder; empty: no environment
    EnvironmentOptions options; // intensity, rotation about the map's +Y
    bool visible = false;       // rays that miss the object see the map (else the background)
};

struct Scene {
    std::string path; // the file it was read from ("" when built in code)
    Camera camera;
    Geometry geometry;
    std::vector<Light> lights; // may be empty when there is an environment
    EnvironmentRef environment;
    Material material;
    NormalMapRef normalMap;
    std::string method = "toksvig"; // a method name, or "groundtruth"
    std::string bakeDir;            // optional: a bake directory to use instead of baking
    std::string albedoMap;          // optional: diffuse colour map (sRGB-encoded unless EXR)
    glm::vec3 background{0.f};
};

// Reads and checks a scene file. Errors are one line naming the file and the field, e.g.
// "scene.json: material.brdf: unknown BRDF 'foo' (lambert, blinnphong, beckmann, ggx)".
Result<Scene> loadScene(const std::string& path);

// The same from JSON text; `name` starts error messages and `baseDir` resolves relative paths.
Result<Scene> parseScene(const std::string& jsonText, const std::string& name,
                         const std::string& baseDir);

} // namespace ndfmip
