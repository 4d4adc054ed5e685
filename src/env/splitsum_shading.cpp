// Each method's split-sum shading (environment_splitsum.h): what an engine's pixel shader does
// with the method's filtered parameters under a prefiltered environment. The shading is
// splitsum_shading.glsl, the GPU renderer's own source, compiled here as C++ (glsl.h) over the
// prepared lighting's lookups.
#include <glm/glm.hpp>

#include "ndfmip/environment_splitsum.h"
#include "ndfmip/glsl.h"

namespace ndfmip {
namespace glsl_detail {

using glm::mat3;

// splitsum_shading.glsl with its lookups on a SplitSumLighting: the data members stand in for
// the GPU's uniforms of the same names.
struct SplitSumShading : ShaderLibrary {
    SplitSumShading(const SplitSumLighting& l, EnvironmentLod r)
        : lighting(l), rule(r), ndfmipEnvRule(int(r)), ndfmipEnvBandFactors(l.vmfBandFactors),
          ndfmipEnvWeightedReflection(l.weightedReflection) {}

    const SplitSumLighting& lighting;
    EnvironmentLod rule;
    int ndfmipEnvRule;
    int ndfmipEnvBandFactors;
    int ndfmipEnvWeightedReflection;

    vec3 ndfmipPrefilteredRadiance(vec3 reflected, float r, float normalVariance) const {
        return prefilteredRadiance(lighting, rule, glm::dvec3(reflected), r, normalVariance);
    }
    float ndfmipSpecularAlbedo(NdfmipMaterial m, float mu, float r) const {
        return specularAlbedo(lighting, Brdf(m.brdf), mu, r);
    }
    vec2 ndfmipSpecularAlbedoAndSlope(NdfmipMaterial m, float mu, float r) const {
        return specularAlbedoAndSlope(lighting, Brdf(m.brdf), mu, r);
    }
    float ndfmipDominantShare(NdfmipMaterial m, float mu, float r) const {
        return dominantShare(lighting, Brdf(m.brdf), mu, r);
    }
    vec3 ndfmipIrradiance(vec3 n, vec3 band) const {
        return irradianceAt(lighting, glm::dvec3(n), glm::dvec3(band));
    }

// clang-format off
#include "splitsum_shading.glsl"
    // clang-format on
};

static_assert(int(EnvironmentLod::Log2Sigma) == 0 && int(EnvironmentLod::Filament) == 1 &&
                  int(EnvironmentLod::Unity) == 2 && int(EnvironmentLod::Unreal) == 3,
              "environment.glsl's ndfmipEnvRule");

} // namespace glsl_detail

namespace {

using glsl_detail::SplitSumShading;

// splitsum.glsl's variance scale is the ours mapping's.
static_assert(kVarianceScale == NDFMIP_VARIANCE_SCALE, "splitsum.glsl's variance scale");

} // namespace

glm::vec3 shadeNaiveSplitSum(const Material& m, glm::vec3 albedo, glm::vec3 filtered,
                             glm::vec3 view, const glm::mat3& tangentToEnvironment,
                             const SplitSumLighting& lighting, EnvironmentLod rule) {
    return SplitSumShading(lighting, rule)
        .ndfmipShadeNaiveEnvironment(glslMaterial(m), albedo, filtered, tangentToEnvironment, view);
}

glm::vec3 shadeToksvigSplitSum(const Material& m, glm::vec3 albedo, glm::vec3 na, glm::vec3 view,
                               const glm::mat3& tangentToEnvironment,
                               const SplitSumLighting& lighting, EnvironmentLod rule,
                               RoughnessMapping mapping, float varianceScale) {
    return SplitSumShading(lighting, rule)
        .ndfmipShadeToksvigEnvironment(glslMaterial(m), albedo, na, tangentToEnvironment, view,
                                       int(mapping), varianceScale);
}

glm::vec3 shadeRoughnessMipsSplitSum(const Material& m, glm::vec3 albedo, glm::vec3 filtered,
                                     float stored, bool isAlpha, glm::vec3 view,
                                     const glm::mat3& tangentToEnvironment,
                                     const SplitSumLighting& lighting, EnvironmentLod rule) {
    return SplitSumShading(lighting, rule)
        .ndfmipShadeRoughnessMipsEnvironment(glslMaterial(m), albedo, filtered, stored, isAlpha,
                                             tangentToEnvironment, view);
}

glm::vec3 shadeVmfSplitSum(const Material& m, glm::vec3 albedo, const float* lobes, int count,
                           const glm::vec3* colors, glm::vec3 view,
                           const glm::mat3& tangentToEnvironment, const SplitSumLighting& lighting,
                           EnvironmentLod rule) {
    SplitSumShading shading(lighting, rule);
    const GlslMaterial material = glslMaterial(m);
    glm::vec3 out(0.f);
    for (int j = 0; j < count; ++j) {
        const float* p = lobes + 4 * j;
        out += shading.ndfmipShadeVmfLobeEnvironment(
            material, colors ? colors[j] * m.albedo : albedo, glm::vec4(p[0], p[1], p[2], p[3]),
            tangentToEnvironment, view);
    }
    return out;
}

} // namespace ndfmip
