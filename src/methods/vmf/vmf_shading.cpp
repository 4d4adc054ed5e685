// Shading from filtered vMF lobes (see method_shading.h).
#include <cmath>

#include "ndfmip/brdf.h"
#include "ndfmip/method_shading.h"
#include "ndfmip/vmf.h"

namespace ndfmip {

namespace {

// Lobe j's specular lobe about mu with the material's lobe widened by kappa (eqs. 29-30).
float widenedLobe(const Material& m, glm::vec3 mu, float kappa, glm::vec3 h) {
    const float cosH = glm::dot(mu, h);
    switch (m.brdf) {
    case Brdf::BlinnPhong: return blinnPhong(cosH, kappa * m.exponent / (kappa + m.exponent));
    case Brdf::Beckmann: return beckmannD(cosH, std::sqrt(m.roughness * m.roughness + 2.f / glm::max(kappa, 1e-6f)));
    case Brdf::Ggx: return ggxD(cosH, std::sqrt(m.roughness * m.roughness + 2.f / glm::max(kappa, 1e-6f)));
    case Brdf::Tabulated: return materialLobe(m, cosH, 0.f, 0.f);
    case Brdf::Lambert: break;
    }
    return 0.f;
}

} // namespace

float vmfLobe(const Material& m, const float* lobes, int count, glm::vec3 h) {
    float sum = 0.f;
    for (int j = 0; j < count; ++j) {
        const float* p = lobes + 4 * j;
        const VmfLobe lobe = unpackLobe(glm::vec4(p[0], p[1], p[2], p[3]));
        if (lobe.alpha > 0.f) sum += lobe.alpha * widenedLobe(m, lobe.mu, lobe.kappa, h);
    }
    return sum;
}

glm::vec3 shadeVmf(const Material& m, glm::vec3 baseAlbedo, const float* lobes, int count, const glm::vec3* colors,
                   glm::vec3 l, glm::vec3 v) {
    const glm::vec3 h = glm::normalize(l + v);
    const float factor = specularFactor(m, l, h);
    const float lobeKappa = lobeConcentration(m);
    glm::vec3 out(0.f);
    for (int j = 0; j < count; ++j) {
        const float* p = lobes + 4 * j;
        const VmfLobe lobe = unpackLobe(glm::vec4(p[0], p[1], p[2], p[3]));
        const float alpha = lobe.alpha, kappa = lobe.kappa;
        if (!(alpha > 0.f)) continue;
        const glm::vec3 mu = lobe.mu;
        const float cosL = glm::dot(mu, l);
        // Diffuse: eq. 29 with s = 1 over the light direction.
        const float sd = kappa / (kappa + 1.f);
        const float diffuse = (sd + 1.f) / (2.f * kPi) * std::pow(glm::max(cosL, 0.f), sd);
        const glm::vec3 albedo = colors ? colors[j] * m.albedo : baseAlbedo;
        const float specular = widenedLobe(m, mu, kappa, h);
        const float cosSpecular = specularCosine(mu, kappa, lobeKappa, h, l);
        out += alpha * (albedo * diffuse + m.specular * (specular * factor * cosSpecular));
    }
    return out;
}

} // namespace ndfmip
