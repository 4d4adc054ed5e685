// Rendering a faceted-sphere scene (interpolated.h): the supersampled truth of its interpolated
// normals, the renormalised normal shaded once per sample, and Toksvig's cube-map lookup.
// Shading happens in world space (every shade function reads only dot products).
#include <algorithm>
#include <atomic>
#include <cmath>

#include "core/splitmix.h"
#include "ndfmip/brdf.h"
#include "ndfmip/interpolated.h"
#include "ndfmip/method_shading.h"

namespace ndfmip {

namespace {

enum class InterpolatedMethod { Truth, Renormalized, CubemapToksvig };

struct InterpolatedContext {
    const Scene* scene = nullptr;
    const RenderOptions* options = nullptr;
    CameraFrame camera;
    FacetedSphereMesh mesh;
    NormalCubeMap cube; // CubemapToksvig only
    float lodBias = kVarianceMatchedLodBias;
    InterpolatedMethod method = InterpolatedMethod::Truth;
};

// Towards the light and its irradiance at p (point lights fall off as 1/d^2, as in render()).
void lightAt(const Light& light, glm::vec3 p, glm::vec3& direction, glm::vec3& irradiance) {
    if (light.type == LightType::Directional) {
        direction = light.direction;
        irradiance = light.color;
        return;
    }
    const glm::vec3 d = light.position - p;
    const float d2 = glm::dot(d, d);
    direction = d2 > 0.f ? d / std::sqrt(d2) : glm::vec3(0.f, 0.f, 1.f);
    irradiance = d2 > 0.f ? light.color / d2 : glm::vec3(0.f);
}

glm::vec3 shadeSample(const InterpolatedContext& ctx, float px, float py) {
    const Scene& scene = *ctx.scene;
    const Ray ray = cameraRay(ctx.camera, px, py);
    const FacetedHit hit = intersectFacetedSphere(ctx.mesh, ray);
    if (!hit.hit) return scene.background;
    const glm::vec3 view = -ray.direction;
    if (glm::dot(view, hit.faceNormal) <= 0.f) return glm::vec3(0.f); // inside the sphere
    // What the lookup shades with: the renormalised normal, or the cube map's shortened one at
    // the LOD of the interpolated normal's change to the neighbouring pixels.
    glm::vec3 normal = glm::normalize(hit.interpolated);
    if (ctx.method == InterpolatedMethod::CubemapToksvig) {
        const glm::vec3 nx = interpolatedNormalOnPlane(
            ctx.mesh, hit.triangle, cameraRay(ctx.camera, px + 1.f, py), hit.interpolated);
        const glm::vec3 ny = interpolatedNormalOnPlane(
            ctx.mesh, hit.triangle, cameraRay(ctx.camera, px, py + 1.f), hit.interpolated);
        normal =
            sampleNormalCubeMap(ctx.cube, hit.interpolated,
                                normalCubeMapLod(ctx.cube, hit.interpolated, nx, ny) + ctx.lodBias);
    }
    const Material& m = scene.material;
    glm::vec3 radiance(0.f);
    for (const Light& light : scene.lights) {
        glm::vec3 l, irradiance;
        lightAt(light, hit.position, l, irradiance);
        if (glm::dot(l, hit.faceNormal) <= 0.f) continue; // behind the facet
        if (ctx.method == InterpolatedMethod::CubemapToksvig)
            radiance += irradiance * shadeToksvig(m, m.albedo, normal, l, view,
                                                  ctx.options->roughnessMapping,
                                                  ctx.options->varianceScale);
        else
            radiance += irradiance * shadeNormal(m, m.albedo, normal, l, glm::normalize(l + view));
    }
    return radiance;
}

} // namespace

std::string interpolatedMethodNames() {
    return std::string(kGroundTruth) + ", " + kRenormalized + ", " + kCubemapToksvig;
}

Result<Image> renderInterpolated(const Scene& scene, const std::string& method,
                                 const RenderOptions& options,
                                 const InterpolatedOptions& interpolated) {
    const int cubeSize = interpolated.cubeSize;
    if (scene.geometry.type != GeometryType::FacetedSphere)
        return Error{"render: " + method + " needs a faceted-sphere scene"};
    const Geometry& g = scene.geometry;
    if (g.segments < kMinSphereSegments || g.segments > kMaxSphereSegments ||
        g.rings < kMinSphereRings || g.rings > kMaxSphereRings || !(g.radius > 0.f))
        return Error{"render: a faceted sphere needs " + std::to_string(kMinSphereSegments) +
                     " .. " + std::to_string(kMaxSphereSegments) + " segments, " +
                     std::to_string(kMinSphereRings) + " .. " + std::to_string(kMaxSphereRings) +
                     " rings and a positive radius"};
    if (cubeSize < 1 || cubeSize > 4096 || (cubeSize & (cubeSize - 1)) != 0)
        return Error{"render: the normal cube map's size must be a power of two in 1 .. 4096"};
    if (options.spp < 1 || options.spp > (1 << 20))
        return Error{"render: spp must be in 1 .. 1048576, got " + std::to_string(options.spp)};
    if (scene.camera.width < 1 || scene.camera.height < 1)
        return Error{"render: the camera's image is empty"};

    InterpolatedContext ctx;
    ctx.scene = &scene;
    ctx.options = &options;
    ctx.camera = cameraFrame(scene.camera);
    ctx.mesh = facetedSphereMesh(g);
    if (method == kGroundTruth)
        ctx.method = InterpolatedMethod::Truth;
    else if (method == kRenormalized)
        ctx.method = InterpolatedMethod::Renormalized;
    else if (method == kCubemapToksvig)
        ctx.method = InterpolatedMethod::CubemapToksvig;
    else
        return Error{"render: unknown method '" + method +
                     "' for a faceted-sphere scene (expected " + interpolatedMethodNames() + ")"};
    if (!std::isfinite(interpolated.lodBias) || std::abs(interpolated.lodBias) > 16.f)
        return Error{"render: the cube map's LOD bias must be finite and within +-16"};
    ctx.lodBias = interpolated.lodBias;
    if (ctx.method == InterpolatedMethod::CubemapToksvig) ctx.cube = buildNormalCubeMap(cubeSize);

    // spp samples as a gx x gy grid of jittered strata, gx the largest divisor of spp <= sqrt(spp).
    int gx = 1;
    for (int d = 1; d * d <= options.spp; ++d)
        if (options.spp % d == 0) gx = d;
    const int gy = options.spp / gx;
    const Camera& camera = scene.camera;
    Image out(camera.width, camera.height, 3);
    std::atomic<int> rowsDone{0};
#pragma omp parallel for schedule(dynamic, 1)
    for (int y = 0; y < camera.height; ++y) {
        for (int x = 0; x < camera.width; ++x) {
            SplitMix64 random{options.seed * 0x2545F4914F6CDD1Dull +
                              uint64_t(y) * uint64_t(camera.width) + uint64_t(x)};
            glm::vec3 sum(0.f);
            for (int sy = 0; sy < gy; ++sy)
                for (int sx = 0; sx < gx; ++sx) {
                    float jx = 0.5f, jy = 0.5f;
                    if (options.spp > 1) {
                        jx = (float(sx) + random.uniform()) / float(gx);
                        jy = (float(sy) + random.uniform()) / float(gy);
                    }
                    sum += shadeSample(ctx, float(x) + jx + options.pixelShift.x,
                                       float(y) + jy + options.pixelShift.y);
                }
            const glm::vec3 mean = sum / float(options.spp);
            float* p = out.at(x, y);
            p[0] = mean.x, p[1] = mean.y, p[2] = mean.z;
        }
        const int done = ++rowsDone;
        if (options.progress) {
#pragma omp critical(ndfmip_render_progress)
            options.progress(done, camera.height);
        }
    }
    return out;
}

double temporalErrorFlicker(const std::vector<Image>& frames,
                            const std::vector<Image>& truthFrames) {
    if (frames.size() < 2 || frames.size() != truthFrames.size()) return 0.0;
    for (size_t f = 0; f < frames.size(); ++f)
        if (frames[f].texelCount() != frames.front().texelCount() ||
            truthFrames[f].texelCount() != frames.front().texelCount())
            return 0.0;
    auto luminance = [](const Image& image, size_t i) {
        const float* p = &image.pixels[i * size_t(image.channels)];
        return image.channels < 3 ? double(p[0]) : 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
    };
    const size_t n = frames.front().texelCount();
    const double count = double(frames.size());
    double variance = 0.0, truthSquare = 0.0;
    for (size_t i = 0; i < n; ++i) {
        double mean = 0.0, square = 0.0;
        for (size_t f = 0; f < frames.size(); ++f) {
            const double e = luminance(frames[f], i) - luminance(truthFrames[f], i);
            mean += e / count;
            square += e * e / count;
            const double t = luminance(truthFrames[f], i);
            truthSquare += t * t;
        }
        variance += std::max(0.0, square - mean * mean);
    }
    truthSquare /= count;
    return truthSquare > 0.0 ? std::sqrt(variance / truthSquare) : 0.0;
}

} // namespace ndfmip
