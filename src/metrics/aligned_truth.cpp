// Aligned-footprint ground truth and error statistics (see evaluate.h).
#include <cassert>
#include <cmath>

#include "ndfmip/evaluate.h"
#include "ndfmip/toksvig.h"

namespace ndfmip {

float shadeSpecular(Method method, const float* p, const ShadeContext& ctx) {
    glm::vec3 v(p[0], p[1], p[2]);
    switch (method) {
    case Method::Naive: return naiveSpecular(v, halfVector(ctx), ctx.exponent);
    case Method::Toksvig: return toksvigSpecular(v, halfVector(ctx), ctx.exponent);
    }
    return 0.f;
}

Image shadeLevel(const Bake& bake, int level, const ShadeContext& ctx) {
    const Image& params = *bake.levels[level].front();
    Image out(params.width, params.height, 1);
    const size_t n = params.texelCount();
#pragma omp parallel for schedule(static)
    for (size_t i = 0; i < n; ++i)
        out.pixels[i] = shadeSpecular(bake.method, &params.pixels[i * params.channels], ctx);
    return out;
}

Image groundTruthLevel(const Pyramid& pyramid, int level, const ShadeContext& ctx) {
    const PyramidLevel& l = pyramid.levels[level];
    const Image& base = *pyramid.base;
    const glm::vec3 h = halfVector(ctx);
    Image out(l.width, l.height, 1);
#pragma omp parallel for schedule(dynamic, 1)
    for (int y = 0; y < l.height; ++y) {
        for (int x = 0; x < l.width; ++x) {
            Footprint f = footprint(pyramid, level, x, y);
            double sum = 0;
            for (int by = f.y0; by < f.y1; ++by)
                for (int bx = f.x0; bx < f.x1; ++bx) {
                    const float* n = base.at(bx, by);
                    sum += blinnPhong(n[0] * h.x + n[1] * h.y + n[2] * h.z, ctx.exponent);
                }
            out.at(x, y)[0] = float(sum / double(f.count()));
        }
    }
    return out;
}

ErrorStats compareToTruth(const Image& image, const Image& truth) {
    assert(image.width == truth.width && image.height == truth.height);
    double diff2 = 0, truth2 = 0, sumA = 0, sumB = 0;
    const size_t n = truth.texelCount();
    for (size_t i = 0; i < n; ++i) {
        double a = image.pixels[i * image.channels], b = truth.pixels[i * truth.channels];
        diff2 += (a - b) * (a - b);
        truth2 += b * b;
        sumA += a;
        sumB += b;
    }
    ErrorStats s;
    s.rmse = std::sqrt(diff2 / double(n));
    s.relativeRmse = truth2 > 0 ? std::sqrt(diff2 / truth2) : 0.0;
    s.energyRatio = sumB > 0 ? sumA / sumB : 0.0;
    return s;
}

} // namespace ndfmip
