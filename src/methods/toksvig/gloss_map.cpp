// Free gloss maps (Toksvig eq. 12): a shorter level-0 normal makes Toksvig's factor lower the
// exponent, so a gloss map is baked into the normals' lengths at no cost.
#include <algorithm>
#include <cassert>

#include "ndfmip/toksvig.h"

namespace ndfmip {

float glossLength(float s, float s0) {
    s = std::clamp(s, 0.f, s0);
    return s * s0 / (s * s0 + s0 - s);
}

void applyGlossMap(Image& normals, const Image& gloss, float s0) {
    assert(normals.width == gloss.width && normals.height == gloss.height);
    const size_t n = normals.texelCount();
    for (size_t i = 0; i < n; ++i) {
        float g = std::clamp(gloss.pixels[i * gloss.channels], 1e-4f, 1.f);
        float length = glossLength(g * s0, s0);
        for (int c = 0; c < 3; ++c) normals.pixels[3 * i + c] *= length;
    }
}

} // namespace ndfmip
