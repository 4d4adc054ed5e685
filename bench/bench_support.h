// Inputs shared by the benchmarks.
#pragma once

#include <cmath>
#include <map>
#include <memory>
#include <random>

#include "ndfmip/image.h"

namespace ndfmip::bench {

// Random unit normals within 45 degrees of +z, fixed seed.
inline const ndfmip::SharedImage& syntheticMap(int size) {
    static std::map<int, ndfmip::SharedImage> cache;
    auto it = cache.find(size);
    if (it != cache.end()) return it->second;
    ndfmip::Image map(size, size, 3);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-0.7f, 0.7f);
    for (size_t i = 0; i < map.texelCount(); ++i) {
        float x = u(rng), y = u(rng), z = 1.f, l = std::sqrt(x * x + y * y + z * z);
        map.pixels[3 * i] = x / l;
        map.pixels[3 * i + 1] = y / l;
        map.pixels[3 * i + 2] = z / l;
    }
    return cache.emplace(size, std::make_shared<const ndfmip::Image>(std::move(map))).first->second;
}

} // namespace ndfmip::bench
