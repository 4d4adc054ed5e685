// Importance sampling of an environment's radiance (environment_lighting.h): a piecewise-constant
// density over texels, marginal over rows and conditional over columns (Pharr et al., PBRT 3rd
// ed., sec. 13.6.7 and 14.2.4), with directions uniform in solid angle within the chosen texel so
// that the density per steradian is exactly the texel's weight over the total.
#include <algorithm>
#include <cmath>

#include "ndfmip/environment_lighting.h"

namespace ndfmip {

namespace {

// Index i with cdf[i] <= u < cdf[i + 1], skipping empty intervals; cdf runs 0 ... 1.
int findInterval(const double* cdf, int count, double u) {
    const double* end = cdf + count + 1;
    int i = int(std::upper_bound(cdf, end, u) - cdf) - 1;
    i = std::clamp(i, 0, count - 1);
    while (i > 0 && !(cdf[i + 1] > cdf[i])) --i; // u landed at the top of trailing empty cells
    while (i < count - 1 && !(cdf[i + 1] > cdf[i])) ++i;
    return i;
}

// Where u falls within [lo, hi), kept strictly inside so the point stays in its texel.
double within(double u, double lo, double hi) {
    const double t = hi > lo ? (u - lo) / (hi - lo) : 0.5;
    return std::clamp(t, 1e-7, 1. - 1e-7);
}

// The texel that unit direction d (environment frame, as stored in the file) falls in.
glm::ivec2 texelOf(int width, int height, glm::dvec3 d) {
    const glm::dvec2 uv = equirectCoordinates(d);
    return {std::clamp(int(uv.x * width), 0, width - 1),
            std::clamp(int(uv.y * height), 0, height - 1)};
}

} // namespace

EnvironmentSampler makeEnvironmentSampler(const Environment& env) {
    const Image& map = env.radiance;
    EnvironmentSampler s;
    s.width = map.width;
    s.height = map.height;
    s.rotation = env.rotation;
    s.weight.resize(size_t(map.width) * size_t(map.height));
    double sum = 0.;
    for (int y = 0; y < map.height; ++y)
        for (int x = 0; x < map.width; ++x) {
            const float* t = map.at(x, y);
            const double w = std::max(rec709Luminance(glm::dvec3(t[0], t[1], t[2])), 0.);
            s.weight[size_t(y) * size_t(map.width) + size_t(x)] = float(w);
            sum += w;
        }
    if (!(sum > 0.)) std::fill(s.weight.begin(), s.weight.end(), 1.f); // black: uniform
    s.columnCdf.assign(size_t(map.height) * size_t(map.width + 1), 0.);
    s.rowCdf.assign(size_t(map.height) + 1, 0.);
    for (int y = 0; y < map.height; ++y) {
        double* cdf = &s.columnCdf[size_t(y) * size_t(map.width + 1)];
        for (int x = 0; x < map.width; ++x)
            cdf[x + 1] = cdf[x] + double(s.weight[size_t(y) * size_t(map.width) + size_t(x)]);
        const double rowSum = cdf[map.width];
        for (int x = 1; x <= map.width; ++x)
            cdf[x] = rowSum > 0. ? cdf[x] / rowSum : double(x) / map.width;
        s.rowCdf[size_t(y) + 1] =
            s.rowCdf[size_t(y)] + rowSum * equirectTexelSolidAngle(map.width, map.height, y);
    }
    s.total = s.rowCdf.back();
    for (double& c : s.rowCdf) c /= s.total;
    s.rowCdf.back() = 1.;
    return s;
}

double environmentPdf(const EnvironmentSampler& s, glm::dvec3 d) {
    const glm::ivec2 t = texelOf(s.width, s.height, rotateAboutY(d, -s.rotation));
    return double(s.weight[size_t(t.y) * size_t(s.width) + size_t(t.x)]) / s.total;
}

EnvironmentSample sampleEnvironment(const EnvironmentSampler& s, double u1, double u2) {
    const int y = findInterval(s.rowCdf.data(), s.height, u1);
    const double* cdf = &s.columnCdf[size_t(y) * size_t(s.width + 1)];
    const int x = findInterval(cdf, s.width, u2);
    // Uniform in solid angle inside the texel: cos(theta) (theta from +Y) uniform over the row,
    // phi uniform over the column.
    const double fy = within(u1, s.rowCdf[size_t(y)], s.rowCdf[size_t(y) + 1]);
    const double fx = within(u2, cdf[x], cdf[x + 1]);
    const double c0 = std::cos(M_PI * y / s.height), c1 = std::cos(M_PI * (y + 1) / s.height);
    const double cosTheta = c0 + (c1 - c0) * fy;
    const double sinTheta = std::sqrt(std::max(0., 1. - cosTheta * cosTheta));
    const double phi = 2. * M_PI * ((x + fx) / s.width - 0.5);
    const glm::dvec3 stored(-sinTheta * std::sin(phi), cosTheta, sinTheta * std::cos(phi));
    EnvironmentSample sample;
    sample.direction = rotateAboutY(stored, s.rotation);
    sample.pdf = double(s.weight[size_t(y) * size_t(s.width) + size_t(x)]) / s.total;
    return sample;
}

EnvironmentLighting makeEnvironmentLighting(Environment environment) {
    EnvironmentLighting lighting;
    lighting.sampler = makeEnvironmentSampler(environment);
    lighting.environment = std::move(environment);
    return lighting;
}

glm::vec3 environmentRadiance(const Environment& env, glm::dvec3 d) {
    const Image& map = env.radiance;
    const glm::ivec2 t = texelOf(map.width, map.height, rotateAboutY(d, -env.rotation));
    const float* texel = map.at(t.x, t.y);
    return {texel[0], texel[1], texel[2]};
}

} // namespace ndfmip
