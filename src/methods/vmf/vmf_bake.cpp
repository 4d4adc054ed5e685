// vMF bake (Han et al. Sec. 7): the lobes fitted at every level, stored as one plane per lobe
// slot with (alpha, alpha r mu) (H eq. 33), which filters linearly; the shader recovers mu and
// kappa from the filtered values (Algorithm 1, lines 12-13).
#include <string>

#include "ndfmip/bake.h"
#include "ndfmip/method_parameters.h"
#include "ndfmip/vmf.h"

namespace ndfmip {

Bake bakeVmf(const Pyramid& pyramid, const BakeOptions& options) {
    auto parameter = [&](const char* key) {
        return parameterValue(Method::Vmf, options.parameters, key);
    };
    const int lobes = int(parameter("lobes"));
    const float coherence = float(parameter("coherent")),
                lobeBudget = float(parameter("lobe_budget"));
    VmfFitOptions fit;
    fit.maxIterations = int(parameter("max_iterations"));
    fit.tolerance = parameter("tolerance");
    // Coherent lobes (H eq. 32) take kappa from r_j . mu_j, the exact M-step of the alignment
    // objective: with kappa from |r_j| the pull costs the sharp lobes of the fine levels much
    // of their likelihood.
    fit.coherence = coherence;
    fit.alignedKappa = coherence > 0.f;
    fit.lobeBudget = lobeBudget;
    VmfFitStats stats;
    std::vector<VmfLevel> levels = fitVmfPyramid(pyramid, lobes, fit, &stats);
    const bool colors = options.albedo != nullptr;
    if (colors) fitLobeColors(pyramid, *options.albedo, levels);

    Bake bake;
    bake.method = Method::Vmf;
    bake.parameters["lobes"] = lobes;
    bake.parameters["kappa_max"] = fit.kappaMax;
    bake.parameters["level0_kappa"] = fit.levelZeroKappa;
    bake.parameters["em_max_iterations"] = fit.maxIterations;
    bake.parameters["em_tolerance"] = fit.tolerance;
    bake.parameters["em_mean_iterations"] = stats.meanIterations;
    bake.parameters["em_most_iterations"] = stats.maxIterations;
    bake.parameters["em_not_converged"] = double(stats.notConverged);
    bake.parameters["lobe_budget"] = lobeBudget;
    bake.parameters["mean_lobes"] = stats.texels ? double(stats.lobes) / double(stats.texels) : 0.0;
    bake.parameters["coherence"] = coherence;
    bake.parameters["lobe_mismatch_degrees"] = lobeMismatch(levels);
    const std::string slot =
        coherence > 0.f ? " (coherent slot, H eq. 32)" : " (slot by decreasing alpha)";
    for (int j = 0; j < lobes; ++j)
        bake.planes.push_back(
            {"lobe" + std::to_string(j),
             {"alpha", "alpha r mu.x", "alpha r mu.y", "alpha r mu.z"},
             "vMF lobe " + std::to_string(j) + slot +
                 ": amplitude and amplitude times mean resultant vector (H eq. 33)",
             true});
    if (colors)
        for (int j = 0; j < lobes; ++j)
            bake.planes.push_back(
                {"color" + std::to_string(j),
                 {"alpha c.r", "alpha c.g", "alpha c.b"},
                 "vMF lobe " + std::to_string(j) +
                     ": amplitude times the lobe's mean albedo (H eq. 31); divide by "
                     "the filtered alpha of lobe plane " +
                     std::to_string(j),
                 true});

    const int count = int(levels.size());
    bake.levels.resize(count);
    for (int k = 0; k < count; ++k) {
        const VmfLevel& level = levels[k];
        std::vector<Image> planes;
        for (int j = 0; j < lobes; ++j) planes.emplace_back(level.width, level.height, 4);
        for (int j = 0; colors && j < lobes; ++j) planes.emplace_back(level.width, level.height, 3);
#pragma omp parallel for schedule(static)
        for (int y = 0; y < level.height; ++y)
            for (int x = 0; x < level.width; ++x) {
                const auto texel = level.texel(x, y);
                for (int j = 0; j < lobes && j < int(texel.size()); ++j) {
                    const glm::vec4 p = packLobe(texel[j]);
                    float* out = planes[j].at(x, y);
                    out[0] = p.x, out[1] = p.y, out[2] = p.z, out[3] = p.w;
                    if (colors) {
                        const glm::vec3 c = packLobeColor(texel[j]);
                        float* o = planes[lobes + j].at(x, y);
                        o[0] = c.x, o[1] = c.y, o[2] = c.z;
                    }
                }
            }
        for (Image& plane : planes)
            bake.levels[k].push_back(std::make_shared<const Image>(std::move(plane)));
        if (options.progress) options.progress(k + 1, count);
    }
    return bake;
}

} // namespace ndfmip
