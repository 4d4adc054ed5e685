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
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <set>

#include <nlohmann/json.hpp>

#include "methods/method_unit.h"
#include "ndfmip/clock.h"
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
#include "report/evaluation_steps.h"
#include "report/webgl_view.h"

namespace ndfmip::evaluation {
namespace {

using json = nlohmann::json;

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

// The view of one footprint: world units are maps (1 unit = the map's width in texels, on
// both axes), an orthographic camera `pixels` pixels square, `elevation` degrees above the plane
// (90: straight down) and tilted about the texel grid's x axis, so that a pixel covers footprint
// texels across and footprint / sin(elevation) along the view, and the truth is still one exact
// integral per pixel (exactBoxView).
Scene evalScene(int mapWidth, int mapHeight, int footprint, int pixels, glm::vec2 shift,
                float elevation = 90.f, float lightPolar = 25.f) {
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
    // Straight down: `lightPolar` degrees off the normal (25 by default). Tilted: near the mirror
    // direction of the view (the glancing highlight a distant floor shows), 30 degrees aside in
    // azimuth.
    const float polar = glm::radians(down ? lightPolar : 90.f - elevation),
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

int viewPixels(const MapData& map, int footprint, int maxPixels) {
    return std::clamp((std::max(map.normals->width, map.normals->height) + footprint - 1) /
                          footprint,
                      32, std::max(32, maxPixels));
}

// The textures of a row: the map's normals, the bake `label` (if any), the environment.
// The bake a row reads under a setting: the spec's own, or one fitted to the setting's roughness
// (ggx-fit); "" where the row does not apply (such a bake under a BRDF other than GGX).
std::string bakeKeyOf(const MethodSpec& spec, const Setting& setting) {
    if (!spec.baked || !bakeFitsMaterialRoughness(spec.method)) return spec.bakeKey;
    if (setting.material.brdf != Brdf::Ggx) return "";
    char alpha[48];
    std::snprintf(alpha, sizeof alpha, " alpha=%g", double(setting.material.roughness));
    return spec.bakeKey + alpha;
}

RenderTextures textures(const MapData& map, const std::string& label, const Lighting& lighting) {
    RenderTextures t;
    t.normals = map.normals;
    if (map.bakes.count(label)) t.bake = map.bakes.at(label);
    t.environment = lighting.environment;
    return t;
}

// The truth's options at one footprint: max(64, footprint^2) samples, at most 1024, unless
// --spp says.
RenderOptions truthOptionsAt(const Plan& plan, int footprint) {
    RenderOptions o;
    o.seed = plan.options.seed;
    o.spp = plan.options.spp > 0 ? plan.options.spp : std::clamp(footprint * footprint, 64, 1024);
    o.truth = plan.filtering.truth;
    o.environmentTruth = plan.options.environmentTruth;
    return o;
}

// The rows' options: the plan's filtering rule.
RenderOptions rowOptionsOf(const Plan& plan) {
    RenderOptions o = plan.filtering;
    o.seed = plan.options.seed;
    o.shViews = plan.options.shViews;
    o.shCosine = plan.options.shCosine;
    o.environmentShOrder = plan.options.environmentShOrder;
    o.dominantDirection = plan.options.dominantDirection;
    return o;
}

} // namespace

// The report's WebGL2 view of `map`: its baked methods that the GPU shaders draw, at the
// footprints >= 2, one plain trilinear lookup per pixel (what WebGL's sampler gives), with the
// CPU renderer's image of the first for the page's own check. Float data kept under ~32 MB.
std::string liveViewOf(const Plan& plan, const MapData& map) {
    const EvalOptions& a = plan.options;
    const Material& material = plan.settings.front().material;
    const glm::vec2 shift = plan.shift;
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
    std::vector<MethodSpec> ordered = plan.specs;
    std::stable_partition(ordered.begin(), ordered.end(),
                          [](const MethodSpec& m) { return m.render == "vmf"; });
    for (const MethodSpec& spec : ordered) {
        const std::string key =
            spec.label == spec.bakeKey ? bakeKeyOf(spec, plan.settings.front()) : "";
        if (!spec.baked || spec.render == kToksvigLut || !map.bakes.count(key)) continue;
        RenderTextures t;
        t.normals = map.normals;
        t.bake = map.bakes.at(key);
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

MapData loadAndBake(const Plan& plan, size_t mapIndex, const Lighting& lighting) {
    const EvalOptions& a = plan.options;
    const std::vector<MethodSpec>& specs = plan.specs;
    const DecodeOptions& decode = a.decode;
    MapData map;
    map.name = std::filesystem::path(a.maps[mapIndex]).filename().string();
    DecodeReport decodeReport;
    // The bakes the rows read: each spec's own, a fitted one (ggx-fit) once per roughness.
    struct PlannedBake {
        std::string key;
        const MethodSpec* spec;
        float baseRoughness;
    };
    std::vector<PlannedBake> planned;
    for (const MethodSpec& spec : specs) {
        std::set<std::string> keys;
        for (const Setting& setting : plan.settings)
            if (std::string key = bakeKeyOf(spec, setting);
                spec.baked && !key.empty() && keys.insert(key).second)
                planned.push_back({key, &spec, setting.material.roughness});
    }
    // Every bake this map gets, held at once, checked by the decoder from the map's header
    // before it allocates.
    double perTexel = 16.0 + 12.0 + 16.0;
    for (const PlannedBake& b : planned)
        perTexel += bakeBytesPerTexel(b.spec->method, b.spec->options);
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
    for (const PlannedBake& b : planned) {
        if (map.bakes.count(b.key)) continue; // variants (@RULE) share their spec's bake
        BakeOptions options = b.spec->options;
        options.baseRoughness = b.baseRoughness;
        map.bakes[b.key] = bakeMethod(b.spec->method, map.pyramid, options);
    }
    if (lighting.externalRows)
        map.bakes["naive (external roughness)"] = bakeMethod(Method::Naive, map.pyramid, {});
    if (a.calibrate && map.bakes.count("toksvig") == 0)
        map.bakes["toksvig"] = bakeMethod(Method::Toksvig, map.pyramid, {});
    if (a.log) {
        char line[512];
        std::snprintf(line, sizeof line, "eval: %s (%zu/%zu), %dx%d", map.name.c_str(),
                      mapIndex + 1, a.maps.size(), map.normals->width, map.normals->height);
        a.log(line);
    }
    return map;
}

Scene footprintScene(const Plan& plan, const MapData& map, int footprint,
                     const Lighting& lighting) {
    const EvalOptions& a = plan.options;
    Scene scene =
        evalScene(map.normals->width, map.normals->height, footprint,
                  viewPixels(map, footprint, a.maxPixels), plan.shift, a.elevation, a.lightPolar);
    if (lighting.environment) { // the environment replaces the directional light
        scene.lights.clear();
        scene.environment.path = a.environment;
        scene.environment.options = a.environmentOptions;
    }
    return scene;
}

namespace {

// One setting's truth and what its rows are compared with.
struct SettingView {
    const std::string& map;
    const Setting& setting;
    int footprint;
    Image truth;
    bool showcase; // its images go into the report
    float stops, errorScale;
    ReportGroup group;
};

// A row's image against the truth: its case in the report and, for a showcase setting, its
// image and error image.
void recordRow(SettingView& view, const std::string& label, const Image& image,
               const std::function<double()>& flicker, Gathered& out) {
    Result<ImageComparison> cmp = compareImages(image, view.truth);
    if (!cmp) fail(cmp.error().message);
    const Setting& setting = view.setting;
    ReportCase c{view.map,          label,
                 setting.brdf,      view.footprint,
                 setting.exponent,  setting.roughness,
                 cmp->relativeRmse, cmp->rmse,
                 cmp->psnr,         cmp->energyRatio,
                 flicker()};
    out.report.cases.push_back(c);
    out.cases.push_back(caseJson(c));
    if (view.showcase) {
        view.group.images.push_back({label, toneMap(image, view.stops)});
        view.group.images.push_back(
            {label + " error",
             errorImage(image, view.truth, view.errorScale > 0 ? view.errorScale : 0.f)});
    }
}

// An --external-roughness row's textures: the standard normal mipmap and the row's roughness
// mips for the setting's alpha, read once per map.
RenderTextures externalTextures(const Plan& plan, const Lighting& lighting, MapData& map,
                                const ExternalRoughness& row, const Setting& setting) {
    char alpha[32];
    std::snprintf(alpha, sizeof alpha, "%g", setting.roughness);
    const std::string key = row.name + " " + alpha;
    RenderTextures t;
    t.normals = map.normals;
    t.bake = map.bakes.at("naive (external roughness)");
    t.environment = lighting.environment; // --environment: the rows are lit by it too
    if (!map.roughness.count(key)) {
        std::vector<std::pair<int, int>> sizes;
        for (const auto& level : t.bake.levels)
            sizes.emplace_back(level[0]->width, level[0]->height);
        map.roughness[key] = loadRoughnessMips(
            row.pattern, sizes,
            {{"stem", std::filesystem::path(map.name).stem().string()}, {"roughness", alpha}});
    }
    t.roughness = map.roughness.at(key);
    t.roughnessIsAlpha = plan.options.externalEncoding == "alpha";
    return t;
}

} // namespace

void evaluateSetting(const Plan& plan, const Lighting& lighting, MapData& map, Scene scene,
                     int footprint, const Setting& setting, Gathered& out) {
    const EvalOptions& a = plan.options;
    const RenderOptions truthOptions = truthOptionsAt(plan, footprint);
    const RenderOptions methodOptions = rowOptionsOf(plan);
    scene.material = setting.material;
    RenderNoise noise;
    Result<Image> truthImage =
        render(scene, textures(map, kGroundTruth, lighting), kGroundTruth, truthOptions, &noise);
    if (!truthImage) fail(truthImage.error().message);
    const bool showcase = a.allImages || setting.label() == plan.settings.front().label() ||
                          (setting.brdf == "blinnphong" && setting.exponent == 32.f) ||
                          (setting.brdf == "ggx" && setting.roughness == a.roughness.front());
    SettingView view{map.name, setting, footprint, std::move(truthImage.value()),
                     showcase, 0.f,     0.f,       {}};
    const Image& truth = view.truth;
    ReportCase truthCase{map.name,
                         kGroundTruth,
                         setting.brdf,
                         footprint,
                         setting.exponent,
                         setting.roughness,
                         0,
                         0,
                         std::numeric_limits<double>::infinity(),
                         1,
                         flickerOf(scene, textures(map, kGroundTruth, lighting), kGroundTruth,
                                   truthOptions, a.frames)};
    out.report.cases.push_back(truthCase);
    out.cases.push_back(caseJson(truthCase));
    if (lighting.environment) {
        out.cases.back()["rel_std_error"] = jsonNumber(noise.relativeStandardError);
        out.truthNoise = std::max(out.truthNoise, noise.relativeStandardError);
        if (a.log) {
            char line[256];
            std::snprintf(line, sizeof line,
                          "eval: truth at footprint %d, %s: relative standard error %.3f%%",
                          footprint, setting.label().c_str(), 100. * noise.relativeStandardError);
            a.log(line);
        }
    }

    view.stops = autoExposure(truth);
    view.errorScale = float(0.5 * percentileLuminance(truth, 0.99));
    if (showcase) {
        char title[256];
        std::snprintf(title, sizeof title, "%s, footprint %d, %s", map.name.c_str(), footprint,
                      setting.label().c_str());
        view.group.title = title;
        view.group.images.push_back({"ground truth", toneMap(truth, view.stops)});
    }
    for (const MethodSpec& spec : plan.specs) {
        // Toksvig's table is for Blinn-Phong only.
        if (spec.label == kToksvigLut && setting.material.brdf != Brdf::BlinnPhong) continue;
        const std::string bakeKey = bakeKeyOf(spec, setting);
        if (bakeKey.empty()) continue;
        RenderOptions rowOptions = methodOptions;
        if (spec.lod) rowOptions.environmentLod = *spec.lod;
        if (spec.way) rowOptions.vmfEnvironment = *spec.way;
        const RenderTextures t = textures(map, bakeKey, lighting);
        const Image image = renderOrFail(scene, t, spec.render, rowOptions);
        recordRow(
            view, spec.label, image,
            [&] { return flickerOf(scene, t, spec.render, rowOptions, a.frames); }, out);
    }
    if (lighting.externalRows &&
        (setting.material.brdf == Brdf::Ggx || setting.material.brdf == Brdf::Beckmann))
        for (const ExternalRoughness& row : plan.externals) {
            const RenderTextures t = externalTextures(plan, lighting, map, row, setting);
            const Image image = renderOrFail(scene, t, kRoughnessMips, methodOptions);
            recordRow(
                view, row.name, image,
                [&] { return flickerOf(scene, t, kRoughnessMips, methodOptions, a.frames); }, out);
        }
    if (showcase) out.report.groups.push_back(std::move(view.group));
}

void calibrateFootprint(const Plan& plan, const Lighting& lighting, const MapData& map, Scene scene,
                        int footprint, Gathered& out) {
    const EvalOptions& a = plan.options;
    const RenderOptions truthOptions = truthOptionsAt(plan, footprint);
    const RenderOptions methodOptions = rowOptionsOf(plan);
    // GGX with each shipped roughness mapping, and ours with every candidate constant.
    for (float alpha : a.calibrationRoughness) {
        scene.material = makeSetting(Brdf::Ggx, 0.f, alpha).material;
        const Image truth =
            renderOrFail(scene, textures(map, kGroundTruth, lighting), kGroundTruth, truthOptions);
        auto record = [&](const std::string& name, RoughnessMapping mapping, float scale) {
            RenderOptions o = methodOptions;
            o.roughnessMapping = mapping;
            o.varianceScale = scale;
            const Image image =
                renderOrFail(scene, textures(map, "toksvig", lighting), "toksvig", o);
            Result<ImageComparison> cmp = compareImages(image, truth);
            if (!cmp) fail(cmp.error().message);
            out.calibration.push_back({{"map", map.name},
                                       {"footprint", footprint},
                                       {"roughness", alpha},
                                       {"mapping", name},
                                       {"rel_rmse", jsonNumber(cmp->relativeRmse)},
                                       {"energy_ratio", jsonNumber(cmp->energyRatio)}});
            // Geometric mean: errors differ by orders of magnitude between alphas.
            auto& [logSum, count] = out.candidateError[name];
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

} // namespace ndfmip::evaluation

namespace ndfmip {
namespace {

using namespace evaluation;

EvalResult evaluateOrThrow(const EvalOptions& options) {
    Plan plan = planEvaluation(options);
    const Lighting lighting = prepareLighting(plan);
    const EvalOptions& a = plan.options;
    Gathered gathered;
    gathered.report.title = "ndfmip evaluation";
    const long long start = nowNanoseconds();
    for (size_t mapIndex = 0; mapIndex < a.maps.size(); ++mapIndex) {
        MapData map = loadAndBake(plan, mapIndex, lighting);
        if (mapIndex == 0 && a.webgl && lighting.environment && a.log)
            a.log("eval: no live view under an environment");
        if (mapIndex == 0 && a.webgl && !lighting.environment) {
            gathered.report.liveView = liveViewOf(plan, map);
            if (a.log && gathered.report.liveView.empty())
                a.log("eval: no live view (no footprint >= 2, or no method the GPU shaders draw)");
        }
        for (int footprint : a.footprints) {
            const Scene scene = footprintScene(plan, map, footprint, lighting);
            for (const Setting& setting : plan.settings)
                evaluateSetting(plan, lighting, map, scene, footprint, setting, gathered);
            if (a.calibrate) calibrateFootprint(plan, lighting, map, scene, footprint, gathered);
        }
    }
    EvalResult result;
    const json root = reportJson(plan, lighting, gathered, result.calibrationBest);
    gathered.report.notes =
        reportNotes(plan, lighting, gathered.truthNoise, result.calibrationBest);
    result.json = root.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
    if (!a.output.empty()) {
        std::error_code ec;
        std::filesystem::create_directories(a.output, ec);
        if (ec) fail(a.output + ": cannot create (" + ec.message() + ")");
        Status s = writeFileAtomic(a.output + "/report.json", result.json);
        if (!s) fail(s.error);
        s = writeFileAtomic(a.output + "/report.html", renderReportHtml(gathered.report));
        if (!s) fail(s.error);
    }
    result.cases = std::move(gathered.report.cases);
    result.seconds = millisecondsSince(start) * 1e-3;
    result.skipped = lighting.skipped;
    result.truthNoise = gathered.truthNoise;
    return result;
}

} // namespace

Result<EvalResult> evaluateMaps(const EvalOptions& options) {
    try {
        return evaluateOrThrow(options);
    } catch (const Problem& p) {
        return Error{p.message};
    }
}

} // namespace ndfmip
