// The report's live WebGL2 view (see webgl_view.h).
#include "report/webgl_view.h"

#include <cstring>

#include <nlohmann/json.hpp>

#include "ndfmip/html_report.h"

namespace ndfmip {

namespace {

const char* kEsHeader = "#version 300 es\nprecision highp float;\nprecision highp int;\n"
                        "precision highp sampler2DArray;\nprecision highp sampler2D;\n";

// A level's layers, layer after layer, RGBA 32-bit floats, base64. Not half floats: a vMF
// lobe's kappa comes from 1 - r, which half precision turns into noise for sharp lobes.
std::string levelData(const std::vector<std::vector<const Image*>>& layers, size_t level) {
    std::string bytes;
    for (const auto& chain : layers) {
        const Image& image = *chain[level];
        for (size_t i = 0; i < image.texelCount(); ++i)
            for (int c = 0; c < 4; ++c) {
                const float v =
                    c < image.channels ? image.pixels[i * size_t(image.channels) + size_t(c)] : 0.f;
                bytes.append(reinterpret_cast<const char*>(&v), 4);
            }
    }
    return base64Encode(bytes);
}

nlohmann::json uniformsJson(const std::vector<UniformValue>& uniforms) {
    nlohmann::json out = nlohmann::json::array();
    for (const UniformValue& u : uniforms)
        out.push_back({{"name", u.name}, {"int", u.integer}, {"v", u.values}});
    return out;
}

const char* kScript = R"js(
(function () {
  const data = JSON.parse(document.getElementById('ndfmip-live-data').textContent);
  const canvas = document.getElementById('ndfmip-live-canvas');
  const status = document.getElementById('ndfmip-webgl-check');
  const work = document.createElement('canvas');
  const gl = work.getContext('webgl2');
  if (!gl || !gl.getExtension('EXT_color_buffer_float') || !gl.getExtension('OES_texture_float_linear')) {
    status.textContent = 'WebGL2 with float render targets and filtered float textures is not available here.';
    status.setAttribute('data-error', 'no webgl2');
    return;
  }
  function bytes(b64) {
    const s = atob(b64), out = new Uint8Array(s.length);
    for (let i = 0; i < s.length; ++i) out[i] = s.charCodeAt(i);
    return out.buffer;
  }
  function compile(type, source) {
    const s = gl.createShader(type);
    gl.shaderSource(s, source);
    gl.compileShader(s);
    if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(s));
    return s;
  }
  const programs = data.methods.map(function (m) {
    const p = gl.createProgram();
    gl.attachShader(p, compile(gl.VERTEX_SHADER, data.vertex));
    gl.attachShader(p, compile(gl.FRAGMENT_SHADER, m.fragment));
    gl.linkProgram(p);
    if (!gl.getProgramParameter(p, gl.LINK_STATUS)) throw new Error(gl.getProgramInfoLog(p));
    const t = gl.createTexture();
    gl.bindTexture(gl.TEXTURE_2D_ARRAY, t);
    gl.texStorage3D(gl.TEXTURE_2D_ARRAY, m.levels.length, gl.RGBA32F, m.width, m.height, m.layers);
    m.levels.forEach(function (level, k) {
      const w = Math.max(m.width >> k, 1), h = Math.max(m.height >> k, 1);
      gl.texSubImage3D(gl.TEXTURE_2D_ARRAY, k, 0, 0, 0, w, h, m.layers, gl.RGBA, gl.FLOAT,
                       new Float32Array(bytes(level)));
    });
    gl.texParameteri(gl.TEXTURE_2D_ARRAY, gl.TEXTURE_MIN_FILTER, gl.LINEAR_MIPMAP_LINEAR);
    gl.texParameteri(gl.TEXTURE_2D_ARRAY, gl.TEXTURE_MAG_FILTER, gl.LINEAR);
    gl.texParameteri(gl.TEXTURE_2D_ARRAY, gl.TEXTURE_WRAP_S, gl.REPEAT);
    gl.texParameteri(gl.TEXTURE_2D_ARRAY, gl.TEXTURE_WRAP_T, gl.REPEAT);
    return {program: p, texture: t};
  });
  const vao = gl.createVertexArray();
  // Draws method m at footprint f into a float target; returns {w, h, rgb} with rows from the top.
  function draw(m, f) {
    const p = programs[m], uniforms = data.methods[m].uniforms[f];
    const size = uniforms.find(function (u) { return u.name === 'ndfmipImageSize'; }).v;
    const w = size[0], h = size[1];
    const target = gl.createTexture();
    gl.bindTexture(gl.TEXTURE_2D, target);
    gl.texStorage2D(gl.TEXTURE_2D, 1, gl.RGBA32F, w, h);
    const fb = gl.createFramebuffer();
    gl.bindFramebuffer(gl.FRAMEBUFFER, fb);
    gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, target, 0);
    gl.viewport(0, 0, w, h);
    gl.useProgram(p.program);
    uniforms.forEach(function (u) {
      const at = gl.getUniformLocation(p.program, u.name);
      if (at === null) return;
      if (u.int) gl.uniform1i(at, u.v[0]);
      else if (u.v.length === 1) gl.uniform1f(at, u.v[0]);
      else if (u.v.length === 2) gl.uniform2f(at, u.v[0], u.v[1]);
      else gl.uniform3f(at, u.v[0], u.v[1], u.v[2]);
    });
    gl.activeTexture(gl.TEXTURE0);
    gl.bindTexture(gl.TEXTURE_2D_ARRAY, p.texture);
    gl.bindVertexArray(vao);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
    const rgba = new Float32Array(w * h * 4);
    gl.readPixels(0, 0, w, h, gl.RGBA, gl.FLOAT, rgba);
    gl.deleteFramebuffer(fb);
    gl.deleteTexture(target);
    const rgb = new Float32Array(w * h * 3);
    for (let y = 0; y < h; ++y)
      for (let x = 0; x < w; ++x)
        for (let c = 0; c < 3; ++c) rgb[(y * w + x) * 3 + c] = rgba[((h - 1 - y) * w + x) * 4 + c];
    return {w: w, h: h, rgb: rgb};
  }
  function show(image) {
    canvas.width = image.w;
    canvas.height = image.h;
    const ctx = canvas.getContext('2d'), out = ctx.createImageData(image.w, image.h), scale = Math.pow(2, data.stops);
    for (let i = 0; i < image.w * image.h; ++i) {
      for (let c = 0; c < 3; ++c) {
        const v = Math.max(image.rgb[i * 3 + c] * scale, 0);
        out.data[i * 4 + c] = Math.round(255 * Math.min(1, v <= 0.0031308 ? 12.92 * v : 1.055 * Math.pow(v, 1 / 2.4) - 0.055));
      }
      out.data[i * 4 + 3] = 255;
    }
    ctx.putImageData(out, 0, 0);
  }
  const methodSelect = document.getElementById('ndfmip-live-method');
  const footprintSelect = document.getElementById('ndfmip-live-footprint');
  const timing = document.getElementById('ndfmip-live-time');
  function update() {
    const t0 = performance.now();
    show(draw(+methodSelect.value, +footprintSelect.value));
    timing.textContent = (performance.now() - t0).toFixed(1) + ' ms (draw and read back)';
  }
  methodSelect.addEventListener('change', update);
  footprintSelect.addEventListener('change', update);
  // The page's own check: the first method at the first footprint against the CPU renderer.
  const mine = draw(0, 0), ref = new Float32Array(bytes(data.reference));
  let num = 0, den = 0;
  for (let i = 0; i < ref.length; ++i) {
    num += (mine.rgb[i] - ref[i]) * (mine.rgb[i] - ref[i]);
    den += ref[i] * ref[i];
  }
  const rel = Math.sqrt(num / Math.max(den, 1e-30));
  status.setAttribute('data-rel-rmse', String(rel));
  status.textContent = 'WebGL2 frame of ' + data.methods[0].label + ' at footprint ' + data.footprints[0] +
      ' against the CPU renderer: relative RMSE ' + rel.toExponential(2) + '.';
  update();
})();
)js";

} // namespace

std::string webglFragmentSource(const RenderProgram& program) {
    std::string source = kEsHeader;
    for (const auto& part : program.fragmentParts) source += part.second + "\n";
    return source;
}

std::string webglViewHtml(const WebglView& view) {
    if (view.methods.empty()) return "";
    nlohmann::json data;
    data["vertex"] = std::string(kEsHeader) + renderVertexShader();
    data["footprints"] = view.footprints;
    data["stops"] = view.exposureStops;
    data["methods"] = nlohmann::json::array();
    for (const WebglMethod& m : view.methods) {
        const auto& layers = m.program.layers;
        const Image& base = *layers.front()[size_t(view.baseLevel)];
        nlohmann::json levels = nlohmann::json::array();
        for (size_t k = size_t(view.baseLevel); k < layers.front().size(); ++k)
            levels.push_back(levelData(layers, k));
        nlohmann::json uniforms = nlohmann::json::array();
        for (const auto& list : m.uniforms) {
            std::vector<UniformValue> shifted = list;
            for (UniformValue& u : shifted) // the texture starts at baseLevel
                if (u.name == "ndfmipLevelCount") u.values[0] -= float(view.baseLevel);
            uniforms.push_back(uniformsJson(shifted));
        }
        data["methods"].push_back({{"label", m.label},
                                   {"fragment", webglFragmentSource(m.program)},
                                   {"width", base.width},
                                   {"height", base.height},
                                   {"layers", layers.size()},
                                   {"levels", levels},
                                   {"uniforms", uniforms}});
    }
    std::string reference(reinterpret_cast<const char*>(view.reference.pixels.data()),
                          view.reference.pixels.size() * sizeof(float));
    data["reference"] = base64Encode(reference);
    std::string json = data.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
    // Inside <script type="application/json">: "</" would end the element.
    for (size_t at = json.find("</"); at != std::string::npos; at = json.find("</", at + 2))
        json.replace(at, 2, "<\\/");

    std::string html =
        "<h2>Live view (WebGL2)</h2><p>" + escapeHtml(view.map) +
        " drawn in this browser by ndfmip's GLSL shaders (GLSL ES 3.00), the bake's own levels as "
        "float mip levels, one trilinear lookup per pixel.</p><p><label>method <select "
        "id=\"ndfmip-live-method\">";
    for (size_t i = 0; i < view.methods.size(); ++i)
        html += "<option value=\"" + std::to_string(i) + "\">" + escapeHtml(view.methods[i].label) +
                "</option>";
    html += "</select></label> <label>footprint <select id=\"ndfmip-live-footprint\">";
    for (size_t i = 0; i < view.footprints.size(); ++i)
        html += "<option value=\"" + std::to_string(i) + "\">" +
                std::to_string(view.footprints[i]) + "</option>";
    html += "</select></label> <span id=\"ndfmip-live-time\"></span></p><canvas "
            "id=\"ndfmip-live-canvas\" "
            "style=\"image-rendering: pixelated; width: 384px\"></canvas><p "
            "id=\"ndfmip-webgl-check\">The live view "
            "needs JavaScript and WebGL2.</p><script type=\"application/json\" "
            "id=\"ndfmip-live-data\">" +
            json + "</script><script>" + kScript + "</script>";
    return html;
}

} // namespace ndfmip
