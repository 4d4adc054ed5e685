// The box mip chain of an environment on cube faces, and the lookups of Toksvig's log2 sigma
// rule's chain (environment_splitsum.h, whose level 0 is this chain's): "Environment Maps" reads a
// mip chain at lod = log2(2 sigma / theta0) (log2SigmaLevel), which assumes texels of about equal
// solid angle at every level. An equirectangular chain breaks that near the poles, where a coarse
// texel is a whole polar cap; a cube face's texels differ by at most 3^(3/2) ~ 5.2 in solid angle,
// the same at every level.
#pragma once

#include <array>
#include <vector>

#include <glm/glm.hpp>

#include "ndfmip/environment.h"
#include "ndfmip/image.h"

namespace ndfmip {

// Level k holds the six faces (cubeFaceDirection's order and orientation), each
// (size >> k) x (size >> k), RGB, radiance as seen (Environment::rotation applied).
struct CubeMipChain {
    std::vector<std::array<Image, kCubeFaces>> levels;
};

// Level 0: each face texel the mean of 4 x 4 bilinear lookups spread over it in the map
// (area-weighted down to 8 size wide first, so every map texel is read); level k + 1: each texel
// the solid-angle-weighted mean of its 2x2 children (cubeTexelSolidAngle), so every level keeps the
// map's integral over the sphere. Down to 1 x 1 faces. Preconditions: size a power of two >= 1, a
// valid environment.
CubeMipChain buildCubeMipChain(const Environment& env, int size);

// Level 0 of that chain alone: the map as seen on six size-wide faces.
std::array<Image, kCubeFaces> cubeMipChainBase(const Environment& env, int size);

// Bilinear within one level along unit d: texel centres at ((x + 0.5) / n, (y + 0.5) / n) of the
// face, and a neighbour one past a face's edge read from the adjacent face (the texel holding that
// centre's direction on the extended face plane), so lookups are continuous across edges.
glm::vec3 sampleCubeLevel(const std::array<Image, kCubeFaces>& level, glm::dvec3 d);

// Trilinear: lod clamped to [0, levels - 1], levels floor(lod) and floor(lod) + 1 blended.
glm::vec3 sampleCubeMipChain(const CubeMipChain& chain, double lod, glm::dvec3 d);

} // namespace ndfmip
