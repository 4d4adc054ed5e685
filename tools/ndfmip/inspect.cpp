// ndfmip inspect DIR --level L --texel X,Y: one texel's stored parameters as JSON.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>

#include <nlohmann/json.hpp>

#include "cli.h"
#include "ndfmip/bake.h"
#include "ndfmip/io.h"

namespace ndfmip::cli {
namespace {

struct InspectArgs {
    std::string dir, texel, ndf;
    int level = 0;
    std::optional<float> exponent;
};

std::pair<int, int> parseTexel(const std::string& text) {
    int x = 0, y = 0;
    char extra = 0;
    if (std::sscanf(text.c_str(), "%d,%d%c", &x, &y, &extra) != 2)
        throw Failure("--texel " + quote(text) + ": expected X,Y (column, row from the top)");
    return {x, y};
}

// Level-0 unit normal at (x, y) of a bake read at level 0, whatever its method.
glm::vec3 levelZeroNormal(const LoadedBake& level0, int x, int y) {
    std::vector<float> texel;
    for (const Image& plane : level0.level)
        texel.insert(texel.end(), plane.at(x, y), plane.at(x, y) + plane.channels);
    const glm::vec3 n = bakeLevelZeroNormal(level0.method, texel.data());
    const float length = glm::length(n);
    return length > 0.f ? n / length : glm::vec3(0.f, 0.f, 1.f);
}

// Direction at the centre of lat-long pixel (i, j): theta from +z down the rows, phi across.
glm::dvec3 latLongDirection(int i, int j, int width, int height) {
    double theta = M_PI * (j + 0.5) / height, phi = 2.0 * M_PI * (i + 0.5) / width;
    return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

// The texel's NDF as densities over the sphere (integrating to 1), side by side: left the
// method's own (bakeNdfDensity: the SH series, the vMF mixture), where it stores one;
// right the histogram of the level-0 normals it covers. One scale for both; written as PNG (and EXR
// beside it).
void writeNdfImage(const InspectArgs& a, const LoadedBake& bake, int x, int y, const Footprint& f) {
    Result<LoadedBake> level0 = readBake(a.dir, 0);
    if (!level0) throw Failure(level0.error().message);
    if (level0->levelSizes != bake.levelSizes)
        throw Failure(a.dir + ": the bake changed while it was read");
    const int width = 256, height = 128;
    Image reconstructed(width, height, 1), histogram(width, height, 1);
    for (int by = f.y0; by < f.y1; ++by)
        for (int bx = f.x0; bx < f.x1; ++bx) {
            glm::vec3 n = levelZeroNormal(level0.value(), bx, by);
            double theta = std::acos(std::clamp(double(n.z), -1.0, 1.0));
            double phi = std::atan2(double(n.y), double(n.x));
            if (phi < 0) phi += 2.0 * M_PI;
            int i = std::min(width - 1, int(phi / (2.0 * M_PI) * width));
            int j = std::min(height - 1, int(theta / M_PI * height));
            histogram.at(i, j)[0] += 1.f;
        }
    for (int j = 0; j < height; ++j) {
        // Solid angle of a pixel of row j.
        double omega = (2.0 * M_PI / width) *
                       (std::cos(M_PI * j / height) - std::cos(M_PI * (j + 1) / height));
        for (int i = 0; i < width; ++i) histogram.at(i, j)[0] /= float(double(f.count()) * omega);
    }
    for (int j = 0; j < height; ++j)
        for (int i = 0; i < width; ++i)
            reconstructed.at(i, j)[0] = float(
                bakeNdfDensity(bake, x, y, latLongDirection(i, j, width, height)).value_or(0.0));
    Image both(2 * width + 2, height, 1);
    float peak = 0.f;
    for (int j = 0; j < height; ++j)
        for (int i = 0; i < width; ++i) {
            both.at(i, j)[0] = reconstructed.at(i, j)[0];
            both.at(width + 2 + i, j)[0] = histogram.at(i, j)[0];
            peak = std::max({peak, reconstructed.at(i, j)[0], histogram.at(i, j)[0]});
        }
    Status s = saveExr(std::filesystem::path(a.ndf).replace_extension(".exr").string(), both);
    if (!s) throw Failure(s.error);
    Image display = both;
    for (float& v : display.pixels) v = peak > 0.f ? std::sqrt(std::max(v, 0.f) / peak) : 0.f;
    s = savePng(a.ndf, display, 8);
    if (!s) throw Failure(s.error);
}

void runInspect(const InspectArgs& a) {
    if (!a.ndf.empty() && std::filesystem::path(a.ndf).extension() != ".png")
        throw Failure(a.ndf + ": --ndf writes a .png (and an .exr beside it)");
    auto [x, y] = parseTexel(a.texel);
    Result<LoadedBake> loaded = readBake(a.dir, a.level);
    if (!loaded) throw Failure(loaded.error().message);
    const LoadedBake& bake = loaded.value();
    auto [w, h] = bake.levelSizes[a.level];
    if (x < 0 || x >= w || y < 0 || y >= h)
        throw Failure(a.dir + ": texel " + quote(a.texel) + " outside level " +
                      std::to_string(a.level) + " (" + std::to_string(w) + "x" + std::to_string(h) +
                      ")");
    Result<std::string> text = inspectTexel(bake, a.dir, a.level, x, y, a.exponent);
    if (!text) throw Failure(text.error().message);
    nlohmann::json out = nlohmann::json::parse(text.value());
    if (!a.ndf.empty()) {
        writeNdfImage(a, bake, x, y,
                      footprintOf(bake.source.width, bake.source.height, a.level, x, y));
        out["ndf_image"] = a.ndf;
    }
    std::printf("%s\n", out.dump(2, ' ', false, nlohmann::json::error_handler_t::replace).c_str());
}

} // namespace

void addInspectCommand(CLI::App& app) {
    auto args = std::make_shared<InspectArgs>();
    CLI::App* c = app.add_subcommand("inspect", "print one texel of a bake as JSON");
    c->add_option("dir", args->dir, "bake directory")->required();
    c->add_option("--level", args->level, "mip level (0 = the map)")->capture_default_str();
    c->add_option("--texel", args->texel, "X,Y: column, and row from the top row")->required();
    c->add_option("--exponent", args->exponent, "Blinn-Phong exponent s, for toksvig_factor")
        ->check(CLI::Range(1e-3f, 1e6f));
    c->add_option("--ndf", args->ndf,
                  "write the texel's NDF as lat-long PNG: SH or vMF reconstruction | histogram of "
                  "its normals");
    c->callback([args] { runInspect(*args); });
}

} // namespace ndfmip::cli
