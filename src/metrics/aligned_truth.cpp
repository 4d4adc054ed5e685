// Aligned-footprint ground truth and error statistics (see evaluate.h).
#include <algorithm>
#include <cassert>
#include <cmath>

#include "methods/method_unit.h"
#include "ndfmip/evaluate.h"
#include "render/texture_sampling.h"

namespace ndfmip {

// Each texel's linear planes shaded by the method's own shader, lobe alone (no cosine, as the
// truth below has none), for a Blinn-Phong material of the context's exponent.
Image shadeLevel(const Bake& bake, int level, const ShadeContext& ctx) {
    const std::vector<SharedImage>& planes = bake.levels[level];
    const Image& first = *planes.front();
    Image out(first.width, first.height, 1);
    const glm::vec3 h = halfVector(ctx);
    const MethodShader* shader = findShader(methodName(bake.method));
    assert(shader);
    Material m;
    m.brdf = Brdf::BlinnPhong;
    m.exponent = ctx.exponent;
    m.albedo = glm::vec3(0.f);
    m.specular = glm::vec3(1.f);
    RenderTextures textures;
    textures.bake = bake;
    ShaderSetup setup;
    if (!shader->prepare(m, textures, RenderOptions{}, setup)) return out;
    const size_t n = first.texelCount();
#pragma omp parallel for schedule(static)
    for (size_t i = 0; i < n; ++i) {
        float params[kMaxFilteredChannels];
        int offset = 0;
        for (size_t p = 0; p < planes.size(); ++p) {
            if (!bake.planes[p].linear) continue;
            const int c = planes[p]->channels;
            std::copy_n(&planes[p]->pixels[size_t(c) * i], c, params + offset);
            offset += c;
        }
        out.pixels[i] = shader->lobe(setup, m, params, h);
    }
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
    return compareToTruth(std::vector<Image>{image}, std::vector<Image>{truth});
}

ErrorStats compareToTruth(const std::vector<Image>& images, const std::vector<Image>& truths) {
    assert(images.size() == truths.size());
    double diff2 = 0, truth2 = 0, sumA = 0, sumB = 0;
    size_t count = 0;
    for (size_t k = 0; k < images.size(); ++k) {
        const Image &image = images[k], &truth = truths[k];
        assert(image.width == truth.width && image.height == truth.height);
        const size_t n = truth.texelCount();
        for (size_t i = 0; i < n; ++i) {
            double a = image.pixels[i * image.channels], b = truth.pixels[i * truth.channels];
            diff2 += (a - b) * (a - b);
            truth2 += b * b;
            sumA += a;
            sumB += b;
        }
        count += n;
    }
    ErrorStats s;
    s.rmse = count ? std::sqrt(diff2 / double(count)) : 0.0;
    s.relativeRmse = truth2 > 0 ? std::sqrt(diff2 / truth2) : 0.0;
    s.energyRatio = sumB > 0 ? sumA / sumB : 0.0;
    return s;
}

} // namespace ndfmip
