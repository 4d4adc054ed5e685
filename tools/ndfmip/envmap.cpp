// ndfmip envmap IN.hdr|IN.exr -o DIR: an environment map's SH, GGX-prefiltered levels and DFG
// table.
#include <cstdio>
#include <memory>
#include <string>

#include "cli.h"
#include "ndfmip/environment.h"
#include "ndfmip/io.h"
#include "ndfmip/limits.h"
#include "ndfmip/spherical_harmonics.h"

namespace ndfmip::cli {
namespace {

struct EnvmapArgs {
    std::string input, output, mapping = "filament", layout = "equirect";
    EnvironmentOptions environment;
    int shOrder = 8;
    int size = 0, levels = 0, samples = 1024;
    int dfgSize = 128, dfgSamples = 4096;
    bool half = false;
    bool ktx2 = false;
    bool dds = false;
    bool quiet = false;
};

int log2Of(int n) {
    int k = 0;
    while ((1 << k) < n) ++k;
    return k;
}

void runEnvmap(const EnvmapArgs& a) {
    PrefilterOptions prefilter;
    if (!lodMappingFromString(a.mapping, prefilter.mapping))
        throw Failure("--lod-mapping " + quote(a.mapping) + ": expected filament or linear");
    if (a.size != 0 && (a.size & (a.size - 1)) != 0)
        throw Failure("--size " + std::to_string(a.size) + ": expected a power of two");
    if (a.layout != "equirect" && a.layout != "cube" && a.layout != "both")
        throw Failure("--layout " + quote(a.layout) + ": expected equirect, cube or both");
    prefilter.levels = a.levels;
    prefilter.samples = a.samples;

    long long start = nowNanoseconds();
    EnvironmentReport report;
    Result<Environment> loaded = [&] {
        // The peak from the options, checked against --max-memory by the decoder from the map's
        // header before it allocates: per texel of the map its decoded file (four floats at
        // most), the radiance and its pyramid; beside them the GGX levels, at most 1024 wide by
        // default, as equirect levels, cube faces and textures.
        const int64_t width = a.size != 0 ? a.size : 1024;
        const auto levelBytes = int64_t(double(width) * double(width / 2) * 12.0 * 4.0 / 3.0);
        const PlannedPeak peak("prefiltering", 16.0 + 12.0 + 16.0, 3 * levelBytes);
        return loadEnvironment(a.input, a.environment, &report);
    }();
    if (!loaded) throw Failure(loaded.error().message);
    const Environment& env = loaded.value();
    prefilter.size = a.size != 0 ? a.size : defaultPrefilterSize(env.radiance.width);
    if (a.levels > log2Of(prefilter.size) - 2)
        throw Failure("--levels " + std::to_string(a.levels) + ": a " +
                      std::to_string(prefilter.size) + "-wide level 0 has at most " +
                      std::to_string(log2Of(prefilter.size) - 2) + " levels (down to 4x2)");
    if (report.negativeTexels && !a.quiet)
        std::fprintf(stderr, "ndfmip: warning: %s: %zu texels with negative values set to 0\n",
                     a.input.c_str(), report.negativeTexels);
    Result<std::string> hash = sha256File(a.input);
    if (!hash) throw Failure(hash.error().message);
    const double loadMs = millisecondsSince(start);

    start = nowNanoseconds();
    EnvironmentBake bake;
    bake.sh = projectEnvironmentSh(env, a.shOrder);
    const double shMs = millisecondsSince(start);

    start = nowNanoseconds();
    if (!a.quiet)
        prefilter.progress = [](int done, int total) {
            showProgress("envmap: GGX level", done, total);
        };
    bake.levels = prefilterGgx(env, prefilter);
    bake.mapping = prefilter.mapping;
    bake.equirect = a.layout != "cube";
    bake.cube = a.layout != "equirect";
    bake.ktx2 = a.ktx2;
    bake.dds = a.dds;
    const double ggxMs = millisecondsSince(start);

    start = nowNanoseconds();
    bake.dfg = dfgTable(a.dfgSize, a.dfgSamples);
    bake.dfgSamples = a.dfgSamples;
    const double dfgMs = millisecondsSince(start);

    start = nowNanoseconds();
    EnvironmentSource source{a.input, hash.value(), env.radiance.width, env.radiance.height,
                             a.environment};
    Status written = writeEnvironment(a.output, bake, source, a.half);
    if (!written) throw Failure(written.error);
    const double writeMs = millisecondsSince(start);

    if (!a.quiet) {
        std::string roughness;
        for (const PrefilteredLevel& level : bake.levels) {
            char text[32];
            std::snprintf(text, sizeof text, "%s%.3g", roughness.empty() ? "" : ", ",
                          level.perceptualRoughness);
            roughness += text;
        }
        std::printf(
            "envmap  : %dx%d -> %s: SH l <= %d, %zu GGX levels %d to %d wide (perceptual roughness "
            "%s), "
            "DFG %dx%d (load %.1f ms, sh %.1f ms, ggx %.1f ms, dfg %.1f ms, write %.1f ms)\n",
            env.radiance.width, env.radiance.height, a.output.c_str(), a.shOrder,
            bake.levels.size(), bake.levels.front().radiance.width,
            bake.levels.back().radiance.width, roughness.c_str(), a.dfgSize, a.dfgSize, loadMs,
            shMs, ggxMs, dfgMs, writeMs);
    }
}

} // namespace

void addEnvmapCommand(CLI::App& app) {
    auto args = std::make_shared<EnvmapArgs>();
    CLI::App* c =
        app.add_subcommand("envmap", "an equirectangular HDR environment's SH, GGX-prefiltered "
                                     "levels and DFG table (docs/ENVIRONMENT.md)");
    c->add_option("input", args->input,
                  "equirectangular (2:1) Radiance .hdr or OpenEXR map, +Y up, centre +Z")
        ->required();
    c->add_option("-o,--output", args->output, "output directory")->required();
    c->add_option("--intensity", args->environment.intensity, "radiance scale")
        ->check(CLI::Range(1e-6f, 1e6f))
        ->capture_default_str();
    c->add_option("--rotation", args->environment.rotationDegrees,
                  "degrees about +Y (right-handed: +Z turns towards +X)")
        ->check(CLI::Range(-360.f, 360.f))
        ->capture_default_str();
    c->add_option("--sh-order", args->shOrder, "highest SH band l of the radiance")
        ->check(CLI::Range(0, kMaxShOrder))
        ->capture_default_str();
    c->add_option(
         "--size", args->size,
         "width of GGX level 0, a power of two (default: the map's, rounded up, at most 1024)")
        ->check(CLI::Range(8, 4096));
    c->add_option("--levels", args->levels,
                  "GGX levels (default: log2(size) - 5, as cmgen's 256 to 16 faces)")
        ->check(CLI::Range(1, 12));
    c->add_option("--samples", args->samples,
                  "GGX samples per texel of level 1, doubled per level from 2")
        ->check(CLI::Range(1, 65536))
        ->capture_default_str();
    c->add_option(
         "--layout", args->layout,
         "GGX level files: equirect (ggx_L<k>.exr), cube (ggx_L<k>_px.exr ... _nz.exr, the "
         "GL/Vulkan/KTX2 face order and orientation) or both")
        ->capture_default_str();
    c->add_option("--lod-mapping", args->mapping,
                  "level k of N has perceptual roughness r with lod = k/(N-1): filament (lod = r "
                  "(2 - r), as "
                  "cmgen and Filament's shaders) or linear (r = lod)")
        ->capture_default_str();
    c->add_option("--dfg-size", args->dfgSize, "the DFG table is N x N")
        ->check(CLI::Range(8, 1024))
        ->capture_default_str();
    c->add_option("--dfg-samples", args->dfgSamples, "samples per DFG texel")
        ->check(CLI::Range(1, 65536))
        ->capture_default_str();
    c->add_flag("--half", args->half, "store the images as 16-bit half floats");
    c->add_flag("--ktx2", args->ktx2,
                "also write the GGX levels as one KTX2 file per layout (ggx_cube.ktx2: a cube map; "
                "ggx_equirect.ktx2), and dfg.ktx2; RGBA16F, every level a mip");
    c->add_flag("--dds", args->dds,
                "the same textures as DDS (DX10 header, R16G16B16A16_FLOAT): ggx_cube.dds, "
                "ggx_equirect.dds, dfg.dds");
    c->add_flag("-q,--quiet", args->quiet, "print nothing but errors");
    c->callback([args] { runEnvmap(*args); });
}

} // namespace ndfmip::cli
