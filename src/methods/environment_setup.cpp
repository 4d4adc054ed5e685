// What the methods prepare to shade under an environment (method_unit.h): the prefiltered levels
// of one level rule, or the SH lighting for the image's view or for a set of views, all made once
// per loaded map (environment_cache.h) and shared by every render under it.
#include "methods/method_unit.h"
#include "ndfmip/environment_cache.h"

namespace ndfmip {

Status prepareSplitSumSetup(const Material& material, const RenderTextures& textures,
                            const RenderOptions& options, ShaderSetup& setup) {
    if (!textures.environment) return Status::success();
    if (Status usable = checkSplitSumMaterial(material); !usable) return usable;
    setup.environmentLod = options.environmentLod;
    // Only the chain it reads; a Blinn-Phong material's convolved with its own lobe.
    setup.splitSum = cachedSplitSum(*textures.environment, options.environmentLod,
                                    material.brdf == Brdf::BlinnPhong, options.dominantDirection);
    return Status::success();
}

Status prepareShLightingSetup(const Material& material, const RenderTextures& textures,
                              const RenderOptions& options, ShaderSetup& setup) {
    if (!textures.environment) return Status::success();
    if (material.brdf == Brdf::Tabulated)
        return Status::failure(
            "render: SH lighting needs a Lambert, Blinn-Phong, Beckmann or GGX material");
    if (options.shViews > 0)
        setup.shViews = cachedShViewSet(*textures.environment, options.environmentShOrder,
                                        shViewFrequency(options.shViews), options.shCosine);
    else
        setup.shLighting = cachedShLighting(*textures.environment, options.environmentShOrder,
                                            setup.environmentView, options.shCosine);
    return Status::success();
}

const ShLighting& shLightingAt(const ShaderSetup& setup, glm::vec3 v,
                               const glm::mat3& toEnvironment) {
    if (!setup.shViews) return *setup.shLighting;
    // A pixel's taps share its view: the same lighting (and id, so the sh shading's rotation into
    // the frame is reused) until the view or the set changes. A new view gets a fresh id
    // (interpolateShLighting), so the rotation cache never serves the previous pixel's lighting.
    // The set is known by its first view's id, unique per preparation.
    thread_local ShLighting perPixel;
    thread_local glm::dvec3 lastView{0.};
    thread_local uint64_t lastSet = 0;
    const glm::dvec3 view(toEnvironment * v);
    const uint64_t set = setup.shViews->views.front().id;
    if (set != lastSet || view != lastView) {
        interpolateShLighting(*setup.shViews, view, perPixel);
        lastSet = set, lastView = view;
    }
    return perPixel;
}

} // namespace ndfmip
