#include <utility>

#include <gtest/gtest.h>

#include "gpu/gl_context.h"
#include "gpu_test_support.h"

namespace ndfmip {
namespace {

TEST(GpuContext, IsOpenGl45OrNewer) {
    NDFMIP_GL_OR_SKIP(gl);
    EXPECT_TRUE(gl->valid());
    EXPECT_GE(glVersion(), 45) << gl->description();
    EXPECT_FALSE(gl->description().empty());
    RecordProperty("renderer", gl->description());
    std::printf("renderer: %s\n", gl->description().c_str());
}

TEST(GpuContext, MovedHandleOwnsTheContext) {
    NDFMIP_GL_OR_SKIP(gl);
    GlContext owner = std::move(gl.value());
    EXPECT_FALSE(gl->valid());
    ASSERT_TRUE(owner.valid());
    EXPECT_TRUE(makeCurrent(owner).ok());
    EXPECT_FALSE(makeCurrent(gl.value()).ok()); // the moved-from handle has nothing to make current
    EXPECT_GE(glVersion(), 45);
}

} // namespace
} // namespace ndfmip
