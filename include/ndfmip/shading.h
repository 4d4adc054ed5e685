// Shading math shared by every method. Written in the subset of C++ that maps one to one
// onto GLSL (glm types, float math, no containers), so the GLSL twin reads the same.
#pragma once

#include <glm/glm.hpp>

namespace ndfmip {

constexpr float kPi = 3.14159265358979323846f;

// Light and view directions in the surface's tangent frame (z = geometric normal), unit length.
struct ShadeContext {
    glm::vec3 light = glm::vec3(0.f, 0.f, 1.f);
    glm::vec3 view = glm::vec3(0.f, 0.f, 1.f);
    float exponent = 32.f; // Blinn-Phong shininess s
};

inline glm::vec3 halfVector(const ShadeContext& c) { return glm::normalize(c.light + c.view); }

// Normalised Blinn-Phong lobe over half-vectors, (s+1)/(2 pi) (n.h)^s: integrates to 1 over
// the hemisphere about n (Toksvig eq. 7; Han et al. eq. 28). `cosH` may be negative.
inline float blinnPhong(float cosH, float s) {
    return (s + 1.f) / (2.f * kPi) * glm::pow(glm::max(cosH, 0.f), s);
}

} // namespace ndfmip
