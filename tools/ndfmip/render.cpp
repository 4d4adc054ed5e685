// ndfmip render SCENE.json: draws a scene with a baked method or as the supersampled ground
// truth; writes a float EXR and a tone-mapped PNG beside it.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>

#include "cli.h"
#include "ndfmip/gpu_render.h"
#include "ndfmip/interpolated.h"
#include "ndfmip/io.h"
#include "ndfmip/render.h"
#include "ndfmip/sh_brdf.h"
#include "ndfmip/tonemap.h"

namespace ndfmip::cli {
namespace {

struct RenderArgs {
    std::string scene;
    std::string method;
    std::string bake;
    std::string output;
    std::string mapping = "ours";
    int spp = 0; // 0: 1 for a method, 64 for the ground truth
    int anisotropy = 1;
    int frames = 0;
    MethodParameterArgs methodParameters; // --order, --lobes: methods baked on the fly
    uint64_t seed = 1;
    bool nearest = false;
    FilteringArgs filtering;
    EnvironmentArgs environment;
    EnvironmentShadingArgs environmentShading;
    EnvironmentTruth environmentTruth = EnvironmentTruth::Sampled;
    bool noPng = false;
    float exposure = std::numeric_limits<float>::quiet_NaN();
    bool quiet = false;
    bool gpu = false;
    int gpuFrames = 1;
    int truthSpp = 256; // faceted spheres: the truth frames of the error flicker
};

// H eq. 17 keeps bands l <= l*: say so when the material's lobe holds more than 1% of its energy
// above the bake's order.
void warnAboutShTruncation(const Material& m, int order) {
    if (m.brdf == Brdf::Lambert) return;
    Result<int> needed = brdfOrderNeeded(m.brdf, m.exponent, m.roughness, 0.01);
    if (!needed || needed.value() <= order) return;
    Result<std::vector<double>> A =
        brdfCoefficients(m.brdf, m.exponent, m.roughness, std::max(4 * needed.value(), 64));
    if (!A) return;
    const std::string advice = needed.value() <= kMaxShOrder
                                   ? "bake with --order " + std::to_string(needed.value())
                                   : "beyond the largest order, " + std::to_string(kMaxShOrder) +
                                         "; a vMF method suits it";
    std::fprintf(
        stderr,
        "ndfmip: warning: the %s lobe needs l* = %d to keep 99%% of its energy; the bake has "
        "l* = %d and drops %.1f%% of it (%s)\n",
        brdfName(m.brdf), needed.value(), order, 100.0 * truncationEnergyLoss(A.value(), order),
        advice.c_str());
}

void runRender(const RenderArgs& a) {
    if (std::filesystem::path(a.output).extension() != ".exr")
        throw Failure(a.output +
                      ": the output must be an .exr file (the PNG is written beside it)");
    Result<Scene> scene = loadScene(a.scene);
    if (!scene) throw Failure(scene.error().message);
    a.environment.apply(scene.value());
    const std::string method = a.method.empty() ? scene->method : a.method;
    // Faceted spheres (interpolated normals) have their own methods and no textures.
    const bool interpolated = scene->geometry.type == GeometryType::FacetedSphere;
    const bool bakeless = method == kGroundTruth || method == kExact || interpolated;
    if (!bakeless && !shaderBake(method))
        throw Failure("unknown method " + quote(method) + " (expected " + renderMethodNames() +
                      ")");
    RenderOptions options;
    options.spp = a.spp > 0 ? a.spp : (method == kGroundTruth ? 64 : 1);
    options.seed = a.seed;
    a.filtering.apply(options);
    a.environmentShading.apply(options);
    options.environmentTruth = a.environmentTruth;
    if (a.nearest) options.truth = TruthFilter::Box;
    options.anisotropy = a.anisotropy;
    options.roughnessMapping = roughnessMappingOrFail(a.mapping);
    if (!a.quiet)
        options.progress = [](int done, int total) { showProgress("render", done, total); };

    const long long start = nowNanoseconds();
    SceneTextureOptions load;
    load.bakeDir = a.bake;
    load.bakeParameters = a.methodParameters.given();
    if (!a.quiet)
        load.decoded = [&](const DecodeReport& report) {
            warnAboutDecode(scene->normalMap.path, report);
        };
    Result<RenderTextures> loaded = loadSceneTextures(scene.value(), method, load);
    if (!loaded) throw Failure(loaded.error().message);
    const RenderTextures& textures = loaded.value();
    if (!a.quiet && textures.bake.method == Method::Sh && method == "sh")
        warnAboutShTruncation(scene->material, bakeShOrder(textures.bake));
    const double loadMs = millisecondsSince(start);

    GpuRenderStats gpuStats;
    auto draw = [&](const RenderOptions& o, GpuRenderStats* statistics, int frames) {
        return a.gpu ? renderGpu(scene.value(), textures, method, o, statistics, frames)
                     : render(scene.value(), textures, method, o);
    };
    const long long renderStart = nowNanoseconds();
    RenderNoise noise;
    Result<Image> image = a.gpu ? draw(options, &gpuStats, a.gpuFrames)
                                : render(scene.value(), textures, method, options, &noise);
    if (!image) throw Failure(a.scene + ": " + image.error().message);
    const double renderMs = millisecondsSince(renderStart);

    double flicker = -1.0, errorFlicker = -1.0;
    if (a.frames > 1) {
        std::vector<Image> frames;
        RenderOptions quiet = options;
        quiet.progress = nullptr;
        for (glm::vec2 shift : flickerShifts(a.frames)) {
            quiet.pixelShift = shift;
            Result<Image> frame = draw(quiet, nullptr, 1);
            if (!frame) throw Failure(frame.error().message);
            frames.push_back(std::move(frame.value()));
        }
        flicker = temporalFlicker(frames);
        if (interpolated &&
            method != kGroundTruth) { // the error's flicker needs the truth's frames
            std::vector<Image> truthFrames;
            quiet.spp = a.truthSpp;
            for (glm::vec2 shift : flickerShifts(a.frames)) {
                quiet.pixelShift = shift;
                Result<Image> frame = render(scene.value(), textures, kGroundTruth, quiet);
                if (!frame) throw Failure(frame.error().message);
                truthFrames.push_back(std::move(frame.value()));
            }
            errorFlicker = temporalErrorFlicker(frames, truthFrames);
        }
    }

    std::string png;
    if (!a.noPng) png = std::filesystem::path(a.output).replace_extension(".png").string();
    const float stops = std::isnan(a.exposure) ? autoExposure(image.value()) : a.exposure;
    if (Status s = saveExrWithPreview(a.output, image.value(), png,
                                      png.empty() ? Image{} : toneMap(image.value(), stops));
        !s)
        throw Failure(s.error);
    std::printf("render: %s, %dx%d, %d spp: load %.0f ms, render %.0f ms -> %s%s%s\n",
                method.c_str(), image->width, image->height, options.spp, loadMs, renderMs,
                a.output.c_str(), png.empty() ? "" : ", ", png.c_str());
    if (method == kGroundTruth && !a.gpu && (textures.environment || options.spp > 1))
        std::printf("noise: relative standard error %.3f%% (mean per-pixel standard error / mean "
                    "luminance over %zu "
                    "covered pixels)\n",
                    100. * noise.relativeStandardError, noise.coveredPixels);
    if (flicker >= 0.0) std::printf("flicker (%d frames): %.5f\n", a.frames, flicker);
    if (errorFlicker >= 0.0)
        std::printf("error flicker (%d frames, truth %d spp): %.5f\n", a.frames, a.truthSpp,
                    errorFlicker);
    if (a.gpu && !gpuStats.frameMs.empty()) {
        auto median = [](std::vector<double> ms) {
            std::sort(ms.begin(), ms.end());
            return ms[ms.size() / 2];
        };
        std::printf(
            "gpu: %s: frame %.3f ms GL timer query, %.3f ms draw to glFinish (medians of %zu), "
            "setup %.0f ms\n",
            gpuStats.device.c_str(), median(gpuStats.frameMs), median(gpuStats.frameWallMs),
            gpuStats.frameMs.size(), gpuStats.compileMs);
    }
}

} // namespace

void addRenderCommand(CLI::App& app) {
    auto a = std::make_shared<RenderArgs>();
    CLI::App* c = app.add_subcommand(
        "render", "render a scene (docs/SCENES.md) with a method or the ground truth");
    c->add_option("scene", a->scene, "scene file (JSON)")->required();
    c->add_option("--method", a->method,
                  renderMethodNames() + "; faceted-sphere scenes: " + interpolatedMethodNames() +
                      " (default: the scene's)");
    c->add_option("--spp", a->spp, "samples per pixel, stratified (default 1; ground truth 64)")
        ->check(CLI::Range(1, 1 << 20));
    c->add_option("--seed", a->seed, "jitter seed")->capture_default_str();
    addFilteringOptions(c, a->filtering);
    addEnvironmentOptions(c, a->environment);
    addEnvironmentShadingOptions(c, a->environmentShading);
    addEnvTruthOption(c, a->environmentTruth, "sampled");
    c->add_flag("--nearest", a->nearest, "the same as --truth box");
    c->add_option("--aniso", a->anisotropy,
                  "methods: anisotropic probes along the footprint (1 = trilinear)")
        ->check(CLI::Range(1, 64))
        ->capture_default_str();
    addMethodParameterOptions(c, kParameterRender, a->methodParameters);
    c->add_option("--bake", a->bake, "use this bake directory instead of baking the scene's map");
    c->add_option("--roughness-mapping", a->mapping,
                  "toksvig with beckmann/ggx: ours, hdrp, filament, godot or unreal")
        ->capture_default_str();
    c->add_option("--frames", a->frames,
                  "also render F sub-pixel-shifted frames and print the flicker")
        ->check(CLI::Range(0, 1024));
    c->add_option("--truth-spp", a->truthSpp,
                  "faceted-sphere scenes with --frames: samples per pixel of the truth frames the "
                  "error flicker needs")
        ->check(CLI::Range(1, 1 << 16))
        ->capture_default_str();
    c->add_option("--exposure", a->exposure, "PNG exposure in stops (default: automatic)");
    c->add_flag("--no-png", a->noPng, "write the EXR only");
    c->add_flag("-q,--quiet", a->quiet, "no progress or warnings");
    c->add_flag(
        "--gpu", a->gpu,
        "methods: render with OpenGL 4.5 (headless EGL; the GLSL of shaders/) instead of the CPU");
    c->add_option("--gpu-frames", a->gpuFrames,
                  "--gpu: draw the frame N times and print the median GPU time")
        ->check(CLI::Range(1, 10000))
        ->capture_default_str();
    c->add_option("-o,--output", a->output, "output .exr (float RGB); the PNG goes beside it")
        ->required();
    c->callback([a] { runRender(*a); });
}

} // namespace ndfmip::cli
