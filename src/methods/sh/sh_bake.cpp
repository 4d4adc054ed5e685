// Spherical-harmonic NDF bake (Han et al. Sec. 5): at level 0 each texel's NDF is a delta at
// its normal, so g_lm = Y_lm(n) (footnote 6: real SH); the coefficients are linear in the NDF,
// so every coarser level is the plain mean over the covered block (H eq. 14 onward).
// Stored four coefficients per plane, band by band (shIndex order), the last plane padded.
#include <string>

#include "ndfmip/bake.h"
#include "ndfmip/method_parameters.h"
#include "ndfmip/spherical_harmonics.h"

namespace ndfmip {

int shPlaneCount(int order) {
    return (shCount(order) + 3) / 4;
}

Bake bakeSh(const Pyramid& pyramid, const BakeOptions& options) {
    const int order = int(parameterValue(Method::Sh, options.parameters, "order"));
    const int coefficients = shCount(order), planeCount = shPlaneCount(order);
    Bake bake;
    bake.method = Method::Sh;
    bake.parameters["order"] = order;
    for (int p = 0; p < planeCount; ++p) {
        PlaneInfo plane;
        plane.name = "sh" + std::to_string(p);
        for (int c = 0; c < 4; ++c) {
            const int i = 4 * p + c;
            if (i >= coefficients) {
                plane.channels.push_back("unused");
                continue;
            }
            int l = 0;
            while (shIndex(l, l) < i) ++l;
            plane.channels.push_back("g(" + std::to_string(l) + "," +
                                     std::to_string(i - shIndex(l, 0)) + ")");
        }
        plane.description = "NDF spherical-harmonic coefficients g_lm, real orthonormal basis";
        plane.linear = true;
        bake.planes.push_back(std::move(plane));
    }

    const int levelCount = int(pyramid.levels.size());
    bake.levels.resize(levelCount);
    const Image& normals = *pyramid.base;
    std::vector<Image> level0;
    for (int p = 0; p < planeCount; ++p)
        level0.emplace_back(normals.width, normals.height, 4, Image::Uninitialized{});
    const size_t n = normals.texelCount();
#pragma omp parallel
    {
        std::vector<double> y(size_t(planeCount) * 4, 0.0);
#pragma omp for schedule(static)
        for (size_t i = 0; i < n; ++i) {
            const float* t = &normals.pixels[3 * i];
            evaluateSh(glm::dvec3(t[0], t[1], t[2]), order, y.data());
            for (int p = 0; p < planeCount; ++p)
                for (int c = 0; c < 4; ++c) level0[p].pixels[4 * i + c] = float(y[4 * p + c]);
        }
    }
    for (Image& plane : level0)
        bake.levels[0].push_back(std::make_shared<const Image>(std::move(plane)));
    if (options.progress) options.progress(1, levelCount);
    for (int k = 1; k < levelCount; ++k) {
        for (int p = 0; p < planeCount; ++p)
            bake.levels[k].push_back(
                std::make_shared<const Image>(averageToLevel(pyramid, *bake.levels[k - 1][p], k)));
        if (options.progress) options.progress(k + 1, levelCount);
    }
    return bake;
}

} // namespace ndfmip
