// The evaluation behind `ndfmip eval`: every map rendered at several view distances with every
// method and with the ground truth, compared, and gathered into report.json and report.html.
//
// Each case is a top-down orthographic view of the map tiled over a plane, so that one pixel
// covers `footprint` x `footprint` texels; the pixel grid is offset from the texel grid by a
// fraction of a pixel so that filtering falls between texels and levels as it does in a real
// view. One directional light, 25 degrees off the normal.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <optional>

#include <nlohmann/json.hpp>

#include "core/clock.h"
#include "methods/method_unit.h"
#include "ndfmip/compare.h"
#include "ndfmip/environment_lighting.h"
#include "ndfmip/evaluate.h"
#include "ndfmip/html_report.h"
#include "ndfmip/io.h"
#include "ndfmip/limits.h"
#include "ndfmip/render.h"
#include "ndfmip/spherical_harmonics.h"
#include "ndfmip/tonemap.h"
#include "render/render_program.h"
#include "report/webgl_view.h"

namespace ndfmip {
namespace {

using json = nlohmann::json;

struct EvalProblem {
    std::string message;
};

[[noreturn]] void fail(std::string message) {
    throw EvalProblem{std::move(message)};
}

// The ranges the command line's parser holds the options to, for callers without it.
void checkRanges(const EvalOptions& a) {
    auto range = [](const char* option, double value, double lo, double hi) {
        if (value >= lo && value <= hi) return;
        char text[160];
        std::snprintf(text, sizeof text, "%s %g: expected %g .. %g", option, value, lo, hi);
        fail(text);
    };
    if (a.maps.empty()) fail("no maps to evaluate");
    for (float s : a.exponents) range("--exponents", s, 1e-3, 1e5);
    for (float r : a.roughness) range("--roughness", r, 1e-3, 1.0);
    for (float r : a.calibrationRoughness) range("--calibration-roughness", r, 1e-3, 1.0);
    for (float c : a.calibrationScales) range("calibration scale", c, 1e-3, 1e3);
    range("--pixels", a.maxPixels, 8, 2048);
    if (a.spp != 0) range("--spp", a.spp, 1, 1 << 16);
    range("--frames", a.frames, 0, 256);
    if (a.coherence) range("--coherent", *a.coherence, 0.0, 1e6);
    range("--elevation", a.elevation, 5.0, 90.0);
    if (a.taps) range("--taps", *a.taps, 1, 16);
    if (a.lodBias) range("--lod-bias", *a.lodBias, -16.0, 16.0);
}

// A mip chain of perceptual roughness written by any tool, one file per level: `pattern` with
// {level} replaced by 0, 1, ... and each {key} of `fields` by its value. Level k must have
// sizes[k] texels; the first channel is kept (8/16-bit files as stored, 0..1, no sRGB decoding,
// as roughness maps are linear data).
std::vector<SharedImage>
loadRoughnessMips(const std::string& pattern, const std::vector<std::pair<int, int>>& sizes,
                  const std::vector<std::pair<std::string, std::string>>& fields) {
    auto substitute = [](std::string text, const std::string& key, const std::string& value) {
        const std::string token = "{" + key + "}";
        for (size_t at = text.find(token); at != std::string::npos;
             at = text.find(token, at + value.size()))
            text.replace(at, token.size(), value);
        return text;
    };
    if (pattern.find("{level}") == std::string::npos)
        fail("roughness mips " + quote(pattern) + ": the pattern has no {level}");
    std::vector<SharedImage> levels;
    for (size_t k = 0; k < sizes.size(); ++k) {
        std::string path = substitute(pattern, "level", std::to_string(k));
        for (const auto& [key, value] : fields) path = substitute(path, key, value);
        Result<SourceImage> source = loadImage(path);
        if (!source) fail(source.error().message);
        const Image& image = source->image;
        if (image.width != sizes[k].first || image.height != sizes[k].second)
            fail(path + ": " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                 ", but mip level " + std::to_string(k) + " is " + std::to_string(sizes[k].first) +
                 "x" + std::to_string(sizes[k].second));
        Image r(image.width, image.height, 1);
        for (size_t i = 0; i < image.texelCount(); ++i) {
            const float v = image.pixels[i * image.channels];
            if (!std::isfinite(v)) fail(path + ": NaN or infinite roughness");
            r.pixels[i] = std::clamp(v, 0.f, 1.f);
        }
        levels.push_back(std::make_shared<const Image>(std::move(r)));
    }
    return levels;
}

// One material setting of the matrix.
struct Setting {
    Material material;
    std::string brdf;
    float exponent = 0.f, roughness = 0.f;
    std::string label() const {
        char text[64];
        if (material.brdf == Brdf::BlinnPhong)
            std::snprintf(text, sizeof text, "%s s=%g", brdf.c_str(), exponent);
        else if (material.brdf == Brdf::Lambert)
            std::snprintf(text, sizeof text, "%s", brdf.c_str());
        else
            std::snprintf(text, sizeof text, "%s alpha=%g", brdf.c_str(), roughness);
        return text;
    }
};

Setting makeSetting(Brdf brdf, float exponent, float roughness) {
    Setting s;
    s.brdf = brdfName(brdf);
    s.material.brdf = brdf;
    if (brdf == Brdf::Lambert) {
        s.material.albedo = glm::vec3(1.f);
        s.material.specular = glm::vec3(0.f);
    } else {
        s.material.albedo = glm::vec3(0.f);
        s.material.specular = glm::vec3(1.f);
    }
    if (brdf == Brdf::BlinnPhong) s.material.exponent = s.exponent = exponent;
    if (brdf == Brdf::Beckmann || brdf == Brdf::Ggx) s.material.roughness = s.roughness = roughness;
    return s;
}

std::vector<Setting> settingsOf(const EvalOptions& a) {
    std::vector<Setting> out;
    for (const std::string& name : a.brdfs) {
        Brdf brdf;
        if (!brdfFromString(name, brdf))
            fail("--brdfs: unknown BRDF " + quote(name) +
                 " (expected lambert, blinnphong, beckmann, ggx)");
        if (brdf == Brdf::Lambert) out.push_back(makeSetting(brdf, 0.f, 0.f));
        if (brdf == Brdf::BlinnPhong)
            for (float s : a.exponents) out.push_back(makeSetting(brdf, s, 0.f));
        if (brdf == Brdf::Beckmann || brdf == Brdf::Ggx)
            for (float r : a.roughness) out.push_back(makeSetting(brdf, 0.f, r));
    }
    return out;
}

// The view of one footprint: world units are maps (1 unit = the map's width in texels, on
// both axes), an orthographic camera `pixels` pixels square, `elevation` degrees above the plane
// (90: straight down) and tilted about the texel grid's x axis, so that a pixel covers footprint
// texels across and footprint / sin(elevation) along the view, and the truth is still one exact
// integral per pixel (exactBoxView).
Scene evalScene(int mapWidth, int mapHeight, int footprint, int pixels, glm::vec2 shift,
                float elevation = 90.f) {
    Scene s;
    const float pixelWorld = float(footprint) / float(mapWidth);
    const float viewWorld = pixelWorld * float(pixels);
    const bool down = elevation >= 90.f;
    const float e = glm::radians(elevation), stretch = down ? 1.f : 1.f / std::sin(e);
    // `shift` pixels off the texel grid, the same for every footprint.
    const glm::vec3 offset(shift.x * pixelWorld, shift.y * pixelWorld * stretch, 0.f);
    s.camera.type = CameraType::Orthographic;
    const glm::vec3 towardsEye =
        down ? glm::vec3(0.f, 0.f, 1.f) : glm::vec3(0.f, -std::cos(e), std::sin(e));
    s.camera.eye = 10.f * towardsEye + offset;
    s.camera.target = offset;
    s.camera.up = down ? glm::vec3(0.f, 1.f, 0.f) : glm::vec3(0.f, std::sin(e), std::cos(e));
    s.camera.orthoHeight = viewWorld;
    s.camera.width = s.camera.height = pixels;
    const float size = 2.f * std::ceil(0.5f * viewWorld * stretch + 1.f);
    s.geometry.size = {size, size};
    s.geometry.tiling = {size, size * float(mapWidth) / float(mapHeight)};
    // Straight down: 25 degrees off the normal. Tilted: near the mirror direction of the view
    // (the glancing highlight a distant floor shows), 30 degrees aside in azimuth.
    const float polar = glm::radians(down ? 25.f : 90.f - elevation),
                azimuth = glm::radians(down ? 30.f : 120.f);
    Light light;
    light.direction = {std::sin(polar) * std::cos(azimuth), std::sin(polar) * std::sin(azimuth),
                       std::cos(polar)};
    s.lights = {light};
    return s;
}

Image renderOrFail(const Scene& scene, const RenderTextures& t, const std::string& method,
                   const RenderOptions& o) {
    Result<Image> image = render(scene, t, method, o);
    if (!image) fail(image.error().message);
    return std::move(image.value());
}

double percentileLuminance(const Image& image, double q) {
    std::vector<float> values(image.texelCount());
    for (size_t i = 0; i < values.size(); ++i) {
        const float* p = &image.pixels[i * image.channels];
        values[i] = 0.2126f * p[0] + 0.7152f * p[1] + 0.0722f * p[2];
    }
    if (values.empty()) return 0.0;
    size_t k = std::min(values.size() - 1, size_t(q * double(values.size())));
    std::nth_element(values.begin(), values.begin() + long(k), values.end());
    return values[k];
}

json number(double v) {
    return std::isfinite(v) ? json(v) : json(nullptr);
}

json caseJson(const ReportCase& c) {
    return {{"map", c.map},
            {"footprint", c.footprint},
            {"method", c.method},
            {"brdf", c.brdf},
            {"exponent", c.exponent},
            {"roughness", c.roughness},
            {"rel_rmse", number(c.relRmse)},
            {"rmse", number(c.rmse)},
            {"psnr", number(c.psnr)},
            {"energy_ratio", number(c.energyRatio)},
            {"flicker", number(c.flicker)}};
}

// Frames of one view shifted by sub-pixel amounts; their flicker.
double flickerOf(const Scene& scene, const RenderTextures& t, const std::string& method,
                 RenderOptions o, int frames) {
    if (frames < 2) return std::nan("");
    std::vector<Image> images;
    for (glm::vec2 shift : flickerShifts(frames)) {
        o.pixelShift = shift;
        images.push_back(renderOrFail(scene, t, method, o));
    }
    return temporalFlicker(images);
}

// A method as the matrix names it: "sh:L" is sh baked at order L ("sh" alone: 7), "vmf:J" is vmf
// with J lobes ("vmf" alone: 4).
struct MethodSpec {
    std::string label;  // as in the report
    std::string render; // the name render() takes
    Method method;      // the bake it shades (exact: none)
    BakeOptions options;
    bool baked = true;
    std::string bakeKey; // the label without its @VARIANT: variants share one bake
    // Under an environment, "@RULE" (log2sigma, filament, unity, unreal) or, for vmf, "@sh" or
    // "@prefiltered": the RenderOptions the row is rendered with.
    std::optional<EnvironmentLod> lod;
    std::optional<EnvironmentWay> way;
};

MethodSpec methodSpecOf(const std::string& label);

MethodSpec methodSpec(const std::string& label) {
    const size_t at = label.find('@');
    if (at == std::string::npos) {
        MethodSpec spec = methodSpecOf(label);
        spec.bakeKey = label;
        return spec;
    }
    MethodSpec spec = methodSpecOf(label.substr(0, at));
    spec.label = label;
    spec.bakeKey = label.substr(0, at);
    const std::string variant = label.substr(at + 1);
    EnvironmentLod lod;
    EnvironmentWay way;
    if (environmentLodFromString(variant, lod) && spec.render != kExact &&
        spec.render != kToksvigLut && spec.method != Method::Sh && spec.method != Method::Lean)
        spec.lod = lod;
    else if (environmentWayFromString(variant, way) && spec.method == Method::Vmf)
        spec.way = way;
    else
        fail("--methods: " + quote(label) +
             ": naive, toksvig and vmf take @log2sigma, @filament, @unity or "
             "@unreal (the prefiltered levels' rule), vmf also @sh or @prefiltered (how it shades "
             "under an "
             "environment)");
    return spec;
}

MethodSpec methodSpecOf(const std::string& label) {
    if (label == kExact) return {label, kExact, Method::Naive, {}, false, label, {}, {}};
    // A second shader of a bake (toksvig-lut, sggx) is a row of its own, over its own bake.
    if (const MethodShader* shader = findShader(label);
        shader && label != methodName(shader->bake) && label != kRoughnessMips)
        return {label, shader->name, shader->bake, {}, true, label, {}, {}};
    MethodSpec spec{label, "", Method::Naive, {}, true, label, {}, {}};
    std::string name = label, order;
    if (size_t colon = label.find(':'); colon != std::string::npos) {
        name = label.substr(0, colon);
        order = label.substr(colon + 1);
    }
    auto method = methodFromString(name);
    if (!method)
        fail("--methods: unknown method " + quote(label) +
             " (expected naive, toksvig, toksvig-lut, sh[:ORDER], vmf[:LOBES[:BUDGET]], lean, "
             "sggx, exact)");
    spec.method = *method;
    spec.render = methodName(*method);
    if (!order.empty()) {
        // sh:ORDER, vmf:J or vmf:J:BUDGET: the values in the method's table's spec order.
        std::vector<std::string> values;
        for (size_t from = 0;;) {
            const size_t colon = order.find(':', from);
            values.push_back(
                order.substr(from, colon == std::string::npos ? std::string::npos : colon - from));
            if (colon == std::string::npos) break;
            from = colon + 1;
        }
        Result<ParameterValues> parsed = parseParameterSpec(*method, label, values);
        if (!parsed) fail(parsed.error().message);
        spec.options.parameters = parsed.value();
    }
    return spec;
}

struct MapData {
    std::string name;
    SharedImage normals;
    Pyramid pyramid;
    std::map<std::string, Bake> bakes;                         // by label
    std::map<std::string, std::vector<SharedImage>> roughness; // external mips by "NAME alpha"
};

int viewPixels(const MapData& map, int footprint, int maxPixels) {
    return std::clamp((std::max(map.normals->width, map.normals->height) + footprint - 1) /
                          footprint,
                      32, std::max(32, maxPixels));
}

// The report's WebGL2 view of `map`: its baked methods that the GPU shaders draw, at the
// footprints >= 2, one plain trilinear lookup per pixel (what WebGL's sampler gives), with the
// CPU renderer's image of the first for the page's own check. Float data kept under ~32 MB.
std::string liveViewOf(const MapData& map, const EvalOptions& a,
                       const std::vector<MethodSpec>& specs, const Material& material,
                       glm::vec2 shift) {
    WebglView view;
    view.map = map.name;
    for (int f : a.footprints)
        if (f >= 2) view.footprints.push_back(f);
    if (view.footprints.empty()) return "";
    const int smallest = *std::min_element(view.footprints.begin(), view.footprints.end());
    view.baseLevel = std::max(0, int(std::floor(std::log2(double(smallest)))) - 1);
    view.baseLevel = std::min(view.baseLevel, int(map.pyramid.levels.size()) - 1);
    RenderOptions plain;
    plain.taps = 1;
    plain.lodBias = 0.f;
    plain.shadeFilter = ShadeFilter::Parameter;
    const double texels = double(map.normals->width >> view.baseLevel) *
                          double(map.normals->height >> view.baseLevel);
    double bytes = 0.0;
    // vMF first: the page checks its first method against the CPU.
    std::vector<MethodSpec> ordered = specs;
    std::stable_partition(ordered.begin(), ordered.end(),
                          [](const MethodSpec& m) { return m.render == "vmf"; });
    for (const MethodSpec& spec : ordered) {
        if (!spec.baked || spec.render == kToksvigLut || !map.bakes.count(spec.label)) continue;
        RenderTextures t;
        t.normals = map.normals;
        t.bake = map.bakes.at(spec.label);
        WebglMethod method;
        method.label = spec.label;
        bool drawable = true;
        for (int footprint : view.footprints) {
            Scene scene = evalScene(map.normals->width, map.normals->height, footprint,
                                    viewPixels(map, footprint, a.maxPixels), shift);
            scene.material = material;
            Result<RenderProgram> program = renderProgram(scene, t, spec.render, plain);
            if (!program) {
                drawable = false;
                break;
            }
            method.uniforms.push_back(program->uniforms);
            if (footprint == view.footprints.front()) method.program = std::move(program.value());
        }
        if (!drawable) continue;
        const double methodBytes = double(method.program.layers.size()) * texels * 16.0 * 4.0 / 3.0;
        if (bytes + methodBytes > 32e6) continue;
        bytes += methodBytes;
        if (view.methods.empty()) {
            Scene scene =
                evalScene(map.normals->width, map.normals->height, view.footprints.front(),
                          viewPixels(map, view.footprints.front(), a.maxPixels), shift);
            scene.material = material;
            view.reference = renderOrFail(scene, t, spec.render, plain);
            view.exposureStops = autoExposure(view.reference);
        }
        view.methods.push_back(std::move(method));
    }
    return webglViewHtml(view);
}

// An --external-roughness row: a peer's perceptual-roughness mips beside the standard normal
// mipmap, rendered as kRoughnessMips for Beckmann and GGX settings.
struct ExternalRoughness {
    std::string name, pattern;
};

std::vector<ExternalRoughness> externalRows(const std::vector<std::string>& specs) {
    std::vector<ExternalRoughness> rows;
    for (const std::string& spec : specs) {
        const size_t eq = spec.find('=');
        if (eq == std::string::npos || eq == 0 || eq + 1 == spec.size())
            fail("--external-roughness: " + quote(spec) + " is not NAME=PATTERN");
        if (spec.find("{level}", eq) == std::string::npos)
            fail("--external-roughness: " + quote(spec) + ": the pattern has no {level}");
        rows.push_back({spec.substr(0, eq), spec.substr(eq + 1)});
    }
    return rows;
}

// The options with the view's rule where they leave it open: lab (the renderer's default rule),
// engine (one trilinear lookup, parameters blended, vmf's lobes coherent: H eq. 32, what hardware
// filtering needs) or aligned (one texel per pixel).
EvalOptions withView(EvalOptions a) {
    if (a.view != "lab" && a.view != "engine" && a.view != "aligned")
        fail("--view " + quote(a.view) + ": expected lab, engine or aligned");
    if (a.aligned && a.view == "engine") fail("--aligned and --view engine: give one");
    if ((a.aligned || a.view == "aligned") && a.elevation < 90.f)
        fail("--elevation: an aligned view looks straight down (--elevation 90)");
    if (a.aligned) a.view = "aligned";
    a.aligned = a.view == "aligned";
    if (a.view == "engine") {
        if (!a.taps) a.taps = 1;
        if (!a.lodBias) a.lodBias = 0.f;
        if (!a.lobeFilter) a.lobeFilter = "parameter";
        if (!a.coherence) a.coherence = kEngineViewCoherence;
    }
    if (!a.lobeFilter) a.lobeFilter = "texel";
    return a;
}

EvalResult evaluateOrThrow(const EvalOptions& options) {
    const EvalOptions a = withView(options);
    checkRanges(a);
    const std::vector<Setting> settings = settingsOf(a);
    const std::vector<ExternalRoughness> externals = externalRows(a.externalRoughness);
    if (a.externalEncoding != "perceptual" && a.externalEncoding != "alpha")
        fail("--external-encoding: " + quote(a.externalEncoding) + " is not perceptual or alpha");
    RenderOptions filtering;
    if (!truthFilterFromString(a.truth, filtering.truth))
        fail("--truth: " + quote(a.truth) + " is not box or bilinear");
    if (!shadeFilterFromString(*a.lobeFilter, filtering.shadeFilter))
        fail("--lobe-filter: " + quote(*a.lobeFilter) + " is not parameter or texel");
    // Aligned: one plain lookup per pixel unless the filtering rule is given.
    filtering.taps = a.taps.value_or(a.aligned ? 1 : filtering.taps);
    filtering.lodBias = a.lodBias.value_or(a.aligned ? 0.f : filtering.lodBias);
    const TruthFilter truthFilter = filtering.truth;
    if (a.offset.size() != 2 || !std::isfinite(a.offset[0]) || !std::isfinite(a.offset[1]))
        fail("--offset: two finite numbers X,Y expected");
    // Aligned: each pixel exactly one texel of a level, so every method reads that one texel.
    const glm::vec2 shift = a.aligned ? glm::vec2(0.f) : glm::vec2(a.offset[0], a.offset[1]);
    if (a.aligned)
        for (int f : a.footprints)
            if ((f & (f - 1)) != 0)
                fail("--aligned: footprint " + std::to_string(f) +
                     " is not a power of two (one texel of a level)");
    std::vector<MethodSpec> specs;
    for (const std::string& m : a.methods) specs.push_back(methodSpec(m));
    for (MethodSpec& spec : specs)
        if (spec.method == Method::Vmf && spec.baked && a.coherence.value_or(0.f) != 0.f)
            spec.options.parameters["coherent"] = *a.coherence;
    for (const MethodSpec& spec : specs)
        if ((spec.lod || spec.way) && a.environment.empty())
            fail("--methods: " + quote(spec.label) +
                 ": a variant after @ applies under --environment only");
    for (int f : a.footprints)
        if (f < 1 || f > 4096) fail("--footprints: " + std::to_string(f) + " is not in 1 .. 4096");
    const DecodeOptions& decode = a.decode;
    // Under an environment: the map loaded once, the methods that cannot shade under it skipped.
    std::shared_ptr<const EnvironmentLighting> lighting;
    std::vector<std::pair<std::string, std::string>> skipped;
    if (!a.environment.empty()) {
        if (a.calibrate)
            fail("--calibrate: the roughness calibration is made under the directional light, not "
                 "--environment");
        Result<Environment> env = loadEnvironment(a.environment, a.environmentOptions);
        if (!env) fail(env.error().message);
        lighting = std::make_shared<const EnvironmentLighting>(
            makeEnvironmentLighting(std::move(env.value())));
        const char* reason = "cannot shade under an environment";
        std::vector<MethodSpec> kept;
        for (const MethodSpec& spec : specs) {
            const MethodShader* shader = findShader(spec.render);
            if (shader && shader->shadeEnvironment)
                kept.push_back(spec);
            else
                skipped.emplace_back(spec.label, reason);
        }
        specs = std::move(kept);
        const MethodShader* roughnessMips = findShader(kRoughnessMips);
        if (!(roughnessMips && roughnessMips->shadeEnvironment))
            for (const ExternalRoughness& row : externals) skipped.emplace_back(row.name, reason);
    }
    const bool externalRows =
        !externals.empty() && (!lighting || findShader(kRoughnessMips)->shadeEnvironment);
    double truthNoise = 0.;

    EvalReport report;
    report.title = "ndfmip evaluation";
    json cases = json::array();
    json calibration = json::array();
    // Sum of log relative RMSE and count per calibration candidate, over every calibration case.
    std::map<std::string, std::pair<double, int>> candidateError;
    const long long start = nowNanoseconds();

    for (size_t mapIndex = 0; mapIndex < a.maps.size(); ++mapIndex) {
        MapData map;
        map.name = std::filesystem::path(a.maps[mapIndex]).filename().string();
        DecodeReport decodeReport;
        // Every bake this map gets, held at once, checked by the decoder from the map's header
        // before it allocates.
        double perTexel = 16.0 + 12.0 + 16.0;
        for (const MethodSpec& spec : specs)
            if (spec.baked) perTexel += bakeBytesPerTexel(spec.method, spec.options);
        Result<Image> normals = [&] {
            const PlannedPeak peak("the evaluation", perTexel);
            return loadNormalMap(a.maps[mapIndex], decode, &decodeReport);
        }();
        if (!normals) fail(normals.error().message);
        if (a.decoded) a.decoded(a.maps[mapIndex], decodeReport);
        map.normals = std::make_shared<const Image>(std::move(normals.value()));
        map.pyramid = buildPyramid(map.normals);
        for (const MethodSpec& spec : specs)
            if (spec.baked)
                if (Status s = checkBakeMemory(a.maps[mapIndex], spec.method, spec.options,
                                               map.normals->width, map.normals->height);
                    !s)
                    fail(s.error);
        for (const MethodSpec& spec : specs)
            if (spec.baked && !map.bakes.count(spec.bakeKey))
                map.bakes[spec.bakeKey] = bakeMethod(spec.method, map.pyramid, spec.options);
        if (externalRows)
            map.bakes["naive (external roughness)"] = bakeMethod(Method::Naive, map.pyramid, {});
        if (a.calibrate && map.bakes.count("toksvig") == 0)
            map.bakes["toksvig"] = bakeMethod(Method::Toksvig, map.pyramid, {});
        if (a.log) {
            char line[512];
            std::snprintf(line, sizeof line, "eval: %s (%zu/%zu), %dx%d", map.name.c_str(),
                          mapIndex + 1, a.maps.size(), map.normals->width, map.normals->height);
            a.log(line);
        }
        auto textures = [&](const std::string& label) {
            RenderTextures t;
            t.normals = map.normals;
            if (map.bakes.count(label)) t.bake = map.bakes.at(label);
            t.environment = lighting;
            return t;
        };
        auto renderName = [&](const std::string& label) {
            if (label == kGroundTruth) return label;
            for (const MethodSpec& spec : specs)
                if (spec.label == label) return spec.render;
            return std::string("toksvig"); // the calibration's own bake
        };

        if (mapIndex == 0 && a.webgl && lighting && a.log)
            a.log("eval: no live view under an environment");
        if (mapIndex == 0 && a.webgl && !lighting) {
            report.liveView = liveViewOf(map, a, specs, settings.front().material, shift);
            if (a.log && report.liveView.empty())
                a.log("eval: no live view (no footprint >= 2, or no method the GPU shaders draw)");
        }

        for (int footprint : a.footprints) {
            const int pixels = std::clamp(
                (std::max(map.normals->width, map.normals->height) + footprint - 1) / footprint, 32,
                std::max(32, a.maxPixels));
            Scene scene = evalScene(map.normals->width, map.normals->height, footprint, pixels,
                                    shift, a.elevation);
            if (lighting) { // the environment replaces the directional light
                scene.lights.clear();
                scene.environment.path = a.environment;
                scene.environment.options = a.environmentOptions;
            }
            RenderOptions truthOptions;
            truthOptions.seed = a.seed;
            truthOptions.spp = a.spp > 0 ? a.spp : std::clamp(footprint * footprint, 64, 1024);
            truthOptions.truth = truthFilter;
            RenderOptions methodOptions = filtering;
            methodOptions.seed = a.seed;
            methodOptions.shViews = a.shViews;

            for (const Setting& setting : settings) {
                scene.material = setting.material;
                RenderNoise noise;
                Result<Image> truthImage =
                    render(scene, textures(kGroundTruth), kGroundTruth, truthOptions, &noise);
                if (!truthImage) fail(truthImage.error().message);
                const Image truth = std::move(truthImage.value());
                ReportCase truthCase{
                    map.name,
                    kGroundTruth,
                    setting.brdf,
                    footprint,
                    setting.exponent,
                    setting.roughness,
                    0,
                    0,
                    std::numeric_limits<double>::infinity(),
                    1,
                    flickerOf(scene, textures(kGroundTruth), kGroundTruth, truthOptions, a.frames)};
                report.cases.push_back(truthCase);
                cases.push_back(caseJson(truthCase));
                if (lighting) {
                    cases.back()["rel_std_error"] = number(noise.relativeStandardError);
                    truthNoise = std::max(truthNoise, noise.relativeStandardError);
                    if (a.log) {
                        char line[256];
                        std::snprintf(
                            line, sizeof line,
                            "eval: truth at footprint %d, %s: relative standard error %.3f%%",
                            footprint, setting.label().c_str(), 100. * noise.relativeStandardError);
                        a.log(line);
                    }
                }

                const bool showcase =
                    a.allImages || setting.label() == settings.front().label() ||
                    (setting.brdf == "blinnphong" && setting.exponent == 32.f) ||
                    (setting.brdf == "ggx" && setting.roughness == a.roughness.front());
                ReportGroup group;
                const float stops = autoExposure(truth);
                const float errorScale = float(0.5 * percentileLuminance(truth, 0.99));
                if (showcase) {
                    char title[256];
                    std::snprintf(title, sizeof title, "%s, footprint %d, %s", map.name.c_str(),
                                  footprint, setting.label().c_str());
                    group.title = title;
                    group.images.push_back({"ground truth", toneMap(truth, stops)});
                }
                for (const MethodSpec& spec : specs) {
                    const std::string& method = spec.label;
                    // Toksvig's table is for Blinn-Phong only.
                    if (method == kToksvigLut && setting.material.brdf != Brdf::BlinnPhong)
                        continue;
                    RenderOptions rowOptions = methodOptions;
                    if (spec.lod) rowOptions.environmentLod = *spec.lod;
                    if (spec.way) rowOptions.vmfEnvironment = *spec.way;
                    const Image image =
                        renderOrFail(scene, textures(spec.bakeKey), renderName(method), rowOptions);
                    Result<ImageComparison> cmp = compareImages(image, truth);
                    if (!cmp) fail(cmp.error().message);
                    ReportCase c{map.name,
                                 method,
                                 setting.brdf,
                                 footprint,
                                 setting.exponent,
                                 setting.roughness,
                                 cmp->relativeRmse,
                                 cmp->rmse,
                                 cmp->psnr,
                                 cmp->energyRatio,
                                 flickerOf(scene, textures(spec.bakeKey), renderName(method),
                                           rowOptions, a.frames)};
                    report.cases.push_back(c);
                    cases.push_back(caseJson(c));
                    if (showcase) {
                        group.images.push_back({method, toneMap(image, stops)});
                        group.images.push_back(
                            {method + " error",
                             errorImage(image, truth, errorScale > 0 ? errorScale : 0.f)});
                    }
                }
                for (const ExternalRoughness& row : externals) {
                    if (!externalRows) break;
                    if (setting.material.brdf != Brdf::Ggx &&
                        setting.material.brdf != Brdf::Beckmann)
                        continue;
                    char alpha[32];
                    std::snprintf(alpha, sizeof alpha, "%g", setting.roughness);
                    const std::string key = row.name + " " + alpha;
                    RenderTextures t;
                    t.normals = map.normals;
                    t.bake = map.bakes.at("naive (external roughness)");
                    t.environment = lighting; // --environment: the rows are lit by it too
                    if (!map.roughness.count(key)) {
                        std::vector<std::pair<int, int>> sizes;
                        for (const auto& level : t.bake.levels)
                            sizes.emplace_back(level[0]->width, level[0]->height);
                        map.roughness[key] = loadRoughnessMips(
                            row.pattern, sizes,
                            {{"stem", std::filesystem::path(map.name).stem().string()},
                             {"roughness", alpha}});
                    }
                    t.roughness = map.roughness.at(key);
                    t.roughnessIsAlpha = a.externalEncoding == "alpha";
                    const Image image = renderOrFail(scene, t, kRoughnessMips, methodOptions);
                    Result<ImageComparison> cmp = compareImages(image, truth);
                    if (!cmp) fail(cmp.error().message);
                    ReportCase c{map.name,
                                 row.name,
                                 setting.brdf,
                                 footprint,
                                 setting.exponent,
                                 setting.roughness,
                                 cmp->relativeRmse,
                                 cmp->rmse,
                                 cmp->psnr,
                                 cmp->energyRatio,
                                 flickerOf(scene, t, kRoughnessMips, methodOptions, a.frames)};
                    report.cases.push_back(c);
                    cases.push_back(caseJson(c));
                    if (showcase) {
                        group.images.push_back({row.name, toneMap(image, stops)});
                        group.images.push_back(
                            {row.name + " error",
                             errorImage(image, truth, errorScale > 0 ? errorScale : 0.f)});
                    }
                }
                if (showcase) report.groups.push_back(std::move(group));
            }

            if (!a.calibrate) continue;
            // GGX with each shipped roughness mapping, and ours with every candidate constant.
            for (float alpha : a.calibrationRoughness) {
                scene.material = makeSetting(Brdf::Ggx, 0.f, alpha).material;
                const Image truth =
                    renderOrFail(scene, textures(kGroundTruth), kGroundTruth, truthOptions);
                auto record = [&](const std::string& name, RoughnessMapping mapping, float scale) {
                    RenderOptions o = methodOptions;
                    o.roughnessMapping = mapping;
                    o.varianceScale = scale;
                    const Image image = renderOrFail(scene, textures("toksvig"), "toksvig", o);
                    Result<ImageComparison> cmp = compareImages(image, truth);
                    if (!cmp) fail(cmp.error().message);
                    calibration.push_back({{"map", map.name},
                                           {"footprint", footprint},
                                           {"roughness", alpha},
                                           {"mapping", name},
                                           {"rel_rmse", number(cmp->relativeRmse)},
                                           {"energy_ratio", number(cmp->energyRatio)}});
                    // Geometric mean: errors differ by orders of magnitude between alphas.
                    auto& [logSum, count] = candidateError[name];
                    if (cmp->relativeRmse > 0 && std::isfinite(cmp->relativeRmse)) {
                        logSum += std::log(cmp->relativeRmse);
                        ++count;
                    }
                };
                for (RoughnessMapping m :
                     {RoughnessMapping::Ours, RoughnessMapping::Hdrp, RoughnessMapping::Filament,
                      RoughnessMapping::Godot, RoughnessMapping::Unreal})
                    record(roughnessMappingName(m), m, kVarianceScale);
                for (float c : a.calibrationScales) {
                    char name[32];
                    std::snprintf(name, sizeof name, "c=%g", c);
                    record(name, RoughnessMapping::Ours, c);
                }
            }
        }
    }

    json root;
    root["version"] = NDFMIP_VERSION;
    root["maps"] = a.maps;
    char viewText[96], lightText[96];
    if (a.elevation >= 90.f) {
        std::snprintf(viewText, sizeof viewText, "orthographic, straight down");
        std::snprintf(lightText, sizeof lightText, "directional, 25 deg off the normal");
    } else {
        std::snprintf(viewText, sizeof viewText, "orthographic, %g deg above the plane",
                      a.elevation);
        std::snprintf(lightText, sizeof lightText,
                      "directional, %g deg above the plane, 30 deg from the mirror azimuth",
                      a.elevation);
    }
    root["setup"] = {{"view", viewText},
                     {"light", lightText},
                     {"elevation_degrees", a.elevation},
                     {"footprints", a.footprints},
                     {"methods", a.methods},
                     {"frames", a.frames},
                     {"truth", a.truth},
                     {"truth_spp", truthFilter == TruthFilter::Box
                                       ? json("exact integral, no samples")
                                   : a.spp > 0 ? json(a.spp)
                                               : json("max(64, footprint^2), at most 1024")},
                     {"aligned", a.aligned},
                     {"offset", {shift.x, shift.y}},
                     {"taps", filtering.taps},
                     {"lod_bias", filtering.lodBias},
                     {"lobe_filter", *a.lobeFilter},
                     {"eval_view", a.view},
                     {"coherent", a.coherence.value_or(0.f)},
                     {"seed", a.seed}};
    if (lighting) {
        root["setup"]["light"] = "environment";
        root["setup"]["environment"] = {{"path", a.environment},
                                        {"intensity", a.environmentOptions.intensity},
                                        {"rotation_degrees", a.environmentOptions.rotationDegrees}};
        root["setup"]["truth_spp"] =
            a.spp > 0 ? json(a.spp) : json("max(64, footprint^2), at most 1024");
        root["setup"]["truth_max_rel_std_error"] = number(truthNoise);
        json left = json::array();
        for (const auto& [method, reason] : skipped)
            left.push_back({{"method", method}, {"reason", reason}});
        root["skipped"] = left;
    }
    root["cases"] = cases;
    if (a.calibrate) {
        json summary = json::object();
        std::string best;
        double bestError = std::numeric_limits<double>::infinity();
        for (const auto& [name, value] : candidateError) {
            double mean = std::exp(value.first / std::max(1, value.second));
            summary[name] = mean;
            if (mean < bestError) bestError = mean, best = name;
        }
        root["calibration"] = {{"cases", calibration}, {"mean_rel_rmse", summary}, {"best", best}};
        report.notes.push_back(
            "Roughness calibration (GGX, geometric mean of the relative RMSE over maps, "
            "footprints and base roughness): best is " +
            best + ".");
    }

    char view[160];
    std::snprintf(view, sizeof view,
                  a.aligned ? "on the texel grid (aligned: each pixel one texel of a level)"
                            : "offset from the texel grid by (%g, %g) pixels",
                  shift.x, shift.y);
    const std::string truthText = truthFilter == TruthFilter::Box
                                      ? "the box surface of the finest normals (each texel's "
                                        "normal over its square, what the mip levels "
                                        "average), integrated exactly over each pixel"
                                      : "stratified supersampling of the bilinear, renormalised "
                                        "surface of the finest normals, "
                                        "max(64, footprint^2) samples per pixel up to 1024";
    char filter[160];
    std::snprintf(filter, sizeof filter, "%d x %d sub-samples per pixel, LOD bias %g, %s filtering",
                  filtering.taps, filtering.taps, filtering.lodBias, a.lobeFilter->c_str());
    if (lighting) {
        char noiseText[128];
        std::snprintf(noiseText, sizeof noiseText, "%.3f%%", 100. * truthNoise);
        std::string left;
        for (const auto& [method, reason] : skipped) left += (left.empty() ? "" : ", ") + method;
        report.notes.insert(
            report.notes.begin(),
            "Lit by the environment " + a.environment +
                " instead of the directional light: the truth is sampled "
                "(environment and BRDF samples, MIS) with a relative standard error of at most " +
                noiseText +
                (left.empty()
                     ? std::string(".")
                     : "; left out (they cannot shade under an environment): " + left + "."));
    }
    report.notes.insert(report.notes.begin(),
                        "Each case: a top-down orthographic view of the map tiled on a plane, one "
                        "pixel covering footprint x "
                        "footprint texels, " +
                            std::string(view) +
                            "; one directional light 25 degrees off the normal. Ground "
                            "truth: " +
                            truthText + ". Methods: trilinear filtering, " + filter +
                            "; 'exact' shades each texel "
                            "read as the exact mean over its normals (the floor of any per-texel "
                            "NDF). Flicker: mean over pixels "
                            "of temporal std / mean over " +
                            std::to_string(a.frames) + " sub-pixel-shifted frames.");
    EvalResult result;
    result.json = root.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
    if (!a.output.empty()) {
        std::error_code ec;
        std::filesystem::create_directories(a.output, ec);
        if (ec) fail(a.output + ": cannot create (" + ec.message() + ")");
        Status s = writeFileAtomic(a.output + "/report.json", result.json);
        if (!s) fail(s.error);
        s = writeFileAtomic(a.output + "/report.html", renderReportHtml(report));
        if (!s) fail(s.error);
    }
    result.cases = std::move(report.cases);
    if (a.calibrate) result.calibrationBest = root["calibration"]["best"].get<std::string>();
    result.seconds = millisecondsSince(start) * 1e-3;
    result.skipped = std::move(skipped);
    result.truthNoise = truthNoise;
    return result;
}

} // namespace

Result<EvalResult> evaluateMaps(const EvalOptions& options) {
    try {
        return evaluateOrThrow(options);
    } catch (const EvalProblem& p) {
        return Error{p.message};
    }
}

} // namespace ndfmip
