// ndfmip demo [MAP]: bakes a map with every method and compares each, level by level, with
// the truth for pixels that cover exactly one texel (the mean of the BRDF over the texel's
// normals). Prints a table and writes a side-by-side picture.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "cli.h"
#include "ndfmip/evaluate.h"
#include "ndfmip/io.h"

namespace ndfmip::cli {
namespace {

struct DemoArgs {
    std::string input = std::string(NDFMIP_DATA_DIR) + "/normalmaps/pyramidwall_256.png";
    std::string output = "demo";
    InputOptions input_options;
    bool defaultGreenDown = true; // the bundled map is DirectX-style
};

// Four lights 30 degrees off the surface normal, viewed from straight above.
std::vector<ShadeContext> lightings(float exponent) {
    std::vector<ShadeContext> out;
    const float tilt = 30.f * kPi / 180.f;
    for (int a = 0; a < 4; ++a) {
        float phi = kPi / 4.f + a * kPi / 2.f;
        ShadeContext c;
        c.light = {std::sin(tilt) * std::cos(phi), std::sin(tilt) * std::sin(phi), std::cos(tilt)};
        c.view = {0.f, 0.f, 1.f};
        c.exponent = exponent;
        out.push_back(c);
    }
    return out;
}

// Nearest-neighbour enlargement of a level image to the map's size, tone-mapped by `scale`.
void paste(Image& canvas, const Image& level, int offsetX, const Pyramid& pyramid, int k,
           float scale) {
    for (int y = 0; y < level.height; ++y)
        for (int x = 0; x < level.width; ++x) {
            Footprint f = footprint(pyramid, k, x, y);
            float v = std::pow(std::clamp(level.at(x, y)[0] * scale, 0.f, 1.f), 1.f / 2.2f);
            for (int by = f.y0; by < f.y1; ++by)
                for (int bx = f.x0; bx < f.x1; ++bx)
                    for (int c = 0; c < 3; ++c) canvas.at(offsetX + bx, by)[c] = v;
        }
}

void writePicture(const DemoArgs& a, const Pyramid& pyramid, const std::vector<Bake>& bakes) {
    const int k = std::min<int>(3, int(pyramid.levels.size()) - 1);
    const ShadeContext ctx = lightings(128.f)[0];
    const int w = pyramid.levels[0].width, h = pyramid.levels[0].height;
    Image canvas((1 + int(bakes.size())) * w + int(bakes.size()) * 4, h, 3);
    std::fill(canvas.pixels.begin(), canvas.pixels.end(), 1.f);
    Image truth = groundTruthLevel(pyramid, k, ctx);
    float peak = *std::max_element(truth.pixels.begin(), truth.pixels.end());
    float scale = peak > 0.f ? 1.f / peak : 1.f;
    paste(canvas, truth, 0, pyramid, k, scale);
    for (size_t m = 0; m < bakes.size(); ++m)
        paste(canvas, shadeLevel(bakes[m], k, ctx), int(m + 1) * (w + 4), pyramid, k, scale);
    std::string file = a.output + "/comparison.png";
    Status s = savePng(file, canvas, 8);
    if (!s) throw Failure(s.error);
    std::string names;
    for (const Bake& bake : bakes)
        names += std::string(names.empty() ? "" : ", ") + methodName(bake.method);
    std::printf("picture: %s (level %d, s = 128: truth, then %s)\n", file.c_str(), k,
                names.c_str());
}

void runDemo(DemoArgs a) {
    DecodeOptions decode = a.input_options.resolved();
    if (a.defaultGreenDown) decode.greenDown = true;
    Pyramid pyramid =
        buildPyramid(std::make_shared<const Image>(loadNormalsOrFail(a.input, decode, false)));
    for (Method m : allMethods())
        checkBakeMemoryOrFail(a.input, m, {}, pyramid.base->width, pyramid.base->height);
    // Only once the map has loaded: a bad map leaves no empty output folder behind.
    std::error_code ec;
    std::filesystem::create_directories(a.output, ec);
    if (ec) throw Failure(a.output + ": cannot create (" + ec.message() + ")");
    const Image& normals = *pyramid.base;
    // The Blinn-Phong comparison: a bake fitted to one GGX material (ggx-fit) has no place in it.
    std::vector<Bake> bakes;
    for (Method m : allMethods())
        if (!bakeFitsMaterialRoughness(m)) bakes.push_back(bakeMethod(m, pyramid, {}));
    const std::vector<float> exponents = {8.f, 32.f, 128.f, 512.f};
    std::printf("%s: %dx%d, %zu levels\n", a.input.c_str(), normals.width, normals.height,
                pyramid.levels.size());
    std::printf(
        "relative RMSE of the specular lobe vs the truth (energy ratio), pooled over 4 lights\n");
    std::printf("%-5s %-9s", "level", "footprint");
    for (float s : exponents)
        for (const Bake& bake : bakes) std::printf(" %9s s=%-4g", methodName(bake.method), s);
    std::printf("\n");
    for (int k = 1; k < int(pyramid.levels.size()); ++k) {
        Footprint f = footprint(pyramid, k, 0, 0);
        std::printf("%-5d %4dx%-4d", k, f.width(), f.height());
        for (float s : exponents) {
            std::vector<ShadeContext> lights = lightings(s);
            std::vector<Image> truths;
            for (const ShadeContext& c : lights) truths.push_back(groundTruthLevel(pyramid, k, c));
            for (const Bake& bake : bakes) {
                std::vector<Image> shaded;
                for (const ShadeContext& c : lights) shaded.push_back(shadeLevel(bake, k, c));
                const ErrorStats e = compareToTruth(shaded, truths); // pooled over the lights
                std::printf(" %6.3f (%5.2f)", e.relativeRmse, e.energyRatio);
            }
        }
        std::printf("\n");
    }
    writePicture(a, pyramid, bakes);
}

} // namespace

void addDemoCommand(CLI::App& app) {
    auto args = std::make_shared<DemoArgs>();
    CLI::App* c = app.add_subcommand(
        "demo", "bake a map with every method and compare each with the truth, level by level");
    c->add_option("input", args->input, "normal map (default: the bundled pyramidwall_256.png)");
    c->add_option("-o,--output", args->output, "folder for the picture")->capture_default_str();
    addInputOptions(c, args->input_options);
    c->callback([args, c] {
        DemoArgs a = *args;
        a.defaultGreenDown = c->count("input") == 0;
        runDemo(a);
    });
}

} // namespace ndfmip::cli
