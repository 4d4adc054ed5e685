// How well the lobes of adjacent texels correspond slot by slot (Han et al. 2007, Sec. 7.3):
// hardware filtering of packed lobes (H eq. 33) blends slot j of neighbouring texels, which only
// makes sense where slot j holds lobes pointing alike.
#include <algorithm>
#include <cmath>

#include "ndfmip/vmf.h"

namespace ndfmip {
namespace {

constexpr double kDegreesPerRadian = 180 / 3.14159265358979323846;

struct WeightedSum {
    double angles = 0; // Sum w * angle (degrees)
    double weight = 0; // Sum w
};

void addPair(std::span<const VmfLobe> a, std::span<const VmfLobe> b, WeightedSum& sum) {
    const size_t slots = std::min(a.size(), b.size());
    for (size_t j = 0; j < slots; ++j) {
        const double w = std::min(a[j].alpha, b[j].alpha);
        if (!(w > 0)) continue;
        // 2 asin(chord / 2): accurate at small angles, where acos of the dot product is not.
        glm::dvec3 u = glm::normalize(glm::dvec3(a[j].mu)), v = glm::normalize(glm::dvec3(b[j].mu));
        double angle = 2 * std::asin(std::min(1.0, glm::length(u - v) / 2));
        sum.angles += w * angle * kDegreesPerRadian;
        sum.weight += w;
    }
}

} // namespace

double lobeMismatch(const std::vector<VmfLevel>& levels, int firstLevel) {
    WeightedSum total;
    for (size_t k = size_t(std::max(firstLevel, 0)); k < levels.size(); ++k) {
        const VmfLevel& level = levels[k];
        // Per row, then the rows in order: the same sum whatever the thread count.
        std::vector<WeightedSum> rows(size_t(level.height));
#pragma omp parallel for schedule(static)
        for (int y = 0; y < level.height; ++y)
            for (int x = 0; x < level.width; ++x) {
                if (x + 1 < level.width) addPair(level.texel(x, y), level.texel(x + 1, y), rows[y]);
                if (y + 1 < level.height)
                    addPair(level.texel(x, y), level.texel(x, y + 1), rows[y]);
            }
        for (const WeightedSum& row : rows) {
            total.angles += row.angles;
            total.weight += row.weight;
        }
    }
    return total.weight > 0 ? total.angles / total.weight : 0.0;
}

} // namespace ndfmip
