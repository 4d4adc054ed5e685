// ndfmip envmap IN.hdr|IN.exr -o DIR: an environment map's SH, GGX-prefiltered levels and DFG
// table.
#include <cstdio>
#include <memory>
#include <string>

#include "cli.h"
#include "ndfmip/environment_file.h"
#include "ndfmip/io.h"
#include "ndfmip/limits.h"
#include "ndfmip/spherical_harmonics.h"

namespace ndfmip::cli {
namespace {

struct EnvmapArgs {
    std::string input, output;
    EnvironmentFileOptions file;
    bool quiet = false;
};

void runEnvmap(const EnvmapArgs& a) {
    EnvironmentFileOptions options = a.file;
    if (!a.quiet)
        options.progress = [](int done, int total) {
            showProgress("envmap: GGX level", done, total);
        };
    Result<EnvironmentFileReport> written = environmentFile(a.input, a.output, options);
    if (!written) throw Failure(written.error().message);
    const EnvironmentFileReport& r = written.value();
    if (a.quiet) return;
    if (r.negativeTexels)
        std::fprintf(stderr, "ndfmip: warning: %s: %zu texels with negative values set to 0\n",
                     a.input.c_str(), r.negativeTexels);
    std::string roughness;
    for (double level : r.perceptualRoughness) {
        char text[32];
        std::snprintf(text, sizeof text, "%s%.3g", roughness.empty() ? "" : ", ", level);
        roughness += text;
    }
    std::printf("envmap  : %dx%d -> %s: SH l <= %d, %zu GGX levels %d to %d wide (perceptual "
                "roughness %s), DFG %dx%d (load %.1f ms, sh %.1f ms, ggx %.1f ms, dfg %.1f ms, "
                "write %.1f ms)\n",
                r.width, r.height, a.output.c_str(), a.file.shOrder, r.perceptualRoughness.size(),
                r.firstLevelWidth, r.lastLevelWidth, roughness.c_str(), a.file.dfgSize,
                a.file.dfgSize, r.loadMs, r.shMs, r.ggxMs, r.dfgMs, r.writeMs);
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
    c->add_option("--intensity", args->file.environment.intensity, "radiance scale")
        ->check(CLI::Range(1e-6f, 1e6f))
        ->capture_default_str();
    c->add_option("--rotation", args->file.environment.rotationDegrees,
                  "degrees about +Y (right-handed: +Z turns towards +X)")
        ->check(CLI::Range(-360.f, 360.f))
        ->capture_default_str();
    c->add_option("--sh-order", args->file.shOrder, "highest SH band l of the radiance")
        ->check(CLI::Range(0, kMaxShOrder))
        ->capture_default_str();
    c->add_option(
         "--size", args->file.size,
         "width of GGX level 0, a power of two (default: the map's, rounded up, at most 1024)")
        ->check(CLI::Range(8, 4096));
    c->add_option("--levels", args->file.levels,
                  "GGX levels (default: log2(size) - 5, as cmgen's 256 to 16 faces)")
        ->check(CLI::Range(1, 12));
    c->add_option("--samples", args->file.samples,
                  "GGX samples per texel of level 1, doubled per level from 2")
        ->check(CLI::Range(1, 65536))
        ->capture_default_str();
    c->add_option(
         "--layout", args->file.layout,
         "GGX level files: equirect (ggx_L<k>.exr), cube (ggx_L<k>_px.exr ... _nz.exr, the "
         "GL/Vulkan/KTX2 face order and orientation) or both")
        ->capture_default_str();
    c->add_option("--lod-mapping", args->file.lodMapping,
                  "level k of N has perceptual roughness r with lod = k/(N-1): filament (lod = r "
                  "(2 - r), as "
                  "cmgen and Filament's shaders) or linear (r = lod)")
        ->capture_default_str();
    c->add_option("--dfg-size", args->file.dfgSize, "the DFG table is N x N")
        ->check(CLI::Range(8, 1024))
        ->capture_default_str();
    c->add_option("--dfg-samples", args->file.dfgSamples, "samples per DFG texel")
        ->check(CLI::Range(1, 65536))
        ->capture_default_str();
    c->add_flag("--half", args->file.half, "store the images as 16-bit half floats");
    c->add_flag("--ktx2", args->file.ktx2,
                "also write the GGX levels as one KTX2 file per layout (ggx_cube.ktx2: a cube map; "
                "ggx_equirect.ktx2), and dfg.ktx2; RGBA16F, every level a mip");
    c->add_flag("--dds", args->file.dds,
                "the same textures as DDS (DX10 header, R16G16B16A16_FLOAT): ggx_cube.dds, "
                "ggx_equirect.dds, dfg.dds");
    c->add_flag("-q,--quiet", args->quiet, "print nothing but errors");
    c->callback([args] { runEnvmap(*args); });
}

} // namespace ndfmip::cli
