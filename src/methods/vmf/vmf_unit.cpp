// vMF mixtures (Han et al. Sec. 7) as a unit, and their shader (H eqs. 29-31).
#include <algorithm>
#include <cmath>

#include <nlohmann/json.hpp>

#include "methods/method_unit.h"
#include "ndfmip/vmf.h"

namespace ndfmip {

namespace {

int lobesOf(const BakeParameters& parameters) {
    auto it = parameters.find("lobes");
    return it == parameters.end() ? 0 : int(it->second);
}

// The texel's lobes as the shader sees them, unpacked from (alpha, alpha r mu).
std::vector<VmfLobe> texelLobes(const LoadedBake& bake, int x, int y) {
    std::vector<VmfLobe> lobes;
    for (size_t p = 0; p < bake.planes.size(); ++p) {
        if (bake.planes[p].name.rfind("lobe", 0) != 0) continue;
        const float* v = bake.level[p].at(x, y);
        lobes.push_back(unpackLobe(glm::vec4(v[0], v[1], v[2], v[3])));
    }
    return lobes;
}

void inspectVmf(nlohmann::json& out, const LoadedBake& bake, int x, int y, const InspectOptions&) {
    nlohmann::json lobes = nlohmann::json::array();
    const std::vector<VmfLobe> all = texelLobes(bake, x, y);
    for (size_t j = 0; j < all.size(); ++j) {
        const VmfLobe& l = all[j];
        if (!(l.alpha > 0.f)) continue;
        nlohmann::json lobe = {
            {"alpha", l.alpha}, {"mu", {l.mu.x, l.mu.y, l.mu.z}}, {"kappa", l.kappa}};
        const int color = findPlane(bake.planes, "color" + std::to_string(j));
        if (color >= 0) {
            const float* c = bake.level[color].at(x, y);
            const glm::vec3 rgb = unpackLobeColor(glm::vec3(c[0], c[1], c[2]), l.alpha);
            lobe["color"] = {rgb.x, rgb.y, rgb.z};
        }
        lobes.push_back(lobe);
    }
    out["lobes"] = lobes;
}

Status prepareVmf(const Material& m, const RenderTextures& textures, const RenderOptions& options,
                  ShaderSetup& setup) {
    setup.vmfLobes = bakeVmfLobes(textures.bake);
    setup.vmfColors = findPlane(textures.bake.planes, "color0") >= 0;
    if (setup.vmfLobes < 1 || setup.vmfLobes > kMaxVmfBakeLobes)
        return Status::failure("render: vmf bakes have 1 to " + std::to_string(kMaxVmfBakeLobes) +
                               " lobes");
    if (!textures.environment) return Status::success();
    if (options.vmfEnvironment == EnvironmentWay::Prefiltered)
        return prepareSplitSumSetup(m, textures, options, setup);
    // The paper's way: the lobes' transfer functions against SH lighting of the options' order.
    Result<ShShading> sh = shShadingFor(m, options.environmentShOrder);
    if (!sh) return Status::failure(sh.error().message);
    setup.sh = std::move(sh.value());
    return prepareShLightingSetup(m, textures, options, setup);
}

// The lobe colours that follow the lobe planes, unpacked into `colors`; null for a bake without
// them.
const glm::vec3* unpackedColors(const ShaderSetup& setup, const float* p,
                                glm::vec3 colors[kMaxVmfBakeLobes]) {
    if (!setup.vmfColors) return nullptr;
    for (int j = 0; j < setup.vmfLobes; ++j) {
        const float* c = p + 4 * setup.vmfLobes + 3 * j;
        colors[j] = unpackLobeColor(glm::vec3(c[0], c[1], c[2]), p[4 * j]);
    }
    return colors;
}

// Lobe planes (4 channels each), then colour planes (3 each) when the bake has them.
glm::vec3 shadeVmfParams(const ShaderSetup& setup, const Material& m, const float* p,
                         glm::vec3 albedo, glm::vec3 l, glm::vec3 v) {
    glm::vec3 colors[kMaxVmfBakeLobes];
    return shadeVmf(m, albedo, p, setup.vmfLobes, unpackedColors(setup, p, colors), l, v);
}

// Under an environment: per lobe, the prefiltered level of its equivalent roughness along the
// reflection about mu_j (the engine way), or H eqs. 35 and 37 with SH lighting (the paper's: Blinn-
// Phong's widened lobe of H eq. 29; Beckmann and GGX by the lobe convolved exactly, as fast and
// without H eq. 30's equivalent-roughness step).
glm::vec3 shadeVmfEnvironment(const ShaderSetup& setup, const Material& m, const float* p,
                              glm::vec3 albedo, glm::vec3 v, const glm::mat3& toEnvironment,
                              const EnvironmentLighting&) {
    glm::vec3 colors[kMaxVmfBakeLobes];
    const glm::vec3* lobeColors = unpackedColors(setup, p, colors);
    if (setup.splitSum)
        return shadeVmfSplitSum(m, albedo, p, setup.vmfLobes, lobeColors, v, toEnvironment,
                                *setup.splitSum, setup.environmentLod);
    const VmfSpecularTransfer transfer =
        m.brdf == Brdf::BlinnPhong ? VmfSpecularTransfer::Widened : VmfSpecularTransfer::Convolved;
    return shadeVmfEnvironmentSh(m, albedo, p, setup.vmfLobes, lobeColors, v, toEnvironment,
                                 shLightingAt(setup, v, toEnvironment), setup.sh, transfer);
}

// The bake's options: the lobe count (also for bakes made on the fly and eval's vmf:J:BUDGET),
// the EM's limits, coherent lobes and the error budget.
std::vector<MethodParameter> vmfParameters() {
    constexpr unsigned everywhere =
        kParameterBake | kParameterRender | kParameterView | kParameterEval;
    return {{.key = "lobes",
             .flag = "--lobes",
             .type = ParameterType::Integer,
             .min = 1,
             .max = kMaxVmfBakeLobes,
             .defaultValue = 4,
             .help = "lobes per texel J",
             .commands = everywhere,
             .recorded = true,
             .specPosition = 0,
             .keyedZeroWhenUnset = true},
            {.key = "coherent",
             .flag = "--coherent",
             .type = ParameterType::Float,
             .min = 0,
             .max = 1e6,
             .defaultValue = 0,
             .help = "coherent lobes for hardware filtering, C the pull of H eq. 32: fitted "
                     "top-down, each texel's EM started from its parent's lobes; 0 = plain lobes, "
                     "the best fit where each texel is shaded alone",
             .commands = kParameterBake,
             // Files are read through hardware filtering, which blends slot j of neighbouring
             // texels (docs/RESULTS.md, "Coherent lobes started from the parent"); not beside
             // --lobe-budget, which plain lobes take.
             .fileDefault = kHardwareFilteringCoherence},
            {.key = "lobe_budget",
             .flag = "--lobe-budget",
             .type = ParameterType::Float,
             .min = 0,
             .max = 10,
             .defaultValue = 0,
             .help = "merge a texel's lobes while a merge loses at most this much (Runnalls' "
                     "bound, e.g. 0.01): "
                     "fewer lobes where more buy little; 0 = J everywhere",
             .commands = kParameterBake | kParameterEval,
             .specPosition = 1},
            {.key = "max_iterations",
             .flag = "--max-iterations",
             .type = ParameterType::Integer,
             .min = 1,
             .max = 10000,
             .defaultValue = 50,
             .help = "EM iterations per texel at most",
             .commands = kParameterBake},
            {.key = "tolerance",
             .flag = "--tolerance",
             .type = ParameterType::Double,
             .min = 0,
             .max = 1,
             .defaultValue = 1e-5,
             .help = "relative log-likelihood gain that ends EM",
             .commands = kParameterBake}};
}

} // namespace

MethodUnit vmfUnit() {
    MethodUnit u{};
    u.method = Method::Vmf;
    u.name = "vmf";
    u.summary = "mixtures of --lobes von Mises-Fisher lobes fitted by spherical EM (Han et al.)";
    u.bake = bakeVmf;
    u.planes = [](const BakeParameters& parameters, bool colours) {
        std::vector<PlaneInfo> planes;
        const int lobes = lobesOf(parameters);
        for (int j = 0; j < lobes; ++j)
            planes.push_back(planeOf("lobe" + std::to_string(j), 4, true));
        for (int j = 0; colours && j < lobes; ++j)
            planes.push_back(planeOf("color" + std::to_string(j), 3, true));
        return planes;
    };
    u.parameters = vmfParameters();
    u.checkParameters = [](const ParameterValues& values, ParameterNaming naming) {
        if (values.count("lobe_budget") && values.at("lobe_budget") != 0.0 &&
            values.count("coherent") && values.at("coherent") != 0.0)
            return Status::failure(
                std::string(naming == ParameterNaming::Flag ? "--lobe-budget" : "lobe_budget") +
                " does not apply to coherent lobes");
        return Status::success();
    };
    // Fitted lobes (32 bytes each) and their offsets, then the lobe and colour planes.
    u.bakeBytesPerTexel = [](const BakeOptions& o) {
        const int lobes = std::clamp(int(parameterValue(Method::Vmf, o.parameters, "lobes")), 1,
                                     kMaxVmfBakeLobes);
        return (4.0 + lobes * (32.0 + 16.0 + (o.albedo ? 12.0 : 0.0))) * 4.0 / 3.0;
    };
    u.describe = [](const BakeParameters& parameters) {
        return "vmf bake with " + std::to_string(lobesOf(parameters)) + " lobes";
    };
    u.inspect = inspectVmf;
    u.levelZeroNormal = [](const float* p) {
        return glm::vec3(p[1], p[2], p[3]);
    }; // alpha r mu, alpha = 1
    u.ndfDensity = [](const LoadedBake& bake, int x, int y, glm::dvec3 w) {
        return std::exp(vmfMixtureLogDensity(glm::vec3(w), texelLobes(bake, x, y)));
    };
    return u;
}

std::vector<MethodShader> vmfShaders() {
    auto lobe = [](const ShaderSetup& setup, const Material& m, const float* p, glm::vec3 h) {
        return vmfLobe(m, p, setup.vmfLobes, h);
    };
    auto defines = [](const ShaderSetup& setup, int layers) {
        std::string text = "#define NDFMIP_LAYERS " + std::to_string(layers) + "\n";
        text += "#define NDFMIP_LOBES " + std::to_string(setup.vmfLobes) + "\n";
        if (setup.vmfColors) text += "#define NDFMIP_LOBE_COLOURS\n";
        return text;
    };
    return {{"vmf", Method::Vmf, "render/vmf.glsl", prepareVmf, shadeVmfParams, lobe,
             shadeVmfEnvironment, nullptr, defines, nullptr, false, nullptr, nullptr}};
}

} // namespace ndfmip
