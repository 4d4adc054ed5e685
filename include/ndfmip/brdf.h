// The reflectance model of the reference renderer, in the surface's tangent frame.
//
// Every specular BRDF here is a lobe D over half-vectors, a function of n.h only, as in
// Han et al. (the radially symmetric case, eq. 5-6). Reflected radiance from a light of
// irradiance E (at normal incidence) arriving from l, seen from v, with h = (l + v)/|l + v|:
//     L = E max(n.l, 0) (albedo / pi + specular * D(n.h)).
// Fresnel and masking-shadowing depend on l and v only under the Kelemen approximation, so they
// are the same for every filtering method and are left out (they would scale every image alike).
// Same GLSL-mappable subset as shading.h.
#pragma once

#include <glm/glm.hpp>

#include "ndfmip/scene.h"
#include "ndfmip/sh_brdf.h"
#include "ndfmip/shading.h"

namespace ndfmip {

// Beckmann distribution, normalised so that its projected area integrates to 1:
// exp(-tan^2 t / a^2) / (pi a^2 cos^4 t).
inline float beckmannD(float cosH, float alpha) {
    return glsl().ndfmipBeckmann(cosH, alpha);
}

// GGX (Trowbridge-Reitz) distribution: a^2 / (pi (cos^2 t (a^2 - 1) + 1)^2).
inline float ggxD(float cosH, float alpha) {
    return glsl().ndfmipGgx(cosH, alpha);
}

// The material's specular lobe at n.h with a given exponent (Blinn-Phong) or alpha.
// Tabulated lobes need the material's table: materialLobe.
inline float specularLobe(Brdf brdf, float cosH, float exponent, float alpha) {
    return glsl().ndfmipLobe(int(brdf), cosH, exponent, alpha);
}

// The material's lobe at n.h (tabulated lobes read their table).
inline float materialLobe(const Material& m, float cosH, float exponent, float alpha) {
    if (m.brdf == Brdf::Tabulated) return m.table ? float(evaluate(*m.table, cosH)) : 0.f;
    return specularLobe(m.brdf, cosH, exponent, alpha);
}

// The unfiltered g(theta_d) of a factored BRDF (1 without one), theta_d = angle(l, h).
inline float specularFactor(const Material& m, glm::vec3 l, glm::vec3 h) {
    if (!m.factor) return 1.f;
    return float(tabulatedFactor(*m.factor, glm::acos(glm::clamp(glm::dot(l, h), -1.f, 1.f))));
}

// Reflected radiance per unit irradiance for one unit normal n: the ground truth's integrand.
// `albedo` replaces the material's (an albedo map's texel times it).
inline glm::vec3 shadeNormal(const Material& m, glm::vec3 albedo, glm::vec3 n, glm::vec3 l,
                             glm::vec3 h) {
    const float factor = specularFactor(m, l, h);
    if (m.brdf != Brdf::Tabulated)
        return glsl().ndfmipShadeNormal(glslMaterial(m, factor), albedo, n, l, h);
    const float cosL = glm::max(glm::dot(n, l), 0.f);
    if (cosL <= 0.f) return glm::vec3(0.f);
    return cosL * (albedo * (1.f / kPi) +
                   m.specular * (materialLobe(m, glm::dot(n, h), 0.f, 0.f) * factor));
}

inline glm::vec3 shadeNormal(const Material& m, glm::vec3 n, glm::vec3 l, glm::vec3 h) {
    return shadeNormal(m, m.albedo, n, l, h);
}

} // namespace ndfmip
