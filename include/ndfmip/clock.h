// A monotonic clock for the stage timings the commands print (and callers of the library may).
#pragma once

#include <chrono>

namespace ndfmip {

inline long long nowNanoseconds() {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(
               std::chrono::steady_clock::now().time_since_epoch())
        .count();
}

inline double millisecondsSince(long long startNanoseconds) {
    return double(nowNanoseconds() - startNanoseconds) * 1e-6;
}

} // namespace ndfmip
