// The SH and vMF methods under an environment, the paper's way (Han et al. 2007, Sec. 8,
// eqs. 34-37): the lighting is projected on spherical harmonics once, and a pixel's filtered NDF
// meets it in a dot product of coefficients instead of an integral over the sphere.
//
// What is computed, per unit of the point-light shade functions (method_shading.h: radiance per
// unit irradiance, so the environment's radiance in, reflected radiance out):
//   diffuse   albedo Integral L(w) Sum_n NDF(n) max(n.w, 0)/pi dw                      (H eq. 34)
//             = albedo Sum_lm A_l^diffuse g_lm L_lm                                     (H eq. 35)
//   specular  specular Integral L(w_i) Sum_n NDF(n) D(n.h) cos dw_i
//             = specular Integral L'(h) Sum_n NDF(n) D(n.h) dh                         (H eq. 36)
//             = specular Sum_lm A_l^specular g_lm L'_lm                                 (H eq. 37)
// with w_i = 2 (w_o.h) h - w_o, dw_i = 4 (w_i.h) dh and the reparameterised lighting
//     L'(h) = L(w_i(h, w_o)) 4 (w_i.h) c(h),   h.w_o > 0 (0 on the other half).
// c is the cosine of the specular term, which the paper multiplies in per lobe or from the
// mipmapped normal (footnote 5) and which, under an environment, sits inside the integral where
// it depends on the unknown normal. SpecularCosine chooses it:
//   HalfVector  c = w_i.h = w_o.h: the cosine at n = h, exact where the lobe is sharp (the
//               point-light specularCosine tends to the same h.l in that limit), and independent
//               of n, so the dot product above stays exact.
//   MeanNormal  c = Na.w_i with the filtered mean normal Na (the SH method: footnote 5's
//               mipmapped normal from g's band 1; the vMF method: A(kappa) mu per lobe), not
//               clamped: linear in Na, so L' is prepared once per axis, L'_k with c = w_i.e_k,
//               and a pixel combines Sum_k Na_k L'_k (three times the preparation and storage).
//               Exact for one normal where no light below its horizon reaches the lobe; the
//               paper's own choice for point lights (footnote 5) and the default: the closest
//               to the truth of the three (docs/ENVIRONMENT.md has the measured gaps).
//   Reflecting  c = A(kappa + s) (share mu.w_i + (1 - share) h.w_i), share = kappa / (kappa + s):
//               the mean n.w_i over the normals that reflect w_i into w_o, as the point-light
//               shading's ndfmipSpecularCosine (brdf.glsl) takes it. The NDF (a lobe of
//               concentration kappa about mu: the vMF method's lobes, the SH method's Na read as
//               one) times the material's lobe (concentration s about h) is a lobe about
//               kappa mu + s h with mean normal A(|.|) times its direction, here with |.| and
//               its direction's normalisation taken at h = mu. Linear in the lighting: L' is
//               prepared for the three axes and for the half vector (four times the preparation
//               of one), and a pixel combines Sum_k c_k L'_k + c_h L'_h. A single normal (kappa
//               -> infinity) gives MeanNormal's exact cosine; a spread NDF under a sharp lobe
//               reads the cosines of the normals near h, which MeanNormal's one mean cosine
//               misses (for a footprint of normals tilted +-theta seen from above: cos 2 theta
//               where they reflect at cos theta).
//   None        c = 1: H eq. 36 as printed, no cosine.
// The fixed-view approximation: L' depends on w_o, and one w_o (environment frame) serves the
// whole image. Lighting prepared for the pixel's own view (prepareShLighting with w_o = the
// pixel's view in the environment frame) is the exact per-view variant; docs/ENVIRONMENT.md has
// the measured cost of the approximation against the angle between the views.
#pragma once

#include <cstdint>

#include <functional>
#include <vector>

#include <glm/glm.hpp>

#include "ndfmip/environment.h"
#include "ndfmip/method_shading.h"

namespace ndfmip {

// ---- lighting -----------------------------------------------------------------------------------

enum class SpecularCosine { HalfVector, MeanNormal, None, Reflecting };

// The cosine's name on the command line and in eval's report: half-vector, mean-normal, none or
// reflecting.
const char* specularCosineName(SpecularCosine cosine);

// How many L' a cosine prepares: 3 (MeanNormal: the axes), 4 (Reflecting: the axes, then the half
// vector's), otherwise 1.
int reparameterisedSets(SpecularCosine cosine);

// Coefficients (l <= order, at shIndex(l, m)) on the basis of spherical_harmonics.h in the
// environment frame (environment.h, Environment::rotation applied).
struct ShLighting {
    uint64_t id =
        0; // unique per preparation (shading caches the lighting rotated into a frame by it)
    int order = 0;
    glm::dvec3 view{0., 0., 1.}; // w_o of `reparameterised`, environment frame, unit
    SpecularCosine cosine = SpecularCosine::MeanNormal;
    std::vector<glm::dvec3> radiance;        // L_lm (projectEnvironmentSh)
    std::vector<glm::dvec3> reparameterised; // L'_lm for `view` (Reflecting: c = w_i.h;
                                             // MeanNormal: empty)
    // MeanNormal and Reflecting: L'_k for c = w_i.e_k, k = x, y, z of the environment frame.
    std::vector<glm::dvec3> reparameterisedAxes[3];
};

// Set k of reparameterisedSets(lighting.cosine): the axes first where there are axes, then
// `reparameterised`.
const std::vector<glm::dvec3>& reparameterisedSet(const ShLighting& lighting, int k);
std::vector<glm::dvec3>& reparameterisedSet(ShLighting& lighting, int k);

// L, then the reparameterisedSets, as interleaved channels for coefficients l <= order:
// coefficient i's 3 (1 + sets) values at 3 (1 + sets) i, L's RGB first, then each set's. What
// the shading reads (rotated into a tangent frame by sh_rotation.h's rotateSh where it must be)
// and the GPU's rows. Precondition: order <= lighting.order.
std::vector<double> interleavedShLighting(const ShLighting& lighting, int order);

// L and L' of the map. L' is projected texel by texel, in the variable w_i where the map is
// given: L'_lm = Integral L(w_i) 4 (w_i.h) c Y_lm(h(w_i)) dh = Integral L(w_i) c Y_lm(h) dw_i, each
// texel's radiance times c Y_lm(h) at its centre times its solid angle.
// Preconditions: 0 <= order <= kMaxShOrder, fixedView of non-zero length (normalised here).
ShLighting prepareShLighting(const Environment& env, int order, glm::dvec3 fixedView,
                             SpecularCosine cosine = SpecularCosine::MeanNormal);

// Radiance in the environment frame as a function of the direction (unit), e.g. an analytic sky.
using RadianceFunction = std::function<glm::dvec3(glm::dvec3)>;

// The same for a radiance function: both projections by a product rule in the frame of the view
// (Gauss-Legendre in w_o.h over [0, 1] for L', over [-1, 1] for L, `nodes` nodes, times 2 nodes
// equally spaced in azimuth). Exact to rounding for a band-limited L with nodes > order; L' is
// smooth on the hemisphere h.w_o > 0, so nodes well above the order converge. Preconditions: as
// above, nodes >= order + 1.
ShLighting prepareShLighting(const RadianceFunction& radiance, int order, glm::dvec3 fixedView,
                             SpecularCosine cosine = SpecularCosine::MeanNormal, int nodes = 64);

// ---- the SH method
// --------------------------------------------------------------------------------

// The sh bake's coefficients g (tangent frame, shCount(a.order) values) under the lighting: L and
// L' are rotated into the tangent frame (sh_rotation.h, with the transpose of
// tangentToEnvironment, whose columns are the hit's tangent, bitangent and normal in the
// environment frame and must be orthonormal), then H eqs. 35 and 37 with ShShading's A_l, up to
// min(a.order, lighting.order). Each sum is clamped at 0 per channel as shadeSh clamps its sums.
// `v` (tangent frame) is not read: the fixed view is the lighting's. The factor g(theta_d) of a
// factored tabulated BRDF is not applied (it would need w_i per h).
glm::vec3 shadeShEnvironment(const Material& m, glm::vec3 albedo, const float* g,
                             const ShShading& a, glm::vec3 v, const glm::mat3& tangentToEnvironment,
                             const ShLighting& lighting);

// ---- the vMF method
// -------------------------------------------------------------------------------

// A_0 ... A_order of the normalised vMF lobe kappa/(4 pi sinh kappa) exp(kappa mu.n) as a
// function of n.mu (sh_brdf.h's convention): A_l = i_l(kappa) / i_0(kappa), the ratio of modified
// spherical Bessel functions of the first kind (A_1 = coth kappa - 1/kappa, Langevin's function).
// Exact: by the terminating series of i_l for kappa >= 32 and by Miller's backward recurrence
// below. kappa = 0 gives 1, 0, 0, ... Preconditions: kappa >= 0 and finite, 0 <= order <=
// kMaxShOrder.
void vmfBandFactors(double kappa, int order, double* out);

// How a lobe's specular transfer r_eff is formed.
enum class VmfSpecularTransfer {
    Widened,   // the widened lobe of shadeVmf (H eq. 29 Blinn-Phong, H eq. 30 Beckmann and GGX, a
               // table unwidened), projected per lobe: Blinn-Phong in closed form, Beckmann and GGX
               // by projectTransfer (slow: for reference renders)
    Convolved, // the exact convolution in SH: vmfBandFactors(kappa) times the material's A_l
};

// Han et al.'s vMF lobes (as shadeVmf receives them: J packed (alpha, alpha r mu) quadruples,
// tangent frame, optional lobe colours that multiply the material's albedo in place of
// `albedo`) under the lighting. Per lobe, with mu mapped to the environment frame:
//   diffuse   alpha Sum_l A_l^vMF(kappa) A_l^Lambert Sum_m L_lm Y_lm(mu)               (H eq. 35)
//   specular  alpha Sum_l A_l^eff Sum_m L'_lm Y_lm(mu)                                 (H eq. 37)
// with A^eff from `transfer`; sums clamped at 0 per lobe and channel. `a` is the material's
// shShadingFor at the lighting's order or above (its specular A_l for Convolved and tabulated
// lobes). Lobes are unpacked as shadeVmf does (Banerjee's kappa, at most 1e5).
glm::vec3 shadeVmfEnvironmentSh(const Material& m, glm::vec3 albedo, const float* lobes, int count,
                                const glm::vec3* colors, glm::vec3 v,
                                const glm::mat3& tangentToEnvironment, const ShLighting& lighting,
                                const ShShading& a,
                                VmfSpecularTransfer transfer = VmfSpecularTransfer::Widened);

} // namespace ndfmip
