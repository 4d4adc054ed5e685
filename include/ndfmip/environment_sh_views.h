// The paper's sparse set of prepared views (Han et al. 2007, Sec. 8: "to interactively rotate
// the lighting, we precompute a sparse set of rotated lighting coefficients and interpolate the
// shading"). The reparameterised lighting L' of H eq. 36 depends on the view w_o
// (environment_sh_shading.h); one prepared view serves a whole image only approximately
// (docs/ENVIRONMENT.md, "the fixed-view approximation"). Here L' is prepared for a set of views
// spread over the sphere, and the lighting for any other view is the weighted sum of its
// neighbours' coefficients. The shading is linear in L' (H eq. 37, and in each of the sets of the
// MeanNormal and Reflecting cosines), so interpolating the coefficients is interpolating the
// shading.
//
// The set: the points of a geodesic grid on the octahedron, normalised. Frequency f cuts each of
// the octahedron's eight faces (|x| + |y| + |z| = 1) into f^2 triangles; the 4 f^2 + 2 corners are
// the views (f = 1: the six axes; f = 2: 18; 4: 66; 8: 258). Why this grid: the cell of a view is
// found in O(1) through the octahedral map v / (|x| + |y| + |z|), with no search; there are no
// poles (a latitude-longitude grid crowds its views there and needs care at them); nearest
// neighbours are 45 degrees apart at f = 2, 18-27 at f = 4, 8-16 at f = 8 (within a factor 2 of
// uniform); and the counts step finely enough to be a knob.
// The weights: barycentric in the face's flat triangle grid (the octahedral map of the view),
// so they are non-negative, sum to 1, are exactly 1 at a prepared view, and are continuous over
// the sphere (on a shared edge or corner, both faces give the same weights).
//
// L (the radiance's coefficients) does not depend on the view: the set keeps one copy.
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include "ndfmip/environment.h"
#include "ndfmip/environment_sh_shading.h"

namespace ndfmip {

// The views of the grid of frequency f: 4 f^2 + 2.
int shViewCount(int frequency);
// The largest set a render may ask for (f = 16): preparing it costs ~1026 prepareShLighting
// calls without L (docs/BENCHMARKS.md).
constexpr int kMaxShViewFrequency = 16;
constexpr int kMaxShViews = 4 * kMaxShViewFrequency * kMaxShViewFrequency + 2;
// The smallest frequency whose grid has at least `views` views. Preconditions: 1 <= views <=
// kMaxShViews.
int shViewFrequency(int views);

// The grid's views (unit, environment frame), in the set's order. Preconditions: 1 <= frequency
// <= kMaxShViewFrequency.
std::vector<glm::dvec3> shViewDirections(int frequency);

// The grid views that interpolate `view` (any non-zero length) and their weights: 1 to 3 of
// them, each weight > 0, summing to 1 (to rounding); one view of weight exactly 1 when `view` is a
// grid view (to 1e-9 in the octahedral map).
struct ShViewWeights {
    int count = 0;
    int index[3] = {0, 0, 0};
    double weight[3] = {0., 0., 0.};
};
ShViewWeights shViewWeights(int frequency, glm::dvec3 view);

struct ShViewSet {
    int order = 0;
    int frequency = 0;
    SpecularCosine cosine = SpecularCosine::MeanNormal;
    std::vector<glm::dvec3> radiance; // L_lm, once for all views
    // One per grid view, in shViewDirections' order: its view and L' (or L'_k), `radiance` empty.
    std::vector<ShLighting> views;
};

// prepareShLighting's L' for every view of the grid of `frequency`, and its L once. Preconditions:
// 0 <= order <= kMaxShOrder, 1 <= frequency <= kMaxShViewFrequency.
ShViewSet prepareShViewSet(const Environment& env, int order, int frequency,
                           SpecularCosine cosine = SpecularCosine::MeanNormal);

// The lighting for `view` (environment frame, non-zero length): the set's L, and L' (or L'_k)
// the weighted sum of shViewWeights' views. `out` is overwritten (its storage reused, so a
// caller can keep one per thread) and gets a fresh ShLighting::id, so shading never takes it for
// an earlier lighting it rotated.
void interpolateShLighting(const ShViewSet& set, glm::dvec3 view, ShLighting& out);
ShLighting interpolateShLighting(const ShViewSet& set, glm::dvec3 view);

} // namespace ndfmip
