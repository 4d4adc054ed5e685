// The standard mipmap: every level stores the mean normal, renormalised.

#include "ndfmip/bake.h"

namespace ndfmip {

Bake bakeNaive(const Pyramid& pyramid, const BakeOptions& options) {
    Bake bake;
    bake.method = Method::Naive;
    bake.planes = {
        {"normal", {"n.x", "n.y", "n.z"}, "mean normal renormalised to unit length", true}};
    const int count = int(pyramid.levels.size());
    bake.levels.resize(count);
    for (int k = 0; k < count; ++k) {
        const Image& mean = levelMean(pyramid, k);
        Image normal(mean.width, mean.height, 3);
        const size_t n = mean.texelCount();
#pragma omp parallel for schedule(static)
        for (size_t i = 0; i < n; ++i) {
            normalizeOrFlat(&mean.pixels[3 * i], &normal.pixels[3 * i]);
        }
        bake.levels[k].push_back(std::make_shared<Image>(std::move(normal)));
        if (options.progress) options.progress(k + 1, count);
    }
    return bake;
}

} // namespace ndfmip
