// The SH and vMF methods shaded by SH lighting (environment_sh_shading.h; Han et al. eqs. 35, 37).
// The shading is sh_lighting_shading.glsl, the GPU renderer's own source, compiled here as C++
// (glsl.h) in double and up to order 30, over the prepared lighting's rows.
#include <algorithm>
#include <cassert>
#include <cmath>

#include <glm/gtc/type_ptr.hpp>

#include "ndfmip/brdf.h"
#include "ndfmip/environment_sh_shading.h"
#include "ndfmip/glsl.h"
#include "ndfmip/method_shading.h"
#include "ndfmip/sh_brdf.h"
#include "ndfmip/sh_rotation.h"
#include "ndfmip/spherical_harmonics.h"

namespace ndfmip {
namespace glsl_detail {

using glm::ceil;

// The arrays' lengths of sh_lighting_shading.glsl on the CPU: every band up to kMaxShOrder.
#define NDFMIP_ENV_SH_BANDS (kMaxShOrder + 1)
#define NDFMIP_ENV_SH_COEFFICIENTS (shCount(kMaxShOrder))

// sh_lighting_shading.glsl in double: its NdfmipReal, vec3 and the basis stand for double, glm's
// double vector and spherical_harmonics.h's evaluateSh here; the data members for the GPU's
// uniforms of the same names. Row r of coefficient i is the RGB triple at rows[r] + stride i.
struct ShLightingShading {
    using NdfmipReal = double;
    using vec3 = glm::dvec3;
    struct NdfmipEnvShBasis {
        double y[shCount(kMaxShOrder)];
    };

    ShLightingShading(int order, SpecularCosine cosine, const ShShading& a)
        : ndfmipEnvShOrder(order), ndfmipEnvShAxes(cosine == SpecularCosine::Reflecting   ? 2
                                                   : cosine == SpecularCosine::MeanNormal ? 1
                                                                                          : 0),
          ndfmipEnvShDiffuse(a.diffuse.data()), ndfmipEnvShSpecular(a.specular.data()) {}

    int ndfmipEnvShOrder;
    int ndfmipEnvShAxes;
    const double* ndfmipEnvShDiffuse;
    const double* ndfmipEnvShSpecular;
    const double* rows[5] = {};
    size_t stride = 3;

    vec3 ndfmipEnvShRow(int i, int row) const {
        const double* p = rows[row] + stride * size_t(i);
        return {p[0], p[1], p[2]};
    }
    NdfmipEnvShBasis ndfmipEnvShBasisAt(vec3 w) const {
        NdfmipEnvShBasis basis;
        evaluateSh(w, ndfmipEnvShOrder, basis.y);
        return basis;
    }

// clang-format off
#include "sh_lighting_shading.glsl"
    // clang-format on
};

#undef NDFMIP_ENV_SH_BANDS
#undef NDFMIP_ENV_SH_COEFFICIENTS

} // namespace glsl_detail

namespace {

using glsl_detail::ShLightingShading;

// The lighting re-expressed in one tangent frame, L_t(d) = L(T d): L, then the cosine's
// reparameterisedSets (the axes' are combined after the rotation since rotation is linear), as
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
    const int channels = 3 * (1 + reparameterisedSets(lighting.cosine));
    cached.values = interleavedShLighting(lighting, order);
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
    // L and L' in the tangent frame, where the NDF's coefficients are.
    const FrameLighting& frame = lightingInFrame(lighting, tangentToEnvironment, order);
    ShLightingShading shading(order, lighting.cosine, a);
    for (int r = 0; r < frame.channels / 3; ++r) shading.rows[r] = frame.values.data() + 3 * r;
    shading.stride = size_t(frame.channels);
    double coefficients[shCount(kMaxShOrder)];
    for (int i = 0; i < count; ++i) coefficients[i] = double(g[i]);
    // Footnote 5's mipmapped normal, (g_11, g_1-1, g_10) / sqrt(3 / 4 pi), in the environment
    // frame (sh.glsl's ndfmipShMeanNormal).
    const glm::dvec3 meanNormal =
        glm::dmat3(tangentToEnvironment) *
        (glm::dvec3(g[shIndex(1, 1)], g[shIndex(1, -1)], g[shIndex(1, 0)]) /
         std::sqrt(3. / (4. * M_PI)));
    // Read as one lobe of Banerjee's kappa for its length (sh.glsl's point-light cosine too).
    const double kappa = double(glsl().ndfmipKappaFromLength(float(glm::length(meanNormal))));
    return glm::vec3(shading.ndfmipShadeShLighting(int(m.brdf), glm::dvec3(albedo),
                                                   glm::dvec3(m.specular), coefficients, meanNormal,
                                                   kappa, lobeConcentration(m)));
}

void vmfBandFactors(double kappa, int order, double* out) {
    assert(kappa >= 0. && std::isfinite(kappa) && order >= 0 && order <= kMaxShOrder);
    const ShShading none;
    const ShLightingShading::NdfmipVmfBands bands =
        ShLightingShading(order, SpecularCosine::None, none).ndfmipVmfBands(kappa, order);
    std::copy(bands.a, bands.a + order + 1, out);
}

glm::vec3 shadeVmfEnvironmentSh(const Material& m, glm::vec3 baseAlbedo, const float* lobes,
                                int count, const glm::vec3* colors, glm::vec3 /*v*/,
                                const glm::mat3& tangentToEnvironment, const ShLighting& lighting,
                                const ShShading& a, VmfSpecularTransfer transfer) {
    const int order = std::min(a.order, lighting.order);
    // The lighting in the environment frame, where the lobes' mu are mapped.
    ShLightingShading shading(order, lighting.cosine, a);
    shading.rows[0] = glm::value_ptr(lighting.radiance[0]);
    for (int k = 0; k < reparameterisedSets(lighting.cosine); ++k)
        shading.rows[1 + k] = glm::value_ptr(reparameterisedSet(lighting, k)[0]);
    const double lobeKappa = double(lobeConcentration(m));
    const bool widen = transfer == VmfSpecularTransfer::Widened;
    glm::dvec3 out(0.);
    for (int j = 0; j < count; ++j) {
        const GlslLibrary::NdfmipLobe lobe = glsl().ndfmipUnpackLobe(
            glm::vec4(lobes[4 * j], lobes[4 * j + 1], lobes[4 * j + 2], lobes[4 * j + 3]));
        if (!(lobe.alpha > 0.f)) continue;
        const double kappa = double(lobe.kappa);
        // mu in the environment frame: the lobe is radially symmetric, so no rotation of the
        // lighting is needed, only Y_lm(mu) (the paper's footnote 10).
        const glm::dvec3 mu = glm::normalize(glm::dvec3(tangentToEnvironment * lobe.mu));
        const auto bands = shading.ndfmipVmfBands(kappa, std::max(order, 1));
        auto t =
            shading.ndfmipVmfLobeTransfer(int(m.brdf), double(m.exponent), kappa, bands, widen);
        if (widen && m.brdf == Brdf::Tabulated) { // a table is not widened
            std::copy(a.specular.begin(), a.specular.begin() + order + 1, t.specular);
        } else if (widen && m.brdf != Brdf::BlinnPhong && m.brdf != Brdf::Lambert) {
            // H eq. 30 and its GGX analogue, as shadeVmf (the same floor on kappa), projected:
            // the slow reference the convolution is checked against.
            const double alpha =
                std::sqrt(double(m.roughness) * double(m.roughness) + 2. / std::max(kappa, 1e-6));
            const bool beckmann = m.brdf == Brdf::Beckmann;
            const std::vector<double> widened = projectTransfer(
                [&](double c) {
                    return beckmann ? beckmannTransfer(c, alpha) : ggxTransfer(c, alpha);
                },
                order);
            std::copy(widened.begin(), widened.end(), t.specular);
        }
        const glm::vec3 albedo = colors ? colors[j] * m.albedo : baseAlbedo;
        out += shading.ndfmipShadeVmfLobeShLighting(int(m.brdf), glm::dvec3(albedo),
                                                    glm::dvec3(m.specular), mu, double(lobe.alpha),
                                                    kappa, bands.a[1], lobeKappa, t);
    }
    return glm::vec3(out);
}

} // namespace ndfmip
