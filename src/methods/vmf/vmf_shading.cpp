// Shading from filtered vMF lobes (see method_shading.h).
#include <cmath>

#include "ndfmip/brdf.h"
#include "ndfmip/method_shading.h"
#include "ndfmip/vmf.h"

namespace ndfmip {

namespace {

// Lobe j's specular lobe about mu with the material's lobe widened by kappa (H eqs. 29-30);
// tabulated lobes have no widening rule and are read about mu.
float widenedLobe(const Material& m, glm::vec3 mu, float kappa, glm::vec3 h) {
    if (m.brdf == Brdf::Tabulated) return materialLobe(m, glm::dot(mu, h), 0.f, 0.f);
    return glsl().ndfmipVmfWidenedLobe(glslMaterial(m), mu, kappa, h);
}

// The GLSL's unpacking (float), as the GPU does it.
GlslLibrary::NdfmipLobe unpacked(const float* p) {
    return glsl().ndfmipUnpackLobe(glm::vec4(p[0], p[1], p[2], p[3]));
}

} // namespace

float vmfLobe(const Material& m, const float* lobes, int count, glm::vec3 h) {
    float sum = 0.f;
    for (int j = 0; j < count; ++j) {
        const GlslLibrary::NdfmipLobe lobe = unpacked(lobes + 4 * j);
        if (lobe.alpha > 0.f) sum += lobe.alpha * widenedLobe(m, lobe.mu, lobe.kappa, h);
    }
    return sum;
}

glm::vec3 shadeVmf(const Material& m, glm::vec3 baseAlbedo, const float* lobes, int count,
                   const glm::vec3* colors, glm::vec3 l, glm::vec3 v) {
    const glm::vec3 h = glm::normalize(l + v);
    const GlslMaterial material = glslMaterial(m, specularFactor(m, l, h));
    glm::vec3 out(0.f);
    for (int j = 0; j < count; ++j) {
        const GlslLibrary::NdfmipLobe lobe = unpacked(lobes + 4 * j);
        if (!(lobe.alpha > 0.f)) continue;
        const glm::vec3 albedo = colors ? colors[j] * m.albedo : baseAlbedo;
        out += glsl().ndfmipVmfLobeTerm(material, albedo, lobe,
                                        widenedLobe(m, lobe.mu, lobe.kappa, h), l, v);
    }
    return out;
}

} // namespace ndfmip
