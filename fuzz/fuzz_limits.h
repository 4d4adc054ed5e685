// Input limits for fuzzing: small enough that no input can make a single run slow or large, so
// libFuzzer's timeouts and memory limits flag only real faults.
#pragma once

#include "ndfmip/limits.h"

namespace ndfmip {

inline void setFuzzLimits() {
    InputLimits limits;
    limits.maxSide = 4096;
    limits.maxPixels = int64_t(1) << 18;
    limits.maxCameraPixels = int64_t(1) << 16;
    limits.maxMemoryBytes = int64_t(256) << 20;
    limits.maxImageFileBytes = int64_t(16) << 20;
    limits.maxTextFileBytes = int64_t(1) << 20;
    setInputLimits(limits);
}

// Stops the run as a crash when an invariant of a successful result does not hold.
#define FUZZ_CHECK(condition)                                                                      \
    do {                                                                                           \
        if (!(condition)) __builtin_trap();                                                        \
    } while (0)

} // namespace ndfmip
