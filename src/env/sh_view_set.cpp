// The sparse set of prepared views of environment_sh_views.h: an octahedral geodesic grid of
// views, each with prepareShLighting's L', and barycentric interpolation between them.
#include <algorithm>
#include <cassert>
#include <cmath>

#include "env/sh_lighting_internal.h"
#include "ndfmip/environment_sh_views.h"

namespace ndfmip {
namespace {

// A grid point: integer coordinates with |X| + |Y| + |Z| = f.
struct GridPoint {
    int x, y, z;
};

// The points in the set's order: X, then Y ascending, then Z positive before negative (one
// point where Z = 0).
std::vector<GridPoint> gridPoints(int f) {
    std::vector<GridPoint> points;
    for (int x = -f; x <= f; ++x)
        for (int y = -(f - std::abs(x)); y <= f - std::abs(x); ++y) {
            const int z = f - std::abs(x) - std::abs(y);
            points.push_back({x, y, z});
            if (z > 0) points.push_back({x, y, -z});
        }
    return points;
}

// The index of grid point (x, y, +-z) in gridPoints' order, counted in closed form: the rows of
// X before x, then the points of row x before y.
int gridIndex(int f, int x, int y, bool negativeZ) {
    // Points of a row X = r with |r| <= f: 2 (2 (f - |r|) + 1) - 2 = 4 (f - |r|) (the two ends,
    // Z = 0, count once), except that f - |r| = 0 gives 1.
    auto rowCount = [f](int r) { return f == std::abs(r) ? 1 : 4 * (f - std::abs(r)); };
    int index = 0;
    for (int r = -f; r < x; ++r) index += rowCount(r);
    const int reach = f - std::abs(x);
    for (int c = -reach; c < y; ++c) index += (reach - std::abs(c) > 0) ? 2 : 1;
    return index + (negativeZ ? 1 : 0);
}

// Within 1e-9 of an integer: that integer (views at grid points get weight exactly 1).
double snapped(double t) {
    const double nearest = std::round(t);
    return std::fabs(t - nearest) < 1e-9 ? nearest : t;
}

// sum_k w_k rows(view_k) over the interpolating views, the first product assigned (weight 1
// copies exactly).
template <class Rows>
void blend(std::vector<glm::dvec3>& out, const ShViewSet& set, const ShViewWeights& w, Rows rows) {
    auto source = [&](int k) -> const std::vector<glm::dvec3>& {
        return rows(set.views[size_t(w.index[k])]);
    };
    const std::vector<glm::dvec3>& first = source(0);
    out.resize(first.size());
    for (size_t i = 0; i < first.size(); ++i) out[i] = w.weight[0] * first[i];
    for (int k = 1; k < w.count; ++k) {
        const std::vector<glm::dvec3>& next = source(k);
        for (size_t i = 0; i < next.size(); ++i) out[i] += w.weight[k] * next[i];
    }
}

} // namespace

int shViewCount(int frequency) {
    return 4 * frequency * frequency + 2;
}

int shViewFrequency(int views) {
    assert(views >= 1 && views <= kMaxShViews);
    int f = 1;
    while (shViewCount(f) < views) ++f;
    return f;
}

std::vector<glm::dvec3> shViewDirections(int frequency) {
    assert(frequency >= 1 && frequency <= kMaxShViewFrequency);
    std::vector<glm::dvec3> directions;
    for (const GridPoint& p : gridPoints(frequency))
        directions.push_back(glm::normalize(glm::dvec3(p.x, p.y, p.z)));
    return directions;
}

ShViewWeights shViewWeights(int f, glm::dvec3 view) {
    assert(f >= 1 && f <= kMaxShViewFrequency);
    const double sum = std::fabs(view.x) + std::fabs(view.y) + std::fabs(view.z);
    assert(sum > 0.);
    // The octahedral map: the view's point on the face of its octant, scaled so the face's grid
    // points are the integers (a, b) with a + b <= f (c = f - a - b along |z|).
    double a = snapped(f * std::fabs(view.x) / sum), b = snapped(f * std::fabs(view.y) / sum);
    b = std::min(b, f - a); // rounding may cross the face's edge c = 0
    const int i0 = std::min(int(std::floor(a)), f), j0 = std::min(int(std::floor(b)), f - i0);
    const double fa = a - i0, fb = b - j0;
    const int sx = view.x < 0. ? -1 : 1, sy = view.y < 0. ? -1 : 1;
    const bool negativeZ = view.z < 0.;
    ShViewWeights w;
    auto add = [&](int i, int j, double weight) {
        if (!(weight > 0.)) return;
        w.index[w.count] = gridIndex(f, sx * i, sy * j, negativeZ && i + j < f);
        w.weight[w.count++] = weight;
    };
    if (i0 + j0 == f) {
        add(i0, j0, 1.);        // a corner of the face's edge c = 0 (then fa = fb = 0)
    } else if (fa + fb <= 1.) { // the cell's lower triangle (i0, j0), (i0 + 1, j0), (i0, j0 + 1)
        add(i0, j0, 1. - fa - fb);
        add(i0 + 1, j0, fa);
        add(i0, j0 + 1, fb);
    } else { // the upper one (i0 + 1, j0 + 1), (i0, j0 + 1), (i0 + 1, j0)
        add(i0 + 1, j0 + 1, fa + fb - 1.);
        add(i0, j0 + 1, 1. - fa);
        add(i0 + 1, j0, 1. - fb);
    }
    return w;
}

ShViewSet prepareShViewSet(const Environment& env, int order, int frequency,
                           SpecularCosine cosine) {
    assert(order >= 0 && order <= kMaxShOrder && frequency >= 1 &&
           frequency <= kMaxShViewFrequency);
    ShViewSet set;
    set.order = order;
    set.frequency = frequency;
    set.cosine = cosine;
    set.radiance = projectEnvironmentSh(env, order).radiance;
    // One view after another, each projection parallel over the map's rows (prepareShLighting's
    // own), so the set does not depend on the thread count either.
    for (glm::dvec3 view : shViewDirections(frequency))
        set.views.push_back(prepareReparameterisedSh(env, order, view, cosine));
    return set;
}

void interpolateShLighting(const ShViewSet& set, glm::dvec3 view, ShLighting& out) {
    assert(glm::length(view) > 0. && !set.views.empty());
    const ShViewWeights w = shViewWeights(set.frequency, view);
    out.id = nextShLightingId();
    out.order = set.order;
    out.view = glm::normalize(view);
    out.cosine = set.cosine;
    out.radiance = set.radiance;
    out.reparameterised.clear();
    for (std::vector<glm::dvec3>& axis : out.reparameterisedAxes) axis.clear();
    for (int k = 0; k < reparameterisedSets(set.cosine); ++k)
        blend(reparameterisedSet(out, k), set, w,
              [k](const ShLighting& prepared) -> const std::vector<glm::dvec3>& {
                  return reparameterisedSet(prepared, k);
              });
}

ShLighting interpolateShLighting(const ShViewSet& set, glm::dvec3 view) {
    ShLighting lighting;
    interpolateShLighting(set, view, lighting);
    return lighting;
}

} // namespace ndfmip
