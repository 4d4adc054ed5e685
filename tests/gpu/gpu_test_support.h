// A GL context for a test, or a clean skip with the one-line reason where there is none (no EGL,
// no driver). NDFMIP_REQUIRE_GPU=1 in the environment turns that skip into a failure, for
// machines that are known to have OpenGL.
#pragma once

#include <cmath>
#include <cstdlib>
#include <memory>
#include <string_view>

#include <glm/glm.hpp>
#include <gtest/gtest.h>

#include "gpu/gl_context.h"
#include "ndfmip/image.h"

namespace ndfmip::test {

inline bool gpuRequired() {
    const char* value = std::getenv("NDFMIP_REQUIRE_GPU");
    return value != nullptr && std::string_view(value) == "1";
}

// The GPU tests' normal map: 64x64 bumps, normals tilted up to ~40 degrees, varying within every
// texel block.
inline SharedImage bumpyMap() {
    auto image = std::make_shared<Image>(64, 64, 3);
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            const glm::vec3 n =
                glm::normalize(glm::vec3(0.8f * std::sin(0.7f * float(x) + 0.3f * float(y)),
                                         0.6f * std::cos(1.1f * float(y)), 1.f));
            float* p = image->at(x, y);
            p[0] = n.x, p[1] = n.y, p[2] = n.z;
        }
    return image;
}

} // namespace ndfmip::test

#define NDFMIP_GL_OR_SKIP(gl)                                                                      \
    ::ndfmip::Result<::ndfmip::GlContext> gl = ::ndfmip::createHeadlessGl();                       \
    if (!gl) {                                                                                     \
        if (::ndfmip::test::gpuRequired()) FAIL() << gl.error().message;                           \
        GTEST_SKIP() << gl.error().message;                                                        \
    }
