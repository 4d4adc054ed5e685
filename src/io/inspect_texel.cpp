// One texel of a bake as JSON: `ndfmip inspect` and the Python module's inspect().
#include <nlohmann/json.hpp>

#include "methods/method_unit.h"
#include "ndfmip/bake.h"

namespace ndfmip {

Result<std::string> inspectTexel(const LoadedBake& bake, const std::string& name, int level, int x,
                                 int y, std::optional<float> exponent) {
    if (level < 0 || level >= int(bake.levelSizes.size()))
        return Error{name + ": level " + std::to_string(level) + " out of range (the bake has " +
                     std::to_string(bake.levelSizes.size()) + " levels)"};
    auto [w, h] = bake.levelSizes[size_t(level)];
    if (x < 0 || x >= w || y < 0 || y >= h)
        return Error{name + ": texel " + quote(std::to_string(x) + "," + std::to_string(y)) +
                     " outside level " + std::to_string(level) + " (" + std::to_string(w) + "x" +
                     std::to_string(h) + ")"};
    if (bake.level.size() != bake.planes.size())
        return Error{name + ": level " + std::to_string(level) + " was not read with the bake"};
    const Footprint f = footprintOf(bake.source.width, bake.source.height, level, x, y);
    nlohmann::json out = {
        {"method", methodName(bake.method)},
        {"level", level},
        {"texel", {x, y}},
        {"footprint",
         {{"x0", f.x0}, {"x1", f.x1}, {"y0", f.y0}, {"y1", f.y1}, {"count", f.count()}}},
    };
    InspectOptions options;
    options.hasExponent = exponent.has_value();
    options.exponent = exponent.value_or(0.f);
    try {
        methodUnit(bake.method).inspect(out, bake, x, y, options);
    } catch (const std::runtime_error& e) {
        return Error{name + ": " + e.what()};
    }
    return out.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

} // namespace ndfmip
