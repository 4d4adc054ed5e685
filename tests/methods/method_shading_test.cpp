// Shading pieces shared by the methods: the specular cosine of a filtered lobe, and Toksvig's
// lookup table against his closed form.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "methods/vmf/vmf_test_support.h"
#include "ndfmip/method_shading.h"
#include "ndfmip/toksvig.h"

namespace ndfmip {
namespace {

using vmftest::direction;
using vmftest::sampleVmf;

TEST(MethodShading, SpecularCosineMatchesTheTruthsMeanOfLobeTimesCosine) {
    // Normals drawn from a vMF: the truth's mean of lobe(n.h) (n.l) against the mean lobe times
    // specularCosine, and times the old max(Na.l, 0) with the unnormalised mean normal.
    std::mt19937_64 rng(5);
    double errorSum = 0, oldSum = 0;
    int cases = 0;
    for (float kappa : {20.f, 80.f, 400.f}) {
        const glm::vec3 mu = direction(25, 40);
        std::vector<glm::vec3> n(40000);
        glm::dvec3 mean(0.0);
        for (glm::vec3& x : n) {
            x = sampleVmf(mu, kappa, rng);
            mean += glm::dvec3(x);
        }
        const glm::vec3 na = glm::vec3(mean / double(n.size()));
        for (float s : {8.f, 32.f, 128.f, 512.f}) {
            for (const glm::vec3 l : {direction(30, 0), direction(50, 200), direction(10, 90)}) {
                const glm::vec3 v(0.f, 0.f, 1.f), h = glm::normalize(l + v);
                double lobe = 0, truth = 0;
                for (const glm::vec3& x : n) {
                    const double b = blinnPhong(glm::dot(x, h), s);
                    lobe += b;
                    truth += b * std::max(0.f, glm::dot(x, l));
                }
                if (truth < 1e-3 * double(n.size())) continue; // nothing reflects here
                const double predicted = lobe * specularCosine(mu, kappa, s, h, l);
                const double old = lobe * std::max(0.f, glm::dot(na, l));
                const double error = std::abs(predicted / truth - 1),
                             oldError = std::abs(old / truth - 1);
                EXPECT_LT(error, 0.1) << "kappa " << kappa << " s " << s << " l.z " << l.z;
                EXPECT_LE(error, oldError + 1e-3)
                    << "kappa " << kappa << " s " << s << " l.z " << l.z;
                errorSum += error;
                oldSum += oldError;
                ++cases;
            }
        }
    }
    // Measured: mean 0.74% against 10.7% for max(Na.l, 0); the worst cases (8%) are lights on the
    // far side, where part of the reflecting normals face away (the clamp).
    EXPECT_LT(errorSum / cases, 0.015);
    EXPECT_GT(oldSum / cases, 5 * errorSum / cases);
    // The limits: a single normal gives mu.l, a uniform NDF A(s) h.l.
    const glm::vec3 mu = direction(20, 0), h = direction(10, 90), l = direction(40, 120);
    EXPECT_NEAR(specularCosine(mu, 1e30f, 100.f, h, l), glm::dot(mu, l), 1e-6);
    EXPECT_NEAR(specularCosine(mu, 1e30f, 0.f, h, l), glm::dot(mu, l), 1e-6);
    EXPECT_NEAR(specularCosine(mu, 0.f, 100.f, h, l),
                (1 / std::tanh(100.0) - 0.01) * glm::dot(h, l), 1e-6);
}

TEST(MethodShading, ToksvigLutMatchesTheClosedFormWhereThePhaseOutIsOff) {
    // Eq. 9 through the 256 x 256 table with the 8-bit phase-out (eqs. 10-11): where |Na| is
    // short enough that quantisation does not matter, the table gives shadeToksvig's lobe up to
    // bilinear interpolation; near |Na| = 1 the phase-out takes it towards the aliased lobe.
    Material m;
    m.brdf = Brdf::BlinnPhong;
    m.exponent = 32.f;
    m.albedo = glm::vec3(0.f);
    m.specular = glm::vec3(1.f);
    ToksvigLutOptions o;
    o.exponent = m.exponent;
    o.size = 256;
    o.bitDepth = 8;
    const Image lut = toksvigLut(o);
    const glm::vec3 l = direction(30, 10), v(0.f, 0.f, 1.f);
    for (float length : {0.7f, 0.8f, 0.9f}) {
        ASSERT_LT(lengthQuantisationError(8) * toksvigIntensitySensitivity(length, m.exponent),
                  o.threshold);
        double worst = 0, peak = 0;
        for (float tilt = 0.f; tilt < 40.f; tilt += 2.f) {
            const glm::vec3 na = length * direction(tilt, 10);
            const float a = shadeToksvigLut(m, m.albedo, na, lut, l, v).x;
            const float b = shadeToksvig(m, m.albedo, na, l, v, RoughnessMapping::Ours).x;
            worst = std::max(worst, double(std::abs(a - b)));
            peak = std::max(peak, double(b));
        }
        EXPECT_LT(worst, 0.02 * peak) << length;
    }
}

} // namespace
} // namespace ndfmip
