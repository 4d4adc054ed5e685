// Inputs shared by the benchmarks.
#pragma once

#include <cmath>
#include <map>
#include <memory>
#include <random>

#include <string>

#include "ndfmip/image.h"
#include "ndfmip/normal_map.h"

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

// A real 1024² normal map (the shared Ground010 map, green down) tiled to size x size, or the
// synthetic map where the shared data is absent: block encoders behave on real maps as they do
// not on noise.
inline const ndfmip::SharedImage& realMap(int size) {
    static std::map<int, ndfmip::SharedImage> cache;
    auto it = cache.find(size);
    if (it != cache.end()) return it->second;
    ndfmip::DecodeOptions decode;
    decode.greenDown = true;
    ndfmip::Result<ndfmip::Image> tile = ndfmip::loadNormalMap(
        std::string(NDFMIP_SOURCE_DIR) + "/../shared/data/normalmaps/Ground010_1K_Normal.png",
        decode, nullptr);
    if (!tile) return syntheticMap(size);
    ndfmip::Image map(size, size, 3);
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x)
            for (int c = 0; c < 3; ++c)
                map.at(x, y)[c] = tile->at(x % tile->width, y % tile->height)[c];
    return cache.emplace(size, std::make_shared<const ndfmip::Image>(std::move(map))).first->second;
}

} // namespace ndfmip::bench
