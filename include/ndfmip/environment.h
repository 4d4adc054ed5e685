// Environment lighting from an equirectangular (latitude-longitude) HDR map: the spherical
// harmonics of its radiance, GGX-prefiltered levels for the split-sum approximation (Karis 2013)
// and the split sum's DFG table. docs/ENVIRONMENT.md has the conventions and the file formats.
//
// Directions are right-handed with +Y up, the frame of Filament's cmgen (after the mirror it
// applies by default): texel coordinates (u, v) in [0, 1]^2, u to the right and v down from the
// top row, look along
//     phi = 2 pi (u - 1/2),   lat = pi (1/2 - v),
//     d = (-cos(lat) sin(phi), sin(lat), cos(lat) cos(phi)),
// so the image centre is +Z, the top row +Y, u = 1/4 is +X and u = 3/4 is -X. Seen from inside
// the sphere, facing +Z with +Y up, the map reads left to right as it does in the file.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "ndfmip/image.h"
#include "ndfmip/result.h"

namespace ndfmip {

// ---- the map and its conventions ----------------------------------------------------------------

// Radiance over the sphere: an equirectangular image, RGB, linear, top row first.
struct Environment {
    Image radiance; // width == 2 * height, 3 channels, finite and >= 0
    // Radians about +Y: what the file shows along d is seen along R_y(rotation) d.
    double rotation = 0.;
};

// The direction of texel coordinates (u, v) (see the top of this file), unit length.
glm::dvec3 equirectDirection(double u, double v);
// Its inverse: u in [0, 1), v in [0, 1].
glm::dvec2 equirectCoordinates(glm::dvec3 d);
// Rotation by `angle` radians about +Y, right-handed: +Z turns towards +X.
glm::dvec3 rotateAboutY(glm::dvec3 d, double angle);
// Solid angle of a texel of row y in a width x height map: dphi (cos theta0 - cos theta1), theta
// the polar angle from +Y of the row's top and bottom edge. The texels sum to 4 pi.
double equirectTexelSolidAngle(int width, int height, int y);

struct EnvironmentOptions {
    float intensity = 1.f;       // radiance scale, > 0
    float rotationDegrees = 0.f; // about +Y, right-handed (Environment::rotation)
};

// What loading changed about the texels, for the caller to warn about.
struct EnvironmentReport {
    size_t negativeTexels = 0; // texels with a negative channel, set to 0
};

// Reads an equirectangular Radiance HDR or OpenEXR file (io.h's loaders). 1-channel images are
// taken as grey, a fourth channel is ignored. Errors, one line naming the file: unreadable or
// corrupt file, a size other than 2:1 (or under 4x2), 2 channels, a NaN or infinite texel;
// options out of range. Negative values (some EXR tools leave tiny ones) are set to 0 and
// counted in the report.
Result<Environment> loadEnvironment(const std::string& path, const EnvironmentOptions& options = {},
                                    EnvironmentReport* report = nullptr);
// The same checks on an image in memory; `name` starts the error messages.
Result<Environment> makeEnvironment(Image image, const std::string& name,
                                    const EnvironmentOptions& options = {},
                                    EnvironmentReport* report = nullptr);

// Bilinear lookup of an equirectangular image (any channel count, width == 2 height) along d:
// texel centres at ((x + 0.5) / w, (y + 0.5) / h), wrapping in u and continuing across the poles.
void sampleEquirect(const Image& map, glm::dvec3 d, float* out);

// Area-weighted resampling to width x width/2 (any width >= 2): each output texel is the mean
// radiance over its solid angle of the map read as constant per texel, turned by `rotation`
// about +Y as Environment::rotation. Halving a power-of-two map is a solid-angle-weighted 2x2 box.
Image resampleEquirect(const Image& map, int width, double rotation = 0.);

// ---- spherical harmonics ----------------------------------------------------------------------

// Coefficients of the radiance L(d) on the basis of spherical_harmonics.h (real, orthonormal, no
// Condon-Shortley phase), in the +Y-up frame above: L_lm = integral of L(d) Y_lm(d) over the
// sphere, so L(d) ~= sum L_lm Y_lm(d).
struct EnvironmentSh {
    int order = 0;                      // l <= order, (order + 1)^2 coefficients each
    std::vector<glm::dvec3> radiance;   // L_lm (RGB) at shIndex(l, m)
    std::vector<glm::dvec3> irradiance; // E_lm = Ahat_l L_lm, E(n) = sum E_lm Y_lm(n)
    std::vector<double>
        lambert; // Ahat_l = pi A_l (sh_brdf.h lambertCoefficients): pi, 2pi/3, pi/4, 0, ...
};

// The exact projection of the map read as constant over each texel: every texel's radiance
// times the integral of Y_lm over its solid angle (phi in closed form, theta by Gauss-Legendre),
// so a constant map gives L_00 = c sqrt(4 pi) and every other coefficient 0 to rounding.
// 0 <= order <= kMaxShOrder.
EnvironmentSh projectEnvironmentSh(const Environment& env, int order);

// ---- GGX prefiltering (split sum)
// ------------------------------------------------------------------

// How a level's position lod = k / (N - 1) in a chain of N levels gives its perceptual roughness
// r (alpha = r^2).
enum class LodMapping {
    Filament, // lod = r (2 - r), r = 1 - sqrt(1 - lod): cmgen 1.9 and Filament's shaders
              // (perceptualRoughnessToLod), so levels 0, 0.134, 0.293, 0.5, 1 for N = 5
    Linear,   // r = lod
};
double lodToPerceptualRoughness(LodMapping mapping, double lod);
double perceptualRoughnessToLod(LodMapping mapping, double roughness);
// "filament" or "linear"; false for anything else.
bool lodMappingFromString(const std::string& name, LodMapping& out);
const char* lodMappingName(LodMapping mapping);

struct PrefilterOptions {
    int size = 0;   // width of level 0, a power of two >= 8 (0: defaultPrefilterSize)
    int levels = 0; // 1 ... log2(size) - 2 (0: log2(size) - 5, at least 1: 1024 gives 5 levels,
                    // 1024 to 64 wide, like cmgen's 256 to 16 cube faces)
    LodMapping mapping = LodMapping::Filament;
    // GGX samples per texel of level 1, doubled at every level from 2 (as cmgen).
    int samples = 1024;
    std::function<void(int done, int total)> progress; // after each level, from the calling thread
};

// PrefilterOptions::size when it is 0: the map's width rounded up to a power of two, within
// [8, 1024].
int defaultPrefilterSize(int mapWidth);

// cmgen's sample schedule, every prefiltered chain's: `levelOneSamples` at level 1, doubled at
// each level after. A coarser level has a quarter of the texels, and a broad lobe's few samples
// would each read a coarse level of the radiance's pyramid, which spreads a small bright light
// outside the lobe (docs/RESULTS.md, "The chain's sample schedule").
int prefilterSamples(int levelOneSamples, int level);

struct PrefilteredLevel {
    Image radiance; // (size >> k) x (size >> k) / 2, RGB
    double perceptualRoughness = 0.;
    int samples = 0; // GGX samples per texel (0 for the unfiltered level 0)
};

// Level k is the radiance convolved with the GGX lobe of alpha = r_k^2 about the reflected
// direction, under the split-sum assumption n = v = r (Karis 2013):
//     LD(r) = integral L(l) D(h) <n.l> dl / integral D(h) <n.l> dl,
// estimated by filtered importance sampling (Krivanek and Colbert 2008): Hammersley samples of
// D, each read from the radiance's area-weighted mip chain at the level whose texels match the
// sample's solid angle (with cmgen's bias K = 4). The map is rotated about +Y only, so every
// texel of an output row shares one set of source rows and mip levels, shifted in u.
// Level 0 (r = 0) is the map resampled. Preconditions: options within the ranges above.
std::vector<PrefilteredLevel> prefilterGgx(const Environment& env, const PrefilterOptions& options);

// The source every prefiltered level reads: the radiance's area-weighted mip chain (power-of-two
// widths, at most 4096, down to 2 x 1) and the map's rotation. Build it once for a chain's levels.
struct RadiancePyramid {
    std::vector<Image> levels;
    double rotation = 0.;
};
RadiancePyramid radiancePyramid(const Environment& env);

// One level: width x width/2 texels at perceptual roughness r (> 0) with `samples` samples.
Image prefilterGgxLevel(const RadiancePyramid& source, double perceptualRoughness, int width,
                        int samples);
Image prefilterGgxLevel(const Environment& env, double perceptualRoughness, int width, int samples);

// The same convolution with the Blinn-Phong lobe D proportional to <n.h>^s (exponent s >= 0)
// instead of GGX: the chain a Blinn-Phong material reads without converting its exponent.
Image prefilterBlinnPhongLevel(const RadiancePyramid& source, double exponent, int width,
                               int samples);
Image prefilterBlinnPhongLevel(const Environment& env, double exponent, int width, int samples);

// ---- the split sum's second factor
// ------------------------------------------------------------------

// For n.v = mu and perceptual roughness r, the GGX specular reflectance with height-correlated
// Smith masking (Heitz 2014) split over Schlick's Fresnel F = f0 + (f90 - f0)(1 - v.h)^5:
//     scale = integral f/F (1 - (1 - v.h)^5) <n.l> dl,  bias = integral f/F (1 - v.h)^5 <n.l> dl,
// so the specular term is prefiltered(r) * (f0 scale + f90 bias). Hammersley samples of D.
glm::dvec2 dfgIntegral(double mu, double perceptualRoughness, int samples);

// Where a table's columns put n.v: at texel centres, (x + 0.5) / size, as a texture's hardware
// sampling reads it, or at x / (size - 1), from 0 to 1 itself (the split sum's own tables).
enum class TableColumns { Centres, Ends };

// The table: size x size, 3 channels: R = scale, G = bias, B = scale + bias (the directional
// albedo of the lobe with F = 1, for multiple-scattering compensation). Column x holds n.v as
// `columns` says ((x + 0.5) / size by default), row y (top row first) perceptual roughness
// (y + 0.5) / size, so a texture uploaded top row first is read at (n.v, r).
Image dfgTable(int size, int samples = 4096, TableColumns columns = TableColumns::Centres);

// n.v of column x of a size-wide table laid out as `columns` says.
double tableColumnCosine(TableColumns columns, int x, int size);

// ---- cube faces ----------------------------------------------------------------------------

// Faces in the order and orientation of OpenGL, Vulkan and KTX2 cube maps (+X, -X, +Y, -Y, +Z,
// -Z), in the frame above; the names of the files cmgen writes.
constexpr int kCubeFaces = 6;
const char* cubeFaceName(int face); // "px", "nx", "py", "ny", "pz", "nz"

// The unit direction through face coordinates (s, t) in [0, 1]^2 of `face`, s to the right and
// t down from the top row: with a = 2 s - 1, b = 1 - 2 t, +X looks along (1, b, -a), -X (-1, b, a),
// +Y (a, 1, -b), -Y (a, -1, b), +Z (a, b, 1), -Z (-a, b, -1) (the GL rule sc = -rz, tc = -ry
// for +X and so on).
glm::dvec3 cubeFaceDirection(int face, double s, double t);

// Its inverse for any non-zero d: the face d points into (the largest |component|; ties go to
// the earlier face) and (s, t) in [0, 1]^2; the zero vector gives +Z's centre. The float
// versions (interpolated.h) and the GPU's are the same source, shaders/render/cube_faces.glsl.
void cubeFaceCoordinates(glm::dvec3 d, int& face, double& s, double& t);

// The solid angle of texel (x, y) of a size x size face; the 6 size^2 texels sum to 4 pi.
double cubeTexelSolidAngle(int size, int x, int y);

// One size x size face of an equirectangular image (any channel count): each texel the mean of
// samples x samples bilinear lookups (sampleEquirect) spread over it.
Image cubeFaceFromEquirect(const Image& map, int face, int size, int samples = 4);

// ---- the output folder ----------------------------------------------------------------------

// Where a folder's map came from, for its manifest.
struct EnvironmentSource {
    std::string path, sha256;
    int width = 0, height = 0;
    EnvironmentOptions options;
};

struct EnvironmentBake {
    EnvironmentSh sh;
    std::vector<PrefilteredLevel> levels;
    LodMapping mapping = LodMapping::Filament;
    Image dfg;          // dfgTable
    int dfgSamples = 0; // its samples per texel
    // Which files hold the GGX levels: equirectangular images, six cube faces per level (each
    // face a quarter of the level's width, cubeFaceFromEquirect), or both.
    bool equirect = true;
    bool cube = false;
    // Also one KTX2 file per layout holding every level as its mips (RGBA16F, alpha 1):
    // ggx_cube.ktx2 (a cube map) and ggx_equirect.ktx2; and dfg.ktx2 (the table, RGBA16F).
    bool ktx2 = false;
    // The same textures as DDS (DX10 header, DXGI_FORMAT_R16G16B16A16_FLOAT; the cube map with
    // each face's levels together): ggx_cube.dds, ggx_equirect.dds, dfg.dds.
    bool dds = false;
};

// Writes DIR/sh.json (the coefficients), DIR/ggx_L<k>.exr (one equirectangular RGB image per
// level) and/or DIR/ggx_L<k>_<face>.exr (its cube faces), DIR/dfg.exr (the table) and
// DIR/environment.json (what each file holds and how it was made; docs/ENVIRONMENT.md). Images are
// float, or half with `half`. Like writeBake, the folder is staged beside DIR and swapped into
// place at the end, so a failure leaves the earlier folder; an existing DIR is replaced only if it
// is empty or holds an earlier environment folder and nothing else.
Status writeEnvironment(const std::string& dir, const EnvironmentBake& bake,
                        const EnvironmentSource& source, bool half = false);

} // namespace ndfmip
