// The slope-moment closed form for GGX (shaders/sggx.glsl) on the lean bake's planes.
#include "ndfmip/method_shading.h"

namespace ndfmip {

float sggxLobe(const Material& m, const float* p, glm::vec3 h) {
    if (m.brdf == Brdf::Tabulated) // no widening rule, as for lean: the table about the mean
                                   // slope's normal
        return materialLobe(m, glm::dot(glm::normalize(glm::vec3(p[0], p[1], 1.f)), h), 0.f, 0.f);
    return glsl().ndfmipSggxLobe(glslMaterial(m), glm::vec4(p[0], p[1], p[2], p[3]), p[4], h);
}

glm::vec3 shadeSggx(const Material& m, glm::vec3 albedo, const float* p, glm::vec3 l, glm::vec3 v) {
    const glm::vec3 h = glm::normalize(l + v);
    return glsl().ndfmipShadeLeanLobe(glslMaterial(m, specularFactor(m, l, h)), albedo,
                                      glm::vec4(p[0], p[1], p[2], p[3]), p[4], l, v,
                                      sggxLobe(m, p, h));
}

} // namespace ndfmip
