// What the methods prepare to shade under an environment (method_unit.h): the prefiltered levels
// of one level rule, or the SH lighting for the image's view.
#include "methods/method_unit.h"
#include "ndfmip/environment_lighting.h"

namespace ndfmip {

Status prepareSplitSumSetup(const Material& material, const RenderTextures& textures, const RenderOptions& options,
                            ShaderSetup& setup) {
    if (!textures.environment) return Status::success();
    if (Status usable = checkSplitSumMaterial(material); !usable) return usable;
    SplitSumOptions split;
    split.rules = {options.environmentLod}; // only the chain this render reads
    setup.environmentLod = options.environmentLod;
    setup.splitSum = std::make_shared<const SplitSumLighting>(prepareSplitSum(textures.environment->environment, split));
    return Status::success();
}

Status prepareShLightingSetup(const Material& material, const RenderTextures& textures, ShaderSetup& setup) {
    if (!textures.environment) return Status::success();
    if (material.brdf == Brdf::Tabulated)
        return Status::failure("render: SH lighting needs a Lambert, Blinn-Phong, Beckmann or GGX material");
    setup.shLighting = std::make_shared<const ShLighting>(
        prepareShLighting(textures.environment->environment, kEnvironmentShOrder, setup.environmentView));
    return Status::success();
}

} // namespace ndfmip
