// Toksvig's method as a unit, and its two shaders: the closed form (T eq. 6 and the roughness
// mapping) and his 2D lookup table with the 8-bit phase-out (T eqs. 9-11).
#include <nlohmann/json.hpp>

#include "methods/method_unit.h"
#include "ndfmip/shading.h"

namespace ndfmip {

namespace {

glm::vec3 shadeClosedForm(const ShaderSetup& setup, const Material& m, const float* p,
                          glm::vec3 albedo, glm::vec3 l, glm::vec3 v) {
    return shadeToksvig(m, albedo, glm::vec3(p[0], p[1], p[2]), l, v, setup.mapping,
                        setup.varianceScale);
}

Status prepareClosedForm(const Material& m, const RenderTextures& textures,
                         const RenderOptions& options, ShaderSetup& setup) {
    setup.mapping = options.roughnessMapping;
    setup.varianceScale = options.varianceScale;
    return prepareSplitSumSetup(m, textures, options, setup);
}

// Under an environment: the lobe widened by |Na| as under point lights, read from the prefiltered
// levels at the rule's level (log2 sigma: Toksvig's own, on the plain mip chain).
glm::vec3 shadeClosedFormEnvironment(const ShaderSetup& setup, const Material& m, const float* p,
                                     glm::vec3 albedo, glm::vec3 v, const glm::mat3& toEnvironment,
                                     const EnvironmentLighting&) {
    return shadeToksvigSplitSum(m, albedo, glm::vec3(p[0], p[1], p[2]), v, toEnvironment,
                                *setup.splitSum, setup.environmentLod, setup.mapping,
                                setup.varianceScale);
}

Status prepareLut(const Material& m, const RenderTextures&, const RenderOptions&,
                  ShaderSetup& setup) {
    if (m.brdf != Brdf::BlinnPhong)
        return Status::failure(
            std::string("render: toksvig-lut is Toksvig's table for Blinn-Phong materials, the "
                        "material is ") +
            brdfName(m.brdf));
    ToksvigLutOptions lut;
    lut.exponent = m.exponent;
    lut.size = kToksvigLutSize;
    lut.bitDepth = kToksvigLutBits;
    setup.lut = toksvigLut(lut);
    return Status::success();
}

glm::vec3 shadeLut(const ShaderSetup& setup, const Material& m, const float* p, glm::vec3 albedo,
                   glm::vec3 l, glm::vec3 v) {
    return shadeToksvigLut(m, albedo, glm::vec3(p[0], p[1], p[2]), setup.lut, l, v);
}

void inspectToksvig(nlohmann::json& out, const LoadedBake& bake, int x, int y,
                    const InspectOptions& options) {
    const float* na = bake.level[requirePlane(bake, "mean")].at(x, y);
    const float length = length3(na);
    out["mean_normal"] = jsonVec3(na);
    out["length"] = length;
    out["sigma2"] = toksvigSigma2(length);
    if (options.hasExponent) out["toksvig_factor"] = toksvigFactor(length, options.exponent);
    out["roughness_beckmann"] = bake.level[requirePlane(bake, "roughness_beckmann")].at(x, y)[0];
    out["roughness_ggx"] = bake.level[requirePlane(bake, "roughness_ggx")].at(x, y)[0];
}

} // namespace

MethodUnit toksvigUnit() {
    MethodUnit u{};
    u.method = Method::Toksvig;
    u.name = "toksvig";
    u.summary = "the mean normal kept unnormalised; its length widens the lobe (Toksvig)";
    u.bake = bakeToksvig;
    u.planes = [](const BakeParameters&, bool) {
        return std::vector<PlaneInfo>{planeOf("mean", 3, true),
                                      planeOf("roughness_beckmann", 1, false),
                                      planeOf("roughness_ggx", 1, false)};
    };
    u.parameters = {materialRoughnessParameter()};
    // Roughness planes, and with a roughness map its alpha^2 chain being averaged.
    u.bakeBytesPerTexel = [](const BakeOptions& o) {
        return 4.0 * 4.0 / 3.0 + (o.roughnessMap ? 8.0 : 0.0);
    };
    u.describe = [](const BakeParameters&) { return std::string("toksvig bake"); };
    u.inspect = inspectToksvig;
    u.levelZeroNormal = [](const float* p) { return glm::vec3(p[0], p[1], p[2]); };
    u.ndfDensity = nullptr;
    return u;
}

std::vector<MethodShader> toksvigShaders() {
    auto lobe = [](const ShaderSetup& setup, const Material& m, const float* p, glm::vec3 h) {
        return toksvigLobe(m, glm::vec3(p[0], p[1], p[2]), h, setup.mapping, setup.varianceScale);
    };
    auto lutLobe = [](const ShaderSetup& setup, const Material& m, const float* p, glm::vec3 h) {
        return toksvigLutLobe(m, glm::vec3(p[0], p[1], p[2]), setup.lut, h);
    };
    auto closedFormUniforms = [](const ShaderSetup& setup, std::vector<UniformValue>& u) {
        addUniform(u, "ndfmipMapping", int(setup.mapping));
        addUniform(u, "ndfmipVarianceScale", setup.varianceScale);
        return Status::success();
    };
    auto lutUniforms = [](const ShaderSetup&, std::vector<UniformValue>& u) {
        addUniform(u, "ndfmipLut", 1); // the table's texture unit
        return Status::success();
    };
    return {{"toksvig", Method::Toksvig, "render/toksvig.glsl", prepareClosedForm, shadeClosedForm,
             lobe, shadeClosedFormEnvironment, nullptr, nullptr, closedFormUniforms, false, nullptr,
             nullptr},
            {kToksvigLut, Method::Toksvig, "render/toksvig_lut.glsl", prepareLut, shadeLut, lutLobe,
             nullptr, nullptr, nullptr, lutUniforms, false, nullptr, nullptr}};
}

} // namespace ndfmip
