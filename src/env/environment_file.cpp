// One environment map into its folder (environment_file.h).
#include "ndfmip/environment_file.h"

#include <cstdint>
#include <cstdio>

#include "ndfmip/clock.h"
#include "ndfmip/io.h"
#include "ndfmip/limits.h"
#include "ndfmip/spherical_harmonics.h"

namespace ndfmip {
namespace {

int log2Of(int n) {
    int k = 0;
    while ((1 << k) < n) ++k;
    return k;
}

// "--NAME VALUE: expected WHAT".
Status outOfRange(const char* name, double value, const char* what) {
    char text[160];
    std::snprintf(text, sizeof text, "%s %g: expected %s", name, value, what);
    return Status::failure(text);
}

// --levels against level 0's width: at most log2(width) - 2 levels, down to 4x2.
Status levelsFit(int levels, int width) {
    const int most = log2Of(width) - 2;
    if (levels <= most) return Status::success();
    return Status::failure("--levels " + std::to_string(levels) + ": a " + std::to_string(width) +
                           "-wide level 0 has at most " + std::to_string(most) +
                           " levels (down to 4x2)");
}

} // namespace

Status checkEnvironmentFileOptions(const EnvironmentFileOptions& o) {
    LodMapping mapping;
    if (!lodMappingFromString(o.lodMapping, mapping))
        return Status::failure("--lod-mapping " + quote(o.lodMapping) +
                               ": expected filament or linear");
    if (o.layout != "equirect" && o.layout != "cube" && o.layout != "both")
        return Status::failure("--layout " + quote(o.layout) + ": expected equirect, cube or both");
    if (!(o.environment.intensity >= 1e-6f && o.environment.intensity <= 1e6f))
        return outOfRange("--intensity", o.environment.intensity, "1e-06 to 1e+06");
    if (!(o.environment.rotationDegrees >= -360.f && o.environment.rotationDegrees <= 360.f))
        return outOfRange("--rotation", o.environment.rotationDegrees, "-360 to 360");
    if (o.shOrder < 0 || o.shOrder > kMaxShOrder)
        return outOfRange("--sh-order", o.shOrder, "0 to 30 (kMaxShOrder)");
    if (o.size != 0 && (o.size < 8 || o.size > 4096 || (o.size & (o.size - 1)) != 0))
        return outOfRange("--size", o.size, "a power of two from 8 to 4096");
    if (o.levels < 0 || o.levels > 12) return outOfRange("--levels", o.levels, "1 to 12");
    if (o.size != 0)
        if (Status s = levelsFit(o.levels, o.size); !s) return s;
    if (o.samples < 1 || o.samples > 65536) return outOfRange("--samples", o.samples, "1 to 65536");
    if (o.dfgSize < 8 || o.dfgSize > 1024) return outOfRange("--dfg-size", o.dfgSize, "8 to 1024");
    if (o.dfgSamples < 1 || o.dfgSamples > 65536)
        return outOfRange("--dfg-samples", o.dfgSamples, "1 to 65536");
    return Status::success();
}

Result<EnvironmentFileReport> environmentFile(const std::string& input, const std::string& output,
                                              const EnvironmentFileOptions& o) {
    if (Status s = checkEnvironmentFileOptions(o); !s) return Error{s.error};
    PrefilterOptions prefilter;
    lodMappingFromString(o.lodMapping, prefilter.mapping);
    prefilter.levels = o.levels;
    prefilter.samples = o.samples;
    prefilter.progress = o.progress;

    EnvironmentFileReport report;
    long long start = nowNanoseconds();
    EnvironmentReport loading;
    Result<Environment> loaded = [&] {
        // The peak from the options, checked against the memory limit by the decoder from the
        // map's header before it allocates: per texel of the map its decoded file (four floats at
        // most), the radiance and its pyramid; beside them the GGX levels, at most 1024 wide by
        // default, as equirect levels, cube faces and textures.
        const int64_t width = o.size != 0 ? o.size : 1024;
        const auto levelBytes = int64_t(double(width) * double(width / 2) * 12.0 * 4.0 / 3.0);
        const PlannedPeak peak("prefiltering", 16.0 + 12.0 + 16.0, 3 * levelBytes);
        return loadEnvironment(input, o.environment, &loading);
    }();
    if (!loaded) return loaded.error();
    const Environment& env = loaded.value();
    report.width = env.radiance.width;
    report.height = env.radiance.height;
    report.negativeTexels = loading.negativeTexels;
    prefilter.size = o.size != 0 ? o.size : defaultPrefilterSize(env.radiance.width);
    if (Status s = levelsFit(o.levels, prefilter.size); !s) return Error{s.error};
    Result<std::string> hash = sha256File(input);
    if (!hash) return hash.error();
    report.loadMs = millisecondsSince(start);

    start = nowNanoseconds();
    EnvironmentBake bake;
    bake.sh = projectEnvironmentSh(env, o.shOrder);
    report.shMs = millisecondsSince(start);

    start = nowNanoseconds();
    bake.levels = prefilterGgx(env, prefilter);
    bake.mapping = prefilter.mapping;
    bake.equirect = o.layout != "cube";
    bake.cube = o.layout != "equirect";
    bake.ktx2 = o.ktx2;
    bake.dds = o.dds;
    report.ggxMs = millisecondsSince(start);
    for (const PrefilteredLevel& level : bake.levels)
        report.perceptualRoughness.push_back(level.perceptualRoughness);
    report.firstLevelWidth = bake.levels.front().radiance.width;
    report.lastLevelWidth = bake.levels.back().radiance.width;

    start = nowNanoseconds();
    bake.dfg = dfgTable(o.dfgSize, o.dfgSamples);
    bake.dfgSamples = o.dfgSamples;
    report.dfgMs = millisecondsSince(start);

    start = nowNanoseconds();
    const EnvironmentSource source{input, hash.value(), env.radiance.width, env.radiance.height,
                                   o.environment};
    if (Status written = writeEnvironment(output, bake, source, o.half); !written)
        return Error{written.error};
    report.writeMs = millisecondsSince(start);
    return report;
}

} // namespace ndfmip
