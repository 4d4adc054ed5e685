// ggx-fit as a unit, and its shader: the level's unit normal with the fitted GGX roughness, both
// blended by the lookup as an engine blends its normal and roughness maps (roughness-mips'
// shading, with the roughness read as alpha).
#include <cstdio>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "methods/method_unit.h"
#include "ndfmip/roughness.h"

namespace ndfmip {

namespace {

Status prepareGgxFit(const Material& m, const RenderTextures& textures,
                     const RenderOptions& options, ShaderSetup& setup) {
    if (Status s = checkFittedMaterial("ggx-fit", m, textures); !s) return s;
    setup.roughnessIsAlpha = true;
    return prepareSplitSumSetup(m, textures, options, setup);
}

void inspectGgxFit(nlohmann::json& out, const LoadedBake& bake, int x, int y,
                   const InspectOptions&) {
    out["normal"] = jsonVec3(bake.level[requirePlane(bake, "normal")].at(x, y));
    const float alpha = bake.level[requirePlane(bake, "roughness_ggx")].at(x, y)[0];
    out["roughness_ggx"] = alpha;
    out["perceptual_roughness"] = perceptualRoughness(alpha);
}

} // namespace

Status checkFittedMaterial(const char* method, const Material& m, const RenderTextures& textures) {
    if (m.brdf != Brdf::Ggx)
        return Status::failure(std::string("render: ") + method +
                               " stores a GGX lobe fitted to a GGX material, the material is " +
                               brdfName(m.brdf));
    // Fitted to one material roughness (not to a roughness map): the material must be it.
    const auto base = textures.bake.parameters.find("base_roughness");
    if (!textures.bake.parameters.count("roughness_map") &&
        base != textures.bake.parameters.end() &&
        std::abs(float(base->second) - m.roughness) > 1e-4f) {
        char text[256];
        std::snprintf(text, sizeof text,
                      "render: the %s bake was fitted to GGX alpha %g, the material's is %g: "
                      "bake it with --base-roughness %g",
                      method, base->second, double(m.roughness), double(m.roughness));
        return Status::failure(text);
    }
    return Status::success();
}

MethodUnit ggxFitUnit() {
    MethodUnit u{};
    u.method = Method::GgxFit;
    u.name = "ggx-fit";
    u.summary = "one GGX lobe per texel, its roughness fitted to the texel's filtered NDF "
                "(needs --base-roughness)";
    u.bake = bakeGgxFit;
    u.planes = [](const BakeParameters&, bool) {
        return std::vector<PlaneInfo>{planeOf("normal", 3, true),
                                      planeOf("roughness_ggx", 1, true)};
    };
    u.parameters = {materialRoughnessParameter()}; // the shader checks the material's
    // The planes, and with a roughness map its alpha.
    u.bakeBytesPerTexel = [](const BakeOptions& o) {
        return 16.0 * 4.0 / 3.0 + (o.roughnessMap ? 4.0 : 0.0);
    };
    u.describe = [](const BakeParameters&) { return std::string("ggx-fit bake"); };
    u.inspect = inspectGgxFit;
    u.levelZeroNormal = [](const float* p) { return glm::vec3(p[0], p[1], p[2]); };
    u.ndfDensity = nullptr;
    u.fitsMaterialRoughness = true;
    return u;
}

std::vector<MethodShader> ggxFitShaders() {
    // An engine's GGX lobe at the stored alpha: roughness-mips' shading and render glue (layer 0
    // the normal, layer 1 the alpha), the roughness one of the bake's own planes, not a chain the
    // renderer adds.
    for (MethodShader shader : naiveShaders()) {
        if (std::string(shader.name) != kRoughnessMips) continue;
        shader.name = "ggx-fit";
        shader.bake = Method::GgxFit;
        shader.prepare = prepareGgxFit;
        shader.gpuLayers = nullptr;
        return {shader};
    }
    throw std::logic_error("no roughness-mips shader");
}

} // namespace ndfmip
