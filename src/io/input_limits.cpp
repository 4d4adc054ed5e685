// The input-size policy (limits.h) and the bounded quoting of user text in messages (result.h).
#include "ndfmip/limits.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "methods/method_unit.h"
#include "ndfmip/paths.h"
#include "ndfmip/spherical_harmonics.h"

namespace ndfmip {
namespace {

InputLimits gLimits;

std::string count(int64_t n) {
    return std::to_string(n);
}

// "16384x16384" when n is a square, else the plain number.
std::string pixelsText(int64_t n) {
    const auto side = int64_t(std::llround(std::sqrt(double(n))));
    std::string text = count(n) + " pixels";
    if (side * side == n) text += " (" + count(side) + "x" + count(side) + ")";
    return text;
}

} // namespace

std::string shortened(std::string_view text, size_t maxChars) {
    return printable(text, maxChars);
}

std::string quote(std::string_view text, size_t maxChars) {
    std::string out(1, '\'');
    out += shortened(text, maxChars);
    out += '\'';
    return out;
}

const InputLimits& inputLimits() {
    return gLimits;
}

void setInputLimits(const InputLimits& limits) {
    gLimits = limits;
}

Status checkImageSize(const std::string& name, int64_t width, int64_t height) {
    const InputLimits& l = gLimits;
    const std::string size = count(width) + "x" + count(height);
    if (width <= 0 || height <= 0) return Status::failure(name + ": image is empty (" + size + ")");
    if (width > l.maxSide || height > l.maxSide)
        return Status::failure(name + ": image is " + size + ", above the limit of " +
                               count(l.maxSide) + " texels per side");
    if (width * height > l.maxPixels)
        return Status::failure(name + ": image is " + size + ", above the limit of " +
                               pixelsText(l.maxPixels) + "; --max-pixels raises it");
    return Status::success();
}

Status checkCameraSize(const std::string& name, int64_t width, int64_t height) {
    const int64_t limit = gLimits.maxCameraPixels;
    if (width > 0 && height > 0 && width <= limit / height) return Status::success();
    return Status::failure(name + ": a " + count(width) + "x" + count(height) +
                           " image is above the limit of " + pixelsText(limit) +
                           " per rendered image; --max-pixels raises it");
}

int64_t bakeMemoryEstimate(Method method, const BakeOptions& options, int64_t width,
                           int64_t height) {
    // Per level-0 texel; a full pyramid holds 4/3 of its level 0. Every bake holds the decoded
    // normals (12 bytes) and the pyramid's means (12 bytes per texel per level).
    double perTexel = 12.0 + 12.0 * 4.0 / 3.0;
    perTexel += methodUnit(method).bakeBytesPerTexel(options);
    return int64_t(perTexel * double(width) * double(height));
}

Status checkBakeMemory(const std::string& name, Method method, const BakeOptions& options,
                       int64_t width, int64_t height) {
    const int64_t need = bakeMemoryEstimate(method, options, width, height);
    if (need <= gLimits.maxMemoryBytes) return Status::success();
    BakeParameters parameters; // those a bake records name it
    for (const MethodParameter& p : methodParameters(method))
        if (p.recorded) parameters[p.key] = parameterValue(method, options.parameters, p.key);
    const std::string what = methodUnit(method).describe(parameters);
    return Status::failure(name + ": a " + what + " of a " + count(width) + "x" +
                           count(height) + " map needs about " + byteSize(need) +
                           ", above the limit of " + byteSize(gLimits.maxMemoryBytes) +
                           "; --max-memory raises it");
}

std::string byteSize(int64_t bytes) {
    const char* units[] = {"bytes", "KiB", "MiB", "GiB", "TiB"};
    double value = double(bytes);
    int unit = 0;
    while (value >= 1024.0 && unit < 4) value /= 1024.0, ++unit;
    char text[64];
    std::snprintf(text, sizeof text, unit == 0 ? "%.0f %s" : "%.1f %s", value, units[unit]);
    return text;
}

} // namespace ndfmip
