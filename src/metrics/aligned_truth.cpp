// Aligned-footprint ground truth and error statistics (see evaluate.h).
#include <cassert>
#include <algorithm>
#include <cmath>

#include "ndfmip/evaluate.h"
#include "ndfmip/method_shading.h"
#include "ndfmip/sh_brdf.h"
#include "ndfmip/spherical_harmonics.h"
#include "ndfmip/toksvig.h"
#include "ndfmip/vmf.h"

namespace ndfmip {

namespace {

// The SH lobe alone (no cosine), as the truth below has none: Sum A_l g_lm Y_lm(h).
float shSpecular(const float* g, const std::vector<double>& A, int order, glm::vec3 h) {
    std::vector<double> y = evaluateSh(glm::dvec3(h), order);
    double sum = 0.0;
    for (int l = 0; l <= order; ++l)
        for (int m = -l; m <= l; ++m) sum += A[l] * g[shIndex(l, m)] * y[shIndex(l, m)];
    return float(std::max(0.0, sum));
}

} // namespace

Image shadeLevel(const Bake& bake, int level, const ShadeContext& ctx) {
    const std::vector<SharedImage>& planes = bake.levels[level];
    const Image& first = *planes.front();
    Image out(first.width, first.height, 1);
    const size_t n = first.texelCount();
    const glm::vec3 h = halfVector(ctx);
    if (bake.method == Method::Sh) {
        const int order = bakeShOrder(bake);
        const std::vector<double> A = blinnPhongCoefficients(ctx.exponent, order);
#pragma omp parallel for schedule(static)
        for (size_t i = 0; i < n; ++i) {
            std::vector<float> g;
            for (const SharedImage& p : planes) g.insert(g.end(), &p->pixels[4 * i], &p->pixels[4 * i + 4]);
            out.pixels[i] = shSpecular(g.data(), A, order, h);
        }
        return out;
    }
    if (bake.method == Method::Vmf) {
        // The lobe alone: shadeVmf's specular term without its cosine, eq. 29 per lobe.
        Material m;
        m.brdf = Brdf::BlinnPhong;
        m.exponent = ctx.exponent;
        m.albedo = glm::vec3(0.f);
        m.specular = glm::vec3(1.f);
        const int lobes = bakeVmfLobes(bake);
#pragma omp parallel for schedule(static)
        for (size_t i = 0; i < n; ++i) {
            std::vector<float> p;
            for (const SharedImage& plane : planes) p.insert(p.end(), &plane->pixels[4 * i], &plane->pixels[4 * i + 4]);
            float sum = 0.f;
            for (int j = 0; j < lobes; ++j) {
                const VmfLobe lobe = unpackLobe(glm::vec4(p[4 * j], p[4 * j + 1], p[4 * j + 2], p[4 * j + 3]));
                if (!(lobe.alpha > 0.f)) continue;
                const float s = lobe.kappa * ctx.exponent / (lobe.kappa + ctx.exponent);
                sum += lobe.alpha * blinnPhong(glm::dot(lobe.mu, h), s);
            }
            out.pixels[i] = sum;
        }
        return out;
    }
    if (bake.method == Method::Lean) { // the lobe alone, leanLobe
        Material m;
        m.brdf = Brdf::BlinnPhong;
        m.exponent = ctx.exponent;
#pragma omp parallel for schedule(static)
        for (size_t i = 0; i < n; ++i) {
            float p[5];
            std::copy_n(&first.pixels[4 * i], 4, p);
            p[4] = planes[1]->pixels[i];
            out.pixels[i] = leanLobe(m, p, h);
        }
        return out;
    }
#pragma omp parallel for schedule(static)
    for (size_t i = 0; i < n; ++i) {
        const float* p = &first.pixels[i * first.channels];
        const glm::vec3 v(p[0], p[1], p[2]);
        out.pixels[i] = bake.method == Method::Naive ? naiveSpecular(v, h, ctx.exponent)
                                                     : toksvigSpecular(v, h, ctx.exponent);
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
