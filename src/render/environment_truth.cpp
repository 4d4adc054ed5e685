// The truth under an environment: environment and BRDF sampling, combined by MIS
// (environment_truth.h).
#include "environment_truth.h"

#include <algorithm>
#include <cmath>

#include "ndfmip/brdf.h"

namespace ndfmip {

namespace {

// An orthonormal frame with n as its third axis (Duff et al. 2017, "Building an orthonormal
// basis, revisited").
void frameAbout(glm::dvec3 n, glm::dvec3& t, glm::dvec3& b) {
    const double sign = std::copysign(1., n.z);
    const double a = -1. / (sign + n.z), c = n.x * n.y * a;
    t = {1. + sign * n.x * n.x * a, sign * c, -sign * n.x};
    b = {c, sign + n.y * n.y * a, -n.y};
}

double powerHeuristic(double chosen, double other) {
    const double a = chosen * chosen, b = other * other;
    return a + b > 0. ? a / (a + b) : 0.;
}

// The integrand at unit tangent-frame l: L(l) shadeNormal, zero below the geometric surface.
glm::vec3 integrand(const EnvironmentLighting& lighting, const glm::mat3& toEnvironment,
                    const Material& material, glm::vec3 albedo, glm::vec3 n, glm::vec3 v,
                    glm::vec3 l) {
    if (l.z <= 0.f) return glm::vec3(0.f);
    const glm::vec3 radiance =
        environmentRadiance(lighting.environment, glm::dvec3(toEnvironment * l));
    if (radiance == glm::vec3(0.f)) return radiance;
    return radiance * shadeNormal(material, albedo, n, l, glm::normalize(l + v));
}

} // namespace

BrdfSampling brdfSampling(const Material& material, glm::vec3 albedo) {
    BrdfSampling s;
    if (material.brdf == Brdf::Tabulated) return s;
    const double diffuse = std::max(rec709Luminance(glm::dvec3(albedo)), 0.);
    const double specular = material.brdf == Brdf::Lambert
                                ? 0.
                                : std::max(rec709Luminance(glm::dvec3(material.specular)), 0.);
    if (!(diffuse + specular > 0.)) return s;
    s.usable = true;
    s.specular = specular / (diffuse + specular);
    return s;
}

double lobeHalfVectorPdf(const Material& material, double c) {
    if (!(c > 0.)) return 0.;
    const double c2 = c * c;
    switch (material.brdf) {
    case Brdf::BlinnPhong: {
        const double s = material.exponent;
        return (s + 2.) / (2. * M_PI) * std::pow(c, s + 1.);
    }
    case Brdf::Beckmann: {
        const double a2 = double(material.roughness) * material.roughness;
        return std::exp((c2 - 1.) / (c2 * a2)) / (M_PI * a2 * c2 * c);
    }
    case Brdf::Ggx: {
        const double a2 = double(material.roughness) * material.roughness;
        const double d = c2 * (a2 - 1.) + 1.;
        return a2 * c / (M_PI * d * d);
    }
    default:
        return 0.;
    }
}

glm::dvec3 sampleLobeHalfVector(const Material& material, double u1, double u2) {
    double c = 1.;
    const double a2 = double(material.roughness) * material.roughness;
    switch (material.brdf) {
    case Brdf::BlinnPhong:
        c = std::pow(u1, 1. / (double(material.exponent) + 2.));
        break;
    case Brdf::Beckmann:
        c = 1. / std::sqrt(1. - a2 * std::log1p(-u1));
        break; // tan^2 = -a^2 ln(1 - u)
    case Brdf::Ggx:
        c = std::sqrt((1. - u1) / (1. + (a2 - 1.) * u1));
        break; // tan^2 = a^2 u / (1 - u)
    default:
        break;
    }
    const double s = std::sqrt(std::max(0., 1. - c * c)), phi = 2. * M_PI * u2;
    return {s * std::cos(phi), s * std::sin(phi), c};
}

double brdfPdf(const Material& material, const BrdfSampling& sampling, glm::dvec3 n, glm::dvec3 v,
               glm::dvec3 l) {
    if (!sampling.usable) return 0.;
    double pdf = (1. - sampling.specular) * std::max(glm::dot(n, l), 0.) / M_PI;
    if (sampling.specular > 0.) {
        const glm::dvec3 sum = l + v;
        const double length = glm::length(sum);
        if (length > 0.) {
            const glm::dvec3 h = sum / length;
            const double vh = glm::dot(v, h);
            if (vh > 0.)
                pdf += sampling.specular * lobeHalfVectorPdf(material, glm::dot(n, h)) / (4. * vh);
        }
    }
    return pdf;
}

bool sampleBrdf(const Material& material, const BrdfSampling& sampling, glm::dvec3 n, glm::dvec3 v,
                const double u[3], glm::dvec3& l) {
    glm::dvec3 t, b;
    frameAbout(n, t, b);
    if (u[0] < sampling.specular) {
        const glm::dvec3 local = sampleLobeHalfVector(material, u[1], u[2]);
        const glm::dvec3 h = local.x * t + local.y * b + local.z * n;
        const double vh = glm::dot(v, h);
        if (!(vh > 0.)) return false;
        l = 2. * vh * h - v;
    } else { // cosine-weighted: a uniform disc lifted to the hemisphere (Malley's method)
        const double r = std::sqrt(u[1]), phi = 2. * M_PI * u[2];
        const double x = r * std::cos(phi), y = r * std::sin(phi);
        l = x * t + y * b + std::sqrt(std::max(0., 1. - x * x - y * y)) * n;
    }
    l = glm::normalize(l);
    return true;
}

glm::vec3 estimateEnvironmentRadiance(const EnvironmentLighting& lighting,
                                      const glm::mat3& toEnvironment, const Material& material,
                                      glm::vec3 albedo, glm::vec3 n, glm::vec3 v,
                                      EnvironmentEstimator estimator, const double u[5]) {
    const BrdfSampling sampling = brdfSampling(material, albedo);
    if (!sampling.usable) estimator = EnvironmentEstimator::Light;
    const glm::dvec3 nd(n), vd(v);
    glm::dvec3 sum(0.);
    if (estimator != EnvironmentEstimator::Brdf) {
        const EnvironmentSample e = sampleEnvironment(lighting.sampler, u[0], u[1]);
        // The inverse of an orthonormal matrix is its transpose.
        const glm::vec3 l = glm::normalize(glm::transpose(toEnvironment) * glm::vec3(e.direction));
        const glm::vec3 f = integrand(lighting, toEnvironment, material, albedo, n, v, l);
        if (f != glm::vec3(0.f)) {
            const double weight =
                estimator == EnvironmentEstimator::Mis
                    ? powerHeuristic(e.pdf, brdfPdf(material, sampling, nd, vd, glm::dvec3(l)))
                    : 1.;
            sum += glm::dvec3(f) * (weight / e.pdf);
        }
    }
    if (estimator != EnvironmentEstimator::Light) {
        glm::dvec3 ld;
        if (sampleBrdf(material, sampling, nd, vd, u + 2, ld)) {
            const glm::vec3 l(ld);
            const glm::vec3 f = integrand(lighting, toEnvironment, material, albedo, n, v, l);
            const double pdf = brdfPdf(material, sampling, nd, vd, ld);
            if (f != glm::vec3(0.f) && pdf > 0.) {
                const double weight =
                    estimator == EnvironmentEstimator::Mis
                        ? powerHeuristic(
                              pdf, environmentPdf(lighting.sampler, glm::dvec3(toEnvironment * l)))
                        : 1.;
                sum += glm::dvec3(f) * (weight / pdf);
            }
        }
    }
    return glm::vec3(sum);
}

} // namespace ndfmip
