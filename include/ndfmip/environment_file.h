// One environment map into its folder (`ndfmip envmap`, Python's envmap_to): the map loaded and
// checked, its SH projected, the GGX levels prefiltered, the DFG table made and the folder
// written (environment.h's steps, docs/ENVIRONMENT.md), with the options checked first.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "ndfmip/environment.h"
#include "ndfmip/result.h"

namespace ndfmip {

struct EnvironmentFileOptions {
    EnvironmentOptions environment;      // --intensity (1e-6 .. 1e6), --rotation (-360 .. 360)
    std::string lodMapping = "filament"; // --lod-mapping: filament or linear
    std::string layout = "equirect";     // --layout: equirect, cube or both
    int shOrder = 8;                     // --sh-order: 0 .. kMaxShOrder
    int size = 0;       // --size: GGX level 0's width, a power of two 8 .. 4096 (0: the map's)
    int levels = 0;     // --levels: 1 .. log2(size) - 2 (0: PrefilterOptions' default)
    int samples = 1024; // --samples: 1 .. 65536
    int dfgSize = 128, dfgSamples = 4096; // --dfg-size 8 .. 1024, --dfg-samples 1 .. 65536
    bool half = false, ktx2 = false, dds = false;
    std::function<void(int done, int total)> progress; // after each GGX level
};

// What was written, and the time of each step.
struct EnvironmentFileReport {
    int width = 0, height = 0;               // the map's
    size_t negativeTexels = 0;               // set to 0 on loading, for a warning
    std::vector<double> perceptualRoughness; // of each GGX level
    int firstLevelWidth = 0, lastLevelWidth = 0;
    double loadMs = 0, shMs = 0, ggxMs = 0, dfgMs = 0, writeMs = 0;
};

// The first option out of range, as one line naming it ("--size 100: expected a power of
// two"); the levels are checked against the size where it is given.
Status checkEnvironmentFileOptions(const EnvironmentFileOptions& options);

// Reads `input` (equirectangular .hdr or .exr) and writes the folder `output` (writeEnvironment).
// Errors are one line naming the file or the option; a failure leaves an earlier folder as it was.
Result<EnvironmentFileReport> environmentFile(const std::string& input, const std::string& output,
                                              const EnvironmentFileOptions& options);

} // namespace ndfmip
