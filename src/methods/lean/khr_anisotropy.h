// One anisotropic GGX lobe as glTF's KHR_materials_anisotropy stores it: the roughness in
// metallicRoughness G (alpha_b = roughness^2), a direction in the tangent frame and a strength
// s with alpha_t = mix(alpha_b, 1, s^2), the extension's own definition.
#pragma once

#include <glm/glm.hpp>

namespace ndfmip {

struct KhrAnisotropy {
    float roughness = 0.f;         // perceptual: sqrt(alpha_b)
    glm::vec2 direction{1.f, 0.f}; // unit, the axis of alpha_t; x >= 0 (a lobe has no sign)
    float strength = 0.f;          // s in [0, 1]
};

// The lobe of squared-roughness tensor A = [[axx, axy], [axy, ayy]] (slope space, as sggx.glsl
// shades it): alpha_t^2 and alpha_b^2 its eigenvalues, each alpha at most 1 (the extension
// cannot store a wider lobe).
KhrAnisotropy khrAnisotropy(float axx, float ayy, float axy);

// The lobe of one texel of a lean bake (sggx.glsl): `moments` its lean_moments (E[bx], E[by],
// E[bx^2], E[by^2]), `cross` its lean_cross (E[bx by]), `alpha2` the material's mean alpha^2;
// the tensor alpha2 I + 2 Sigma, Sigma the slopes' covariance (lean.glsl's).
KhrAnisotropy khrAnisotropyOfMoments(const float* moments, float cross, float alpha2);

// The lobe's anisotropyTexture texel (RGBA): the direction as (d + 1)/2, the strength, 1.
void khrAnisotropyTexel(const KhrAnisotropy& lobe, float* rgba);

// What the anisotropyTexture's R, G, B hold, for the files' own descriptions.
constexpr const char* kKhrAnisotropyChannels[3] = {"direction of alpha_t, tangent x, (d + 1)/2",
                                                   "direction of alpha_t, bitangent y, (d + 1)/2",
                                                   "strength s: alpha_t = mix(alpha_b, 1, s^2)"};

} // namespace ndfmip
