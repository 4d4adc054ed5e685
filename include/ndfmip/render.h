// The reference CPU renderer. It draws a scene's normal-mapped object either as a GPU would
// with a baked method (ray-differential footprint -> mip LOD -> trilinear filtering of the
// method's linear planes -> the method's shade function), or as the ground truth (many
// stratified samples per pixel, each shaded with the finest normal under it).
// Shading happens in the surface's tangent frame with tangent-space normals.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "ndfmip/bake.h"
#include "ndfmip/environment_sh_shading.h"
#include "ndfmip/environment_splitsum.h"
#include "ndfmip/roughness.h"
#include "ndfmip/scene.h"

namespace ndfmip {

constexpr const char* kGroundTruth = "groundtruth";
// The representation-perfect reference: every texel a lookup reads is shaded as the exact mean
// of the BRDF over all the level-0 normals it covers, then the texels are blended with the
// lookup's weights. What any method that stores an NDF per texel could at best reach through
// the same filtering; needs constant light and view directions (an orthographic view of a
// plane under directional lights), where that mean is a linear mip chain of shaded normals.
constexpr const char* kExact = "exact";
// Toksvig's own way to shade: the toksvig bake looked up through the 2D table of T eq. 9,
// indexed by (Na.H, Na.Na), with the 8-bit phase-out of T eqs. 10-11. Blinn-Phong only.
constexpr const char* kToksvigLut = "toksvig-lut";
// An engine's usual inputs, from any tool: the standard normal mipmap (a naive bake) with a mip
// chain of roughness (RenderTextures::roughness: perceptual p, alpha = p^2, or alpha itself),
// filtered as stored and shaded with the material's Beckmann or GGX lobe at that alpha per
// lookup. What a peer's roughness mips are judged by.
constexpr const char* kRoughnessMips = "roughness-mips";
constexpr int kToksvigLutSize = 256; // table side, as the paper's
constexpr int kToksvigLutBits = 8;   // bits of the normals whose |Na| the phase-out allows for

// Every name render() takes, for messages: "groundtruth, exact, naive, toksvig, ...".
std::string renderMethodNames();

// The shaders (render methods that read a bake), in the method table's order: naive, toksvig,
// toksvig-lut, roughness-mips, sh, vmf, lean, ...
std::vector<std::string> shaderNames();

// The bake a shader reads (toksvig-lut: toksvig's; roughness-mips: naive's); nullopt for a name
// that is no shader (groundtruth, exact, a typo).
std::optional<Method> shaderBake(const std::string& shader);

// The ground truth's finest normals. Box: each texel's normal over its whole square, the
// surface the mip pyramid averages (so a level-k texel's NDF is exactly its footprint's
// normals). Bilinear: the bilinearly interpolated, renormalised surface a magnified view shows.
enum class TruthFilter { Box, Bilinear };
constexpr int kBilinearCells = 4;                // RenderOptions::exact on the bilinear surface
const char* truthFilterName(TruthFilter filter); // "box", "bilinear"
bool truthFilterFromString(const std::string& name, TruthFilter& out);

// What a method does with the texels a lookup reads. Parameter: blends their parameters, then
// shades once (what a GPU's texture sampler gives a shader). Texel: shades each texel's own
// parameters and blends the results, which is exact for a mixture NDF (shading is linear in
// the NDF) at the cost of one shade per texel read (8 for trilinear).
enum class ShadeFilter { Parameter, Texel };
const char* shadeFilterName(ShadeFilter filter); // "parameter", "texel"
bool shadeFilterFromString(const std::string& name, ShadeFilter& out);

// The ground truth under an environment: each pixel sample's estimate of the reflected light
// (docs/RENDERING.md). Mis: one environment sample and one BRDF sample weighted by the power
// heuristic; Light, Brdf: either sampler alone (unbiased too, noisier; for checks).
enum class EnvironmentEstimator { Mis, Light, Brdf };

// Where the view fixes every direction but the normal's (an orthographic camera over a plane, its
// image rows along the texel grid, directional lights, no albedo map), the ground truth under an
// environment may be tabulated: the light reflected at each normal estimated once per node of a
// grid over the normals (spp estimates each) and each pixel integrated over its texels as
// without an environment, its noise the nodes' alone (docs/RENDERING.md). Sampled: spp samples
// per pixel, each at a random point of it.
enum class EnvironmentTruth { Sampled, Table };
const char* environmentTruthName(EnvironmentTruth truth); // "sampled", "table"

// How vmf shades under an environment: the engine way (each lobe's equivalent roughness read from
// prefiltered levels, environment_splitsum.h) or the paper's (lobes against SH lighting, Han et al.
// eqs. 34-37, environment_sh_shading.h).
enum class EnvironmentWay { Prefiltered, ShLighting };
const char* environmentWayName(EnvironmentWay way); // "prefiltered", "sh"
bool environmentWayFromString(const std::string& name, EnvironmentWay& out);

// An engine's geometric specular anti-aliasing (Kaplanyan 2016; Tokuyoshi and Kaplanyan 2019):
// the shading normal's change to the next pixel across and down (du, dv) is taken as a spread of
// normals inside the pixel, and its variance is added to the lobe's squared roughness:
//   alpha'^2 = alpha^2 + min(2 variance (|du|^2 + |dv|^2), threshold).
// Filament's `specularAntiAliasingVariance` / `Threshold` (defaults 0.15 / 0.2) and HDRP's
// Geometric Specular AA (Screen Space Variance / Threshold) shade so (Babylon.js's
// enableSpecularAntiAliasing is a variant of the idea). variance 0: off.
struct SpecularAntiAliasing {
    float variance = 0.f;
    float threshold = 0.2f;
};
// The squared roughness the rule adds, from the normal's differences to the next pixels.
float specularAntiAliasingKernel(const SpecularAntiAliasing& aa, glm::vec3 du, glm::vec3 dv);

struct RenderOptions {
    int spp = 1;       // samples per pixel, stratified and jittered (box filter); 1 = pixel centre
    uint64_t seed = 1; // jitter seed: the same seed gives the same image on any thread count
    TruthFilter truth = TruthFilter::Box; // ground truth: which surface the finest normals form
    // Ground truth: where the view allows it (orthographic, looking straight down on a plane
    // whose texel grid runs along the image axes, directional lights only), integrate each pixel
    // without samples: the box surface exactly, texel by texel with its covered area; the
    // bilinear surface by a midpoint rule on kBilinearCells x kBilinearCells cells per texel.
    // No noise, and spp is then unused.
    bool exact = true;
    int anisotropy =
        1; // methods: up to this many trilinear probes along the footprint's major axis
    // Methods: the filtering rule. Each pixel sample becomes taps x taps sub-samples on a regular
    // grid over the pixel, each looked up with a taps-times smaller footprint (so one level finer
    // per doubling) plus lodBias levels, shaded, and averaged. The default (2 x 2 sub-samples,
    // half a level finer, each texel shaded) measured best on real maps for every method
    // (docs/RESULTS.md); taps = 1, lodBias = 0, Parameter is a GPU's plain trilinear lookup.
    int taps = 2;
    float lodBias = -0.5f;
    ShadeFilter shadeFilter = ShadeFilter::Texel;
    glm::vec2 pixelShift{0.f}; // sub-pixel shift of the whole image (frames of a flicker test)
    RoughnessMapping roughnessMapping = RoughnessMapping::Ours; // toksvig with Beckmann/GGX
    float varianceScale = kVarianceScale;                       // c of the Ours mapping
    std::function<void(int, int)> progress; // (rows done, rows in all), from one thread
    // Ground truth under an environment: estimates (each one environment + one BRDF sample) per
    // pixel sample, and how they are made.
    int environmentSamples = 1;
    // Methods under an environment: the level rule of the prefiltered shading (naive, toksvig,
    // roughness-mips, vmf the engine way) and how vmf shades (sh always uses SH lighting).
    EnvironmentLod environmentLod = EnvironmentLod::Filament;
    EnvironmentWay vmfEnvironment = EnvironmentWay::Prefiltered;
    // SH lighting (sh, vmf with EnvironmentWay::ShLighting): 0 prepares it for the one view at the
    // image centre; N > 0 prepares the paper's sparse set of at least N views (the smallest
    // octahedral grid with N or more, environment_sh_views.h) and each pixel reads the lighting
    // interpolated at its own view. At most kMaxShViews (1026); CPU only.
    int shViews = 0;
    // SH lighting's specular cosine (environment_sh_shading.h): the normals' that reflect.
    SpecularCosine shCosine = SpecularCosine::Reflecting;
    // SH lighting's order (and the vmf lobes' transfer's): the paper's l* = 8 (Sec. 8). At most
    // kMaxShOrder (30) on the CPU, 10 on the GPU; the sh method reads min(its bake's, this).
    int environmentShOrder = 8;
    // The split-sum rows (naive, toksvig, roughness-mips, vmf the engine way, ggx-fit, ggx-aniso)
    // read the prefiltered radiance along the lobe's dominant direction (SplitSumOptions::
    // dominantDirection); false reads along the mirror direction.
    bool dominantDirection = true;
    // Methods with one GGX or Beckmann lobe an engine shades (naive, roughness-mips, ggx-fit,
    // ggx-aniso): the engine's specular anti-aliasing, from the normal filtered at the next pixel
    // across and down (two more lookups of the normal plane).
    SpecularAntiAliasing specularAntiAliasing;
    EnvironmentEstimator environmentEstimator = EnvironmentEstimator::Mis;
    EnvironmentTruth environmentTruth = EnvironmentTruth::Sampled; // spp: per node with Table
};

struct EnvironmentLighting; // environment_lighting.h

// What the renderer samples: the level-0 unit normals (ground truth) and, for a method, its
// bake (every level). `bake.levels` is empty when only the ground truth is rendered.
struct RenderTextures {
    SharedImage normals;
    Bake bake;
    // Optional albedo map (linear RGB, level-0 size) and its mip chain (albedoMips), which
    // multiply the material's albedo: the truth samples level 0 per sample, methods filter the
    // chain trilinearly, and vmf bakes with colour planes use their lobes' colours instead.
    std::vector<SharedImage> albedo;
    // kRoughnessMips: roughness, one channel, one image per level of the bake (the same sizes),
    // filtered like the other planes; perceptual (alpha = value^2) unless roughnessIsAlpha.
    std::vector<SharedImage> roughness;
    bool roughnessIsAlpha = false;
    // The scene's environment, loaded (null without one): lights the truth and the methods.
    std::shared_ptr<const EnvironmentLighting> environment;
};

// The albedo's mips, averaged with the normal map's pyramid footprints (linear, like Na).
std::vector<SharedImage> albedoMips(const Pyramid& pyramid, SharedImage albedo);

// An albedo (colour) map file as linear RGB, 3 channels: 8/16-bit files are sRGB-decoded, EXR is
// taken as linear. An error unless it has `width` x `height` texels, 3 or 4 channels and finite
// values.
Result<SharedImage> loadAlbedo(const std::string& path, int width, int height);

// How `ndfmip render` gets a scene's textures for `method` (a name render() takes).
struct SceneTextureOptions {
    std::string bakeDir; // a bake folder to draw; empty: the scene's, or else baked on the fly
    ParameterValues bakeParameters; // the method's own options for a bake made on the fly
    std::function<void(const DecodeReport&)> decoded; // once the normal map is decoded (warnings)
};

// The scene's normal map (decoded as the scene says), its albedo map and mips, and for a method
// its bake: read from the bake folder, or baked with `options` within the memory limit.
Result<RenderTextures> loadSceneTextures(const Scene& scene, const std::string& method,
                                         const SceneTextureOptions& options);

// RenderOptions within the ranges the command line allows (spp, anisotropy, taps, LOD bias, the
// variance scale); the first problem as one line naming the option.
Status checkRenderOptions(const RenderOptions& options);

// Renders `scene` with `method` (a method name, kToksvigLut, kExact or kGroundTruth); RGB
// radiance, 3 channels. Errors: unknown method, a bake of another method or size, a view that
// kExact cannot handle.
Result<Image> render(const Scene& scene, const RenderTextures& textures, const std::string& method,
                     const RenderOptions& options);

// How noisy a render is (any sampled render; the truth under an environment is the one that
// needs it). Each pixel's standard error is that of its stratified mean of per-sample luminance
// estimates, from the differences of paired neighbouring strata (the spread between strata,
// which the stratification removes, is not counted; a slight upper bound).
struct RenderNoise {
    Image standardError;               // 1 channel, the image's size (0 where nothing was sampled)
    double relativeStandardError = 0.; // mean standard error / mean luminance over covered pixels
    size_t coveredPixels = 0;          // pixels where some sample saw the object's front
};

// render() that also measures its noise into `noise` (when not null).
Result<Image> render(const Scene& scene, const RenderTextures& textures, const std::string& method,
                     const RenderOptions& options, RenderNoise* noise);

// ---- Pieces, exposed for tests and for the evaluation ---------------------------------------

struct Ray {
    glm::vec3 origin, direction;
};

// A camera's basis and projection constants, computed once per image.
struct CameraFrame {
    CameraType type = CameraType::Perspective;
    glm::vec3 eye{0.f}, forward{0.f, 0.f, -1.f}, right{1.f, 0.f, 0.f}, up{0.f, 1.f, 0.f};
    float halfWidth = 1.f,
          halfHeight = 1.f; // of the image plane: at distance 1 (perspective) or in world units
    float width = 1.f, height = 1.f; // pixels
};
CameraFrame cameraFrame(const Camera& camera);

// The ray through image position (px, py), in pixels from the top-left corner.
Ray cameraRay(const CameraFrame& frame, float px, float py);
inline Ray cameraRay(const Camera& camera, float px, float py) {
    return cameraRay(cameraFrame(camera), px, py);
}

struct SurfaceHit {
    bool hit = false;
    float t = 0.f;
    glm::vec3 position{0.f};
    glm::vec2 uv{0.f};                  // texture coordinates (tiling applied): 1 = one map
    glm::vec3 tangent{1.f, 0.f, 0.f};   // unit frame: +x of the normal map (towards +u)
    glm::vec3 bitangent{0.f, 1.f, 0.f}; // +y of the normal map (towards the top row, -v)
    glm::vec3 normal{0.f, 0.f, 1.f};
    glm::vec3 dpdu{0.f}, dpdv{0.f}; // position derivatives along uv
};

SurfaceHit intersect(const Geometry& geometry, const Ray& ray);

// Derivatives of uv with respect to the image x and y (ray differentials through the tangent
// plane at the hit, PBRT-style).
struct UvFootprint {
    glm::vec2 dx{0.f}, dy{0.f};
};
UvFootprint uvFootprint(const CameraFrame& frame, const SurfaceHit& hit, float px, float py);
inline UvFootprint uvFootprint(const Camera& camera, const SurfaceHit& hit, float px, float py) {
    return uvFootprint(cameraFrame(camera), hit, px, py);
}

// Whether the view of `scene` lets a box-surface truth be integrated exactly
// (RenderOptions::exact): an orthographic camera whose image rows run along one axis of a plane's
// texel grid (straight down, or tilted about that axis), directional lights, no environment.
bool exactBoxView(const Scene& scene);
// The same view with an environment allowed (EnvironmentTruth::Table).
bool fixedDirectionsView(const Scene& scene);

// GPU LOD: log2 of the longer footprint axis measured in level-0 texels.
float mipLod(const UvFootprint& footprint, int width, int height);

// Mean over pixels of (temporal standard deviation / temporal mean) of the luminance, over
// pixels whose temporal mean exceeds `floor` times the frames' overall mean luminance.
double temporalFlicker(const std::vector<Image>& frames, double floor = 1e-3);

// `count` sub-pixel shifts in [-0.5, 0.5)^2 for flicker frames (a fixed low-discrepancy set).
std::vector<glm::vec2> flickerShifts(int count);

} // namespace ndfmip
