// The GLSL shading library (shaders/*.glsl) compiled as C++: the same text the GPU runs, so
// the CPU renderer's shade functions and the shaders cannot drift apart. The files are
// included inside a class (member functions defined there are inline and may call each other
// in any order) with glm standing in for GLSL's types and built-ins.
#pragma once

#include <glm/glm.hpp>

#include "ndfmip/scene.h"

namespace ndfmip {
namespace glsl_detail {

using glm::atan;
using glm::clamp;
using glm::cos;
using glm::dot;
using glm::exp;
using glm::length;
using glm::log;
using glm::max;
using glm::min;
using glm::normalize;
using glm::pow;
using glm::sin;
using glm::sqrt;
using glm::tanh;
using glm::vec2;
using glm::vec3;
using glm::vec4;

// The library's files in the order they depend on each other (a file's structs before the files
// that take them as parameters), which the formatter's include sorting must not change.
struct ShaderLibrary {
// clang-format off
#include "brdf.glsl"
#include "naive.glsl"
#include "toksvig.glsl"
#include "toksvig_lut.glsl"
#include "sh.glsl"
#include "vmf.glsl"
#include "lean.glsl"
#include "sggx.glsl"
#include "ggx_aniso.glsl"
#include "splitsum.glsl"
    // clang-format on
};

} // namespace glsl_detail

// Calls read glsl().ndfmipBlinnPhong(...).
using GlslLibrary = glsl_detail::ShaderLibrary;
using GlslMaterial = GlslLibrary::NdfmipMaterial;
inline GlslLibrary glsl() {
    return {};
}

// A material as the shaders take it; `specularScale` multiplies its specular colour (a
// factored BRDF's g(theta_d), which depends on l and h only). Tabulated lobes have no GLSL
// form: their brdf id (4) makes every GLSL lobe 0, and the C++ callers add the table's lobe.
inline GlslMaterial glslMaterial(const Material& m, float specularScale = 1.f) {
    GlslMaterial g;
    g.brdf = int(m.brdf);
    g.exponent = m.exponent;
    g.roughness = m.roughness;
    g.specular = m.specular * specularScale;
    return g;
}

static_assert(int(Brdf::Lambert) == NDFMIP_LAMBERT && int(Brdf::BlinnPhong) == NDFMIP_BLINN_PHONG &&
              int(Brdf::Beckmann) == NDFMIP_BECKMANN && int(Brdf::Ggx) == NDFMIP_GGX);

} // namespace ndfmip
