// The ground truth under an environment where the view fixes every direction but the normal's (an
// orthographic camera over a plane: v and the tangent frame are the same at every point). The
// light reflected at a unit normal n,
//     g(n) = integral over l.z > 0 of L(l) shadeNormal(n, l, h) dl,
// is then a function of n alone. It is estimated once per node of a grid over the sphere of
// normals (the octahedral map, kEnvironmentTruthTableSize nodes per side), with `samples` MIS
// estimates each (estimateEnvironmentRadiance, the sampled truth's own), on first use, and read
// bilinearly. A pixel's truth is g's exact integral over its texels (the renderer's exactPixel,
// as for directional lights), and its noise is the nodes' alone: the footprint's normals are no
// longer sampled, which is where most of a sampled truth's noise comes from when small bright
// lights meet a spread of normals (docs/RENDERING.md).
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

#include <glm/glm.hpp>

#include "ndfmip/environment_lighting.h"
#include "ndfmip/render.h"
#include "ndfmip/scene.h"

namespace ndfmip {

// 256 nodes per side: about 0.7 degrees apart near the pole, where a bilinear read of g under a
// GGX lobe of alpha = 0.2 is within 0.2% of a grid twice as fine (docs/RESULTS.md).
constexpr int kEnvironmentTruthTableSize = 256;

// What fixes a table: the lighting, the material and, in the tangent frame, the view, with the
// frame's map into the environment; the samples per node, the estimator and the seed. A table
// made from a key holds its lighting.
struct EnvironmentTruthKey {
    std::shared_ptr<const EnvironmentLighting> lighting;
    Material material;
    glm::vec3 view{0.f, 0.f, 1.f};
    glm::mat3 toEnvironment{1.f};
    int samples = 1;
    EnvironmentEstimator estimator = EnvironmentEstimator::Mis;
    uint64_t seed = 1;
};

class EnvironmentTruthTable;

// A pixel's weights on the nodes it reads, for its noise: the nodes are independent estimates, so
// the variance of the pixel's weighted sum of them is Sum_i W_i^2 var_i.
struct EnvironmentTruthNoise {
    std::vector<double> weight; // per node, 0 where not read
    std::vector<size_t> read;   // the nodes read
    void add(size_t node, double w);
    // Sum_i W_i^2 var_i of the luminance, then every weight back to 0.
    double take(const EnvironmentTruthTable& table);
};

class EnvironmentTruthTable {
  public:
    explicit EnvironmentTruthTable(const EnvironmentTruthKey& key);

    // g at unit n, bilinear over the four nearest nodes (each estimated on first use, by whichever
    // thread needs it first; the others wait); with `noise`, the nodes' weights times `weight`
    // added to it.
    glm::vec3 radiance(glm::vec3 n, EnvironmentTruthNoise* noise = nullptr,
                       double weight = 1.) const;
    // Node i's variance of its mean's luminance (the estimates' spread over their count;
    // stratification makes it an upper bound, as for the sampled truth's pixels).
    double variance(size_t node) const { return nodes_[node].variance; }

    const EnvironmentTruthKey& key() const { return key_; }
    size_t nodesEstimated() const; // for reports and tests

  private:
    struct Node {
        glm::vec3 radiance{0.f};
        double variance = 0.; // of the mean's luminance
    };
    const Node& node(int x, int y) const;
    void estimate(size_t index, Node& out) const;

    EnvironmentTruthKey key_;
    mutable std::vector<Node> nodes_;
    mutable std::unique_ptr<std::atomic<int>[]> state_; // 0 empty, 1 being estimated, 2 ready
};

// The table for `key`: the one made for an equal key while it is still kept here (the last few,
// so an evaluation's footprints and maps share their nodes), else a new one. The pointer returned
// holds the lighting too; what is kept here does not, so a lighting no longer held elsewhere is
// freed, and its tables leave at the next call.
std::shared_ptr<const EnvironmentTruthTable> environmentTruthTable(const EnvironmentTruthKey& key);

// The octahedral map of unit directions to [-1, 1]^2 (the upper hemisphere inside |x| + |y| <= 1)
// and back.
glm::vec2 octahedralEncode(glm::vec3 n);
glm::vec3 octahedralDecode(glm::vec2 p);

} // namespace ndfmip
