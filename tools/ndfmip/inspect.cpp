// ndfmip inspect DIR --level L --texel X,Y: one texel's stored parameters as JSON.
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>

#include <nlohmann/json.hpp>

#include "cli.h"
#include "ndfmip/bake.h"
#include "ndfmip/toksvig.h"

namespace ndfmip::cli {
namespace {

struct InspectArgs {
    std::string dir, texel;
    int level = 0;
    std::optional<float> exponent;
};

std::pair<int, int> parseTexel(const std::string& text) {
    int x = 0, y = 0;
    char extra = 0;
    if (std::sscanf(text.c_str(), "%d,%d%c", &x, &y, &extra) != 2)
        throw Failure("--texel '" + text + "': expected X,Y (column, row from the top)");
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

void runInspect(const InspectArgs& a) {
    auto [x, y] = parseTexel(a.texel);
    Result<LoadedBake> loaded = readBake(a.dir, a.level);
    if (!loaded) throw Failure(loaded.error().message);
    const LoadedBake& bake = loaded.value();
    auto [w, h] = bake.levelSizes[a.level];
    if (x < 0 || x >= w || y < 0 || y >= h)
        throw Failure(a.dir + ": texel (" + a.texel + ") outside level " + std::to_string(a.level) +
                      " (" + std::to_string(w) + "x" + std::to_string(h) + ")");
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
    }
    std::printf("%s\n", out.dump(2).c_str());
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
    c->callback([args] { runInspect(*args); });
}

} // namespace ndfmip::cli
