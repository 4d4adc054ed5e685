// An environment map as the renderer's light: the frame mapping between the renderer's world
// (+Z up) and the environment's (+Y up, environment.h), the radiance the truth reads, and an
// importance sampler of that radiance. docs/ENVIRONMENT.md and docs/RENDERING.md.
#pragma once

#include <memory>
#include <mutex>
#include <vector>

#include <glm/glm.hpp>

#include "ndfmip/environment.h"

namespace ndfmip {

// ---- frames -------------------------------------------------------------------------------------

// World (+Z up, the default camera looking along +Y) to environment (+Y up): e = (-w.x, w.z, w.y).
// A proper rotation: world up is the map's top row, world +Y (where the default camera looks)
// the map's centre +Z.
inline glm::vec3 worldToEnvironment(glm::vec3 w) {
    return {-w.x, w.z, w.y};
}
inline glm::dvec3 worldToEnvironment(glm::dvec3 w) {
    return {-w.x, w.z, w.y};
}
// Its inverse: w = (-e.x, e.z, e.y).
inline glm::vec3 environmentToWorld(glm::vec3 e) {
    return {-e.x, e.z, e.y};
}
inline glm::dvec3 environmentToWorld(glm::dvec3 e) {
    return {-e.x, e.z, e.y};
}

// The matrix taking tangent-frame vectors to the environment frame: its columns are the
// surface's tangent, bitangent and normal (world space, orthonormal) mapped world -> environment.
// Its transpose is the inverse.
inline glm::mat3 tangentToEnvironment(glm::vec3 tangent, glm::vec3 bitangent, glm::vec3 normal) {
    return glm::mat3(worldToEnvironment(tangent), worldToEnvironment(bitangent),
                     worldToEnvironment(normal));
}

// ---- importance sampling of the radiance --------------------------------------------------------

// A piecewise-constant density over the map's texels: texel (x, y) is chosen with probability
// proportional to its luminance times its solid angle (a marginal over rows, then a conditional
// over the row's columns), and a direction uniformly in solid angle within it. The density per
// steradian is therefore luminance / sum(luminance * solid angle), constant over each texel.
// Directions are the seen ones (Environment::rotation applied). A black map is sampled uniformly.
struct EnvironmentSampler {
    int width = 0, height = 0;
    double rotation = 0.;      // Environment::rotation
    std::vector<float> weight; // per texel, row after row: luminance (1 everywhere for a black map)
    double total = 0.;         // sum of weight * texel solid angle
    std::vector<double> rowCdf;    // height + 1 entries, 0 ... 1
    std::vector<double> columnCdf; // per row width + 1 entries, 0 ... 1
};

EnvironmentSampler makeEnvironmentSampler(const Environment& env);

struct EnvironmentSample {
    glm::dvec3 direction{0., 1., 0.}; // unit, environment frame, as seen
    double pdf = 0.;                  // per steradian, equal to environmentPdf(direction)
};

// Two uniform numbers in [0, 1) to a direction and its density.
EnvironmentSample sampleEnvironment(const EnvironmentSampler& sampler, double u1, double u2);

// The density sampleEnvironment draws unit direction d (environment frame, as seen) with.
double environmentPdf(const EnvironmentSampler& sampler, glm::dvec3 d);

// ---- the lighting a render uses
// ------------------------------------------------------------------

// The methods' prepared data for one environment (environment_cache.h): made on first use, then
// shared by every later render, since a prefiltered chain or an SH lighting costs ~0.1 s and an
// eval renders the same map hundreds of times. A copy starts empty, so a copy whose environment
// is changed never reads the original's data.
struct EnvironmentCache {
    struct Entry; // environment_cache.cpp
    std::mutex mutex;
    std::vector<std::shared_ptr<Entry>> entries; // oldest first
    EnvironmentCache() = default;
    EnvironmentCache(const EnvironmentCache&) {}
    EnvironmentCache& operator=(const EnvironmentCache&) {
        std::lock_guard<std::mutex> lock(mutex);
        entries.clear();
        return *this;
    }
};

struct EnvironmentLighting {
    Environment environment;
    EnvironmentSampler sampler;
    mutable EnvironmentCache cache; // filled through const references (environment_cache.h)
};

EnvironmentLighting makeEnvironmentLighting(Environment environment);

// The radiance seen along unit direction d (environment frame): the texel d falls in, read as
// constant over its solid angle (the model the sampler and projectEnvironmentSh use).
glm::vec3 environmentRadiance(const Environment& env, glm::dvec3 d);

// Rec. 709 luminance, the weight of the sampler and of the render's noise figures.
inline double rec709Luminance(glm::dvec3 c) {
    return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z;
}

} // namespace ndfmip
