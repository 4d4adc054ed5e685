// Shading math shared by every method; the formulas themselves are the GLSL library's
// (shaders/*.glsl through ndfmip/glsl.h).
#pragma once

#include <glm/glm.hpp>

#include "ndfmip/glsl.h"

namespace ndfmip {

constexpr float kPi = 3.14159265358979323846f;

// Light and view directions in the surface's tangent frame (z = geometric normal), unit length.
struct ShadeContext {
    glm::vec3 light = glm::vec3(0.f, 0.f, 1.f);
    glm::vec3 view = glm::vec3(0.f, 0.f, 1.f);
    float exponent = 32.f; // Blinn-Phong shininess s
};

inline glm::vec3 halfVector(const ShadeContext& c) {
    return glm::normalize(c.light + c.view);
}

// Normalised Blinn-Phong lobe over half-vectors, (s+1)/(2 pi) (n.h)^s: integrates to 1 over
// the hemisphere about n (Toksvig eq. 7; Han et al. eq. 28). `cosH` may be negative.
inline float blinnPhong(float cosH, float s) {
    return glsl().ndfmipBlinnPhong(cosH, s);
}

} // namespace ndfmip
