#include <bit>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "gpu/gl_compute.h"
#include "gpu_test_support.h"

namespace ndfmip {
namespace {

const char* kCopy = R"(void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= ndfmipItems) return;
    ndfmipOutput[i] = ndfmipInput[i];
}
)";

// y = x*x + 1 and exp(x) against C++ in double. The polynomial may be fused into one fma on the
// GPU (one rounding instead of two), and GLSL lets exp(x) be off by 3 + 2|x| ulp (llvmpipe
// computes exp2(x * log2 e), whose rounding of the product grows with |x|: 1.1e-6 relative at
// |x| = 20), so the inputs stay in [-8, 8] and the check is relative, not bit for bit.
TEST(GpuCompute, PolynomialAndExpMatchCpu) {
    NDFMIP_GL_OR_SKIP(gl);
    const int n = 10000;
    std::vector<float> x(n);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-8.f, 8.f);
    for (float& v : x) v = u(rng);

    Result<std::vector<float>> out = runCompute(gl.value(), R"(void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= ndfmipItems) return;
    float x = ndfmipInput[i];
    ndfmipOutput[2 * i] = x * x + 1.0;
    ndfmipOutput[2 * i + 1] = exp(x);
}
)",
                                                x, 2, n, "square_exp.glsl");
    ASSERT_TRUE(out.ok()) << out.error().message;
    ASSERT_EQ(out->size(), size_t(2 * n));

    double worstSquare = 0, worstExp = 0;
    for (int i = 0; i < n; ++i) {
        double xd = x[size_t(i)];
        double square = xd * xd + 1, e = std::exp(xd);
        worstSquare = std::max(worstSquare, std::abs(out.value()[size_t(2 * i)] - square) / square);
        worstExp = std::max(worstExp, std::abs(out.value()[size_t(2 * i + 1)] - e) / e);
    }
    EXPECT_LT(worstSquare, 1e-6) << gl->description();
    EXPECT_LT(worstExp, 1e-6) << gl->description();
    RecordProperty("worst_rel_exp", std::to_string(worstExp));
    std::printf("worst relative error: x*x+1 %.3g, exp %.3g\n", worstSquare, worstExp);
}

// Values go through the buffers and a shader variable unchanged: every float bit pattern but
// NaN (whose payload a GPU may canonicalise), infinities and subnormals included.
TEST(GpuCompute, Float32RoundTripIsBitExact) {
    NDFMIP_GL_OR_SKIP(gl);
    std::vector<float> in;
    std::mt19937 rng(11);
    while (in.size() < 20000) {
        float v = std::bit_cast<float>(uint32_t(rng()));
        if (!std::isnan(v)) in.push_back(v);
    }
    in.insert(in.end(),
              {0.f, -0.f, INFINITY, -INFINITY, 1e-45f, -1e-45f, 1.17549435e-38f, 3.40282347e38f});
    Result<std::vector<float>> out =
        runCompute(gl.value(), kCopy, in, 1, int(in.size()), "copy.glsl");
    ASSERT_TRUE(out.ok()) << out.error().message;
    ASSERT_EQ(out->size(), in.size());
    int mismatches = 0;
    for (size_t i = 0; i < in.size(); ++i)
        if (std::bit_cast<uint32_t>(out.value()[i]) != std::bit_cast<uint32_t>(in[i]) &&
            mismatches++ < 5)
            ADD_FAILURE() << "item " << i << ": 0x" << std::hex << std::bit_cast<uint32_t>(in[i])
                          << " came back 0x" << std::bit_cast<uint32_t>(out.value()[i]);
    EXPECT_EQ(mismatches, 0);
}

TEST(GpuCompute, UnwrittenOutputIsZeroAndNoItemsIsEmpty) {
    NDFMIP_GL_OR_SKIP(gl);
    // 70 items: two work groups, the second mostly past the end (the ndfmipItems guard).
    std::vector<float> in(70, 5.f);
    Result<std::vector<float>> out = runCompute(gl.value(), R"(void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i < ndfmipItems) ndfmipOutput[3 * i] = ndfmipInput[i];
}
)",
                                                in, 3, 70);
    ASSERT_TRUE(out.ok()) << out.error().message;
    ASSERT_EQ(out->size(), 210u);
    for (size_t i = 0; i < 70; ++i) {
        EXPECT_EQ(out.value()[3 * i], 5.f);
        EXPECT_EQ(out.value()[3 * i + 1], 0.f);
        EXPECT_EQ(out.value()[3 * i + 2], 0.f);
    }

    Result<std::vector<float>> none = runCompute(gl.value(), kCopy, {}, 1, 0);
    ASSERT_TRUE(none.ok()) << none.error().message;
    EXPECT_TRUE(none->empty());
}

TEST(GpuCompute, KernelErrorNamesTheKernelLine) {
    NDFMIP_GL_OR_SKIP(gl);
    Result<std::vector<float>> out =
        runCompute(gl.value(),
                   "void main() {\n    uint i = gl_GlobalInvocationID.x;\n    ndfmipOutput[i] = "
                   "undefinedName;\n}\n",
                   {1.f}, 1, 1, "kernel.glsl");
    ASSERT_FALSE(out.ok());
    const std::string& message = out.error().message;
    EXPECT_NE(message.find("kernel.glsl:3:"), std::string::npos) << message;
    EXPECT_NE(message.find("undefinedName"), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

} // namespace
} // namespace ndfmip
