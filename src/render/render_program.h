// What the GPU renderer draws a scene with, independent of the graphics API: the fragment
// shader's parts (the GLSL library, the ray caster, the method's glue, the main), the bake's
// planes as texture layers, and every uniform's value. OpenGL (src/gpu/gpu_renderer.cpp) and
// the report's WebGL2 view (src/report/webgl_view.cpp) both draw from it.
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "methods/method_unit.h"
#include "ndfmip/interpolated.h"
#include "ndfmip/render.h"

namespace ndfmip {

constexpr int kGpuMaxLights = 16; // NDFMIP_MAX_LIGHTS in shaders/render/main.frag

struct RenderProgram {
    const MethodShader* shader = nullptr;
    ShaderSetup setup;
    // The fragment shader after its #version line: (file name, text) in order.
    std::vector<std::pair<std::string, std::string>> fragmentParts;
    // One layer per linear plane (at most 4 channels), then roughness mips, then the albedo
    // map: layers[layer][level].
    std::vector<std::vector<const Image*>> layers;
    Bake encoded;                       // the shader's planesOf: owns the planes' layers point into
    std::vector<UniformValue> uniforms; // the scene's, the rule's and the method's
    // Under an environment (shaders/render/environment.glsl), the split-sum way: the rule's
    // prefiltered chain (in setup.splitSum; its levels are the mips of one texture) and the
    // split sum's second factor as one channel; the SH-lighting way: the lighting's coefficients
    // as rows (L, then L' or its three axes), in the plane's tangent frame for sh. Both: the
    // lighting whose map a visible background shows. Null and empty otherwise.
    const SplitSumChain* environmentChain = nullptr;
    Image environmentAlbedo;
    Image environmentSh;
    std::shared_ptr<const EnvironmentLighting> environment;
    bool environmentVisible = false;
    // A faceted-sphere scene (render/interpolated.frag, no layers): the CPU's mesh as rows
    // (faceted.glsl's ndfmipMesh) and, for cubemap-toksvig, Toksvig's normal cube map, its
    // levels the texture's mips. Empty otherwise.
    Image facetedMesh;
    std::shared_ptr<const NormalCubeMap> normalCube;
};

// The full-screen triangle's vertex stage, after its #version line.
const char* renderVertexShader();

// Checks that the GPU path can draw `method` (errors, one line, as renderGpu's) and assembles it.
// Faceted-sphere scenes take the methods renormalized and cubemap-toksvig (interpolated.h).
Result<RenderProgram> renderProgram(const Scene& scene, const RenderTextures& textures,
                                    const std::string& method, const RenderOptions& options);

} // namespace ndfmip
