// Each method under an environment the way engines shade it: the split-sum approximation
// (Karis 2013; Filament, Unreal, Unity). The specular term is a prefiltered radiance chain read
// along the reflection of v about the method's normal, at a level that the method's roughness
// selects (a LOD rule), times the lobe's directional albedo; the diffuse term is albedo/pi times
// the irradiance (order-2 SH) about the method's normal(s).
//
// Units are the renderer's: reflected radiance. Directions: the shading functions take the view
// v in the tangent frame (z = geometric normal) and `tangentToEnvironment`, whose columns are the
// tangent, bitangent and normal of the hit in the environment frame (environment.h, +Y up, the
// seen frame: Environment::rotation is already applied by prepareSplitSum).
//
// The project's BRDF is the lobe alone, f = specular D(n.h) (brdf.h: no Fresnel, no masking, no
// 1/(4 n.l n.v)), so the split sum's second factor is by default that lobe's directional albedo
// E(n.v, r) = integral D(n.h) <n.l> dl (SpecularAlbedo::Lobe); the engines' DFG (environment.h's
// dfgTable, GGX with Smith masking, F = 1: scale + bias) is offered as SpecularAlbedo::EngineDfg.
// docs/ENVIRONMENT.md, "Methods under an environment: the engine way", has the formulas.
#pragma once

#include <array>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "ndfmip/environment.h"
#include "ndfmip/environment_cube_chain.h"
#include "ndfmip/image.h"
#include "ndfmip/result.h"
#include "ndfmip/roughness.h"
#include "ndfmip/scene.h"

namespace ndfmip {

// ---- LOD rules ------------------------------------------------------------------------------

// How a roughness picks a level of a prefiltered chain, and so how that chain is prefiltered
// (every chain's level k holds the GGX lobe of the roughness its own rule assigns to k).
enum class EnvironmentLod {
    Log2Sigma, // Toksvig ("Environment Maps"): lod = log2(2 sigma / theta0) on the plain box mip
               // chain (on cube faces, environment_cube_chain.h), sigma the angular spread of the
               // reflected lobe, theta0 a level-0 texel's (log2SigmaLevel)
    Filament,  // lod = r (2 - r) (N - 1) (Filament's perceptualRoughnessToLod)
    Unity,     // mip = r (1.7 - 0.7 r) 6 (perceptualRoughnessToMipmapLevel, 7 levels)
    Unreal,    // mip = N - 1 - (1 - 1.2 log2 r) (ComputeReflectionCaptureMipFromRoughness)
};

// "log2sigma", "filament", "unity", "unreal"; and back (false for any other name).
const char* environmentLodName(EnvironmentLod rule);
bool environmentLodFromString(const std::string& name, EnvironmentLod& out);

// Unity's UNITY_SPECCUBE_LOD_STEPS: the last of its 7 convolved levels.
constexpr int kUnitySpecCubeLodSteps = 6;

// The level (fractional, clamped to [0, levels - 1]) that perceptual roughness r reads on a
// chain of `levels` levels, for the engine rules (not Log2Sigma).
double environmentLodLevel(EnvironmentLod rule, double perceptualRoughness, int levels);
// Its inverse: the perceptual roughness the rule assigns to level k (0 for k = 0, at most 1).
double environmentLodRoughness(EnvironmentLod rule, int level, int levels);

// Toksvig's rule, lod "a function of log2 sigma": log2(kLog2SigmaSpan sigma / texelAngle) -
// kLog2SigmaLobeLevels clamped to [0, levels - 1], the level of the Log2Sigma chain whose lobe
// has that reflected spread sigma (SplitSumChain). A box chain's texels at level L, w = 2^L
// texelAngle wide, blended by a tent of half-width w, spread as w^2/12 + w^2/6 = w^2/4 per axis:
// sigma^2 at w = 2 sigma (kLog2SigmaSpan; with w = sigma the reads were one level too sharp, twice
// the error under venice, docs/RESULTS.md). The chain's levels hold lobes four texels wide
// instead (kLog2SigmaLobeLevels = 2 levels finer), so their shape, not the texels, is the spread.
constexpr double kLog2SigmaSpan = 2.;
constexpr int kLog2SigmaLobeLevels = 2;
double log2SigmaLevel(double sigma, double texelAngle, int levels);

// The angular spread (radians, per axis) of the reflected direction: a lobe over half vectors of
// per-axis variance `lobeVariance` (Blinn-Phong exp(-s t^2/2): 1/s; Beckmann and GGX
// exp(-t^2/alpha^2): alpha^2/2) widened by normals of per-axis variance `normalVariance`
// (Toksvig eq. 1: (1 - |Na|)/|Na|), doubled by the reflection: 2 sqrt(lobe + normal).
double reflectedSpread(double lobeVariance, double normalVariance);

// Blinn-Phong exponent s read as a GGX/Beckmann alpha, Walter et al. 2007: alpha^2 = 2/(s + 2).
double blinnPhongAlpha(double exponent);

// ---- preparation ----------------------------------------------------------------------------

// The split sum's second factor.
enum class SpecularAlbedo {
    Lobe,      // the project's lobe: integral D(n.h) <n.l> dl, per BRDF (matches shadeNormal)
    EngineDfg, // environment.h's dfgTable, scale + bias (GGX, Smith masking, F = 1)
};

struct SplitSumOptions {
    int size = 256;         // width of level 0 of every chain, a power of two >= 16
    int samples = 512;      // GGX samples per texel at level 1, doubled from level 2 (as cmgen)
    int filamentLevels = 5; // Filament's N (cmgen's 5 levels)
    std::vector<EnvironmentLod> rules = {EnvironmentLod::Log2Sigma, EnvironmentLod::Filament,
                                         EnvironmentLod::Unity, EnvironmentLod::Unreal};
    SpecularAlbedo albedo = SpecularAlbedo::Lobe;
    int albedoTableSize = 32;   // n.v x perceptual roughness entries
    int albedoSamples = 512;    // samples per entry
    bool vmfBandFactors = true; // diffuse about a vMF lobe (and Toksvig's Na) band-attenuated
    // The radiance read along the lobe's dominant direction (its centroid, bent from the
    // reflection towards the normal: lobeDominantShare) instead of the mirror direction; off reads
    // along the reflection, the split sum as Karis wrote it.
    bool dominantDirection = true;
    // A spread texel's radiance read about its albedo-weighted reflecting normal (the mean normal
    // tilted towards the view: splitsum_shading.glsl ndfmipWeightedReflectingNormal) instead of
    // its mean normal.
    bool weightedReflection = true;
    // The engine rules' levels convolved with the Blinn-Phong lobe of exponent
    // s_k = 2/alpha_k^2 - 2 (the inverse of blinnPhongAlpha) instead of GGX alpha_k = r_k^2: the
    // chain a Blinn-Phong material reads at its own lobe (it reads a level by the roughness
    // sqrt(blinnPhongAlpha(s)), so level k's lobe is its exponent's exactly).
    bool blinnPhongLobe = false;
};

// One chain: level k is (size >> k) x (size >> k)/2 (at least 4 x 2 for the GGX chains), RGB, at
// perceptualRoughness[k] (0 for the unfiltered level 0). Log2Sigma's chain is on cube faces
// instead, size/4 wide at level 0 (as many texels around the horizon) down to 1 x 1, in `cube`,
// level k >= 1 the material's lobe at the spread log2SigmaLevel reads there; its `levels` are
// empty.
struct SplitSumChain {
    EnvironmentLod rule = EnvironmentLod::Filament;
    std::vector<Image> levels;
    CubeMipChain cube;
    std::vector<double> perceptualRoughness; // one per level of either
    bool blinnPhongLobe = false;             // SplitSumOptions::blinnPhongLobe
};

struct SplitSumLighting {
    std::vector<SplitSumChain> chains; // one per prepared rule
    SpecularAlbedo albedoKind = SpecularAlbedo::Lobe;
    // Lobe: one table per BRDF (index int(Brdf) - 1: Blinn-Phong, Beckmann, GGX), EngineDfg:
    // the DFG table in [0] (R scale, G bias, B their sum). Column x: n.v = x/(size - 1), from
    // 0 to 1 itself (straight down is the commonest view, and a column centred at 1 - 1/(2 size)
    // read the albedo there 3% low); row y: perceptual roughness (y + 0.5)/size (Blinn-Phong:
    // sqrt(blinnPhongAlpha(s))).
    std::array<Image, 3> albedo;
    // The dominant direction's share of the normal, per BRDF (index int(Brdf) - 1), the same
    // columns and rows as the lobe's albedo table; zero without SplitSumOptions::dominantDirection.
    std::array<Image, 3> dominant;
    std::vector<glm::dvec3> irradiance; // E_lm, order 2 (projectEnvironmentSh)
    double texelAngle = 0.;             // angular height of a level-0 texel, pi / (size / 2)
                            // (Log2Sigma's cube faces: pi/2 over size/4 texels, the same)
    bool vmfBandFactors = true;
    bool weightedReflection = true; // SplitSumOptions::weightedReflection
};

// Prepares every chain of options.rules, the albedo table(s) and the irradiance SH.
// Preconditions: options within the ranges above, a valid environment.
SplitSumLighting prepareSplitSum(const Environment& env, const SplitSumOptions& options = {});

// The Blinn-Phong exponent of GGX/Beckmann alpha: 2/alpha^2 - 2, the inverse of blinnPhongAlpha.
double blinnPhongExponent(double alpha);

// A split-sum material check: tabulated lobes have no prefiltered form (error naming them);
// every other BRDF is supported (Lambert: diffuse only). The shading functions give a
// tabulated material its diffuse term only.
Status checkSplitSumMaterial(const Material& m);

// ---- lookups --------------------------------------------------------------------------------

// The chain prepared for `rule` (nullptr when it was not prepared).
const SplitSumChain* findChain(const SplitSumLighting& lighting, EnvironmentLod rule);
// Trilinear: bilinear within levels floor(lod) and floor(lod) + 1 (sampleEquirect, or
// sampleCubeLevel for the cube chain), blended.
glm::vec3 sampleChain(const SplitSumChain& chain, double lod, glm::dvec3 direction);
// The irradiance E(n) = sum E_lm Y_lm(n) (environment frame), bands l scaled by `band[l]`.
glm::vec3 irradianceAt(const SplitSumLighting& lighting, glm::dvec3 n,
                       glm::dvec3 band = glm::dvec3(1.));
// The split sum's second factor for `brdf` at n.v = mu and perceptual roughness r (bilinear,
// clamped); EngineDfg ignores brdf.
float specularAlbedo(const SplitSumLighting& lighting, Brdf brdf, float mu,
                     float perceptualRoughness);
// specularAlbedo and its slope in n.v (the bilinear interpolant's: the table's cell's), from
// one lookup's four entries.
glm::vec2 specularAlbedoAndSlope(const SplitSumLighting& lighting, Brdf brdf, float mu,
                                 float perceptualRoughness);
// The directional albedo of the project's lobe, integral D(n.h) <n.l> dl, by `samples`
// Hammersley samples of D(h) <n.h> (the table's entries).
double lobeAlbedo(Brdf brdf, double mu, double perceptualRoughness, int samples);
// The lobe's dominant direction at n.v = mu: the centroid of D(n.h) <n.l> over l (the same
// samples), written as the share f of the normal in normalize(mix(reflect(-v, n), n, f)), in
// [0, 1]. At grazing views the lobe's part below the horizon is cut and its cosine weighs the
// directions nearer the normal: its centroid leaves the mirror direction towards n (Lagarde and
// de Rousiers 2014 fit the same idea for a BRDF with masking and 1/(4 n.l n.v), which this lobe
// has not).
double lobeDominantShare(Brdf brdf, double mu, double perceptualRoughness, int samples);
// The table's share for `brdf` at n.v = mu and perceptual roughness r (bilinear, clamped); 0 for
// a material without a lobe.
float dominantShare(const SplitSumLighting& lighting, Brdf brdf, float mu,
                    float perceptualRoughness);

// The prefiltered radiance of a lobe along `reflected` (environment frame): the rule's chain at
// the level of perceptual roughness r, or for Log2Sigma at the level of
// reflectedSpread(lobeVariance, normalVariance).
glm::vec3 prefilteredRadiance(const SplitSumLighting& lighting, EnvironmentLod rule,
                              glm::dvec3 reflected, double perceptualRoughness,
                              double normalVariance = 0.);

// ---- each method ----------------------------------------------------------------------------
// Arguments as the point-light functions of method_shading.h take them; `albedo` the material's
// albedo times the filtered albedo map. Specular: m.specular x prefiltered radiance x albedo
// factor; diffuse: albedo/pi x irradiance. The radiance is read at the method's (widened)
// roughness, the albedo factor at the material's own roughness averaged over the n.v of the
// texel's normals (a two-point rule in their mean and mean square, ndfmipSpreadAlbedo), those
// estimated from their mean length (|Na|, a vMF lobe's A(kappa), or the
// stored roughness read back through the ours mapping): each normal of a filtered texel reflects
// with the material's lobe, so the texel's energy is the mean of their albedos, which the widened
// lobe's albedo about the mean normal underestimates (it loses what falls below its horizon).

// Standard mipmap: the filtered normal renormalised, the material's own roughness.
glm::vec3 shadeNaiveSplitSum(const Material& m, glm::vec3 albedo, glm::vec3 filtered,
                             glm::vec3 view, const glm::mat3& tangentToEnvironment,
                             const SplitSumLighting& lighting, EnvironmentLod rule);

// Toksvig: Na unnormalised; the radiance at Blinn-Phong s' = ft s (T eq. 6), Beckmann/GGX alpha' by
// `mapping` (roughness.h), as shadeToksvig; Log2Sigma adds the normals' variance (1 - |Na|)/|Na|
// to the material's lobe spread instead. The albedo factor over normals of mean length |Na|.
// Diffuse about Na/|Na|, band 1 scaled by |Na| with vmfBandFactors (the mean of irradiance's linear
// band over the normals).
glm::vec3 shadeToksvigSplitSum(const Material& m, glm::vec3 albedo, glm::vec3 na, glm::vec3 view,
                               const glm::mat3& tangentToEnvironment,
                               const SplitSumLighting& lighting, EnvironmentLod rule,
                               RoughnessMapping mapping, float varianceScale = kVarianceScale);

// Roughness mips: the filtered normal renormalised, the radiance at alpha from `stored`
// (perceptual, alpha = stored^2, unless isAlpha); the albedo factor over normals of the mean length
// 1/(1 + (alpha^2 - m.roughness^2)/kVarianceScale) that widens the material's alpha to the stored
// one under the ours mapping. Blinn-Phong materials keep their exponent.
glm::vec3 shadeRoughnessMipsSplitSum(const Material& m, glm::vec3 albedo, glm::vec3 filtered,
                                     float stored, bool isAlpha, glm::vec3 view,
                                     const glm::mat3& tangentToEnvironment,
                                     const SplitSumLighting& lighting, EnvironmentLod rule);

// vMF mixture: `lobes` holds J (alpha, alpha r mu) quadruples, unpacked as shadeVmf; per lobe
// Blinn-Phong s' = kappa s/(kappa + s), Beckmann/GGX alpha'^2 = alpha^2 + 2/kappa (Han et al.
// eqs. 29-30), a prefiltered read along the reflection about mu_j, the albedo factor over the
// lobe's normals (mean length A(kappa)); diffuse from the irradiance
// at mu_j (band l scaled by the vMF's Legendre moment with vmfBandFactors: A(kappa),
// 1 - 3 A(kappa)/kappa). Weights alpha_j; `colors` (J lobe colours) as shadeVmf.
glm::vec3 shadeVmfSplitSum(const Material& m, glm::vec3 albedo, const float* lobes, int count,
                           const glm::vec3* colors, glm::vec3 view,
                           const glm::mat3& tangentToEnvironment, const SplitSumLighting& lighting,
                           EnvironmentLod rule);

} // namespace ndfmip
