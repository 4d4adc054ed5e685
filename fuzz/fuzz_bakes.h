// The small bakes the manifest fuzzer reads: one of every method (and vmf with colours) over a
// 5x3 map, written by the library itself, so manifests from the seeds match real files.
#pragma once

#include <cmath>
#include <filesystem>
#include <memory>
#include <string>

#include "ndfmip/bake.h"
#include "ndfmip/io.h"

namespace ndfmip {

// Writes DIR/<name>/ for naive, toksvig, sh (l* = 2), vmf (J = 2, colours); false on failure.
inline bool writeFuzzBakes(const std::filesystem::path& dir) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    const int w = 5, h = 3;
    Image normals(w, h, 3), albedo(w, h, 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float n[3] = {0.3f * std::sin(float(x)), 0.2f * std::cos(float(y + x)), 1.f};
            const float length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
            for (int c = 0; c < 3; ++c) {
                normals.at(x, y)[c] = n[c] / length;
                albedo.at(x, y)[c] = 0.1f * float(c + x);
            }
        }
    const Pyramid pyramid = buildPyramid(std::make_shared<const Image>(normals));
    BakeSource source{.path = "map.png", .sha256 = std::string(64, '0'), .width = w, .height = h};
    struct Case {
        const char* name;
        Method method;
        bool png16;
    };
    for (const Case& c :
         {Case{"naive", Method::Naive, true}, Case{"toksvig", Method::Toksvig, true},
          Case{"sh", Method::Sh, false}, Case{"vmf", Method::Vmf, false}}) {
        BakeOptions options;
        options.parameters["order"] = 2;
        options.parameters["lobes"] = 2;
        if (c.method == Method::Vmf) options.albedo = std::make_shared<const Image>(albedo);
        BakeWriteOptions write;
        write.png16 = c.png16;
        if (!writeBake((dir / c.name).string(), bakeMethod(c.method, pyramid, options), source,
                       write))
            return false;
    }
    return true;
}

} // namespace ndfmip
