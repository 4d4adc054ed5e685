// The reference renderer (see render.h): rows in parallel, each pixel on its own random
// stream, so the image does not depend on the thread count.
#include <atomic>
#include <cmath>
#include <optional>

#include "ndfmip/method_shading.h"
#include "ndfmip/render.h"
#include "ndfmip/vmf.h"
#include "texture_sampling.h"

namespace ndfmip {

namespace {

// SplitMix64: a tiny, well-mixed generator; one stream per pixel.
struct PixelRandom {
    uint64_t state;
    uint64_t next() {
        uint64_t z = (state += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    float uniform() { return float(next() >> 40) * (1.f / 16777216.f); } // [0, 1)
};

// spp samples as a gx x gy grid with gx the largest divisor of spp not above sqrt(spp).
void strataGrid(int spp, int& gx, int& gy) {
    gx = 1;
    for (int d = 1; d * d <= spp; ++d)
        if (spp % d == 0) gx = d;
    gy = spp / gx;
}

// A method's linear planes, each as a mip chain, and where its channels go in the
// parameter vector handed to the shade function.
struct FilteredPlanes {
    std::vector<MipChain> chains;
    int channels = 0;
};

FilteredPlanes linearPlanes(const Bake& bake) {
    FilteredPlanes f;
    for (size_t p = 0; p < bake.planes.size(); ++p) {
        if (!bake.planes[p].linear) continue;
        MipChain chain;
        for (const auto& level : bake.levels) chain.levels.push_back(level[p].get());
        chain.channels = chain.levels.front()->channels;
        f.channels += chain.channels;
        f.chains.push_back(std::move(chain));
    }
    return f;
}

struct LightSample {
    glm::vec3 direction; // towards the light, world space
    glm::vec3 irradiance;
};

LightSample lightAt(const Light& light, glm::vec3 p) {
    if (light.type == LightType::Directional) return {light.direction, light.color};
    glm::vec3 d = light.position - p;
    float d2 = glm::dot(d, d);
    if (d2 <= 0.f) return {glm::vec3(0.f, 0.f, 1.f), glm::vec3(0.f)};
    return {d / std::sqrt(d2), light.color / d2};
}

glm::vec3 toTangent(const SurfaceHit& hit, glm::vec3 w) {
    return {glm::dot(w, hit.tangent), glm::dot(w, hit.bitangent), glm::dot(w, hit.normal)};
}

struct Context {
    const Scene* scene;
    CameraFrame camera;
    const RenderTextures* textures;
    const RenderOptions* options;
    std::optional<Method> method; // empty: ground truth
    FilteredPlanes planes;
    ShShading sh;            // sh: the material's A_l
    int vmfLobes = 0;        // vmf: J
    bool vmfColors = false;  // vmf: colour planes follow the lobe planes
    MipChain albedo;         // empty without an albedo map
};

glm::vec3 shadeSample(const Context& ctx, float px, float py) {
    const Scene& scene = *ctx.scene;
    const Ray ray = cameraRay(ctx.camera, px, py);
    const SurfaceHit hit = intersect(scene.geometry, ray);
    if (!hit.hit) return scene.background;
    const glm::vec3 view = toTangent(hit, -ray.direction);
    if (view.z <= 0.f) return glm::vec3(0.f); // the back of the surface

    glm::vec3 normal(0.f, 0.f, 1.f);
    float params[kMaxFilteredChannels];
    glm::vec3 albedo = scene.material.albedo;
    glm::vec3 colors[8];
    if (!ctx.method) {
        normal = sampleNormal(*ctx.textures->normals, hit.uv, ctx.options->nearest);
        if (!ctx.albedo.levels.empty()) {
            float a[4] = {0.f, 0.f, 0.f, 0.f};
            if (ctx.options->nearest) {
                const float* t = nearestTexel(*ctx.albedo.levels.front(), hit.uv);
                a[0] = t[0], a[1] = t[1], a[2] = t[2];
            } else {
                accumulateBilinear(*ctx.albedo.levels.front(), hit.uv, 1.f, a);
            }
            albedo *= glm::vec3(a[0], a[1], a[2]);
        }
    } else {
        const UvFootprint footprint = uvFootprint(ctx.camera, hit, px, py);
        int offset = 0;
        for (const MipChain& chain : ctx.planes.chains) {
            sampleFiltered(chain, hit.uv, footprint, ctx.options->anisotropy, params + offset);
            offset += chain.channels;
        }
        if (!ctx.albedo.levels.empty()) {
            float a[4];
            sampleFiltered(ctx.albedo, hit.uv, footprint, ctx.options->anisotropy, a);
            albedo *= glm::vec3(a[0], a[1], a[2]);
        }
        for (int j = 0; ctx.vmfColors && j < ctx.vmfLobes; ++j) {
            const float* c = params + 4 * ctx.vmfLobes + 3 * j;
            colors[j] = unpackLobeColor(glm::vec3(c[0], c[1], c[2]), params[4 * j]);
        }
    }

    glm::vec3 radiance(0.f);
    for (const Light& light : scene.lights) {
        const LightSample ls = lightAt(light, hit.position);
        const glm::vec3 l = toTangent(hit, ls.direction);
        if (l.z <= 0.f) continue; // below the geometric surface
        glm::vec3 r(0.f);
        if (!ctx.method) {
            r = shadeNormal(scene.material, albedo, normal, l, glm::normalize(l + view));
        } else {
            const glm::vec3 p(params[0], params[1], params[2]);
            switch (*ctx.method) {
            case Method::Naive: r = shadeNaive(scene.material, albedo, p, l, view); break;
            case Method::Toksvig:
                r = shadeToksvig(scene.material, albedo, p, l, view, ctx.options->roughnessMapping,
                                 ctx.options->varianceScale);
                break;
            case Method::Sh: r = shadeSh(scene.material, albedo, params, ctx.sh, l, view); break;
            case Method::Vmf:
                r = shadeVmf(scene.material, albedo, params, ctx.vmfLobes, ctx.vmfColors ? colors : nullptr, l, view);
                break;
            }
        }
        radiance += ls.irradiance * r;
    }
    return radiance;
}

} // namespace

Result<Image> render(const Scene& scene, const RenderTextures& textures, const std::string& methodName,
                     const RenderOptions& options) {
    if (!textures.normals || textures.normals->channels != 3 || textures.normals->empty())
        return Error{"render: no normal map (3 channels) to render with"};
    if (options.spp < 1 || options.spp > (1 << 20))
        return Error{"render: spp must be in 1 .. 1048576, got " + std::to_string(options.spp)};
    if (options.anisotropy < 1 || options.anisotropy > 64)
        return Error{"render: anisotropy must be in 1 .. 64, got " + std::to_string(options.anisotropy)};
    if (scene.camera.width < 1 || scene.camera.height < 1)
        return Error{"render: the camera's image is empty"};

    Context ctx{&scene, cameraFrame(scene.camera), &textures, &options, std::nullopt, {}, {}, 0, false, {}};
    if (!textures.albedo.empty()) {
        const Image& a = *textures.albedo.front();
        if (a.width != textures.normals->width || a.height != textures.normals->height || a.channels < 3)
            return Error{"render: the albedo map must be RGB and the normal map's size"};
        for (const SharedImage& level : textures.albedo) ctx.albedo.levels.push_back(level.get());
        ctx.albedo.channels = a.channels;
    }
    if (methodName != kGroundTruth) {
        ctx.method = methodFromString(methodName);
        if (!ctx.method) {
            std::string known = kGroundTruth;
            for (Method m : allMethods()) known += std::string(", ") + ndfmip::methodName(m);
            return Error{"render: unknown method '" + methodName + "' (expected " + known + ")"};
        }
        const Bake& bake = textures.bake;
        if (bake.levels.empty() || bake.method != *ctx.method)
            return Error{"render: no bake of method '" + methodName + "' to render with"};
        const Image& level0 = *bake.levels.front().front();
        if (level0.width != textures.normals->width || level0.height != textures.normals->height)
            return Error{"render: the bake's level 0 is " + std::to_string(level0.width) + "x" +
                         std::to_string(level0.height) + " but the normal map is " +
                         std::to_string(textures.normals->width) + "x" +
                         std::to_string(textures.normals->height)};
        ctx.planes = linearPlanes(bake);
        ctx.vmfLobes = bakeVmfLobes(bake);
        ctx.vmfColors = findPlane(bake.planes, "color0") >= 0;
        if (ctx.vmfLobes > 8) return Error{"render: vmf bakes have at most 8 lobes"};
        if (*ctx.method == Method::Sh) {
            Result<ShShading> sh = shShadingFor(scene.material, bakeShOrder(bake));
            if (!sh) return sh.error();
            ctx.sh = std::move(sh.value());
        }
        if (ctx.planes.channels < 3 || ctx.planes.channels > kMaxFilteredChannels)
            return Error{"render: method '" + methodName + "' has no filterable planes"};
    }

    const Camera& camera = scene.camera;
    Image out(camera.width, camera.height, 3);
    int gx = 1, gy = 1;
    strataGrid(options.spp, gx, gy);
    std::atomic<int> rowsDone{0};

#pragma omp parallel for schedule(dynamic, 1)
    for (int y = 0; y < camera.height; ++y) {
        for (int x = 0; x < camera.width; ++x) {
            PixelRandom random{options.seed * 0x2545F4914F6CDD1Dull + uint64_t(y) * uint64_t(camera.width) +
                               uint64_t(x)};
            glm::vec3 sum(0.f);
            for (int sy = 0; sy < gy; ++sy) {
                for (int sx = 0; sx < gx; ++sx) {
                    float jx = 0.5f, jy = 0.5f;
                    if (options.spp > 1) {
                        jx = (float(sx) + random.uniform()) / float(gx);
                        jy = (float(sy) + random.uniform()) / float(gy);
                    }
                    sum += shadeSample(ctx, float(x) + jx + options.pixelShift.x,
                                       float(y) + jy + options.pixelShift.y);
                }
            }
            float* px = out.at(x, y);
            const glm::vec3 mean = sum / float(options.spp);
            px[0] = mean.x;
            px[1] = mean.y;
            px[2] = mean.z;
        }
        int done = ++rowsDone;
        if (options.progress) {
#pragma omp critical(ndfmip_render_progress)
            options.progress(done, camera.height);
        }
    }
    return out;
}

} // namespace ndfmip
