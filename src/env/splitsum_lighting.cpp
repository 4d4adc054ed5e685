// The split sum's prepared lighting (environment_splitsum.h): the LOD rules, one prefiltered
// chain per rule, the albedo tables and the irradiance SH, and the lookups into them.
//
// Sources of the engine rules (docs/ENVIRONMENT.md): Filament's perceptualRoughnessToLod
// (lod = r (2 - r), as environment.h's LodMapping::Filament); Unity's
// perceptualRoughnessToMipmapLevel in ImageBasedLighting.hlsl (render-pipelines.core),
// mip = r (1.7 - 0.7 r) UNITY_SPECCUBE_LOD_STEPS with 6 steps, 7 convolved mips; Unreal's
// ComputeReflectionCaptureMipFromRoughness in ReflectionEnvironmentShared.ush,
// LevelFrom1x1 = 1 - 1.2 log2(max(r, 0.001)), mip = NumMips - 1 - LevelFrom1x1, and its inverse
// ComputeReflectionCaptureRoughnessFromMip, r = 2^((1 - LevelFrom1x1) / 1.2).
#include "ndfmip/environment_splitsum.h"

#include <algorithm>
#include <cassert>
#include <cmath>

#include "env/env_internal.h"
#include "ndfmip/spherical_harmonics.h"

namespace ndfmip {

namespace {

constexpr double kUnrealRoughestMip = 1.;
constexpr double kUnrealMipScale = 1.2;

int log2Floor(int n) {
    int k = 0;
    while ((2 << k) <= n) ++k;
    return k;
}

// Levels of each chain for a level-0 width `size`: Unity has its fixed 7; Unreal runs down to
// 4 x 2 texels, the equirect counterpart of a 1 x 1 cube face (4 faces span the horizon); the
// cube chain of Log2Sigma runs from size/4-wide faces down to 1 x 1.
int chainLevels(EnvironmentLod rule, int size, int filamentLevels) {
    switch (rule) {
    case EnvironmentLod::Log2Sigma:
        return log2Floor(size) - 1;
    case EnvironmentLod::Filament:
        return filamentLevels;
    case EnvironmentLod::Unity:
        return kUnitySpecCubeLodSteps + 1;
    case EnvironmentLod::Unreal:
        return log2Floor(size) - 1;
    }
    return 1;
}

// One prefiltered level of a chain: the radiance convolved with GGX of perceptual roughness r,
// or with the Blinn-Phong lobe of alpha = r^2 where the material's lobe is Blinn-Phong.
Image prefilteredLevel(const RadiancePyramid& source, bool blinnPhongLobe,
                       double perceptualRoughness, int width, int samples) {
    const double r = perceptualRoughness;
    return blinnPhongLobe
               ? prefilterBlinnPhongLevel(source, blinnPhongExponent(r * r), width, samples)
               : prefilterGgxLevel(source, r, width, samples);
}

// Toksvig's chain on cube faces: level 0 the radiance (size/4-wide faces, cubeMipChainBase),
// level k >= 1 the radiance prefiltered with the material's lobe shape at the reflected spread
// log2SigmaLevel reads there, sigma_k = 2^(k + kLog2SigmaLobeLevels) theta0 / kLog2SigmaSpan:
// GGX alpha_k = sigma_k / sqrt(2) (reflectedSpread of the lobe variance alpha^2/2), or the
// Blinn-Phong lobe of that alpha. Each level's lobe is four of its texels wide (sigma_k = 2 w_k),
// so the texels' own box and the trilinear tent add a sixteenth of its variance. The plain box
// chain (each level the mean of its children, read where its texels spread as the lobe does)
// keeps the map's integral, but its reads have compact support: a GGX lobe's tail reaches small
// bright lights the box does not, and under a studio's lamps it kept 6-30% of the truth's energy
// (docs/RESULTS.md).
CubeMipChain log2SigmaChain(const Environment& env, const RadiancePyramid& source, int size,
                            int levels, int samples, bool blinnPhongLobe, double texelAngle,
                            std::vector<double>& perceptualRoughness) {
    CubeMipChain chain;
    chain.levels.push_back(cubeMipChainBase(env, size / 4));
    perceptualRoughness.assign(1, 0.);
    for (int k = 1; k < levels; ++k) {
        const double sigma =
            std::exp2(double(k + kLog2SigmaLobeLevels)) * texelAngle / kLog2SigmaSpan;
        const double alpha = std::min(sigma / std::sqrt(2.), 1.);
        const int faceSize = std::max((size / 4) >> k, 1);
        const int width = std::max(4 * faceSize, 8); // one texel per face texel at the horizon
        // As the engine chains (with one count at every level the studio's energy at 30 degrees
        // fell to 0.76-0.78).
        const Image map = prefilteredLevel(source, blinnPhongLobe, std::sqrt(alpha), width,
                                           prefilterSamples(samples, k));
        std::array<Image, kCubeFaces> faces;
        for (int face = 0; face < kCubeFaces; ++face)
            faces[size_t(face)] = cubeFaceFromEquirect(map, face, faceSize);
        chain.levels.push_back(std::move(faces));
        perceptualRoughness.push_back(std::sqrt(alpha));
    }
    return chain;
}

} // namespace

const char* environmentLodName(EnvironmentLod rule) {
    switch (rule) {
    case EnvironmentLod::Log2Sigma:
        return "log2sigma";
    case EnvironmentLod::Filament:
        return "filament";
    case EnvironmentLod::Unity:
        return "unity";
    case EnvironmentLod::Unreal:
        return "unreal";
    }
    return "?";
}

bool environmentLodFromString(const std::string& name, EnvironmentLod& out) {
    for (EnvironmentLod rule : {EnvironmentLod::Log2Sigma, EnvironmentLod::Filament,
                                EnvironmentLod::Unity, EnvironmentLod::Unreal})
        if (name == environmentLodName(rule)) {
            out = rule;
            return true;
        }
    return false;
}

double environmentLodLevel(EnvironmentLod rule, double perceptualRoughness, int levels) {
    assert(rule != EnvironmentLod::Log2Sigma && levels >= 1);
    const double r = std::clamp(perceptualRoughness, 0., 1.);
    double lod = 0.;
    if (rule == EnvironmentLod::Filament)
        lod = perceptualRoughnessToLod(LodMapping::Filament, r) * (levels - 1);
    if (rule == EnvironmentLod::Unity) lod = r * (1.7 - 0.7 * r) * kUnitySpecCubeLodSteps;
    if (rule == EnvironmentLod::Unreal) {
        const double levelFrom1x1 =
            kUnrealRoughestMip - kUnrealMipScale * std::log2(std::max(r, 0.001));
        lod = levels - 1 - levelFrom1x1;
    }
    return std::clamp(lod, 0., double(levels - 1));
}

double environmentLodRoughness(EnvironmentLod rule, int level, int levels) {
    assert(rule != EnvironmentLod::Log2Sigma && level >= 0 && level < levels);
    if (level == 0) return 0.; // every chain's level 0 is the radiance itself
    double r = 1.;
    if (rule == EnvironmentLod::Filament)
        r = lodToPerceptualRoughness(LodMapping::Filament, double(level) / (levels - 1));
    if (rule == EnvironmentLod::Unity) {
        // The root in [0, 1] of 0.7 r^2 - 1.7 r + t = 0, t = level / 6.
        const double t = double(level) / kUnitySpecCubeLodSteps;
        r = (1.7 - std::sqrt(std::max(0., 1.7 * 1.7 - 2.8 * t))) / 1.4;
    }
    if (rule == EnvironmentLod::Unreal) {
        const double levelFrom1x1 = levels - 1 - level;
        r = std::exp2((kUnrealRoughestMip - levelFrom1x1) / kUnrealMipScale);
    }
    return std::min(r, 1.);
}

double log2SigmaLevel(double sigma, double texelAngle, int levels) {
    assert(texelAngle > 0. && levels >= 1);
    if (!(sigma > 0.)) return 0.;
    return std::clamp(std::log2(kLog2SigmaSpan * sigma / texelAngle) - kLog2SigmaLobeLevels, 0.,
                      double(levels - 1));
}

double reflectedSpread(double lobeVariance, double normalVariance) {
    return 2. * std::sqrt(std::max(lobeVariance, 0.) + std::max(normalVariance, 0.));
}

double blinnPhongAlpha(double exponent) {
    return std::sqrt(2. / (std::max(exponent, 0.) + 2.));
}

double blinnPhongExponent(double alpha) {
    return std::max(2. / std::max(alpha * alpha, 1e-12) - 2., 0.);
}

// ---- the lobe's directional albedo ----------------------------------------------------------

namespace {

// The lobe's integral D(n.h) <n.l> dl over l and its first moment (x, z; y vanishes by symmetry),
// for v = (sqrt(1 - mu^2), 0, mu).
struct LobeMoments {
    double albedo = 0., x = 0., z = 0.;
};

LobeMoments lobeMoments(Brdf brdf, double mu, double perceptualRoughness, int samples) {
    assert(samples >= 1);
    if (brdf != Brdf::BlinnPhong && brdf != Brdf::Beckmann && brdf != Brdf::Ggx) return {};
    mu = std::clamp(mu, 1e-6, 1.);
    const double alpha = std::max(perceptualRoughness * perceptualRoughness, 1e-4);
    const double exponent = blinnPhongExponent(alpha);
    // h is drawn with pdf D(h) <n.h> / norm, norm = integral D <n.h>: 1 for the projected-area
    // normalised Beckmann and GGX, (s + 1)/(s + 2) for Blinn-Phong (normalised over solid angle).
    const double norm = brdf == Brdf::BlinnPhong ? (exponent + 1.) / (exponent + 2.) : 1.;
    const glm::dvec3 v(std::sqrt(1. - mu * mu), 0., mu);
    LobeMoments sum;
    for (int i = 0; i < samples; ++i) {
        glm::dvec3 h;
        if (brdf == Brdf::Ggx) {
            h = env::ggxHalfVector(i, samples, alpha);
        } else {
            const double u = env::radicalInverse(uint32_t(i)), phi = 2. * M_PI * i / samples;
            double cosH;
            if (brdf == Brdf::Beckmann) // tan^2 = -alpha^2 log(1 - u)
                cosH = 1. / std::sqrt(1. - alpha * alpha * std::log1p(-u));
            else // the CDF of c^(s+1) dc is c^(s+2)
                cosH = std::pow(u, 1. / (exponent + 2.));
            const double sinH = std::sqrt(std::max(0., 1. - cosH * cosH));
            h = {sinH * std::cos(phi), sinH * std::sin(phi), cosH};
        }
        // l = reflect(-v, h), dl = 4 <v.h> dh: D <n.l> dl = (D <n.h>) 4 <v.h> <n.l> / <n.h> dh.
        const double vh = glm::dot(v, h), nl = 2. * vh * h.z - mu;
        if (vh <= 0. || nl <= 0. || h.z <= 0.) continue;
        const double w = 4. * vh * nl / h.z;
        sum.albedo += w;
        sum.x += w * (2. * vh * h.x - v.x);
        sum.z += w * nl;
    }
    const double scale = norm / samples;
    return {sum.albedo * scale, sum.x * scale, sum.z * scale};
}

} // namespace

double lobeAlbedo(Brdf brdf, double mu, double perceptualRoughness, int samples) {
    return lobeMoments(brdf, mu, perceptualRoughness, samples).albedo;
}

namespace {

// The dominant direction's share of the normal from the lobe's moments at n.v = mu.
double dominantShareOf(const LobeMoments& m, double mu) {
    mu = std::clamp(mu, 1e-6, 1.);
    const double sinTheta = std::sqrt(1. - mu * mu);
    if (!(m.albedo > 0.) || !(m.z > 0.) || sinTheta < 1e-6) return 0.;
    // The centroid's angle phi from n (towards the mirror direction r, at theta = acos mu): the
    // mix (1 - f) r + f n is at angle phi where tan phi = (1 - f) sin theta / ((1 - f) mu + f).
    const double tanPhi = -m.x / m.z;
    if (!(tanPhi > 0.)) return 1.; // the centroid at the normal or past it: read along n
    const double a = sinTheta - mu * tanPhi;
    return std::clamp(a / (a + tanPhi), 0., 1.);
}

} // namespace

double lobeDominantShare(Brdf brdf, double mu, double perceptualRoughness, int samples) {
    return dominantShareOf(lobeMoments(brdf, mu, perceptualRoughness, samples), mu);
}

namespace {

// The lobe's albedo and dominant share tables for `brdf`, from one set of moments per entry.
struct LobeTables {
    Image albedo, dominant;
};

LobeTables lobeTables(Brdf brdf, int size, int samples) {
    LobeTables t{Image(size, size, 1), Image(size, size, 1)};
#pragma omp parallel for schedule(dynamic, 1)
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const double mu = tableColumnCosine(TableColumns::Ends, x, size);
            const LobeMoments m = lobeMoments(brdf, mu, (y + 0.5) / size, samples);
            *t.albedo.at(x, y) = float(m.albedo);
            *t.dominant.at(x, y) = float(dominantShareOf(m, mu));
        }
    return t;
}

// Bilinear with clamped edges at (u, v) in [0, 1]^2, and its slope in u (the interpolant's: the
// cell's, the last cell's at u = 1): columns at u = x/(width - 1), rows at texel centres,
// v = (y + 0.5)/height (SplitSumLighting::albedo). A table at least two entries wide.
glm::vec2 sampleTableAndSlope(const Image& table, int channel, float u, float v) {
    assert(table.width >= 2);
    const float x = std::clamp(u * float(table.width - 1), 0.f, float(table.width - 1));
    const float y = std::clamp(v * table.height - 0.5f, 0.f, float(table.height - 1));
    const int x0 = std::min(int(x), table.width - 2), y0 = int(y);
    const int y1 = std::min(y0 + 1, table.height - 1);
    const float fx = x - x0, fy = y - y0;
    const auto at = [&](int i, int j) { return table.at(i, j)[channel]; };
    const float low = (1.f - fx) * at(x0, y0) + fx * at(x0 + 1, y0);
    const float high = (1.f - fx) * at(x0, y1) + fx * at(x0 + 1, y1);
    const float slopeLow = at(x0 + 1, y0) - at(x0, y0), slopeHigh = at(x0 + 1, y1) - at(x0, y1);
    return {(1.f - fy) * low + fy * high,
            float(table.width - 1) * ((1.f - fy) * slopeLow + fy * slopeHigh)};
}

} // namespace

// ---- preparation ----------------------------------------------------------------------------

SplitSumLighting prepareSplitSum(const Environment& env, const SplitSumOptions& options) {
    const int size = options.size;
    assert(size >= 16 && (size & (size - 1)) == 0 && options.samples >= 1 &&
           options.filamentLevels >= 1 && options.filamentLevels <= log2Floor(size) - 1 &&
           options.albedoTableSize >= 2 && options.albedoSamples >= 1);
    SplitSumLighting lighting;
    lighting.albedoKind = options.albedo;
    lighting.vmfBandFactors = options.vmfBandFactors;
    lighting.weightedReflection = options.weightedReflection;
    lighting.texelAngle = M_PI / (size / 2);
    lighting.irradiance = projectEnvironmentSh(env, 2).irradiance;

    Image base;             // level 0 of the GGX chains, made when one is asked for
    RadiancePyramid source; // what their prefiltered levels read, made once
    for (EnvironmentLod rule : options.rules) {
        if (findChain(lighting, rule)) continue;
        SplitSumChain chain;
        chain.rule = rule;
        chain.blinnPhongLobe = options.blinnPhongLobe;
        const int levels = chainLevels(rule, size, options.filamentLevels);
        if (source.levels.empty() && levels > 1) source = radiancePyramid(env);
        if (rule == EnvironmentLod::Log2Sigma) {
            // Toksvig's chain on cube faces: an equirect chain's coarse texels near the poles are
            // whole polar caps.
            chain.cube =
                log2SigmaChain(env, source, size, levels, options.samples, chain.blinnPhongLobe,
                               lighting.texelAngle, chain.perceptualRoughness);
            assert(int(chain.cube.levels.size()) == levels);
            lighting.chains.push_back(std::move(chain));
            continue;
        }
        if (base.pixels.empty()) base = resampleEquirect(env.radiance, size, env.rotation);
        chain.levels.push_back(base);
        chain.perceptualRoughness.push_back(0.);
        for (int k = 1; k < levels; ++k) {
            const double r = environmentLodRoughness(rule, k, levels);
            const int samples = prefilterSamples(options.samples, k);
            // Never narrower than 4 x 2 (Unity's 7 levels from a small level 0 would run out).
            const int width = std::max(size >> k, 4);
            chain.levels.push_back(
                prefilteredLevel(source, chain.blinnPhongLobe, r, width, samples));
            chain.perceptualRoughness.push_back(r);
        }
        lighting.chains.push_back(std::move(chain));
    }

    for (Brdf brdf : {Brdf::BlinnPhong, Brdf::Beckmann, Brdf::Ggx}) {
        LobeTables t = lobeTables(brdf, options.albedoTableSize, options.albedoSamples);
        const size_t i = size_t(int(brdf) - 1);
        if (options.albedo == SpecularAlbedo::Lobe) lighting.albedo[i] = std::move(t.albedo);
        lighting.dominant[i] = options.dominantDirection
                                   ? std::move(t.dominant)
                                   : Image(options.albedoTableSize, options.albedoTableSize, 1);
    }
    if (options.albedo == SpecularAlbedo::EngineDfg)
        lighting.albedo[0] =
            dfgTable(options.albedoTableSize, options.albedoSamples, TableColumns::Ends);
    return lighting;
}

Status checkSplitSumMaterial(const Material& m) {
    if (m.brdf == Brdf::Tabulated)
        return Status::failure(
            "material.brdf: tabulated lobes have no split-sum (prefiltered) form");
    return Status::success();
}

// ---- lookups --------------------------------------------------------------------------------

const SplitSumChain* findChain(const SplitSumLighting& lighting, EnvironmentLod rule) {
    for (const SplitSumChain& chain : lighting.chains)
        if (chain.rule == rule) return &chain;
    return nullptr;
}

glm::vec3 sampleChain(const SplitSumChain& chain, double lod, glm::dvec3 direction) {
    if (!chain.cube.levels.empty()) return sampleCubeMipChain(chain.cube, lod, direction);
    assert(!chain.levels.empty());
    lod = std::clamp(lod, 0., double(chain.levels.size() - 1));
    const int k0 = int(lod), k1 = std::min(k0 + 1, int(chain.levels.size()) - 1);
    const float f = float(lod - k0);
    float a[3], b[3] = {0.f, 0.f, 0.f};
    sampleEquirect(chain.levels[size_t(k0)], direction, a);
    if (f > 0.f && k1 != k0) sampleEquirect(chain.levels[size_t(k1)], direction, b);
    return (1.f - f) * glm::vec3(a[0], a[1], a[2]) + f * glm::vec3(b[0], b[1], b[2]);
}

glm::vec3 irradianceAt(const SplitSumLighting& lighting, glm::dvec3 n, glm::dvec3 band) {
    assert(lighting.irradiance.size() >= size_t(shCount(2)));
    double y[9];
    evaluateSh(glm::normalize(n), 2, y);
    glm::dvec3 e(0.);
    for (int l = 0; l <= 2; ++l)
        for (int m = -l; m <= l; ++m)
            e += band[l] * y[shIndex(l, m)] * lighting.irradiance[size_t(shIndex(l, m))];
    return glm::vec3(glm::max(e, glm::dvec3(0.))); // truncation can ring below zero
}

float specularAlbedo(const SplitSumLighting& lighting, Brdf brdf, float mu,
                     float perceptualRoughness) {
    return specularAlbedoAndSlope(lighting, brdf, mu, perceptualRoughness).x;
}

glm::vec2 specularAlbedoAndSlope(const SplitSumLighting& lighting, Brdf brdf, float mu,
                                 float perceptualRoughness) {
    mu = std::clamp(mu, 0.f, 1.f);
    perceptualRoughness = std::clamp(perceptualRoughness, 0.f, 1.f);
    if (lighting.albedoKind == SpecularAlbedo::EngineDfg)
        return sampleTableAndSlope(lighting.albedo[0], 2, mu, perceptualRoughness);
    if (brdf != Brdf::BlinnPhong && brdf != Brdf::Beckmann && brdf != Brdf::Ggx)
        return glm::vec2(0.f);
    return sampleTableAndSlope(lighting.albedo[size_t(int(brdf) - 1)], 0, mu, perceptualRoughness);
}

float dominantShare(const SplitSumLighting& lighting, Brdf brdf, float mu,
                    float perceptualRoughness) {
    if (brdf != Brdf::BlinnPhong && brdf != Brdf::Beckmann && brdf != Brdf::Ggx) return 0.f;
    return sampleTableAndSlope(lighting.dominant[size_t(int(brdf) - 1)], 0,
                               std::clamp(mu, 0.f, 1.f), std::clamp(perceptualRoughness, 0.f, 1.f))
        .x;
}

glm::vec3 prefilteredRadiance(const SplitSumLighting& lighting, EnvironmentLod rule,
                              glm::dvec3 reflected, double perceptualRoughness,
                              double normalVariance) {
    const SplitSumChain* chain = findChain(lighting, rule);
    assert(chain && "the rule's chain was not prepared (SplitSumOptions::rules)");
    if (!chain) return glm::vec3(0.f);
    const int levels = int(chain->perceptualRoughness.size());
    double lod;
    if (rule == EnvironmentLod::Log2Sigma) {
        const double alpha = perceptualRoughness * perceptualRoughness;
        lod = log2SigmaLevel(reflectedSpread(alpha * alpha / 2., normalVariance),
                             lighting.texelAngle, levels);
    } else {
        lod = environmentLodLevel(rule, perceptualRoughness, levels);
    }
    return sampleChain(*chain, lod, glm::normalize(reflected));
}

} // namespace ndfmip
