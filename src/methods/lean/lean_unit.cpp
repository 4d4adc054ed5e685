// LEAN mapping (Olano and Baker 2010) as a unit, and its shader.
#include <nlohmann/json.hpp>

#include "methods/method_unit.h"

namespace ndfmip {

namespace {

void inspectLean(nlohmann::json& out, const LoadedBake& bake, int x, int y, const InspectOptions&) {
    const float* m = bake.level[requirePlane(bake, "lean_moments")].at(x, y);
    const float cross = bake.level[requirePlane(bake, "lean_cross")].at(x, y)[0];
    out["mean_slope"] = {m[0], m[1]};
    out["slope_covariance"] = {{m[2] - m[0] * m[0], cross - m[0] * m[1]},
                               {cross - m[0] * m[1], m[3] - m[1] * m[1]}};
    const glm::vec3 n = glm::normalize(glm::vec3(m[0], m[1], 1.f));
    out["mean_normal"] = {n.x, n.y, n.z};
}

glm::vec3 shadeLeanParams(const ShaderSetup&, const Material& m, const float* p, glm::vec3 albedo,
                          glm::vec3 l, glm::vec3 v) {
    return shadeLean(m, albedo, p, l, v);
}

} // namespace

MethodUnit leanUnit() {
    MethodUnit u{};
    u.method = Method::Lean;
    u.name = "lean";
    u.summary = "slope moments: one anisotropic Beckmann lobe (LEAN mapping, Olano and Baker)";
    u.bake = bakeLean;
    u.planes = [](const BakeParameters&, bool) {
        return std::vector<PlaneInfo>{planeOf("lean_moments", 4, true),
                                      planeOf("lean_cross", 1, true)};
    };
    // The five slope moments being averaged (20 bytes), then the two planes (20 bytes).
    u.bakeBytesPerTexel = [](const BakeOptions&) { return 20.0 + 20.0 * 4.0 / 3.0; };
    u.describe = [](const BakeParameters&) { return std::string("lean bake"); };
    u.inspect = inspectLean;
    u.levelZeroNormal = [](const float* p) {
        return glm::vec3(p[0], p[1], 1.f);
    }; // the slope's normal
    u.ndfDensity = nullptr;
    return u;
}

std::vector<MethodShader> leanShaders() {
    auto none = [](const Material&, const RenderTextures&, const RenderOptions&, ShaderSetup&) {
        return Status::success();
    };
    auto lobe = [](const ShaderSetup&, const Material& m, const float* p, glm::vec3 h) {
        return leanLobe(m, p, h);
    };
    auto shadeSggxParams = [](const ShaderSetup&, const Material& m, const float* p,
                              glm::vec3 albedo, glm::vec3 l,
                              glm::vec3 v) { return shadeSggx(m, albedo, p, l, v); };
    auto sggx = [](const ShaderSetup&, const Material& m, const float* p, glm::vec3 h) {
        return sggxLobe(m, p, h);
    };
    // sggx: the same moments read as one anisotropic GGX lobe (shaders/sggx.glsl).
    return {{"lean", Method::Lean, "render/lean.glsl", none, shadeLeanParams, lobe, nullptr,
             nullptr, nullptr, nullptr, false, nullptr, nullptr},
            {"sggx", Method::Lean, "render/sggx.glsl", none, shadeSggxParams, sggx, nullptr,
             nullptr, nullptr, nullptr, false, nullptr, nullptr}};
}

} // namespace ndfmip
