// SplitMix64 (Steele, Lea and Flood 2014), the renderers' per-pixel random streams: one stream
// per pixel seeded from the pixel's index, so that an image does not depend on the thread count.
#pragma once

#include <cstdint>

namespace ndfmip {

struct SplitMix64 {
    uint64_t state;
    uint64_t next() {
        uint64_t z = (state += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    float uniform() { return float(next() >> 40) * (1.f / 16777216.f); }               // [0, 1)
    double uniformDouble() { return double(next() >> 11) * (1. / 9007199254740992.); } // [0, 1)
};

} // namespace ndfmip
