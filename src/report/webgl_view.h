// The evaluation report's live WebGL2 view: a map's bakes drawn in the browser by the same
// shaders as `render --gpu` (the GLSL library under `#version 300 es`), method and distance
// switchable. The page checks itself on load: one frame against the CPU renderer's image of
// the same view, the relative RMSE written into the page (element #ndfmip-webgl-check,
// attribute data-rel-rmse), which the tests read back from a headless browser.
#pragma once

#include <string>
#include <vector>

#include "render/render_program.h"

namespace ndfmip {

struct WebglMethod {
    std::string label;
    RenderProgram program; // layers and shader parts (uniforms: per footprint below)
    std::vector<std::vector<UniformValue>> uniforms; // one list per footprint of the view
};

struct WebglView {
    std::string map;
    std::vector<int> footprints;
    int baseLevel = 0; // levels below it are left out (no footprint of the view reads them)
    std::vector<WebglMethod> methods;
    // The CPU renderer's image of methods[0] at footprints[0], for the page's own check.
    Image reference;
    float exposureStops = 0.f;
};

// The fragment shader as GLSL ES 3.00 (the parts after "#version 300 es" and precisions).
std::string webglFragmentSource(const RenderProgram& program);

// The view as an HTML section (canvas, controls, data, script); empty without methods.
std::string webglViewHtml(const WebglView& view);

} // namespace ndfmip
