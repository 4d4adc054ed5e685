// Spherical-harmonic NDFs (Han et al. Sec. 5) as a unit, and their shader (H eq. 17).
#include <algorithm>
#include <cmath>

#include <nlohmann/json.hpp>

#include "methods/method_unit.h"
#include "ndfmip/spherical_harmonics.h"

namespace ndfmip {

namespace {

int orderOf(const BakeParameters& parameters) {
    auto it = parameters.find("order");
    return it == parameters.end() ? 0 : int(it->second);
}

// The coefficients of texel (x, y), four per plane, cut to (l*+1)^2.
std::vector<float> coefficients(const LoadedBake& bake, int x, int y) {
    std::vector<float> g;
    for (const Image& plane : bake.level) g.insert(g.end(), plane.at(x, y), plane.at(x, y) + 4);
    g.resize(size_t(shCount(orderOf(bake.parameters))));
    return g;
}

// The coefficients band by band (l = 0 .. l*, m = -l .. l), and the mean normal they hold in
// band 1 (Y_1,-1 Y_1,0 Y_1,1 = sqrt(3 / 4 pi) (y, z, x)).
void inspectSh(nlohmann::json& out, const LoadedBake& bake, int x, int y, const InspectOptions&) {
    const std::vector<float> g = coefficients(bake, x, y);
    out["order"] = orderOf(bake.parameters);
    out["sh"] = g;
    const float c = std::sqrt(3.f / (4.f * kPi));
    const float na[3] = {g[3] / c, g[1] / c, g[2] / c};
    out["mean_normal"] = jsonVec3(na);
    out["length"] = length3(na);
}

// Sum g_lm Y_lm(w): the stored NDF.
double shDensity(const LoadedBake& bake, int x, int y, glm::dvec3 w) {
    const std::vector<float> g = coefficients(bake, x, y);
    const std::vector<double> basis = evaluateSh(w, orderOf(bake.parameters));
    double sum = 0.0;
    for (size_t k = 0; k < g.size(); ++k) sum += g[k] * basis[k];
    return sum;
}

Status prepareSh(const Material& m, const RenderTextures& textures, const RenderOptions& options,
                 ShaderSetup& setup) {
    Result<ShShading> sh = shShadingFor(m, bakeShOrder(textures.bake));
    if (!sh) return Status::failure(sh.error().message);
    setup.sh = std::move(sh.value());
    return prepareShLightingSetup(m, textures, options, setup);
}

// Under an environment: Han et al. eqs. 35 and 37, the lighting rotated into the tangent frame.
glm::vec3 shadeShEnvironmentParams(const ShaderSetup& setup, const Material& m, const float* p,
                                   glm::vec3 albedo, glm::vec3 v, const glm::mat3& toEnvironment,
                                   const EnvironmentLighting&) {
    return shadeShEnvironment(m, albedo, p, setup.sh, v, toEnvironment,
                              shLightingAt(setup, v, toEnvironment));
}

glm::vec3 shadeShParams(const ShaderSetup& setup, const Material& m, const float* p,
                        glm::vec3 albedo, glm::vec3 l, glm::vec3 v) {
    return shadeSh(m, albedo, p, setup.sh, l, v);
}

} // namespace

MethodUnit shUnit() {
    MethodUnit u{};
    u.method = Method::Sh;
    u.name = "sh";
    u.summary = "spherical-harmonic coefficients of the NDF, up to band --order (Han et al.)";
    u.bake = bakeSh;
    u.planes = [](const BakeParameters& parameters, bool) {
        std::vector<PlaneInfo> planes;
        for (int p = 0; p < shPlaneCount(orderOf(parameters)); ++p)
            planes.push_back(planeOf("sh" + std::to_string(p), 4, true));
        return planes;
    };
    // The highest band, for bakes of its own, bakes made on the fly and eval's sh:ORDER.
    u.parameters = {
        {.key = "order",
         .flag = "--order",
         .type = ParameterType::Integer,
         .min = 1,
         .max = kMaxShOrder,
         .defaultValue = 7,
         .help = "highest band l* ((l*+1)^2 coefficients)",
         .commands = kParameterBake | kParameterRender | kParameterView | kParameterEval,
         .recorded = true,
         .specPosition = 0,
         .keyedZeroWhenUnset = true}};
    u.bakeBytesPerTexel = [](const BakeOptions& o) {
        const int order = int(parameterValue(Method::Sh, o.parameters, "order"));
        return 16.0 * ((shCount(std::clamp(order, 0, kMaxShOrder)) + 3) / 4) * 4.0 / 3.0;
    };
    u.describe = [](const BakeParameters& parameters) {
        return "sh bake of order " + std::to_string(orderOf(parameters));
    };
    u.inspect = inspectSh;
    u.levelZeroNormal = [](const float* p) {
        return glm::vec3(p[3], p[1], p[2]);
    }; // band 1: (y, z, x)
    u.ndfDensity = shDensity;
    return u;
}

std::vector<MethodShader> shShaders() {
    auto lobe = [](const ShaderSetup& setup, const Material&, const float* p, glm::vec3 h) {
        return shLobe(p, setup.sh, h);
    };
    auto defines = [](const ShaderSetup&, int layers) {
        return "#define NDFMIP_LAYERS " + std::to_string(layers) + "\n";
    };
    // The BRDF's A_l per band (H eq. 17) beside the coefficients, up to the GLSL arrays' size.
    auto uniforms = [](const ShaderSetup& setup, std::vector<UniformValue>& u) {
        if (setup.sh.order > kGpuMaxShOrder)
            return Status::failure("render --gpu: sh bakes up to order " +
                                   std::to_string(kGpuMaxShOrder) + " (this one is " +
                                   std::to_string(setup.sh.order) + ")");
        addUniform(u, "ndfmipShOrder", setup.sh.order);
        for (int l = 0; l <= setup.sh.order; ++l) {
            std::string index =
                "["; // appended, not "[" + ...: GCC 12 warns falsely (-Wrestrict) on that at -O3
            index += std::to_string(l);
            index += "]";
            addUniform(u, "ndfmipShDiffuse" + index, float(setup.sh.diffuse[size_t(l)]));
            addUniform(u, "ndfmipShSpecular" + index, float(setup.sh.specular[size_t(l)]));
        }
        return Status::success();
    };
    return {{"sh", Method::Sh, "render/sh.glsl", prepareSh, shadeShParams, lobe,
             shadeShEnvironmentParams, nullptr, defines, uniforms, true, nullptr, nullptr}};
}

} // namespace ndfmip
