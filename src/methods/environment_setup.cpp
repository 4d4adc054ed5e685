// What the methods prepare to shade under an environment (method_unit.h): the prefiltered levels
// of one level rule, or the SH lighting for the image's view, both made once per loaded map
// (environment_cache.h) and shared by every render under it.
#include "methods/method_unit.h"
#include "ndfmip/environment_cache.h"

namespace ndfmip {

Status prepareSplitSumSetup(const Material& material, const RenderTextures& textures, const RenderOptions& options,
                            ShaderSetup& setup) {
    if (!textures.environment) return Status::success();
    if (Status usable = checkSplitSumMaterial(material); !usable) return usable;
    setup.environmentLod = options.environmentLod;
    // Only the chain it reads; a Blinn-Phong material's convolved with its own lobe.
    setup.splitSum = cachedSplitSum(*textures.environment, options.environmentLod, material.brdf == Brdf::BlinnPhong);
    return Status::success();
}

Status prepareShLightingSetup(const Material& material, const RenderTextures& textures, ShaderSetup& setup) {
    if (!textures.environment) return Status::success();
    if (material.brdf == Brdf::Tabulated)
        return Status::failure("render: SH lighting needs a Lambert, Blinn-Phong, Beckmann or GGX material");
    setup.shLighting = cachedShLighting(*textures.environment, kEnvironmentShOrder, setup.environmentView);
    return Status::success();
}

} // namespace ndfmip
