// Helpers shared by the environment tests: maps of a function, and the split-sum integral by
// brute force over every texel (the reference the prefilter is measured against).
#pragma once

#include <cmath>
#include <filesystem>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>
#include <gtest/gtest.h>

#include "ndfmip/environment.h"
#include "test_support.h"

namespace ndfmip::envtest {

using Radiance = std::function<glm::dvec3(glm::dvec3)>;

// A width x width/2 map of f at the texel centres.
inline Environment mapOf(int width, const Radiance& f) {
    Environment env;
    env.radiance = Image(width, width / 2, 3);
    for (int y = 0; y < width / 2; ++y)
        for (int x = 0; x < width; ++x) {
            const glm::dvec3 c = f(equirectDirection((x + 0.5) / width, (y + 0.5) / (width / 2)));
            float* p = env.radiance.at(x, y);
            for (int i = 0; i < 3; ++i) p[i] = float(c[i]);
        }
    return env;
}

// The shared maps found beside the checkout (venice_sunset_1k, studio_small_03_1k), each
// resampled to width x width/2, with their file names; none where there is no ../shared.
inline std::vector<std::pair<std::string, Environment>> sharedMapsAt(int width) {
    std::vector<std::pair<std::string, Environment>> maps;
    const std::filesystem::path dir = test::sharedEnvMaps();
    if (dir.empty()) return maps;
    for (const char* file : {"venice_sunset_1k.hdr", "studio_small_03_1k.hdr"}) {
        if (!std::filesystem::exists(dir / file)) continue;
        Result<Environment> loaded = loadEnvironment((dir / file).string());
        if (!loaded) {
            ADD_FAILURE() << loaded.error().message;
            continue;
        }
        Environment env;
        env.radiance = resampleEquirect(loaded.value().radiance, width);
        maps.emplace_back(file, std::move(env));
    }
    return maps;
}

// Point i of `count` spread evenly over the sphere (a Fibonacci spiral).
inline glm::dvec3 spiralDirection(int i, int count) {
    const double z = 1. - 2. * (i + 0.5) / count, phi = i * 2.399963229728653,
                 s = std::sqrt(1. - z * z);
    return {s * std::cos(phi), z, s * std::sin(phi)};
}

// The split-sum level LD(r) = sum L D(h) <r.l> / sum D(h) <r.l> over every texel of the map
// read as constant per texel, as the prefilter reads it.
class BruteForceGgx {
  public:
    explicit BruteForceGgx(const Environment& env) : env_(env) {
        const Image& m = env.radiance;
        for (int y = 0; y < m.height; ++y)
            for (int x = 0; x < m.width; ++x)
                directions_.push_back(rotateAboutY(
                    equirectDirection((x + 0.5) / m.width, (y + 0.5) / m.height), env.rotation));
    }

    glm::dvec3 operator()(glm::dvec3 r, double alpha) const {
        const double a2 = alpha * alpha;
        return convolve(r, [a2](double nh2) {
            const double f = nh2 * (a2 - 1.) + 1.;
            return a2 / (M_PI * f * f);
        });
    }

    // The same with the Blinn-Phong lobe D proportional to <n.h>^s.
    glm::dvec3 blinnPhong(glm::dvec3 r, double exponent) const {
        return convolve(r, [exponent](double nh2) { return std::pow(nh2, exponent / 2.); });
    }

  private:
    // sum L D <r.l> / sum D <r.l>, D given as a function of <n.h>^2.
    glm::dvec3 convolve(glm::dvec3 r, const std::function<double(double)>& lobe) const {
        const Image& m = env_.radiance;
        glm::dvec3 sum(0.);
        double weights = 0.;
        for (int y = 0; y < m.height; ++y) {
            const double omega = equirectTexelSolidAngle(m.width, m.height, y);
            for (int x = 0; x < m.width; ++x) {
                const glm::dvec3& l = directions_[size_t(y) * size_t(m.width) + size_t(x)];
                const double nl = glm::dot(r, l);
                if (nl <= 0.) continue;
                const glm::dvec3 h = l + r;
                const double nh2 = glm::dot(r, h) * glm::dot(r, h) / glm::dot(h, h);
                const double w = lobe(nh2) * nl * omega;
                const float* p = m.at(x, y);
                sum += w * glm::dvec3(p[0], p[1], p[2]);
                weights += w;
            }
        }
        return sum / weights;
    }

    const Environment& env_;
    std::vector<glm::dvec3> directions_;
};

// Relative RMSE (all channels together) of `lookup(r)` against the brute-force level at `count`
// spiral directions.
inline double relativeRmseAgainstBruteForce(const Environment& env, double alpha, int count,
                                            const std::function<glm::dvec3(glm::dvec3)>& lookup) {
    const BruteForceGgx truthOf(env);
    double error = 0., norm = 0.;
#pragma omp parallel for reduction(+ : error, norm) schedule(dynamic, 1)
    for (int i = 0; i < count; ++i) {
        const glm::dvec3 r = spiralDirection(i, count);
        const glm::dvec3 truth = truthOf(r, alpha), got = lookup(r);
        for (int c = 0; c < 3; ++c) {
            error += (got[c] - truth[c]) * (got[c] - truth[c]);
            norm += truth[c] * truth[c];
        }
    }
    return std::sqrt(error / norm);
}

// The same for an equirectangular level, read bilinearly.
inline double relativeRmseAgainstBruteForce(const Environment& env, const Image& level,
                                            double alpha, int count) {
    return relativeRmseAgainstBruteForce(env, alpha, count, [&](glm::dvec3 r) {
        float got[3];
        sampleEquirect(level, r, got);
        return glm::dvec3(got[0], got[1], got[2]);
    });
}

} // namespace ndfmip::envtest
