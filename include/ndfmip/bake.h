// A method turns a normal map's pyramid into per-level parameter images ("planes") that a
// shader samples. Every method is a bake function plus shade functions (in its own header);
// this header holds the data they share and the bake directory on disk.
#pragma once

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "ndfmip/image.h"
#include "ndfmip/normal_map.h"
#include "ndfmip/pyramid.h"
#include "ndfmip/result.h"
#include "ndfmip/texture_container.h"

namespace ndfmip {

struct EnginePreset; // engine_presets.h

enum class Method {
    Naive,    // standard mipmap: mean normal, renormalised
    Toksvig,  // mean normal kept unnormalised; |Na| widens the lobe
    Sh,       // spherical-harmonic coefficients of the NDF (Han et al. Sec. 5)
    Vmf,      // mixtures of von Mises-Fisher lobes fitted by spherical EM (Han et al. Sec. 7)
    Lean,     // slope moments: one anisotropic Beckmann lobe (Olano and Baker 2010)
    GgxFit,   // one GGX lobe per texel, its roughness fitted to the filtered NDF
    GgxAniso, // one anisotropic GGX lobe per texel, fitted to the filtered NDF
};

std::optional<Method> methodFromString(std::string_view name);
const char* methodName(Method method);
std::vector<Method> allMethods();
std::string methodNames();     // "naive, toksvig, sh, vmf, lean"
std::string methodSummaries(); // one "name: what it stores" line per method

// One parameter image per level: its name, what each channel means, and whether it may be
// interpolated linearly (trilinear filtering) before shading.
struct PlaneInfo {
    std::string name;                  // file stem: <name>_L<level>.exr
    std::vector<std::string> channels; // meaning of each channel, e.g. "Na.x"
    std::string description;
    bool linear = true;
};

// Index of the plane called `name`, or -1.
int findPlane(const std::vector<PlaneInfo>& planes, const std::string& name);

// A method's own options by key, as its parameter table (method_parameters.h) names them:
// sh's "order", vmf's "lobes", "coherent" ... A key not given takes the table's default.
using ParameterValues = std::map<std::string, double>;

struct BakeOptions {
    ParameterValues parameters; // the method's own options (method_parameters.h)
    float baseRoughness = 0.f;  // alpha of the material before filtering (roughness planes)
    // toksvig: the material's own alpha per texel (one channel, level-0 sized), in place of
    // baseRoughness: level k's roughness is sqrt(mean alpha0^2 + c sigma^2) over the texel's
    // footprint (variances add: the material's lobe widths and the normals' spread).
    SharedImage roughnessMap;
    SharedImage albedo; // vmf: colour per lobe (H eq. 31) from this map, level-0 sized
    // Called after each level is done: (levels done, levels in all).
    std::function<void(int, int)> progress;
};

struct Bake {
    Method method = Method::Naive;
    std::vector<PlaneInfo> planes;
    std::vector<std::vector<SharedImage>> levels; // levels[k][p]: plane p at level k
    std::map<std::string, double> parameters;
};

Bake bakeNaive(const Pyramid& pyramid, const BakeOptions& options);
Bake bakeToksvig(const Pyramid& pyramid, const BakeOptions& options);
Bake bakeSh(const Pyramid& pyramid, const BakeOptions& options);
Bake bakeVmf(const Pyramid& pyramid, const BakeOptions& options);
Bake bakeLean(const Pyramid& pyramid, const BakeOptions& options);
Bake bakeGgxFit(const Pyramid& pyramid, const BakeOptions& options);
Bake bakeGgxAniso(const Pyramid& pyramid, const BakeOptions& options);

// lean: normals are clamped to n.z >= this before their slopes n.xy/n.z are taken (84 degrees;
// steeper normals would give unbounded slopes).
constexpr float kLeanMinZ = 0.1f;
Bake bakeMethod(Method method, const Pyramid& pyramid, const BakeOptions& options);

// Planes of an sh bake of order l*: four coefficients each, ceil((l*+1)^2 / 4).
int shPlaneCount(int order);

// The order l* of an sh bake (its "order" parameter), 0 for other methods.
int bakeShOrder(const Bake& bake);

// Whether `method`'s bake is fitted to the material's own roughness (BakeOptions::baseRoughness,
// ggx-fit): it holds for that roughness only.
bool bakeFitsMaterialRoughness(Method method);
constexpr float kMinFittedRoughness = 0.01f; // the least material alpha such a bake takes

// The lobe count J of a vmf bake (its "lobes" parameter), 0 for other methods.
int bakeVmfLobes(const Bake& bake);

// Where a bake came from, recorded in its manifest.
struct BakeSource {
    std::string path;
    std::string sha256;
    int width = 0, height = 0;
    DecodeOptions decode;
    std::string gloss; // gloss map path, if one shortened the normals
    // What the bake was made from and how (the sources' SHA-256s, the options, the version), as
    // one SHA-256: a later bake with the same key would write the same files, so it may skip.
    // Written as the manifest's "cache_key" when set.
    std::string cacheKey;
};

struct BakeWriteOptions {
    // The planes as float EXRs, one per plane per level: the bake that render, inspect and eval
    // read. Without them the folder holds only the exports below, and its manifest says
    // "storage": "none" (readers then refuse it with that reason).
    bool exr = true;
    // Engine-ready 16-bit PNG mips in DIR/png16: normal_L<k>.png (unit normal, encoded
    // c = (n+1)/2 in the source's green convention) and, where the method has roughness,
    // roughness_L<k>.png (perceptual GGX roughness, sqrt(alpha)).
    bool png16 = false;
    // Engine texture files with every level in DIR/ktx2 and DIR/dds (DX10 header):
    // normal_<format> (the unit normal's xy encoded (n+1)/2, green as the source) where the
    // method stores a normal, roughness_<format> (perceptual GGX roughness) where it has
    // roughness, and <plane> for each linear plane (RGBA32F, or RGBA16F with `half`): SH
    // coefficients, vMF lobes, mean normals, slope moments.
    bool ktx2 = false;
    bool dds = false;
    // Which of those the exports hold (png16 has no planes).
    bool exportNormal = true, exportRoughness = true, exportPlanes = true;
    // The normal's format (bc5, rg16 or rgba8: xyz, alpha 1) and the roughness's (bc4 or r16f).
    TextureFormat normalFormat = TextureFormat::Bc5Unorm;
    TextureFormat roughnessFormat = TextureFormat::Bc4Unorm;
    // KTX2 Zstandard supercompression level, 1-22 (0: none).
    int zstdLevel = 0;
    // An engine preset (engine_presets.h; null: none): the ktx2/dds files also get the engine's
    // BC5 normal map (its green convention) and its packed material map (RGBA8: roughness or
    // smoothness, metallic, occlusion in its channels), named <engine>_<file>.
    const EnginePreset* engine = nullptr;
    // A lean bake's engine files (one anisotropic lobe per texel, each engine's inputs): the
    // material's alpha, the same at every texel, whose alpha^2 the slopes' variance widens per
    // axis.
    float baseRoughness = 0.f;
    // Per level, one channel each, for the packed map (empty: metallic 0, occlusion 1).
    std::vector<SharedImage> metallic, occlusion;
    // Planes stored as 16-bit half floats instead of 32-bit floats (half the disk; ~3 decimal
    // digits, enough for SH coefficients and mean normals).
    bool half = false;
};

// Writes DIR/manifest.json and DIR/<plane>_L<k>.exr (float). The whole folder is staged beside
// DIR (DIR.partial-PID) and swapped into place at the end, atomically where the file system
// allows (renameat2 RENAME_EXCHANGE): a failure or a kill at any instant leaves either the
// complete earlier bake or the complete new one. An existing DIR is replaced only if it holds an
// earlier bake and nothing else (or nothing). Leftovers of killed runs beside DIR (staging and
// set-aside folders whose process is gone) are cleaned up first, and a DIR that a kill left
// missing is restored from its set-aside copy.
Status writeBake(const std::string& dir, const Bake& bake, const BakeSource& source,
                 const BakeWriteOptions& options = {});

// Cleans up beside DIR after killed bakes, as writeBake does first: removes DIR.partial-PID and
// DIR.old-PID folders whose process is gone, restoring a missing DIR from the newest
// DIR.old-PID. Commands call it before they start, so a run that then fails still cleans up.
void recoverInterruptedBake(const std::string& dir);

// A bake read back: the manifest's facts and, for one level, the plane images. Everything in it
// has been checked (parseBakeManifest, then each image against its level's size and plane).
struct LoadedBake {
    Method method = Method::Naive;
    std::vector<PlaneInfo> planes;
    std::vector<std::pair<int, int>> levelSizes;      // the GPU mip chain of the source's size
    std::vector<std::vector<std::string>> levelFiles; // [level][plane]: plain names in DIR
    std::map<std::string, double> parameters;
    BakeSource source;
    std::string storage = "float";    // "float", "half", or "none" (exports only, no planes)
    std::vector<std::string> exports; // png16/, ktx2/ and dds/<name> files
    std::vector<Image> level;         // planes of the requested level
};

// The manifest's facts (no images), checked: method, parameters in range (those the method's
// table records: sh order 1 .. kMaxShOrder, vmf lobes 1 .. kMaxVmfBakeLobes), exactly the
// method's planes, the source size within the input
// limits, one level per step of the GPU mip rule with its size, and level files that are plain
// names inside the folder. Errors are one line starting with `name`, naming the key.
Result<LoadedBake> parseBakeManifest(const std::string& json, const std::string& name);

// The manifest and the plane images of one level; each image must be a regular file with the
// level's size, the plane's channel count and finite values.
Result<LoadedBake> readBake(const std::string& dir, int level);

// One texel (x, y) of `level` of a bake read by readBake at that level, as compact JSON text:
// method, level, texel, its level-0 footprint and the method's own keys (docs/METHODS.md; with
// `exponent`, Toksvig's factor for that Blinn-Phong exponent). Errors start with `name`.
Result<std::string> inspectTexel(const LoadedBake& bake, const std::string& name, int level, int x,
                                 int y, std::optional<float> exponent = std::nullopt);

// The normal a level-0 texel of `method`'s bake stands for, from its planes' values in order
// (LoadedBake::level's planes, each texel's channels one after another); not normalised.
glm::vec3 bakeLevelZeroNormal(Method method, const float* planes);

// The NDF a texel (x, y) of a bake's loaded level stores, as a density over the sphere (integrating
// to 1) in direction w: the SH series (sh), the vMF mixture (vmf); nullopt for the methods that
// store no NDF of their own (naive, toksvig, lean).
std::optional<double> bakeNdfDensity(const LoadedBake& bake, int x, int y, glm::dvec3 w);

// Every level of a bake, back in memory, with the same checks; refused before loading when the
// planes of every level together would exceed the input limits' memory.
Result<Bake> loadBake(const std::string& dir);

} // namespace ndfmip
