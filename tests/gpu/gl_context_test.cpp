#include <utility>

#include <gtest/gtest.h>

#include "gpu/gl_compute.h"
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

// Contexts share the process's EGL display: destroying the current one must leave the other
// usable (made current again by runCompute).
TEST(GpuContext, TwoContextsOutliveEachOther) {
    NDFMIP_GL_OR_SKIP(first);
    Result<GlContext> second = createHeadlessGl();
    ASSERT_TRUE(second.ok()) << second.error().message;
    second = Error{"destroyed"};
    Result<std::vector<float>> out =
        runCompute(first.value(),
                   "void main() { uint i = gl_GlobalInvocationID.x; if (i < ndfmipItems) "
                   "ndfmipOutput[i] = 2.0 * ndfmipInput[i]; }",
                   {1.f, 2.f, 3.f}, 1, 3);
    ASSERT_TRUE(out.ok()) << out.error().message;
    EXPECT_EQ(out.value(), (std::vector<float>{2.f, 4.f, 6.f}));
}

} // namespace
} // namespace ndfmip
