// What the ground truth's tests under an environment share: lighting from an in-memory map, the
// textures a render reads, and an uneven map (a bright blob, a coloured band, a dark half).
#pragma once

#include <cmath>
#include <memory>

#include "env/env_test_support.h"
#include "ndfmip/environment_lighting.h"
#include "ndfmip/render.h"

namespace ndfmip::envtruth {

inline std::shared_ptr<const EnvironmentLighting> lightingOf(Environment env) {
    return std::make_shared<const EnvironmentLighting>(makeEnvironmentLighting(std::move(env)));
}

inline RenderTextures texturesOf(const Image& normals,
                                 std::shared_ptr<const EnvironmentLighting> lighting) {
    RenderTextures t;
    t.normals = std::make_shared<const Image>(normals);
    t.environment = std::move(lighting);
    return t;
}

inline Environment unevenMap(int width) {
    return envtest::mapOf(width, [](glm::dvec3 d) {
        const double blob =
            std::exp(40. * (glm::dot(d, glm::normalize(glm::dvec3(0.3, 0.8, -0.4))) - 1.));
        const double band = std::abs(d.z) < 0.3 ? 0.6 : 0.;
        return glm::dvec3(0.1 + 40. * blob + band, 0.1 + 30. * blob, d.y > 0. ? 0.3 : 0.02);
    });
}

} // namespace ndfmip::envtruth
