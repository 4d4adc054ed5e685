// The files of shaders/ compiled into the library (cmake/EmbedShaders.cmake), by their path
// relative to shaders/ ("brdf.glsl", "render/main.frag").
#pragma once

#include <string_view>
#include <vector>

namespace ndfmip {

struct EmbeddedShader {
    std::string_view path;
    std::string_view text;
};

const std::vector<EmbeddedShader>& embeddedShaders();

} // namespace ndfmip
