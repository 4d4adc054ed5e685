// Specular aliasing from interpolated (Phong) normals, and Toksvig's cure for it (the last
// section of Toksvig, "Mipmapping Normal Maps", "Anti-aliasing Specular Highlights from
// Interpolated Normals"): a normalisation cube map (each direction -> the unit vector in that
// direction) mipmapped WITHOUT renormalisation. Looked up with the interpolated normal at the LOD
// of the normal's change across the pixel, it returns a vector shortened by how much the normal
// varies there; that shortened vector is used as Na (toksvig.h), widening the highlight.
//
// The pieces: a faceted UV sphere with per-vertex normals (the geometry of a faceted-sphere
// scene, docs/SCENES.md), the cube map, and a renderer for such scenes with three methods.
#pragma once

#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "ndfmip/image.h"
#include "ndfmip/render.h"
#include "ndfmip/result.h"
#include "ndfmip/scene.h"

namespace ndfmip {

// ---- Faceted sphere (src/render/faceted_sphere.cpp) -----------------------------------------

constexpr int kMinSphereSegments = 3, kMaxSphereSegments = 64; // longitude
constexpr int kMinSphereRings = 2, kMaxSphereRings = 32;       // latitude

// A UV sphere as triangles: vertices on the sphere at polar angle pi i / rings (from +z) and
// azimuth 2 pi j / segments, each with the sphere's normal there; one triangle per segment at
// each pole, two per quad between.
struct FacetedSphereMesh {
    std::vector<glm::vec3> positions;
    std::vector<glm::vec3> normals; // unit, per vertex
    std::vector<glm::ivec3> triangles;
    std::vector<glm::vec3> faceNormals; // unit, pointing away from the centre
    glm::vec3 center{0.f};
    float radius = 1.f;
};

FacetedSphereMesh facetedSphereMesh(const Geometry& geometry);

struct FacetedHit {
    bool hit = false;
    float t = 0.f;
    glm::vec3 position{0.f};
    int triangle = -1;
    glm::vec3 faceNormal{0.f, 0.f, 1.f};
    glm::vec3 interpolated{0.f, 0.f, 1.f}; // b0 n0 + b1 n1 + b2 n2, not renormalised
};

// The nearest triangle the ray meets (t > 0).
FacetedHit intersectFacetedSphere(const FacetedSphereMesh& mesh, const Ray& ray);

// The interpolated normal (not renormalised) where `ray` meets the plane of `triangle`, with
// barycentrics extrapolated beyond its edges: what a GPU's screen-space derivative of the
// interpolated attribute sees at a neighbouring pixel. Returns `fallback` when the ray runs
// parallel to the plane.
glm::vec3 interpolatedNormalOnPlane(const FacetedSphereMesh& mesh, int triangle, const Ray& ray,
                                    glm::vec3 fallback);

// ---- Normalisation cube map (src/render/normal_cube_map.cpp) ---------------------------------

// Faces in OpenGL order: +x, -x, +y, -y, +z, -z.
struct CubeLevel {
    int size = 0;                  // face side in texels
    std::vector<glm::vec3> texels; // 6 faces of size x size, face-major, rows top to bottom
    const glm::vec3& at(int face, int x, int y) const {
        return texels[(size_t(face) * size + y) * size + x];
    }
};

struct NormalCubeMap {
    std::vector<CubeLevel> levels; // level 0 first, down to 1 x 1 faces
};

constexpr int kNormalCubeMapSize = 128;

// Level 0: the unit direction through each texel's centre. Level k+1: each texel the mean of
// its 2 x 2 children weighted by their solid angles, NOT renormalised, so a coarse texel holds
// the mean unit vector over its solid angle (up to level 0's midpoint rule). A GPU's box filter
// weighs the four children equally, which shortens texels near a face's corners a little less.
// `size` must be a power of two >= 1.
NormalCubeMap buildNormalCubeMap(int size);

// The direction through face coordinates (a, b) in [-1, 1]^2 (a to the right, b down), and back:
// the face whose axis has the largest |component| (ties to the earlier axis; the zero vector to
// +Z's centre) and the coordinates of `d` on it. One source with the GPU's and environment.h's
// double versions: shaders/render/cube_faces.glsl.
glm::vec3 cubeFaceDirection(int face, float a, float b);
void cubeFaceCoordinates(glm::vec3 d, int& face, float& a, float& b);

// Trilinear lookup in direction `d` (any length) at `lod` (clamped to the levels). Edges are
// seamless: a bilinear tap that falls off its face reads the texel of the neighbouring face that
// contains the tap's direction (the face's plane extended), as seamless cube filtering does.
glm::vec3 sampleNormalCubeMap(const NormalCubeMap& map, glm::vec3 d, float lod);

// A GPU's cube-map LOD for a lookup direction `n` whose neighbours one pixel right and one pixel
// down are `nx` and `ny`: the three projected onto n's face, the footprint's longer axis in
// level-0 texels rho, lod = log2(rho) (0 when rho <= 1).
float normalCubeMapLod(const NormalCubeMap& map, glm::vec3 n, glm::vec3 nx, glm::vec3 ny);

// ---- Rendering a faceted-sphere scene (src/render/interpolated_render.cpp) -------------------

// The methods for interpolated normals. Ground truth: options.spp stratified samples per pixel,
// each shading the renormalised interpolated normal of the triangle it hits (shadeNormal).
constexpr const char* kRenormalized = "renormalized";      // the same, one shade per pixel sample
constexpr const char* kCubemapToksvig = "cubemap-toksvig"; // the cube map's shortened normal as Na
std::string interpolatedMethodNames(); // "groundtruth, renormalized, cubemap-toksvig"

// The cube map's LOD bias that matches the pixel's spread of normals. Across a pixel (a box) the
// normal sweeps rho level-0 texels, a spread of variance rho^2/12 per axis; a trilinear lookup
// at level L reads box texels of width w = 2^L blended by a tent of half-width w, variance
// w^2/12 + w^2/6 = w^2/4. Equal variances give w = rho/sqrt(3): L = log2(rho) - log2(sqrt(3)).
// (Measured on the far-sphere scene, docs/RENDERING.md: -0.79 beats 0, -0.5 and -1 for
// Blinn-Phong.)
constexpr float kVarianceMatchedLodBias = -0.79248125f; // -log2(sqrt(3))

struct InterpolatedOptions {
    int cubeSize = kNormalCubeMapSize;
    float lodBias = kVarianceMatchedLodBias; // added to log2(rho) (normalCubeMapLod)
};

// Renders a faceted-sphere scene (no textures): RGB radiance, 3 channels. Methods shade each of
// the options.spp pixel samples once (1: the pixel centre, as a GPU does); taps, lodBias (the
// cube map has its own, InterpolatedOptions), anisotropy and the truth/exact settings do not
// apply. cubemap-toksvig shades with shadeToksvig (Blinn-Phong: T eq. 6; Beckmann/GGX:
// options.roughnessMapping).
Result<Image> renderInterpolated(const Scene& scene, const std::string& method,
                                 const RenderOptions& options,
                                 const InterpolatedOptions& interpolated = {});

// Flicker beyond the image's true motion: `frames` and `truthFrames` rendered with the same
// sub-pixel shifts (flickerShifts). Per pixel, the standard deviation over the frames of the
// luminance error (frame - truth); their root mean square over the pixels, divided by the truth
// frames' root mean square luminance (as relativeRmse, so the background does not dilute it).
// temporalFlicker (render.h) also counts the change a moving object truly makes at its edges, which
// a far, small object is mostly made of. 0 when the error does not change from frame to frame.
double temporalErrorFlicker(const std::vector<Image>& frames,
                            const std::vector<Image>& truthFrames);

} // namespace ndfmip
