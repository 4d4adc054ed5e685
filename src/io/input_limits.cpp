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

// The innermost PlannedPeak alive on this thread, and the last peak estimated on it (for
// outOfMemoryMessage once the allocation it was about has failed).
thread_local const PlannedPeak* tPlanned = nullptr;
thread_local int64_t tLastEstimate = 0;
thread_local std::string tLastName; // the file that estimate was for

// A decoded image's own bytes per texel at most (four float channels).
constexpr double kDecodedBytesPerTexel = 16.0;

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

Status checkDecodedSize(const std::string& name, int64_t width, int64_t height) {
    if (Status s = checkImageSize(name, width, height); !s) return s;
    const InputLimits& l = gLimits;
    const std::string size = count(width) + "x" + count(height);
    const double texels = double(width) * double(height);
    const std::string what = tPlanned ? tPlanned->what : "the decoded image";
    const double need = tPlanned ? tPlanned->bytesPerTexel * texels + double(tPlanned->fixedBytes)
                                 : kDecodedBytesPerTexel * texels;
    tLastEstimate = int64_t(std::min(need, 9e18));
    tLastName = name;
    if (need > double(l.maxMemoryBytes))
        return Status::failure(name + ": " + what + " of a " + size + " map needs about " +
                               byteSize(tLastEstimate) + ", above the limit of " +
                               byteSize(l.maxMemoryBytes) + "; --max-memory raises it");
    return Status::success();
}

PlannedPeak::PlannedPeak(std::string what_, double bytesPerTexel_, int64_t fixedBytes_)
    : what(std::move(what_)), bytesPerTexel(bytesPerTexel_), fixedBytes(fixedBytes_),
      outer_(tPlanned) {
    tPlanned = this;
    tLastEstimate = 0; // an earlier file's figure is not this one's
    tLastName.clear();
}

PlannedPeak::~PlannedPeak() {
    tPlanned = outer_;
}

std::string outOfMemoryMessage(const std::string& name) {
    // The figure is this file's only where the last estimate was made for it.
    if (tLastEstimate <= 0 || (!tLastName.empty() && tLastName != name))
        return name + ": out of memory";
    return name + ": out of memory (needs about " + byteSize(tLastEstimate) + ")";
}

std::string outOfMemoryMessage() {
    if (tLastName.empty()) return "out of memory";
    return outOfMemoryMessage(tLastName);
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
    return int64_t(bakeBytesPerTexel(method, options) * double(width) * double(height));
}

std::string bakeDescription(Method method, const BakeOptions& options) {
    BakeParameters parameters; // those a bake records name it
    for (const MethodParameter& p : methodParameters(method))
        if (p.recorded) parameters[p.key] = parameterValue(method, options.parameters, p.key);
    return "a " + methodUnit(method).describe(parameters);
}

double bakeBytesPerTexel(Method method, const BakeOptions& options) {
    // Per level-0 texel; a full pyramid holds 4/3 of its level 0. Every bake holds the decoded
    // normals (12 bytes) and the pyramid's means (12 bytes per texel per level).
    return 12.0 + 12.0 * 4.0 / 3.0 + methodUnit(method).bakeBytesPerTexel(options);
}

Status checkBakeMemory(const std::string& name, Method method, const BakeOptions& options,
                       int64_t width, int64_t height) {
    const int64_t need = bakeMemoryEstimate(method, options, width, height);
    tLastEstimate = need;
    tLastName = name;
    if (need <= gLimits.maxMemoryBytes) return Status::success();
    const std::string what = bakeDescription(method, options);
    return Status::failure(name + ": " + what + " of a " + count(width) + "x" + count(height) +
                           " map needs about " + byteSize(need) + ", above the limit of " +
                           byteSize(gLimits.maxMemoryBytes) + "; --max-memory raises it");
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
