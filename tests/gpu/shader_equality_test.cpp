// Every method's GLSL shade function run on the GPU (a compute kernel over 10^4 random inputs)
// against the C++ the renderer calls, relative difference at most 1e-4. The C++ compiles the
// same GLSL text (ndfmip/glsl.h), so what this checks is the GPU's arithmetic and the parts
// that stay in C++: the SH convolution in double, the vMF lobe unpacking.
#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "gpu/gl_compute.h"
#include "gpu_test_support.h"
#include "ndfmip/method_shading.h"

namespace ndfmip {
namespace {

constexpr int kItems = 10000;
// Per item: brdf, exponent, roughness, specular (3), albedo (3), l (3), v (3), p (4), q, then
// method-specific extras.
constexpr int kBase = 20;

struct Inputs {
    int stride = kBase;
    std::vector<float> data;
    float* item(int i) { return data.data() + size_t(i) * size_t(stride); }
};

glm::vec3 upperDirection(std::mt19937& rng) {
    std::normal_distribution<float> g;
    for (;;) {
        glm::vec3 d(g(rng), g(rng), g(rng));
        d.z = std::abs(d.z);
        const float len = glm::length(d);
        if (len > 1e-3f && d.z / len > 0.05f) return d / len;
    }
}

// Random materials, directions and a filtered parameter vector p (a shortened normal or a lobe)
// plus q; `extra` floats after them for the method's own data.
Inputs randomInputs(uint32_t seed, int extra) {
    Inputs in;
    in.stride = kBase + extra;
    in.data.resize(size_t(kItems) * size_t(in.stride));
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    for (int i = 0; i < kItems; ++i) {
        float* x = in.item(i);
        x[0] = float(1 + i % 3);                   // Blinn-Phong, Beckmann, GGX
        x[1] = std::exp(u(rng) * std::log(512.f)); // exponent 1 .. 512
        x[2] = 0.05f + 0.95f * u(rng);             // alpha
        for (int c = 3; c < 9; ++c) x[c] = u(rng); // specular, albedo
        const glm::vec3 l = upperDirection(rng), v = upperDirection(rng);
        x[9] = l.x, x[10] = l.y, x[11] = l.z, x[12] = v.x, x[13] = v.y, x[14] = v.z;
        const glm::vec3 n = upperDirection(rng) * (0.3f + 0.7f * u(rng));
        x[15] = n.x, x[16] = n.y, x[17] = n.z, x[18] = u(rng), x[19] = u(rng);
    }
    return in;
}

Material materialOf(const float* x) {
    Material m;
    m.brdf = Brdf(int(x[0]));
    m.exponent = x[1];
    m.roughness = x[2];
    m.specular = glm::vec3(x[3], x[4], x[5]);
    return m;
}
glm::vec3 at3(const float* x, int k) {
    return {x[k], x[k + 1], x[k + 2]};
}

const char* kHead = R"(
uint ndfmipBase;
float in1(int k) { return ndfmipInput[ndfmipBase + uint(k)]; }
vec3 in3(int k) { return vec3(in1(k), in1(k + 1), in1(k + 2)); }
void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= ndfmipItems) return;
    ndfmipBase = i * uint(STRIDE);
    NdfmipMaterial m;
    m.brdf = int(in1(0));
    m.exponent = in1(1);
    m.roughness = in1(2);
    m.specular = in3(3);
    vec3 albedo = in3(6);
    vec3 l = in3(9);
    vec3 v = in3(12);
    vec4 p = vec4(in1(15), in1(16), in1(17), in1(18));
    float q = in1(19);
)";

// Runs `call` (a GLSL expression of m, albedo, l, v, p, q giving a vec3; `body` may come before
// it) on the GPU and compares with `cpu` item by item.
void expectGpuMatchesCpu(const Inputs& in, const std::string& body, const std::string& call,
                         const std::function<glm::vec3(const float*)>& cpu) {
    NDFMIP_GL_OR_SKIP(gl);
    Result<ShaderSource> source =
        loadShaderFiles(NDFMIP_SOURCE_DIR "/shaders",
                        {"brdf.glsl", "naive.glsl", "toksvig.glsl", "toksvig_lut.glsl", "sh.glsl",
                         "vmf.glsl", "lean.glsl", "sggx.glsl", "ggx_aniso.glsl"},
                        computeShaderHead());
    ASSERT_TRUE(source) << source.error().message;
    std::string kernel = "#define STRIDE " + std::to_string(in.stride) + "\n" + kHead + body +
                         "    vec3 r = " + call +
                         ";\n"
                         "    ndfmipOutput[3u * i] = r.x; ndfmipOutput[3u * i + 1u] = r.y; "
                         "ndfmipOutput[3u * i + 2u] = r.z;\n}\n";
    appendShaderText(source.value(), "<kernel>", kernel);
    Result<std::vector<float>> out = runCompute(gl.value(), source.value(), in.data, 3, kItems);
    ASSERT_TRUE(out) << out.error().message;
    double worst = 0.0;
    int worstItem = -1;
    for (int i = 0; i < kItems; ++i) {
        const float* item = in.data.data() + size_t(i) * size_t(in.stride);
        const glm::vec3 expected = cpu(item);
        // The function's own float sensitivity: the C++ again with l, v, p and q moved by a few ulp
        // (a GPU's normalize and inversesqrt round differently; a lobe of s = 512 turns that into
        // 1e-4). Differences up to twice that spread are allowed on top of 1e-4.
        std::vector<float> moved(item, item + in.stride);
        for (int k = 9; k < 20; ++k) moved[size_t(k)] *= 1.f + ((k % 2) ? 3e-7f : -3e-7f);
        const glm::vec3 spread = glm::abs(cpu(moved.data()) - expected);
        const float scale =
            std::max({std::abs(expected.x), std::abs(expected.y), std::abs(expected.z)});
        for (int c = 0; c < 3; ++c) {
            const double gpu = out.value()[3 * size_t(i) + size_t(c)];
            // Relative to the item's largest channel, with a floor for values that are 0 on both.
            const double difference =
                std::max(std::abs(gpu - double(expected[c])) - 2.0 * double(spread[c]), 0.0) /
                std::max(double(scale), 1e-6);
            if (!(difference <= worst)) worst = difference, worstItem = i;
        }
    }
    EXPECT_LE(worst, 1e-4) << "worst item " << worstItem << " on " << gl.value().description();
    ::testing::Test::RecordProperty("worst_relative_difference", std::to_string(worst));
}

TEST(GpuShaders, NaiveMatchesCpu) {
    expectGpuMatchesCpu(
        randomInputs(1, 0), "", "ndfmipShadeNaive(m, albedo, vec3(p.x, p.y, p.z), l, v)",
        [](const float* x) {
            return shadeNaive(materialOf(x), at3(x, 6), at3(x, 15), at3(x, 9), at3(x, 12));
        });
}

TEST(GpuShaders, RoughnessMipsMatchCpu) {
    // Perceptual roughness 0.22 .. 1 (alpha >= 0.05, as the other materials here).
    Inputs in = randomInputs(2, 0);
    for (int i = 0; i < kItems; ++i) in.item(i)[19] = 0.22f + 0.78f * in.item(i)[19];
    expectGpuMatchesCpu(in, "",
                        "ndfmipShadeRoughnessMips(m, albedo, vec3(p.x, p.y, p.z), q, false, l, v)",
                        [](const float* x) {
                            return shadeRoughnessMipsTexel(materialOf(x), at3(x, 6), at3(x, 15),
                                                           x[19], false, at3(x, 9), at3(x, 12));
                        });
}

TEST(GpuShaders, ToksvigMatchesCpuForEveryRoughnessMapping) {
    Inputs in = randomInputs(3, 0);
    for (int i = 0; i < kItems; ++i) in.item(i)[18] = float(i % 5); // the mapping
    expectGpuMatchesCpu(in, "",
                        "ndfmipShadeToksvig(m, albedo, vec3(p.x, p.y, p.z), l, v, int(p.w), 2.0f)",
                        [](const float* x) {
                            return shadeToksvig(materialOf(x), at3(x, 6), at3(x, 15), at3(x, 9),
                                                at3(x, 12), RoughnessMapping(int(x[18])), 2.f);
                        });
}

TEST(GpuShaders, ToksvigLutMatchesCpu) {
    // q stands for the table's relative value at (Na.H, Na.Na), which a texture fetch gives.
    Inputs in = randomInputs(4, 0);
    for (int i = 0; i < kItems; ++i) in.item(i)[0] = 1.f; // Blinn-Phong only
    expectGpuMatchesCpu(in, "", "ndfmipShadeToksvigLut(m, albedo, vec3(p.x, p.y, p.z), q, l, v)",
                        [](const float* x) {
                            const Material m = materialOf(x);
                            return shadeToksvigLobe(m, at3(x, 6), at3(x, 15), at3(x, 9), at3(x, 12),
                                                    glsl().ndfmipToksvigLutLobe(m.exponent, x[19]));
                        });
}

TEST(GpuShaders, VmfMatchesCpu) {
    // p = (alpha, alpha r mu): alpha in (0, 1], r from the shortened normal's length.
    Inputs in = randomInputs(5, 0);
    for (int i = 0; i < kItems; ++i) {
        float* x = in.item(i);
        const float alpha = 0.05f + 0.95f * x[18];
        const glm::vec3 rmu = at3(x, 15) * alpha;
        x[15] = alpha, x[16] = rmu.x, x[17] = rmu.y, x[18] = rmu.z;
    }
    expectGpuMatchesCpu(in, "", "ndfmipShadeVmfLobe(m, albedo, p, l, v)", [](const float* x) {
        return shadeVmf(materialOf(x), at3(x, 6), x + 15, 1, nullptr, at3(x, 9), at3(x, 12));
    });
}

// Random items whose p, q hold the moments of a slope Gaussian (the lean bake's planes): mean
// (p.x, p.y), variances and covariance from q and p.w.
Inputs slopeMomentInputs(unsigned seed) {
    Inputs in = randomInputs(seed, 1);
    for (int i = 0; i < kItems; ++i) {
        float* x = in.item(i);
        const float bx = 0.5f * x[15] / x[17], by = 0.5f * x[16] / x[17];
        const float vx = 0.3f * x[18], vy = 0.3f * x[19],
                    c = 0.5f * std::sqrt(vx * vy) * (x[3] - 0.5f);
        x[15] = bx, x[16] = by, x[17] = bx * bx + vx, x[18] = by * by + vy, x[19] = bx * by + c;
    }
    return in;
}

TEST(GpuShaders, LeanMatchesCpu) {
    const Inputs in = slopeMomentInputs(6);
    expectGpuMatchesCpu(in, "", "ndfmipShadeLean(m, albedo, p, q, l, v)", [](const float* x) {
        return shadeLean(materialOf(x), at3(x, 6), x + 15, at3(x, 9), at3(x, 12));
    });
}

TEST(GpuShaders, SggxMatchesCpu) {
    const Inputs in = slopeMomentInputs(7);
    expectGpuMatchesCpu(in, "", "ndfmipShadeSggx(m, albedo, p, q, l, v)", [](const float* x) {
        return shadeSggx(materialOf(x), at3(x, 6), x + 15, at3(x, 9), at3(x, 12));
    });
}

TEST(GpuShaders, ShOrderSevenMatchesCpuInDouble) {
    // 64 coefficients of a smooth NDF (decaying bands) and the material's own A_l, order 7.
    const int order = 7, count = shCount(order);
    Inputs in = randomInputs(7, count);
    std::mt19937 rng(8);
    std::uniform_real_distribution<float> u(-1.f, 1.f);
    for (int i = 0; i < kItems; ++i) {
        float* g = in.item(i) + kBase;
        for (int k = 0; k < count; ++k) {
            int l = 0;
            while (shCount(l) <= k) ++l;
            g[k] = k == 0 ? 0.2820948f : 0.3f * u(rng) / float(1 + l * l);
        }
    }
    // A_l per material, as the renderer's ShShading: computed in C++ and passed in.
    auto shadingOf = [](const float* x) {
        Result<ShShading> a = shShadingFor(materialOf(x), 7);
        return a ? a.value() : ShShading{};
    };
    const std::string body = R"(
    float g[NDFMIP_SH_MAX_COEFFICIENTS];
    float diffuseA[NDFMIP_SH_MAX_ORDER + 1];
    float specularA[NDFMIP_SH_MAX_ORDER + 1];
    for (int k = 0; k < NDFMIP_SH_MAX_COEFFICIENTS; ++k) g[k] = k < 64 ? in1(20 + k) : 0.0f;
    for (int k = 0; k <= NDFMIP_SH_MAX_ORDER; ++k) {
        diffuseA[k] = k <= 7 ? in1(84 + k) : 0.0f;
        specularA[k] = k <= 7 ? in1(92 + k) : 0.0f;
    }
)";
    Inputs withA = in;
    withA.stride = in.stride + 16;
    withA.data.assign(size_t(kItems) * size_t(withA.stride), 0.f);
    for (int i = 0; i < kItems; ++i) {
        std::copy_n(in.item(i), in.stride, withA.item(i));
        const ShShading a = shadingOf(in.item(i));
        for (int l = 0; l <= order; ++l) {
            withA.item(i)[84 + l] = float(a.diffuse[size_t(l)]);
            withA.item(i)[92 + l] = float(a.specular[size_t(l)]);
        }
    }
    expectGpuMatchesCpu(withA, body, "ndfmipShadeSh(m, albedo, g, diffuseA, specularA, 7, l, v)",
                        [&](const float* x) {
                            ShShading a = shadingOf(x);
                            // The GPU gets A_l rounded to float; so does this.
                            for (double& value : a.diffuse) value = double(float(value));
                            for (double& value : a.specular) value = double(float(value));
                            return shadeSh(materialOf(x), at3(x, 6), x + kBase, a, at3(x, 9),
                                           at3(x, 12));
                        });
}

} // namespace
} // namespace ndfmip
