// Percentiles of sample sets, shared by the comparison and tone-mapping code.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

namespace ndfmip {

// The value at rank round(q * (n - 1)) of the finite samples (q in [0, 1]); 0 when there are
// none. Takes `samples` by value because it reorders them.
inline float percentile(std::vector<float> samples, double q) {
    std::erase_if(samples, [](float v) { return !std::isfinite(v); });
    if (samples.empty()) return 0.f;
    auto rank = long(std::lround(q * double(samples.size() - 1)));
    std::nth_element(samples.begin(), samples.begin() + rank, samples.end());
    return samples[size_t(rank)];
}

} // namespace ndfmip
