// Toksvig's normalisation cube map mipmapped without renormalisation (interpolated.h): its
// coarse texels are shorter than unit by how much the directions they average spread.
#include <cassert>
#include <cmath>

#include <glm/glm.hpp>

#include "ndfmip/glsl.h"
#include "ndfmip/interpolated.h"

namespace ndfmip {
namespace glsl_detail {

using glm::abs;
using glm::log2;

// cube_faces.glsl: OpenGL's cube face table and its inverse, in float.
struct CubeFaces : ShaderLibrary {
// clang-format off
#include "render/cube_faces.glsl"
    // clang-format on
};

// normal_cube_lod.glsl over a map of level-0 face side `size`: the data member stands in for the
// GPU's uniform of the same name.
struct NormalCubeLod : CubeFaces {
    explicit NormalCubeLod(int size) : ndfmipNormalCubeSize(size) {}
    int ndfmipNormalCubeSize;
// clang-format off
#include "render/normal_cube_lod.glsl"
    // clang-format on
};

} // namespace glsl_detail

glm::vec3 cubeFaceDirection(int face, float a, float b) {
    return glsl_detail::CubeFaces().ndfmipCubeFaceDirection(face, glm::vec2(a, b));
}

void cubeFaceCoordinates(glm::vec3 d, int& face, float& a, float& b) {
    const auto p = glsl_detail::CubeFaces().ndfmipCubeFacePoint(d);
    face = p.face, a = p.ab.x, b = p.ab.y;
}

namespace {

// The solid angle of the face rectangle [a0, a1] x [b0, b1] seen from the cube's centre:
// the area of a unit-distance rectangle's projection, by the antiderivative
// atan(ab/sqrt(1+a^2+b^2)).
double faceSolidAngle(double a0, double a1, double b0, double b1) {
    auto corner = [](double a, double b) {
        return std::atan2(a * b, std::sqrt(1.0 + a * a + b * b));
    };
    return corner(a1, b1) - corner(a0, b1) - corner(a1, b0) + corner(a0, b0);
}

// Face coordinate of texel edge `i` on a face of `size` texels.
float texelEdge(int i, int size) {
    return 2.f * float(i) / float(size) - 1.f;
}

// The texel of `level` nearest to direction d (any face).
const glm::vec3& texelAt(const CubeLevel& level, glm::vec3 d) {
    int face;
    float a, b;
    cubeFaceCoordinates(d, face, a, b);
    const int n = level.size;
    const int x = glm::clamp(int(std::floor((a + 1.f) * 0.5f * float(n))), 0, n - 1);
    const int y = glm::clamp(int(std::floor((b + 1.f) * 0.5f * float(n))), 0, n - 1);
    return level.at(face, x, y);
}

// Texel (x, y) of `face`, where x or y may lie one texel off the face: then the texel of the
// neighbouring face that holds the direction through the off-face texel's centre.
glm::vec3 seamlessTexel(const CubeLevel& level, int face, int x, int y) {
    const int n = level.size;
    if (x >= 0 && x < n && y >= 0 && y < n) return level.at(face, x, y);
    const float a = texelEdge(x, n) + 1.f / float(n), b = texelEdge(y, n) + 1.f / float(n);
    return texelAt(level, cubeFaceDirection(face, a, b));
}

glm::vec3 bilinear(const CubeLevel& level, int face, float a, float b) {
    const float x = (a + 1.f) * 0.5f * float(level.size) - 0.5f,
                y = (b + 1.f) * 0.5f * float(level.size) - 0.5f;
    const int x0 = int(std::floor(x)), y0 = int(std::floor(y));
    const float fx = x - float(x0), fy = y - float(y0);
    return (1.f - fy) * ((1.f - fx) * seamlessTexel(level, face, x0, y0) +
                         fx * seamlessTexel(level, face, x0 + 1, y0)) +
           fy * ((1.f - fx) * seamlessTexel(level, face, x0, y0 + 1) +
                 fx * seamlessTexel(level, face, x0 + 1, y0 + 1));
}

} // namespace

NormalCubeMap buildNormalCubeMap(int size) {
    assert(size >= 1 && (size & (size - 1)) == 0);
    NormalCubeMap map;
    // Level 0: unit directions through texel centres, with each texel's solid angle for the
    // weighted averages below.
    CubeLevel level0;
    level0.size = size;
    level0.texels.resize(size_t(6) * size * size);
    std::vector<double> weight(level0.texels.size());
    for (int face = 0; face < 6; ++face)
        for (int y = 0; y < size; ++y)
            for (int x = 0; x < size; ++x) {
                const float a0 = texelEdge(x, size), a1 = texelEdge(x + 1, size);
                const float b0 = texelEdge(y, size), b1 = texelEdge(y + 1, size);
                const size_t i = (size_t(face) * size + y) * size + x;
                level0.texels[i] =
                    glm::normalize(cubeFaceDirection(face, 0.5f * (a0 + a1), 0.5f * (b0 + b1)));
                weight[i] = faceSolidAngle(a0, a1, b0, b1);
            }
    map.levels.push_back(std::move(level0));
    // Coarser levels: solid-angle-weighted means of 2 x 2 children, never renormalised.
    while (map.levels.back().size > 1) {
        const CubeLevel& fine = map.levels.back();
        CubeLevel coarse;
        coarse.size = fine.size / 2;
        coarse.texels.resize(size_t(6) * coarse.size * coarse.size);
        std::vector<double> coarseWeight(coarse.texels.size());
        for (int face = 0; face < 6; ++face)
            for (int y = 0; y < coarse.size; ++y)
                for (int x = 0; x < coarse.size; ++x) {
                    glm::dvec3 sum(0.0);
                    double total = 0.0;
                    for (int j = 0; j < 2; ++j)
                        for (int i = 0; i < 2; ++i) {
                            const size_t f =
                                (size_t(face) * fine.size + 2 * y + j) * fine.size + 2 * x + i;
                            sum += weight[f] * glm::dvec3(fine.texels[f]);
                            total += weight[f];
                        }
                    const size_t c = (size_t(face) * coarse.size + y) * coarse.size + x;
                    coarse.texels[c] = glm::vec3(sum / total);
                    coarseWeight[c] = total;
                }
        weight = std::move(coarseWeight);
        map.levels.push_back(std::move(coarse));
    }
    return map;
}

glm::vec3 sampleNormalCubeMap(const NormalCubeMap& map, glm::vec3 d, float lod) {
    int face;
    float a, b;
    cubeFaceCoordinates(d, face, a, b);
    const float top = float(map.levels.size() - 1);
    const float l = std::isfinite(lod) ? glm::clamp(lod, 0.f, top) : 0.f;
    const int k0 = int(std::floor(l));
    const int k1 = std::min(k0 + 1, int(map.levels.size()) - 1);
    const float f = l - float(k0);
    const glm::vec3 fine = bilinear(map.levels[size_t(k0)], face, a, b);
    if (f <= 0.f || k1 == k0) return fine;
    return (1.f - f) * fine + f * bilinear(map.levels[size_t(k1)], face, a, b);
}

float normalCubeMapLod(const NormalCubeMap& map, glm::vec3 n, glm::vec3 nx, glm::vec3 ny) {
    return glsl_detail::NormalCubeLod(map.levels.front().size).ndfmipNormalCubeLod(n, nx, ny);
}

} // namespace ndfmip
