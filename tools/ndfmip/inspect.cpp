// ndfmip inspect DIR --level L --texel X,Y: one texel's stored parameters as JSON.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <cstdio>
#include <memory>
#include <optional>

#include <nlohmann/json.hpp>

#include "cli.h"
#include "ndfmip/bake.h"
#include "ndfmip/io.h"
#include "ndfmip/shading.h"
#include "ndfmip/spherical_harmonics.h"
#include "ndfmip/toksvig.h"
#include "ndfmip/vmf.h"

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

nlohmann::json vec3(const float* v) { return {v[0], v[1], v[2]}; }

int planeIndex(const LoadedBake& bake, const std::string& name) {
    int p = findPlane(bake.planes, name);
    if (p < 0) throw Failure("bake has no plane '" + name + "'");
    return p;
}

void addToksvigKeys(nlohmann::json& out, const LoadedBake& bake, int x, int y,
                    std::optional<float> exponent) {
    const float* na = bake.level[planeIndex(bake, "mean")].at(x, y);
    float length = length3(na);
    out["mean_normal"] = vec3(na);
    out["length"] = length;
    out["sigma2"] = toksvigSigma2(length);
    if (exponent) out["toksvig_factor"] = toksvigFactor(length, *exponent);
    out["roughness_beckmann"] = bake.level[planeIndex(bake, "roughness_beckmann")].at(x, y)[0];
    out["roughness_ggx"] = bake.level[planeIndex(bake, "roughness_ggx")].at(x, y)[0];
}

// The coefficients band by band (l = 0 .. l*, m = -l .. l), and the mean normal they hold in
// band 1 (Y_1,-1 Y_1,0 Y_1,1 = sqrt(3 / 4 pi) (y, z, x)).
void addShKeys(nlohmann::json& out, const LoadedBake& bake, int x, int y) {
    const int order = int(bake.parameters.at("order"));
    std::vector<float> g;
    for (const Image& plane : bake.level) g.insert(g.end(), plane.at(x, y), plane.at(x, y) + 4);
    g.resize(size_t(shCount(order)));
    out["order"] = order;
    out["sh"] = g;
    const float c = std::sqrt(3.f / (4.f * kPi));
    const float na[3] = {g[3] / c, g[1] / c, g[2] / c};
    out["mean_normal"] = vec3(na);
    out["length"] = length3(na);
}

// Level-0 unit normal at (x, y) of a bake read at level 0, whatever its method.
glm::vec3 levelZeroNormal(const LoadedBake& level0, int x, int y) {
    const float* p = level0.level.front().at(x, y);
    glm::vec3 n = level0.method == Method::Sh     ? glm::vec3(p[3], p[1], p[2]) // band 1: sqrt(3 / 4 pi) (y, z, x)
                  : level0.method == Method::Lean ? glm::vec3(p[0], p[1], 1.f)  // the slope's normal
                                                  : glm::vec3(p[0], p[1], p[2]);
    float length = glm::length(n);
    return length > 0.f ? n / length : glm::vec3(0.f, 0.f, 1.f);
}

// Direction at the centre of lat-long pixel (i, j): theta from +z down the rows, phi across.
glm::dvec3 latLongDirection(int i, int j, int width, int height) {
    double theta = M_PI * (j + 0.5) / height, phi = 2.0 * M_PI * (i + 0.5) / width;
    return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

// The texel's lobes as the shader sees them, unpacked from (alpha, alpha r mu).
std::vector<VmfLobe> texelLobes(const LoadedBake& bake, int x, int y) {
    std::vector<VmfLobe> lobes;
    for (size_t p = 0; p < bake.planes.size(); ++p) {
        if (bake.planes[p].name.rfind("lobe", 0) != 0) continue;
        const float* v = bake.level[p].at(x, y);
        lobes.push_back(unpackLobe(glm::vec4(v[0], v[1], v[2], v[3])));
    }
    return lobes;
}

void addVmfKeys(nlohmann::json& out, const LoadedBake& bake, int x, int y) {
    nlohmann::json lobes = nlohmann::json::array();
    const std::vector<VmfLobe> all = texelLobes(bake, x, y);
    for (size_t j = 0; j < all.size(); ++j) {
        const VmfLobe& l = all[j];
        if (!(l.alpha > 0.f)) continue;
        nlohmann::json lobe = {{"alpha", l.alpha}, {"mu", {l.mu.x, l.mu.y, l.mu.z}}, {"kappa", l.kappa}};
        const int color = findPlane(bake.planes, "color" + std::to_string(j));
        if (color >= 0) {
            const float* c = bake.level[color].at(x, y);
            const glm::vec3 rgb = unpackLobeColor(glm::vec3(c[0], c[1], c[2]), l.alpha);
            lobe["color"] = {rgb.x, rgb.y, rgb.z};
        }
        lobes.push_back(lobe);
    }
    out["lobes"] = lobes;
}

// The texel's NDF as densities over the sphere (integrating to 1), side by side: left the
// reconstruction from its stored SH, Sum g_lm Y_lm(w) (sh bakes), or its fitted vMF mixture
// (vmf bakes); right the histogram of the level-0 normals it covers. One scale for both; written as PNG (and EXR beside it).
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
        double omega = (2.0 * M_PI / width) * (std::cos(M_PI * j / height) - std::cos(M_PI * (j + 1) / height));
        for (int i = 0; i < width; ++i) histogram.at(i, j)[0] /= float(double(f.count()) * omega);
    }
    if (bake.method == Method::Vmf) {
        const std::vector<VmfLobe> lobes = texelLobes(bake, x, y);
        for (int j = 0; j < height; ++j)
            for (int i = 0; i < width; ++i)
                reconstructed.at(i, j)[0] =
                    float(std::exp(vmfMixtureLogDensity(glm::vec3(latLongDirection(i, j, width, height)), lobes)));
    }
    if (bake.method == Method::Sh) {
        const int order = int(bake.parameters.at("order"));
        std::vector<float> g;
        for (const Image& plane : bake.level) g.insert(g.end(), plane.at(x, y), plane.at(x, y) + 4);
        for (int j = 0; j < height; ++j)
            for (int i = 0; i < width; ++i) {
                std::vector<double> basis = evaluateSh(latLongDirection(i, j, width, height), order);
                double sum = 0;
                for (int k = 0; k < shCount(order); ++k) sum += g[k] * basis[k];
                reconstructed.at(i, j)[0] = float(sum);
            }
    }
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
    Footprint f = footprintOf(bake.source.width, bake.source.height, a.level, x, y);
    nlohmann::json out = {
        {"method", methodName(bake.method)},
        {"level", a.level},
        {"texel", {x, y}},
        {"footprint", {{"x0", f.x0}, {"x1", f.x1}, {"y0", f.y0}, {"y1", f.y1}, {"count", f.count()}}},
    };
    switch (bake.method) {
    case Method::Naive: out["normal"] = vec3(bake.level[planeIndex(bake, "normal")].at(x, y)); break;
    case Method::Toksvig: addToksvigKeys(out, bake, x, y, a.exponent); break;
    case Method::Sh: addShKeys(out, bake, x, y); break;
    case Method::Vmf: addVmfKeys(out, bake, x, y); break;
    case Method::Lean: {
        const float* m = bake.level[planeIndex(bake, "lean_moments")].at(x, y);
        const float cross = bake.level[planeIndex(bake, "lean_cross")].at(x, y)[0];
        out["mean_slope"] = {m[0], m[1]};
        out["slope_covariance"] = {{m[2] - m[0] * m[0], cross - m[0] * m[1]}, {cross - m[0] * m[1], m[3] - m[1] * m[1]}};
        const glm::vec3 n = glm::normalize(glm::vec3(m[0], m[1], 1.f));
        out["mean_normal"] = {n.x, n.y, n.z};
        break;
    }
    }
    if (!a.ndf.empty()) {
        writeNdfImage(a, bake, x, y, f);
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
                  "write the texel's NDF as lat-long PNG: SH or vMF reconstruction | histogram of its normals");
    c->callback([args] { runInspect(*args); });
}

} // namespace ndfmip::cli
