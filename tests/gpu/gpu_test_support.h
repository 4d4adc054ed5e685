// A GL context for a test, or a clean skip with the one-line reason where there is none (no EGL,
// no driver). NDFMIP_REQUIRE_GPU=1 in the environment turns that skip into a failure, for
// machines that are known to have OpenGL.
#pragma once

#include <cstdlib>
#include <string_view>

#include <gtest/gtest.h>

#include "gpu/gl_context.h"

namespace ndfmip::test {

inline bool gpuRequired() {
    const char* value = std::getenv("NDFMIP_REQUIRE_GPU");
    return value != nullptr && std::string_view(value) == "1";
}

} // namespace ndfmip::test

#define NDFMIP_GL_OR_SKIP(gl)                                                                      \
    ::ndfmip::Result<::ndfmip::GlContext> gl = ::ndfmip::createHeadlessGl();                       \
    if (!gl) {                                                                                     \
        if (::ndfmip::test::gpuRequired()) FAIL() << gl.error().message;                           \
        GTEST_SKIP() << gl.error().message;                                                        \
    }
