// The SH and vMF methods shaded by SH lighting (environment_sh_shading.h; Han et al. eqs. 35, 37).
#include <algorithm>
#include <cassert>
#include <cmath>

#include "ndfmip/brdf.h"
#include "ndfmip/environment_sh_shading.h"
#include "ndfmip/sh_brdf.h"
#include "ndfmip/sh_rotation.h"
#include "ndfmip/spherical_harmonics.h"
#include "ndfmip/vmf.h"

namespace ndfmip {
namespace {

// Sum over l <= order of A_l Sum_m c_lm x_lm, x RGB.
glm::dvec3 weightedDot(const std::vector<double>& A, int order, const double* c,
                       const glm::dvec3* x) {
    glm::dvec3 sum(0.);
    for (int l = 0; l <= order; ++l) {
        glm::dvec3 band(0.);
        for (int i = shIndex(l, -l); i <= shIndex(l, l); ++i) band += c[i] * x[i];
        sum += A[size_t(l)] * band;
    }
    return sum;
}

glm::vec3 clampedColour(glm::dvec3 x) {
    return glm::vec3(glm::max(x, glm::dvec3(0.)));
}

// The L'_lm a pixel's specular term reads: the prepared one, or for the MeanNormal cosine the
// axes' combined with the mean normal (environment frame).
glm::dvec3 reparameterisedAt(const ShLighting& lighting, int i, glm::dvec3 meanNormal) {
    if (lighting.cosine != SpecularCosine::MeanNormal) return lighting.reparameterised[size_t(i)];
    return meanNormal.x * lighting.reparameterisedAxes[0][size_t(i)] +
           meanNormal.y * lighting.reparameterisedAxes[1][size_t(i)] +
           meanNormal.z * lighting.reparameterisedAxes[2][size_t(i)];
}

GlslLibrary::NdfmipLobe unpacked(const float* p) {
    return glsl().ndfmipUnpackLobe(glm::vec4(p[0], p[1], p[2], p[3]));
}

} // namespace

namespace {

// The lighting re-expressed in one tangent frame, L_t(d) = L(T d): L, then L' (or, for the
// MeanNormal cosine, its three axes, combined after the rotation since rotation is linear), as
// interleaved channels. Rotating costs ~10 us at order 8, so each thread keeps the last frame's:
// a plane has one frame for every pixel.
struct FrameLighting {
    uint64_t lighting = 0; // ShLighting::id
    glm::mat3 frame{0.f};
    int order = -1, channels = 0;
    std::vector<double> values;
};

const FrameLighting& lightingInFrame(const ShLighting& lighting,
                                     const glm::mat3& tangentToEnvironment, int order) {
    thread_local FrameLighting cached;
    if (cached.lighting == lighting.id && cached.order == order &&
        cached.frame == tangentToEnvironment)
        return cached;
    const bool axes = lighting.cosine == SpecularCosine::MeanNormal;
    const int count = shCount(order), channels = axes ? 12 : 6;
    cached.values.assign(size_t(channels) * size_t(count), 0.);
    for (int i = 0; i < count; ++i) {
        double* p = &cached.values[size_t(channels) * size_t(i)];
        for (int c = 0; c < 3; ++c) {
            p[c] = lighting.radiance[size_t(i)][c];
            if (axes)
                for (int k = 0; k < 3; ++k)
                    p[3 + 3 * k + c] = lighting.reparameterisedAxes[k][size_t(i)][c];
            else
                p[3 + c] = lighting.reparameterised[size_t(i)][c];
        }
    }
    rotateSh(glm::transpose(glm::dmat3(tangentToEnvironment)), order, cached.values.data(),
             cached.values.data(), channels);
    cached.lighting = lighting.id, cached.order = order, cached.frame = tangentToEnvironment,
    cached.channels = channels;
    return cached;
}

} // namespace

glm::vec3 shadeShEnvironment(const Material& m, glm::vec3 albedo, const float* g,
                             const ShShading& a, glm::vec3 /*v*/,
                             const glm::mat3& tangentToEnvironment, const ShLighting& lighting) {
    const int order = std::min(a.order, lighting.order), count = shCount(order);
    assert(int(lighting.radiance.size()) >= count);
    // Footnote 5's mipmapped normal, (g_11, g_1-1, g_10) / sqrt(3 / 4 pi), in the environment
    // frame.
    const glm::dvec3 meanNormal =
        glm::dmat3(tangentToEnvironment) *
        (glm::dvec3(g[shIndex(1, 1)], g[shIndex(1, -1)], g[shIndex(1, 0)]) /
         std::sqrt(3. / (4. * M_PI)));
    // L and L' in the tangent frame, where the NDF's coefficients are.
    const FrameLighting& frame = lightingInFrame(lighting, tangentToEnvironment, order);
    glm::dvec3 radiance[shCount(kMaxShOrder)], reparameterised[shCount(kMaxShOrder)];
    double coefficients[shCount(kMaxShOrder)];
    for (int i = 0; i < count; ++i) {
        const double* p = &frame.values[size_t(frame.channels) * size_t(i)];
        radiance[i] = glm::dvec3(p[0], p[1], p[2]);
        reparameterised[i] = frame.channels == 12
                                 ? meanNormal.x * glm::dvec3(p[3], p[4], p[5]) +
                                       meanNormal.y * glm::dvec3(p[6], p[7], p[8]) +
                                       meanNormal.z * glm::dvec3(p[9], p[10], p[11])
                                 : glm::dvec3(p[3], p[4], p[5]);
        coefficients[i] = double(g[i]);
    }
    const glm::vec3 diffuse =
        clampedColour(weightedDot(a.diffuse, order, coefficients, radiance)); // H eq. 35
    if (m.brdf == Brdf::Lambert) return albedo * diffuse;
    const glm::vec3 specular =
        clampedColour(weightedDot(a.specular, order, coefficients, reparameterised)); // H eq. 37
    return albedo * diffuse + m.specular * specular;
}

void vmfBandFactors(double kappa, int order, double* out) {
    assert(kappa >= 0. && std::isfinite(kappa) && order >= 0 && order <= kMaxShOrder);
    out[0] = 1.;
    if (order == 0) return;
    if (kappa == 0.) {
        std::fill(out + 1, out + order + 1, 0.);
        return;
    }
    if (kappa >= 32.) {
        // i_n(k) = (e^k S_-(n) - (-1)^n e^-k S_+(n)) / (2k), S_-+ = Sum_j (-+1)^j (n+j)! / (j!
        // (n-j)! (2k)^j), and i_0 = sinh(k)/k: the ratio in terms of e^-2k, which cannot overflow.
        // The alternating sum cancels most at the smallest k and largest n: 3.5e-12 at k = 32, n =
        // 30 against projectTransfer, 1e-15 from k = 200 on.
        const double decay = std::exp(-2. * kappa);
        for (int n = 1; n <= order; ++n) {
            double term = 1., minus = 1., plus = 1.;
            for (int j = 0; j < n; ++j) {
                term *= double(n + j + 1) * double(n - j) / (double(j + 1) * 2. * kappa);
                minus += (j % 2 == 0 ? -term : term);
                plus += term;
            }
            out[n] = (minus - (n % 2 == 0 ? 1. : -1.) * decay * plus) / (1. - decay);
        }
        return;
    }
    // Miller: r_l = i_l / i_(l-1) = 1 / ((2l + 1)/k + r_(l+1)) from i_(l-1) - i_(l+1) = (2l+1)/k
    // i_l, started at 0 far enough above both l and k that the start's error has died out (the
    // ratios fall below 1/2 past l ~ k).
    const int start = order + 2 * int(std::ceil(kappa)) + 60;
    double ratio = 0.;
    double ratios[kMaxShOrder + 1];
    for (int l = start; l >= 1; --l) {
        ratio = 1. / ((2. * l + 1.) / kappa + ratio);
        if (l <= order) ratios[l] = ratio;
    }
    for (int l = 1; l <= order; ++l) out[l] = out[l - 1] * ratios[l];
}

glm::vec3 shadeVmfEnvironmentSh(const Material& m, glm::vec3 baseAlbedo, const float* lobes,
                                int count, const glm::vec3* colors, glm::vec3 /*v*/,
                                const glm::mat3& tangentToEnvironment, const ShLighting& lighting,
                                const ShShading& a, VmfSpecularTransfer transfer) {
    const int order = std::min(a.order, lighting.order);
    glm::dvec3 out(0.);
    double basis[shCount(kMaxShOrder)], band[kMaxShOrder + 1];
    std::vector<double> specularA(size_t(order) + 1);
    for (int j = 0; j < count; ++j) {
        const GlslLibrary::NdfmipLobe lobe = unpacked(lobes + 4 * j);
        if (!(lobe.alpha > 0.f)) continue;
        const double kappa = double(lobe.kappa);
        // mu in the environment frame: the lobe is radially symmetric, so no rotation of the
        // lighting is needed, only Y_lm(mu) (the paper's footnote 10).
        const glm::dvec3 mu = glm::normalize(glm::dvec3(tangentToEnvironment * lobe.mu));
        evaluateSh(mu, order, basis);
        vmfBandFactors(kappa, std::max(order, 1), band);
        const glm::dvec3 meanNormal = band[1] * mu; // A(kappa) mu: the lobe's mean normal
        glm::dvec3 diffuse(0.), specular(0.);
        for (int l = 0; l <= order; ++l) {
            glm::dvec3 sum(0.);
            for (int i = shIndex(l, -l); i <= shIndex(l, l); ++i)
                sum += lighting.radiance[size_t(i)] * basis[i];
            diffuse += band[l] * a.diffuse[size_t(l)] * sum; // H eq. 35
        }
        if (m.brdf != Brdf::Lambert) {
            if (transfer == VmfSpecularTransfer::Convolved || m.brdf == Brdf::Tabulated) {
                for (int l = 0; l <= order; ++l)
                    specularA[size_t(l)] =
                        a.specular[size_t(l)] *
                        (m.brdf == Brdf::Tabulated && transfer == VmfSpecularTransfer::Widened
                             ? 1.
                             : band[l]);
            } else if (m.brdf == Brdf::BlinnPhong) {
                const double s = double(m.exponent);
                specularA = blinnPhongCoefficients(kappa * s / (kappa + s), order); // H eq. 29
            } else {
                // H eq. 30 and its GGX analogue, as shadeVmf (the same floor on kappa).
                const double alpha = std::sqrt(double(m.roughness) * double(m.roughness) +
                                               2. / std::max(kappa, 1e-6));
                const bool beckmann = m.brdf == Brdf::Beckmann;
                specularA = projectTransfer(
                    [&](double t) {
                        return beckmann ? beckmannTransfer(t, alpha) : ggxTransfer(t, alpha);
                    },
                    order);
            }
            for (int l = 0; l <= order; ++l) {
                glm::dvec3 sum(0.);
                for (int i = shIndex(l, -l); i <= shIndex(l, l); ++i)
                    sum += reparameterisedAt(lighting, i, meanNormal) * basis[i];
                specular += specularA[size_t(l)] * sum; // H eq. 37
            }
        }
        const glm::vec3 albedo = colors ? colors[j] * m.albedo : baseAlbedo;
        out += double(lobe.alpha) * (glm::dvec3(albedo) * glm::max(diffuse, glm::dvec3(0.)) +
                                     glm::dvec3(m.specular) * glm::max(specular, glm::dvec3(0.)));
    }
    return glm::vec3(out);
}

} // namespace ndfmip
