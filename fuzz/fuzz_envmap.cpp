// Fuzzes `ndfmip envmap`'s input: the bytes decoded as the command reads its map (Radiance HDR,
// OpenEXR or any image, by signature), the environment made of them (the equirect checks, the
// finiteness after the intensity), its SH projection and a small GGX prefiltering.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz_limits.h"
#include "ndfmip/environment.h"
#include "ndfmip/io.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    ndfmip::setFuzzLimits();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace ndfmip;
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    Result<SourceImage> image = decodeImage(bytes, "fuzz.hdr");
    if (!image) {
        FUZZ_CHECK(image.error().message.rfind("fuzz.hdr: ", 0) == 0);
        FUZZ_CHECK(image.error().message.find('\n') == std::string::npos);
        return 0;
    }
    // A strong intensity and a rotation, as --intensity and --rotation give them: radiance that
    // overflows a float once scaled must be refused, not passed on.
    EnvironmentOptions options;
    options.intensity = size % 2 ? 1e6f : 1.f;
    options.rotationDegrees = float(size % 720) - 360.f;
    Result<Environment> env = makeEnvironment(std::move(image->image), "fuzz.hdr", options);
    if (!env) {
        FUZZ_CHECK(env.error().message.rfind("fuzz.hdr: ", 0) == 0);
        FUZZ_CHECK(env.error().message.find('\n') == std::string::npos);
        return 0;
    }
    const Image& radiance = env->radiance;
    FUZZ_CHECK(radiance.width == 2 * radiance.height && radiance.channels == 3);
    for (float v : radiance.pixels) FUZZ_CHECK(std::isfinite(v) && v >= 0.f);
    // Cheap settings: SH to band 2, one GGX level 8 texels wide from 2 samples a texel.
    const EnvironmentSh sh = projectEnvironmentSh(env.value(), 2);
    FUZZ_CHECK(sh.radiance.size() == 9);
    // Double sums of at most 2^18 finite floats are finite.
    for (const auto& c : sh.radiance)
        FUZZ_CHECK(std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z));
    PrefilterOptions prefilter;
    prefilter.size = 8;
    prefilter.levels = 1;
    prefilter.samples = 2;
    const std::vector<PrefilteredLevel> levels = prefilterGgx(env.value(), prefilter);
    FUZZ_CHECK(levels.size() == 1 && levels[0].radiance.width == 8 &&
               levels[0].radiance.height == 4);
    // Weighted means of radiance >= 0 are never negative (envmap itself refuses what is not
    // finite before writing).
    for (float v : levels[0].radiance.pixels) FUZZ_CHECK(!(v < 0.f));
    return 0;
}
