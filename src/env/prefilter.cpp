// GGX prefiltering of an equirectangular map for the split-sum approximation (environment.h).
//
// Filtered importance sampling (Krivanek and Colbert 2008), as Filament's cmgen does it: with
// n = v = r, GGX samples h give l = 2 (n.h) h - n with pdf(l) = D(h) / 4, and the level is
//     LD(r) = sum L(l) <n.l> / sum <n.l>,
// each L(l) read from the radiance's mip chain at lod = log4(K Omega_s / Omega_p) with
// Omega_s = 1 / (N pdf) the sample's solid angle, Omega_p a source texel's and K = 4 (cmgen's
// bias, one level coarser than the footprint). Omega_p is the squared angular height of a texel,
// pi^2 / h^2: the texel's solid angle at the equator and the size it keeps towards the poles,
// where its width shrinks with cos(lat).
//
// The speed comes from the map's symmetry: turning a direction about +Y shifts it along u and
// keeps its row, so all texels of an output row share one list of (mip level, source row, u
// offset, weight) taps; each tap then adds a shifted source row to the whole output row. Source
// rows are stored in phases (texels p, p + s, p + 2s, ... for a level s times wider than the
// output; a narrower level is first interpolated to the output's width) so that every tap is one
// contiguous multiply-add over the row.
#include "ndfmip/environment.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdint>

#include "env/env_internal.h"

namespace ndfmip {

double lodToPerceptualRoughness(LodMapping mapping, double lod) {
    lod = std::clamp(lod, 0., 1.);
    return mapping == LodMapping::Filament ? 1. - std::sqrt(1. - lod) : lod;
}

double perceptualRoughnessToLod(LodMapping mapping, double roughness) {
    roughness = std::clamp(roughness, 0., 1.);
    return mapping == LodMapping::Filament ? roughness * (2. - roughness) : roughness;
}

bool lodMappingFromString(const std::string& name, LodMapping& out) {
    if (name == "filament")
        out = LodMapping::Filament;
    else if (name == "linear")
        out = LodMapping::Linear;
    else
        return false;
    return true;
}

const char* lodMappingName(LodMapping mapping) {
    return mapping == LodMapping::Filament ? "filament" : "linear";
}

namespace {

// cmgen's LOD bias: a sample reads the level one step coarser than its own footprint.
constexpr double kLodBias = 4.;
// The working chain starts at most this wide (an 8k map is first averaged down to 4k).
constexpr int kMaxSourceWidth = 4096;

int log2Exact(int n) {
    int k = 0;
    while ((1 << k) < n) ++k;
    return k;
}

// A source level laid out for one output width w: for a level s = width / w times wider, row y,
// phase p holds texels p, p + s, p + 2s, ... (2w + 1 of them, wrapping), so reading every s-th
// texel from any start is contiguous. A level narrower than the output is first interpolated
// linearly to the output's width (s = 1), so that its taps also step one texel per output
// texel; `width` is then the output's.
struct PhasedLevel {
    int width = 0, height = 0;
    int stride = 1;      // s
    int phaseTexels = 0; // texels per phase
    std::vector<float> texels;
    size_t offset(int y, int p) const {
        return (size_t(y) * size_t(stride) + size_t(p)) * size_t(phaseTexels) * 3;
    }
    const float* phase(int y, int p) const { return texels.data() + offset(y, p); }
};

PhasedLevel phasedLevel(const Image& level, int outWidth) {
    PhasedLevel out;
    out.width = std::max(level.width, outWidth);
    out.height = level.height;
    out.stride = out.width / outWidth;
    out.phaseTexels = 2 * outWidth + 1;
    out.texels.resize(size_t(out.height) * size_t(out.stride) * size_t(out.phaseTexels) * 3);
    const double scale = double(level.width) / out.width; // source texels per texel of `out`
    for (int y = 0; y < out.height; ++y)
        for (int p = 0; p < out.stride; ++p) {
            float* dst = out.texels.data() + out.offset(y, p);
            for (int q = 0; q < out.phaseTexels; ++q) {
                const int x = (p + out.stride * q) % out.width;
                if (level.width == out.width) {
                    const float* src = level.at(x, y);
                    std::copy(src, src + 3, dst + 3 * q);
                    continue;
                }
                // Texel centres: x + 0.5 of `out` is at (x + 0.5) scale of the level.
                const double c = (x + 0.5) * scale - 0.5 + level.width;
                const int i = int(c);
                const float f = float(c - i);
                const float* a = level.at(i % level.width, y);
                const float* b = level.at((i + 1) % level.width, y);
                for (int k = 0; k < 3; ++k) dst[3 * q + k] = (1.f - f) * a[k] + f * b[k];
            }
        }
    return out;
}

// A GGX sample in the frame n = v = z: its direction l, weight <n.l> / sum <n.l>, and lod.
struct LobeSample {
    glm::dvec3 l;
    double weight;
    double lod;
};

// The lobe a level is convolved with: GGX of `alpha`, or Blinn-Phong of exponent `exponent`
// (D proportional to <n.h>^s).
struct PrefilterLobe {
    bool blinnPhong = false;
    double alpha = 0.;
    double exponent = 0.;
};

std::vector<LobeSample> lobeSamples(const PrefilterLobe& lobe, int count, double texelSolidAngle,
                                    int maxLevel) {
    std::vector<LobeSample> samples;
    double total = 0.;
    const double a2 = lobe.alpha * lobe.alpha, s = lobe.exponent;
    for (int i = 0; i < count; ++i) {
        glm::dvec3 h;
        double pdfH; // D(h) <n.h>, a density over half vectors
        if (lobe.blinnPhong) {
            // D <n.h> = (s + 2)/(2 pi) c^(s+1) integrates to 1; its CDF in c is c^(s+2).
            const double phi = 2. * M_PI * i / count, u = env::radicalInverse(uint32_t(i));
            const double c = std::pow(std::max(u, 1e-300), 1. / (s + 2.));
            const double sinH = std::sqrt(std::max(0., 1. - c * c));
            h = {sinH * std::cos(phi), sinH * std::sin(phi), c};
            pdfH = (s + 2.) / (2. * M_PI) * std::pow(c, s + 1.);
        } else {
            h = env::ggxHalfVector(i, count, lobe.alpha);
            const double f = (lobe.alpha - 1.) * ((lobe.alpha + 1.) * h.z * h.z) + 1.;
            pdfH = a2 / (M_PI * f * f) * h.z;
        }
        const double cos2 = h.z * h.z, cosH = h.z;
        const double cosL = 2. * cos2 - 1.;
        if (cosL <= 0.) continue;
        const glm::dvec3 l(2. * cosH * h.x, 2. * cosH * h.y, cosL);
        // pdf(l) = D(h) <n.h> / (4 <v.h>), and <v.h> = <n.h> with n = v.
        const double pdf = pdfH / (4. * cosH);
        const double omegaS = 1. / (count * pdf);
        const double lod =
            std::clamp(0.5 * std::log2(kLodBias * omegaS / texelSolidAngle), 0., double(maxLevel));
        samples.push_back({l, cosL, lod});
        total += cosL;
    }
    for (LobeSample& sample : samples) sample.weight /= total;
    return samples;
}

// One bilinear read of source level `level`, row `row`, at texel coordinate `start` of output
// texel 0 (advancing by width / outWidth per output texel), times `weight`.
struct Tap {
    int level, row;
    double start;
    float weight;
};

// The taps of output row y of a width-texel level: every sample turned to the row's texel 0,
// split over two mip levels and two source rows.
void rowTaps(const std::vector<LobeSample>& samples, const std::vector<PhasedLevel>& levels,
             int width, int y, double rotation, std::vector<Tap>& taps) {
    taps.clear();
    const int height = width / 2;
    const glm::dvec3 n = equirectDirection(0.5 / width, (y + 0.5) / height);
    // East and north at the texel (cos(lat) > 0 at every texel centre).
    const glm::dvec3 t = glm::normalize(glm::dvec3(n.z, 0., -n.x));
    const glm::dvec3 b = glm::cross(n, t);
    const double uShift = rotation / (2. * M_PI); // file u = seen u + rotation / 2 pi
    for (const LobeSample& s : samples) {
        const glm::dvec2 uv = equirectCoordinates(t * s.l.x + b * s.l.y + n * s.l.z);
        const int j0 = int(s.lod), j1 = std::min(j0 + 1, int(levels.size()) - 1);
        const double fraction = s.lod - j0;
        for (int side = 0; side < 2; ++side) {
            const int j = side == 0 ? j0 : j1;
            const double levelWeight = side == 0 ? 1. - fraction : fraction;
            if (levelWeight <= 0.) continue;
            const PhasedLevel& level = levels[size_t(j)];
            const double sy = uv.y * level.height - 0.5, sx = (uv.x + uShift) * level.width - 0.5;
            const int y0 = int(std::floor(sy));
            const double fy = sy - y0;
            for (int r = 0; r < 2; ++r) {
                const double w = s.weight * levelWeight * (r == 0 ? 1. - fy : fy);
                if (w <= 0.) continue;
                int row = y0 + r;
                double x = sx;
                // Past a pole the row continues on the far side of the sphere.
                if (row < 0 || row >= level.height) {
                    row = row < 0 ? -1 - row : 2 * level.height - 1 - row;
                    x += 0.5 * level.width;
                }
                x = std::fmod(x, double(level.width));
                if (x < 0.) x += level.width;
                taps.push_back({j, row, x, float(w)});
            }
        }
    }
}

// out += wa a + wb b over n floats: the inner loop of every tap, vectorised (the arrays never
// overlap), in AVX2 where the CPU has it (25% faster than SSE2 here).
inline void addWeightedLoop(float* __restrict out, const float* __restrict a,
                            const float* __restrict b, float wa, float wb, int n) {
    for (int t = 0; t < n; ++t) out[t] += wa * a[t] + wb * b[t];
}

#if defined(__x86_64__) && defined(__GNUC__)
__attribute__((target("avx2"))) void addWeightedAvx2(float* out, const float* a, const float* b,
                                                     float wa, float wb, int n) {
    addWeightedLoop(out, a, b, wa, wb, n);
}
#endif

void addWeighted(float* out, const float* a, const float* b, float wa, float wb, int n) {
#if defined(__x86_64__) && defined(__GNUC__)
    static const bool avx2 = __builtin_cpu_supports("avx2");
    if (avx2) return addWeightedAvx2(out, a, b, wa, wb, n);
#endif
    addWeightedLoop(out, a, b, wa, wb, n);
}

// Adds the taps to one output row of `width` RGB texels.
void applyTaps(const std::vector<Tap>& taps, const std::vector<PhasedLevel>& levels, int width,
               float* out) {
    for (const Tap& tap : taps) {
        // Texels i0 + s x and i0 + 1 + s x: two phases, both contiguous.
        const PhasedLevel& level = levels[size_t(tap.level)];
        const int s = level.stride, i0 = int(tap.start), i1 = i0 + 1;
        const float fx = float(tap.start - i0);
        addWeighted(out, level.phase(tap.row, i0 % s) + 3 * (i0 / s),
                    level.phase(tap.row, i1 % s) + 3 * (i1 / s), tap.weight * (1.f - fx),
                    tap.weight * fx, 3 * width);
    }
}

Image filterLevel(const std::vector<Image>& pyramid, const PrefilterLobe& lobe, int width,
                  int sampleCount, double rotation) {
    const int height = width / 2;
    const double texelAngle = M_PI / pyramid[0].height;
    const auto samples =
        lobeSamples(lobe, sampleCount, texelAngle * texelAngle, int(pyramid.size()) - 1);
    // Only the levels some sample reads are laid out (rough lobes never read the finest).
    double finest = double(pyramid.size());
    for (const LobeSample& s : samples) finest = std::min(finest, s.lod);
    std::vector<PhasedLevel> levels(pyramid.size());
    for (size_t j = size_t(finest); j < pyramid.size(); ++j)
        levels[j] = phasedLevel(pyramid[j], width);
    Image out(width, height, 3);
#pragma omp parallel
    {
        std::vector<Tap> taps;
#pragma omp for schedule(dynamic, 1)
        for (int y = 0; y < height; ++y) {
            rowTaps(samples, levels, width, y, rotation, taps);
            applyTaps(taps, levels, width, out.at(0, y));
        }
    }
    return out;
}

} // namespace

// Area-weighted halvings of the map at a power-of-two width.
RadiancePyramid radiancePyramid(const Environment& env) {
    RadiancePyramid pyramid;
    pyramid.rotation = env.rotation;
    std::vector<Image>& levels = pyramid.levels;
    const Image& map = env.radiance;
    const int base = std::min(1 << log2Exact(map.width), kMaxSourceWidth);
    levels.push_back(base == map.width ? map : resampleEquirect(map, base));
    while (levels.back().width > 2)
        levels.push_back(resampleEquirect(levels.back(), levels.back().width / 2));
    return pyramid;
}

int defaultPrefilterSize(int mapWidth) {
    return std::clamp(1 << log2Exact(mapWidth), 8, 1024);
}

int prefilterSamples(int levelOneSamples, int level) {
    return levelOneSamples << std::max(0, level - 1);
}

std::vector<PrefilteredLevel> prefilterGgx(const Environment& env,
                                           const PrefilterOptions& options) {
    const int size = options.size > 0 ? options.size : defaultPrefilterSize(env.radiance.width);
    const int levelCount = options.levels > 0 ? options.levels : std::max(1, log2Exact(size) - 5);
    assert(size >= 8 && (size & (size - 1)) == 0 && levelCount <= log2Exact(size) - 2 &&
           options.samples >= 1);
    RadiancePyramid source;
    std::vector<PrefilteredLevel> out;
    for (int k = 0; k < levelCount; ++k) {
        const int width = size >> k;
        PrefilteredLevel level;
        level.perceptualRoughness =
            levelCount == 1
                ? 0.
                : lodToPerceptualRoughness(options.mapping, double(k) / (levelCount - 1));
        if (level.perceptualRoughness <= 0.) {
            level.radiance = resampleEquirect(env.radiance, width, env.rotation);
        } else {
            if (source.levels.empty()) source = radiancePyramid(env);
            level.samples = prefilterSamples(options.samples, k);
            level.radiance =
                prefilterGgxLevel(source, level.perceptualRoughness, width, level.samples);
        }
        out.push_back(std::move(level));
        if (options.progress) options.progress(k + 1, levelCount);
    }
    return out;
}

Image prefilterGgxLevel(const RadiancePyramid& source, double perceptualRoughness, int width,
                        int samples) {
    assert(perceptualRoughness > 0. && width >= 4 && (width & (width - 1)) == 0 && samples >= 1 &&
           !source.levels.empty());
    return filterLevel(source.levels, {false, perceptualRoughness * perceptualRoughness, 0.}, width,
                       samples, source.rotation);
}

Image prefilterGgxLevel(const Environment& env, double perceptualRoughness, int width,
                        int samples) {
    return prefilterGgxLevel(radiancePyramid(env), perceptualRoughness, width, samples);
}

Image prefilterBlinnPhongLevel(const RadiancePyramid& source, double exponent, int width,
                               int samples) {
    assert(exponent >= 0. && width >= 4 && (width & (width - 1)) == 0 && samples >= 1 &&
           !source.levels.empty());
    return filterLevel(source.levels, {true, 0., exponent}, width, samples, source.rotation);
}

Image prefilterBlinnPhongLevel(const Environment& env, double exponent, int width, int samples) {
    return prefilterBlinnPhongLevel(radiancePyramid(env), exponent, width, samples);
}

} // namespace ndfmip
