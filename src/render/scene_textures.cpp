// What a render reads besides the scene: the normal map, the albedo and its mips, the bake
// (from a folder or made on the fly). Shared by `ndfmip render` and the Python module.
#include <cmath>
#include <cstdio>
#include <optional>

#include "methods/method_unit.h"
#include "ndfmip/environment_lighting.h"
#include "ndfmip/io.h"
#include "ndfmip/limits.h"
#include "ndfmip/method_parameters.h"
#include "ndfmip/render.h"
#include "ndfmip/vmf.h"

namespace ndfmip {
namespace {
const std::pair<const char*, RoughnessMapping> kMappings[] = {
    {"ours", RoughnessMapping::Ours},         {"hdrp", RoughnessMapping::Hdrp},
    {"filament", RoughnessMapping::Filament}, {"godot", RoughnessMapping::Godot},
    {"unreal", RoughnessMapping::Unreal},
};
} // namespace

const char* roughnessMappingName(RoughnessMapping mapping) {
    for (const auto& [n, m] : kMappings)
        if (m == mapping) return n;
    return "?";
}

bool roughnessMappingFromString(const std::string& name, RoughnessMapping& out) {
    for (const auto& [n, m] : kMappings)
        if (name == n) {
            out = m;
            return true;
        }
    return false;
}

Result<SharedImage> loadAlbedo(const std::string& path, int width, int height) {
    Result<SourceImage> source = loadImage(path);
    if (!source) return source.error();
    const Image& image = source->image;
    if (Status size = checkAlbedoSize(image, width, height, path); !size) return Error{size.error};
    Image rgb(image.width, image.height, 3);
    for (size_t i = 0; i < image.texelCount(); ++i)
        for (int c = 0; c < 3; ++c) {
            float v = image.pixels[i * image.channels + c];
            if (!std::isfinite(v)) return Error{path + ": NaN or infinite albedo value"};
            // The sRGB transfer function (IEC 61966-2-1) for integer files.
            if (!source->isFloat)
                v = v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
            rgb.pixels[3 * i + c] = std::max(v, 0.f);
        }
    return std::make_shared<const Image>(std::move(rgb));
}

Result<RenderTextures> loadSceneTextures(const Scene& scene, const std::string& method,
                                         const SceneTextureOptions& options) {
    if (scene.geometry.type == GeometryType::FacetedSphere) return RenderTextures{}; // no textures
    const bool bakeless = method == kGroundTruth || method == kExact;
    // The bake a shader reads (toksvig-lut: toksvig's; roughness-mips: naive's), from the method
    // table.
    const MethodShader* shader = findShader(method);
    if (!bakeless && !shader)
        return Error{"unknown method " + quote(method) + " (expected " + renderMethodNames() + ")"};
    RenderTextures textures;
    DecodeReport report;
    // The peak from the options, checked by the decoder from the map's header before it
    // allocates: the decoded file, the normals and their pyramid, and a bake made here.
    const bool bakesHere = !bakeless && options.bakeDir.empty() && scene.bakeDir.empty();
    BakeOptions planned;
    if (bakesHere) planned.parameters = parametersOf(shader->bake, options.bakeParameters);
    Result<Image> normals = [&] {
        const PlannedPeak peak(
            bakesHere ? bakeDescription(shader->bake, planned) : std::string("the normal map"),
            16.0 + (bakesHere ? bakeBytesPerTexel(shader->bake, planned) : 12.0 + 16.0));
        return loadNormalMap(scene.normalMap.path, scene.normalMap.decode, &report);
    }();
    if (!normals) return normals.error();
    if (options.decoded) options.decoded(report);
    textures.normals = std::make_shared<const Image>(std::move(normals.value()));
    const std::string bakeDir = options.bakeDir.empty() ? scene.bakeDir : options.bakeDir;
    SharedImage albedo;
    if (!scene.albedoMap.empty()) {
        Result<SharedImage> loaded =
            loadAlbedo(scene.albedoMap, textures.normals->width, textures.normals->height);
        if (!loaded) return loaded.error();
        albedo = loaded.value();
    }
    // Needed to bake on the fly and for the albedo's mips.
    std::optional<Pyramid> pyramid;
    if ((!bakeless && bakeDir.empty()) || albedo) pyramid = buildPyramid(textures.normals);
    if (!bakeless) {
        if (!bakeDir.empty()) {
            Result<Bake> bake = loadBake(bakeDir);
            if (!bake) return bake.error();
            textures.bake = std::move(bake.value());
        } else {
            BakeOptions bakeOptions;
            bakeOptions.parameters = parametersOf(shader->bake, options.bakeParameters);
            bakeOptions.albedo = albedo;
            // A bake fitted to the material's roughness (ggx-fit) is fitted to the scene's.
            if (methodUnit(shader->bake).fitsMaterialRoughness)
                bakeOptions.baseRoughness = scene.material.roughness;
            if (Status s = checkCommandParameterValues(options.bakeParameters, kParameterRender,
                                                       ParameterNaming::Key);
                !s)
                return Error{s.error};
            if (Status s = checkBakeMemory(scene.normalMap.path, shader->bake, bakeOptions,
                                           textures.normals->width, textures.normals->height);
                !s)
                return Error{s.error};
            textures.bake = bakeMethod(shader->bake, *pyramid, bakeOptions);
        }
    }
    if (albedo) textures.albedo = albedoMips(*pyramid, albedo);
    if (!scene.environment.path.empty()) {
        Result<Environment> env =
            loadEnvironment(scene.environment.path, scene.environment.options);
        if (!env) return env.error();
        textures.environment = std::make_shared<const EnvironmentLighting>(
            makeEnvironmentLighting(std::move(env.value())));
    }
    return textures;
}

Status checkRenderOptions(const RenderOptions& o) {
    auto outside = [](const char* name, double value, double lo, double hi) {
        char text[160];
        std::snprintf(text, sizeof text, "%s %.10g: expected %.10g .. %.10g", name, value, lo, hi);
        return Status::failure(text);
    };
    if (!(o.spp >= 1 && o.spp <= (1 << 20))) return outside("spp", o.spp, 1, 1 << 20);
    if (!(o.anisotropy >= 1 && o.anisotropy <= 64))
        return outside("anisotropy", o.anisotropy, 1, 64);
    if (!(o.taps >= 1 && o.taps <= 16)) return outside("taps", o.taps, 1, 16);
    if (!(o.lodBias >= -16.f && o.lodBias <= 16.f)) return outside("lod_bias", o.lodBias, -16, 16);
    if (!(o.varianceScale > 0.f && o.varianceScale <= 1e3f))
        return outside("variance_scale", o.varianceScale, 0, 1e3);
    if (!(o.specularAntiAliasing.variance >= 0.f && o.specularAntiAliasing.variance <= 1e3f))
        return outside("specular_aa_variance", o.specularAntiAliasing.variance, 0, 1e3);
    if (!(o.specularAntiAliasing.threshold >= 0.f && o.specularAntiAliasing.threshold <= 1.f))
        return outside("specular_aa_threshold", o.specularAntiAliasing.threshold, 0, 1);
    if (!std::isfinite(o.pixelShift.x) || !std::isfinite(o.pixelShift.y))
        return Status::failure("pixel_shift: not finite");
    return Status::success();
}

} // namespace ndfmip
