// The ground truth's estimate of the light an environment reflects at one surface point:
//     integral over the upper hemisphere (tangent frame, l.z > 0) of L(l) shadeNormal(n, l, h) dl,
// shadeNormal being the point-light truth's integrand (radiance per unit irradiance, with n.l),
// so the truth means the same under lights and under an environment. One environment sample
// and one BRDF sample, combined by multiple importance sampling with the power heuristic
// (Veach 1997, sec. 9.2). docs/RENDERING.md.
#pragma once

#include <glm/glm.hpp>

#include "ndfmip/environment_lighting.h"
#include "ndfmip/render.h"
#include "ndfmip/scene.h"

namespace ndfmip {

// How the BRDF is sampled: the specular lobe (h from D(h) (n.h) about n, l = reflect(v, h))
// with probability `specular`, else cosine-weighted about n for the diffuse term. `usable` is
// false for tabulated lobes (then only the environment is sampled) and for black materials.
struct BrdfSampling {
    bool usable = false;
    double specular = 0.; // probability of sampling the lobe
};

// Mixture weights from the luminance of the diffuse albedo against the specular colour.
BrdfSampling brdfSampling(const Material& material, glm::vec3 albedo);

// The density per steradian of h about n from the lobe's sampler, at cos(theta_h) = c: D(h) c for
// Beckmann and GGX (their projected areas integrate to 1), (s + 2)/(2 pi) c^(s + 1) for
// Blinn-Phong (whose D integrates to 1 by itself).
double lobeHalfVectorPdf(const Material& material, double c);

// A half vector about +Z from two uniform numbers, with density lobeHalfVectorPdf.
glm::dvec3 sampleLobeHalfVector(const Material& material, double u1, double u2);

// The density per steradian of the BRDF sampler drawing unit l, for unit normal n and view v.
double brdfPdf(const Material& material, const BrdfSampling& sampling, glm::dvec3 n, glm::dvec3 v,
               glm::dvec3 l);

// A direction from the BRDF sampler (three uniform numbers); false when the draw is lost (the
// half vector faces away from v), which the estimate counts as zero.
bool sampleBrdf(const Material& material, const BrdfSampling& sampling, glm::dvec3 n, glm::dvec3 v,
                const double u[3], glm::dvec3& l);

// One estimate of the reflected radiance: `u` holds 5 uniform numbers in [0, 1) (2 for the
// environment sample, 3 for the BRDF sample). `toEnvironment` maps tangent to environment
// directions (environment_lighting.h tangentToEnvironment); n is the (finest) unit normal and v
// the unit view, both in the tangent frame. `estimator` picks MIS or one of its two halves alone
// (tabulated lobes and black materials always sample the environment alone).
glm::vec3 estimateEnvironmentRadiance(const EnvironmentLighting& lighting,
                                      const glm::mat3& toEnvironment, const Material& material,
                                      glm::vec3 albedo, glm::vec3 n, glm::vec3 v,
                                      EnvironmentEstimator estimator, const double u[5]);

// spp samples as a gx x gy grid with gx the largest divisor of spp not above sqrt(spp).
inline void strataGrid(int spp, int& gx, int& gy) {
    gx = 1;
    for (int d = 1; d * d <= spp; ++d)
        if (spp % d == 0) gx = d;
    gy = spp / gx;
}

} // namespace ndfmip
