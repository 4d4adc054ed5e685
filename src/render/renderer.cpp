// The reference renderer (see render.h): rows in parallel, each pixel on its own random
// stream, so the image does not depend on the thread count.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <optional>

#include "core/splitmix.h"
#include "environment_truth.h"
#include "environment_truth_table.h"
#include "methods/method_unit.h"
#include "ndfmip/environment_lighting.h"
#include "ndfmip/environment_sh_views.h"
#include "ndfmip/glsl.h"
#include "ndfmip/interpolated.h"
#include "ndfmip/render.h"
#include "ndfmip/vmf.h"
#include "texture_sampling.h"

namespace ndfmip {

namespace {

using PixelRandom = SplitMix64; // one stream per pixel

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

// How a pixel is shaded: the truth, the exact reference, or what a method's shader does with
// its filtered planes.
enum class Shader { Truth, Exact, Method };

struct Context {
    const Scene* scene = nullptr;
    CameraFrame camera;
    const RenderTextures* textures = nullptr;
    const RenderOptions* options = nullptr;
    Shader shader = Shader::Truth;
    bool exactTruth = false; // truth integrated texel by texel (exactBoxView)
    // fixedDirectionsView scenes: the view and the lights in the plane's tangent frame, the same
    // at every point (orthographic camera, directional lights).
    glm::vec3 fixedView{0.f, 0.f, 1.f};
    glm::mat3 fixedToEnvironment{1.f}; // the plane's frame into the environment's
    std::vector<LightSample> fixedLights;
    // The truth under an environment in such a view, tabulated (EnvironmentTruth::Table).
    std::shared_ptr<const EnvironmentTruthTable> environmentTable;
    FilteredPlanes planes;                // methods: the linear planes (exact: the shaded chain)
    std::vector<glm::ivec2> sizes;        // their levels' sizes
    const MethodShader* method = nullptr; // Shader::Method
    ShaderSetup setup;                    // what it prepared for this material and bake
    MipChain albedo;                      // empty without an albedo map
    const EnvironmentLighting* lighting = nullptr; // the environment, if any
    std::vector<SharedImage> exactChain; // kExact: owns the shaded chain the planes point into
    Bake encoded;                        // a shader's planesOf: owns the planes they point into
};

glm::mat3 hitToEnvironment(const SurfaceHit& hit) {
    return tangentToEnvironment(hit.tangent, hit.bitangent, hit.normal);
}

// One method's shading of one set of parameters (filtered, or one texel's) at a surface point,
// with `material` (the scene's, or widened by specular anti-aliasing).
glm::vec3 shadeParameters(const Context& ctx, const Material& material, const float* params,
                          glm::vec3 albedo, const SurfaceHit& hit, glm::vec3 view) {
    if (ctx.shader == Shader::Exact) return {params[0], params[1], params[2]}; // already radiance
    const Scene& scene = *ctx.scene;
    glm::vec3 radiance(0.f);
    for (const Light& light : scene.lights) {
        const LightSample ls = lightAt(light, hit.position);
        const glm::vec3 l = toTangent(hit, ls.direction);
        if (l.z <= 0.f) continue; // below the geometric surface
        const glm::vec3 r = ctx.method->shade(ctx.setup, material, params, albedo, l, view);
        radiance += ls.irradiance * r;
    }
    if (ctx.lighting)
        radiance += ctx.method->shadeEnvironment(ctx.setup, material, params, albedo, view,
                                                 hitToEnvironment(hit), *ctx.lighting);
    return radiance;
}

// Specular anti-aliasing's kernel at a lookup: the unit normal (the first plane, filtered by the
// same rule) here and at the next pixel across and down, as a GPU's derivatives of the shading
// normal take it; 0 where the shader takes none.
float antiAliasingKernel(const Context& ctx, glm::vec2 uv, const UvFootprint& footprint) {
    const RenderOptions& o = *ctx.options;
    if (!(o.specularAntiAliasing.variance > 0.f) || ctx.shader != Shader::Method ||
        !ctx.method->widenRoughness || ctx.planes.chains.empty() ||
        ctx.planes.chains.front().channels < 3)
        return 0.f;
    auto normalAt = [&](glm::vec2 at) {
        TapList taps;
        filteredTaps(ctx.sizes, at, footprint, o.anisotropy, o.lodBias, taps);
        float n[kMaxFilteredChannels];
        gatherTaps(ctx.planes.chains.front(), taps, n);
        const glm::vec3 v(n[0], n[1], n[2]);
        const float length = glm::length(v);
        return length > 0.f ? v / length : glm::vec3(0.f, 0.f, 1.f);
    };
    const glm::vec3 n = normalAt(uv);
    return specularAntiAliasingKernel(o.specularAntiAliasing, normalAt(uv + footprint.dx) - n,
                                      normalAt(uv + footprint.dy) - n);
}

// A method's lookup at one hit with footprint `footprint`: the filtering rule's taps, then the
// parameters blended and shaded once, or each texel shaded and the results blended.
glm::vec3 shadeLookup(const Context& ctx, const SurfaceHit& hit, glm::vec3 view,
                      const UvFootprint& footprint) {
    const RenderOptions& o = *ctx.options;
    TapList taps;
    filteredTaps(ctx.sizes, hit.uv, footprint, o.anisotropy, o.lodBias, taps);
    const glm::vec3 material = ctx.scene->material.albedo;
    const float kernel = antiAliasingKernel(ctx, hit.uv, footprint);
    auto shade = [&](float* params, glm::vec3 albedo) {
        if (!(kernel > 0.f)) // off, or no change to the next pixels
            return shadeParameters(ctx, ctx.scene->material, params, albedo, hit, view);
        Material widened = ctx.scene->material;
        ctx.method->widenRoughness(ctx.setup, widened, params, kernel);
        return shadeParameters(ctx, widened, params, albedo, hit, view);
    };
    float params[kMaxFilteredChannels];
    if (o.shadeFilter == ShadeFilter::Parameter || ctx.shader == Shader::Exact) {
        int offset = 0;
        for (const MipChain& chain : ctx.planes.chains) {
            gatherTaps(chain, taps, params + offset);
            offset += chain.channels;
        }
        glm::vec3 albedo = material;
        if (!ctx.albedo.levels.empty()) {
            float a[4];
            gatherTaps(ctx.albedo, taps, a);
            albedo *= glm::vec3(a[0], a[1], a[2]);
        }
        return shade(params, albedo);
    }
    glm::vec3 sum(0.f);
    for (int t = 0; t < taps.count; ++t) {
        const TexelTap& tap = taps.tap[t];
        int offset = 0;
        for (const MipChain& chain : ctx.planes.chains) {
            const float* texel = chain.levels[tap.level]->at(tap.x, tap.y);
            std::copy(texel, texel + chain.channels, params + offset);
            offset += chain.channels;
        }
        glm::vec3 albedo = material;
        if (!ctx.albedo.levels.empty()) {
            const float* a = ctx.albedo.levels[tap.level]->at(tap.x, tap.y);
            albedo *= glm::vec3(a[0], a[1], a[2]);
        }
        sum += tap.weight * shade(params, albedo);
    }
    return sum;
}

// The ray through (px, py), what it hits and the view direction in the hit's tangent frame;
// false where it misses the object or sees its back (`radiance` then holds what the pixel sees).
bool traceSurface(const Context& ctx, float px, float py, SurfaceHit& hit, glm::vec3& view,
                  glm::vec3& radiance) {
    const Ray ray = cameraRay(ctx.camera, px, py);
    hit = intersect(ctx.scene->geometry, ray);
    if (!hit.hit) {
        radiance = ctx.scene->background;
        if (ctx.lighting && ctx.scene->environment.visible)
            radiance = environmentRadiance(ctx.lighting->environment,
                                           glm::dvec3(worldToEnvironment(ray.direction)));
        return false;
    }
    view = toTangent(hit, -ray.direction);
    if (view.z <= 0.f) { // the back of the surface
        radiance = glm::vec3(0.f);
        return false;
    }
    return true;
}

// The truth at one point: the finest normal (box or bilinear surface) shaded by every light,
// and the environment's estimate (environment_truth.h) when there is one.
glm::vec3 shadeTruth(const Context& ctx, const SurfaceHit& hit, glm::vec3 view,
                     PixelRandom& random) {
    const Scene& scene = *ctx.scene;
    const bool box = ctx.options->truth == TruthFilter::Box;
    const glm::vec3 normal = sampleNormal(*ctx.textures->normals, hit.uv, box);
    glm::vec3 albedo = scene.material.albedo;
    if (!ctx.albedo.levels.empty()) {
        float a[4] = {0.f, 0.f, 0.f, 0.f};
        if (box) {
            const float* t = nearestTexel(*ctx.albedo.levels.front(), hit.uv);
            a[0] = t[0], a[1] = t[1], a[2] = t[2];
        } else {
            accumulateBilinear(*ctx.albedo.levels.front(), hit.uv, 1.f, a);
        }
        albedo *= glm::vec3(a[0], a[1], a[2]);
    }
    glm::vec3 radiance(0.f);
    for (const Light& light : scene.lights) {
        const LightSample ls = lightAt(light, hit.position);
        const glm::vec3 l = toTangent(hit, ls.direction);
        if (l.z <= 0.f) continue;
        radiance += ls.irradiance *
                    shadeNormal(scene.material, albedo, normal, l, glm::normalize(l + view));
    }
    if (ctx.lighting) {
        const glm::mat3 toEnvironment = hitToEnvironment(hit);
        const int n = ctx.options->environmentSamples;
        glm::vec3 sum(0.f);
        for (int i = 0; i < n; ++i) {
            double u[5];
            for (double& x : u) x = random.uniformDouble();
            sum += estimateEnvironmentRadiance(*ctx.lighting, toEnvironment, scene.material, albedo,
                                               normal, view, ctx.options->environmentEstimator, u);
        }
        radiance += sum / float(n);
    }
    return radiance;
}

// One pixel sample; `covered` tells whether some ray of it saw the object's front.
glm::vec3 shadeSample(const Context& ctx, float px, float py, PixelRandom& random, bool& covered) {
    SurfaceHit hit;
    glm::vec3 view, radiance;
    if (ctx.shader == Shader::Truth) {
        covered = traceSurface(ctx, px, py, hit, view, radiance);
        return covered ? shadeTruth(ctx, hit, view, random) : radiance;
    }
    // Methods: taps x taps sub-samples over the pixel around (px, py), each with its share of
    // the footprint.
    const int k = ctx.options->taps;
    if (k == 1) {
        covered = traceSurface(ctx, px, py, hit, view, radiance);
        if (!covered) return radiance;
        return shadeLookup(ctx, hit, view, uvFootprint(ctx.camera, hit, px, py));
    }
    glm::vec3 sum(0.f);
    covered = false;
    const float step = 1.f / float(k);
    for (int j = 0; j < k; ++j)
        for (int i = 0; i < k; ++i) {
            const float qx = px + (float(i) + 0.5f) * step - 0.5f,
                        qy = py + (float(j) + 0.5f) * step - 0.5f;
            if (!traceSurface(ctx, qx, qy, hit, view, radiance)) {
                sum += radiance;
                continue;
            }
            covered = true;
            UvFootprint footprint = uvFootprint(ctx.camera, hit, qx, qy);
            footprint.dx *= step;
            footprint.dy *= step;
            sum += shadeLookup(ctx, hit, view, footprint);
        }
    return sum * (step * step);
}

// The uv rectangle a pixel covers (corners' hits), in level-0 texels; false where a corner
// misses the plane.
bool pixelTexels(const Context& ctx, float px, float py, glm::vec2& lo, glm::vec2& hi) {
    const Image& normals = *ctx.textures->normals;
    const glm::vec2 size(float(normals.width), float(normals.height));
    glm::vec2 corner[2];
    for (int c = 0; c < 2; ++c) {
        const SurfaceHit hit =
            intersect(ctx.scene->geometry, cameraRay(ctx.camera, px + float(c), py + float(c)));
        if (!hit.hit) return false;
        corner[c] = hit.uv * size;
    }
    lo = glm::min(corner[0], corner[1]);
    hi = glm::max(corner[0], corner[1]);
    return true;
}

// The truth of one pixel of an exactBoxView, integrated without samples: the pixel's rectangle
// cut into cells, K x K per level-0 texel (box surface: K = 1, the texel itself, exact; bilinear
// surface: K = kBilinearCells, a midpoint rule), each shaded at the centre of its part inside
// the pixel and weighted by that part's area. Under an environment the cells read its table,
// and `variance` gets the pixel's variance from the nodes' (else 0).
glm::vec3 exactPixel(const Context& ctx, float px, float py, PixelRandom& random,
                     double& variance) {
    variance = 0.;
    glm::vec2 lo, hi;
    bool covered = false;
    if (!pixelTexels(ctx, px, py, lo, hi))
        return shadeSample(ctx, px + 0.5f, py + 0.5f, random, covered);
    SurfaceHit hit;
    glm::vec3 view, radiance;
    if (!traceSurface(ctx, px + 0.5f, py + 0.5f, hit, view, radiance)) return radiance;
    const Image& normals = *ctx.textures->normals;
    const Scene& scene = *ctx.scene;
    const glm::vec2 extent = hi - lo;
    if (!(extent.x > 0.f && extent.y > 0.f)) return shadeTruth(ctx, hit, view, random);
    const double pixelArea = double(extent.x) * double(extent.y);
    thread_local EnvironmentTruthNoise noise; // the nodes' weights, cleared by take()
    const bool box = ctx.options->truth == TruthFilter::Box;
    const double k = box ? 1.0 : double(kBilinearCells);
    const glm::dvec2 size(normals.width, normals.height);
    glm::dvec3 sum(0.0);
    const long x0 = long(std::floor(double(lo.x) * k)), x1 = long(std::ceil(double(hi.x) * k));
    const long y0 = long(std::floor(double(lo.y) * k)), y1 = long(std::ceil(double(hi.y) * k));
    for (long y = y0; y < y1; ++y) {
        const double top = std::max(double(y) / k, double(lo.y)),
                     bottom = std::min(double(y + 1) / k, double(hi.y));
        if (bottom <= top) continue;
        for (long x = x0; x < x1; ++x) {
            const double left = std::max(double(x) / k, double(lo.x)),
                         right = std::min(double(x + 1) / k, double(hi.x));
            if (right <= left) continue;
            const glm::vec2 uv(glm::dvec2(0.5 * (left + right), 0.5 * (top + bottom)) / size);
            const glm::vec3 n = sampleNormal(normals, uv, box);
            glm::vec3 albedo = scene.material.albedo;
            if (!ctx.albedo.levels.empty()) {
                float a[4] = {0.f, 0.f, 0.f, 0.f};
                if (box) {
                    const float* t = nearestTexel(*ctx.albedo.levels.front(), uv);
                    a[0] = t[0], a[1] = t[1], a[2] = t[2];
                } else {
                    accumulateBilinear(*ctx.albedo.levels.front(), uv, 1.f, a);
                }
                albedo *= glm::vec3(a[0], a[1], a[2]);
            }
            glm::vec3 r(0.f);
            for (const LightSample& light : ctx.fixedLights)
                r += light.irradiance * shadeNormal(scene.material, albedo, n, light.direction,
                                                    glm::normalize(light.direction + view));
            const double area = (right - left) * (bottom - top);
            if (ctx.environmentTable)
                r += ctx.environmentTable->radiance(n, &noise, area / pixelArea);
            sum += area * glm::dvec3(r);
        }
    }
    if (ctx.environmentTable) variance = noise.take(*ctx.environmentTable);
    return glm::vec3(sum / pixelArea);
}

// The exact reference's planes: level 0 every texel's normal shaded (RGB radiance, every
// light), coarser levels the pyramid's exact footprint means of it. Needs constant l and v.
std::vector<SharedImage> shadedChain(const Scene& scene, const RenderTextures& textures,
                                     const Context& ctx) {
    const Image& normals = *textures.normals;
    const glm::vec3 view = ctx.fixedView;
    auto level0 = std::make_shared<Image>(normals.width, normals.height, 3, Image::Uninitialized{});
#pragma omp parallel for schedule(static)
    for (int y = 0; y < normals.height; ++y)
        for (int x = 0; x < normals.width; ++x) {
            const float* n = normals.at(x, y);
            glm::vec3 albedo = scene.material.albedo;
            if (!ctx.albedo.levels.empty()) {
                const float* a = ctx.albedo.levels.front()->at(x, y);
                albedo *= glm::vec3(a[0], a[1], a[2]);
            }
            glm::vec3 r(0.f);
            for (const LightSample& light : ctx.fixedLights)
                r += light.irradiance * shadeNormal(scene.material, albedo,
                                                    glm::vec3(n[0], n[1], n[2]), light.direction,
                                                    glm::normalize(light.direction + view));
            float* out = level0->at(x, y);
            out[0] = r.x, out[1] = r.y, out[2] = r.z;
        }
    const Pyramid pyramid = buildPyramid(textures.normals);
    std::vector<SharedImage> chain{level0};
    for (int k = 1; k < int(pyramid.levels.size()); ++k)
        chain.push_back(std::make_shared<const Image>(averageToLevel(pyramid, *chain.back(), k)));
    return chain;
}

// A roughness-mips render's roughness: one image per level of the bake, the levels' sizes,
// filtered like the planes (its channels after theirs).
Status addRoughnessChain(Context& ctx, const RenderTextures& textures, const Bake& bake) {
    if (textures.roughness.size() != bake.levels.size())
        return Status::failure("render: roughness-mips needs a roughness image per level (" +
                               std::to_string(bake.levels.size()) + "), got " +
                               std::to_string(textures.roughness.size()));
    MipChain chain;
    for (size_t k = 0; k < textures.roughness.size(); ++k) {
        const Image& r = *textures.roughness[k];
        const Image& level = *bake.levels[k].front();
        if (r.width != level.width || r.height != level.height || r.channels < 1)
            return Status::failure("render: roughness level " + std::to_string(k) + " is " +
                                   std::to_string(r.width) + "x" + std::to_string(r.height) +
                                   ", the mip level " + std::to_string(level.width) + "x" +
                                   std::to_string(level.height));
        chain.levels.push_back(&r);
    }
    chain.channels = textures.roughness.front()->channels;
    ctx.planes.channels += chain.channels;
    ctx.planes.chains.push_back(std::move(chain));
    return Status::success();
}

// What render() is asked that no scene can do: the options out of range (checkRenderOptions),
// no normal map, an empty image, an environment the textures lack.
Status checkRenderInputs(const Scene& scene, const RenderTextures& textures,
                         const RenderOptions& options) {
    if (!textures.normals || textures.normals->channels != 3 || textures.normals->empty())
        return Status::failure("render: no normal map (3 channels) to render with");
    if (Status s = checkRenderOptions(options); !s) return Status::failure("render: " + s.error);
    if (scene.camera.width < 1 || scene.camera.height < 1)
        return Status::failure("render: the camera's image is empty");
    if (options.environmentSamples < 1 || options.environmentSamples > 4096)
        return Status::failure("render: environment samples must be in 1 .. 4096, got " +
                               std::to_string(options.environmentSamples));
    if (!scene.environment.path.empty() && !textures.environment)
        return Status::failure("render: the scene's environment " + quote(scene.environment.path) +
                               " is not loaded");
    if (options.shViews < 0 || options.shViews > kMaxShViews)
        return Status::failure("render: SH views must be in 0 .. " + std::to_string(kMaxShViews) +
                               ", got " + std::to_string(options.shViews));
    return Status::success();
}

// The context every pixel reads: the camera, the albedo map's levels and, in an exactBoxView,
// the view and the lights in the plane's tangent frame.
Status prepareContext(Context& ctx, const Scene& scene, const RenderTextures& textures,
                      const RenderOptions& options) {
    ctx.scene = &scene;
    ctx.camera = cameraFrame(scene.camera);
    ctx.textures = &textures;
    ctx.options = &options;
    ctx.lighting = textures.environment.get();
    if (!textures.albedo.empty()) {
        const Image& a = *textures.albedo.front();
        if (a.width != textures.normals->width || a.height != textures.normals->height ||
            a.channels < 3)
            return Status::failure("render: the albedo map must be RGB and the normal map's size");
        for (const SharedImage& level : textures.albedo) ctx.albedo.levels.push_back(level.get());
        ctx.albedo.channels = a.channels;
    }
    if (fixedDirectionsView(scene)) {
        // The plane's tangent frame, as intersect() builds it, and what is fixed in it.
        const Geometry& g = scene.geometry;
        SurfaceHit frame;
        frame.normal = g.normal;
        frame.tangent = g.tangent;
        frame.bitangent = glm::cross(g.normal, g.tangent);
        ctx.fixedView = toTangent(frame, -ctx.camera.forward);
        ctx.fixedToEnvironment = hitToEnvironment(frame);
        for (const Light& light : scene.lights) {
            const glm::vec3 l = toTangent(frame, light.direction);
            if (l.z > 0.f && ctx.fixedView.z > 0.f) ctx.fixedLights.push_back({l, light.color});
        }
    }
    return Status::success();
}

// A method's shading: its shader's setup for the material and bake, the bake's linear planes
// (and roughness-mips' roughness) as the chains the pixels filter.
Result<bool> prepareMethod(Context& ctx, const std::string& methodName, const Scene& scene,
                           const RenderTextures& textures, const RenderOptions& options) {
    ctx.method = findShader(methodName);
    if (!ctx.method)
        return Error{"render: unknown method " + quote(methodName) + " (expected " +
                     renderMethodNames() + ")"};
    ctx.shader = Shader::Method;
    if (ctx.lighting && !ctx.method->shadeEnvironment)
        return Error{"render: method " + quote(methodName) + " cannot shade under an environment"};
    const Bake& bake = textures.bake;
    if (bake.levels.empty() || bake.method != ctx.method->bake)
        return Error{"render: no bake of method '" +
                     std::string(ndfmip::methodName(ctx.method->bake)) + "' to render with"};
    const Image& level0 = *bake.levels.front().front();
    if (level0.width != textures.normals->width || level0.height != textures.normals->height)
        return Error{"render: the bake's level 0 is " + std::to_string(level0.width) + "x" +
                     std::to_string(level0.height) + " but the normal map is " +
                     std::to_string(textures.normals->width) + "x" +
                     std::to_string(textures.normals->height)};
    if (ctx.lighting)
        ctx.setup.environmentView = worldToEnvironment(glm::dvec3(-ctx.camera.forward));
    if (Status ready = ctx.method->prepare(scene.material, textures, options, ctx.setup); !ready)
        return Error{ready.error};
    if (ctx.method->planesOf) ctx.encoded = ctx.method->planesOf(bake);
    ctx.planes = linearPlanes(ctx.method->planesOf ? ctx.encoded : bake);
    if (methodName == kRoughnessMips) // an engine's roughness mips, filtered like the planes
        if (Status s = addRoughnessChain(ctx, textures, bake); !s) return Error{s.error};
    if (ctx.planes.channels < 3 || ctx.planes.channels > kMaxFilteredChannels)
        return Error{"render: method " + quote(methodName) + " has no filterable planes"};
    return true;
}

// What the pixels shade: the truth, the exact reference's shaded chain, or a method's planes.
Result<bool> prepareShading(Context& ctx, const std::string& methodName) {
    const Scene& scene = *ctx.scene;
    const RenderTextures& textures = *ctx.textures;
    if (methodName == kGroundTruth) {
        ctx.shader = Shader::Truth;
        ctx.exactTruth = ctx.options->exact && exactBoxView(scene) && !ctx.lighting;
        if (ctx.lighting && ctx.options->environmentTruth == EnvironmentTruth::Table) {
            if (!fixedDirectionsView(scene) || !ctx.options->exact || !ctx.albedo.levels.empty())
                return Error{"render: a tabulated truth under an environment needs every "
                             "direction but the normal fixed: an orthographic view of a plane "
                             "with its image rows along the texel grid, directional lights, no "
                             "albedo map"};
            EnvironmentTruthKey key;
            key.lighting = textures.environment;
            key.material = scene.material;
            key.view = ctx.fixedView;
            key.toEnvironment = ctx.fixedToEnvironment;
            key.samples = ctx.options->spp;
            key.estimator = ctx.options->environmentEstimator;
            key.seed = ctx.options->seed;
            ctx.environmentTable = environmentTruthTable(key);
            ctx.exactTruth = true;
        }
    } else if (methodName == kExact) {
        if (ctx.lighting) return Error{"render: 'exact' cannot shade under an environment"};
        if (!exactBoxView(scene))
            return Error{
                "render: 'exact' needs constant light and view directions: an orthographic view "
                "straight down on a plane, directional lights"};
        ctx.shader = Shader::Exact;
        ctx.exactChain = shadedChain(scene, textures, ctx);
        MipChain chain;
        for (const SharedImage& level : ctx.exactChain) chain.levels.push_back(level.get());
        chain.channels = 3;
        ctx.planes.chains.push_back(std::move(chain));
        ctx.planes.channels = 3;
    } else if (Result<bool> ready = prepareMethod(ctx, methodName, scene, textures, *ctx.options);
               !ready) {
        return ready.error();
    }
    if (!ctx.planes.chains.empty()) ctx.sizes = levelSizes(ctx.planes.chains.front());
    if (!ctx.albedo.levels.empty() && ctx.shader != Shader::Truth &&
        ctx.albedo.levels.size() < ctx.sizes.size())
        return Error{"render: the albedo map has fewer mip levels than the bake"};
    return true;
}

struct PixelValue {
    glm::vec3 mean{0.f};
    double standardError = 0.; // of the mean's luminance (0 with one sample)
    bool covered = false;      // some sample hit the surface
};

// One pixel: one exact integral, or options.spp stratified samples and their standard error.
PixelValue renderPixel(const Context& ctx, int x, int y, int gx, int gy) {
    PixelRandom random{ctx.options->seed * 0x2545F4914F6CDD1Dull +
                       uint64_t(y) * uint64_t(ctx.scene->camera.width) + uint64_t(x)};
    // The environment's samples draw from a stream of their own, so the jitter (and the
    // lights' part of the image) is the same with or without an environment.
    PixelRandom lightingRandom{random.state ^ 0xD1B54A32D192ED03ull};
    glm::vec3 mean(0.f);
    double standardError = 0.;
    bool covered = false;
    if (ctx.exactTruth) { // one exact integral over the whole pixel
        double variance = 0.;
        mean = exactPixel(ctx, float(x) + ctx.options->pixelShift.x,
                          float(y) + ctx.options->pixelShift.y, lightingRandom, variance);
        standardError = std::sqrt(variance);
        covered = true;
    } else {
        // The noise of a stratified mean: consecutive strata paired, each pair's squared
        // difference its sum's variance (a pair is one stratum of two samples), so the spread
        // between strata, which stratification removes, is not counted as noise. An odd last
        // stratum takes the samples' plain variance.
        double sumY = 0., sumY2 = 0., pairs = 0., previous = 0.;
        for (int sy = 0; sy < gy; ++sy) {
            for (int sx = 0; sx < gx; ++sx) {
                float jx = 0.5f, jy = 0.5f;
                if (ctx.options->spp > 1) {
                    jx = (float(sx) + random.uniform()) / float(gx);
                    jy = (float(sy) + random.uniform()) / float(gy);
                }
                bool seen = false;
                const glm::vec3 r =
                    shadeSample(ctx, float(x) + jx + ctx.options->pixelShift.x,
                                float(y) + jy + ctx.options->pixelShift.y, lightingRandom, seen);
                mean += r;
                covered = covered || seen;
                const double lum = rec709Luminance(glm::dvec3(r));
                sumY += lum;
                sumY2 += lum * lum;
                if ((sy * gx + sx) % 2) pairs += (lum - previous) * (lum - previous);
                previous = lum;
            }
        }
        mean /= float(ctx.options->spp);
        const double n = double(ctx.options->spp);
        if (ctx.options->spp > 1) {
            double variance = pairs;
            if (ctx.options->spp % 2)
                variance += std::max(0., (sumY2 - sumY * sumY / n) / (n - 1.));
            standardError = std::sqrt(variance) / n;
        }
    }
    return {mean, standardError, covered};
}

} // namespace

Result<Image> render(const Scene& scene, const RenderTextures& textures,
                     const std::string& methodName, const RenderOptions& options) {
    return render(scene, textures, methodName, options, nullptr);
}

Result<Image> render(const Scene& scene, const RenderTextures& textures,
                     const std::string& methodName, const RenderOptions& options,
                     RenderNoise* noise) {
    // Interpolated normals, no normal map: their own renderer.
    if (scene.geometry.type == GeometryType::FacetedSphere) {
        if (!scene.environment.path.empty())
            return Error{
                "render: faceted-sphere scenes are lit by point lights only, not an environment"};
        return renderInterpolated(scene, methodName, options);
    }
    if (Status s = checkRenderInputs(scene, textures, options); !s) return Error{s.error};
    Context ctx;
    if (Status s = prepareContext(ctx, scene, textures, options); !s) return Error{s.error};
    if (Result<bool> ready = prepareShading(ctx, methodName); !ready) return ready.error();

    const Camera& camera = scene.camera;
    Image out(camera.width, camera.height, 3);
    int gx = 1, gy = 1;
    strataGrid(options.spp, gx, gy);
    std::atomic<int> rowsDone{0};
    if (noise) *noise = RenderNoise{Image(camera.width, camera.height, 1), 0., 0};
    // Per row: sums of the covered pixels' standard errors and luminances, and their count.
    std::vector<glm::dvec3> rowNoise(size_t(camera.height), glm::dvec3(0.));

#pragma omp parallel for schedule(dynamic, 1)
    for (int y = 0; y < camera.height; ++y) {
        for (int x = 0; x < camera.width; ++x) {
            const PixelValue p = renderPixel(ctx, x, y, gx, gy);
            if (noise) {
                noise->standardError.at(x, y)[0] = float(p.standardError);
                if (p.covered)
                    rowNoise[size_t(y)] +=
                        glm::dvec3(p.standardError, rec709Luminance(glm::dvec3(p.mean)), 1.);
            }
            float* px = out.at(x, y);
            px[0] = p.mean.x;
            px[1] = p.mean.y;
            px[2] = p.mean.z;
        }
        int done = ++rowsDone;
        if (options.progress) {
#pragma omp critical(ndfmip_render_progress)
            options.progress(done, camera.height);
        }
    }
    if (noise) {
        glm::dvec3 total(0.);
        for (const glm::dvec3& row : rowNoise)
            total += row; // in row order: the same on any thread count
        noise->coveredPixels = size_t(total.z);
        noise->relativeStandardError = total.y > 0. ? total.x / total.y : 0.;
    }
    return out;
}

std::string renderMethodNames() {
    std::string names = std::string(kGroundTruth) + ", " + kExact;
    for (const MethodShader& shader : methodShaders()) names += std::string(", ") + shader.name;
    return names;
}

std::vector<std::string> shaderNames() {
    std::vector<std::string> names;
    for (const MethodShader& shader : methodShaders()) names.emplace_back(shader.name);
    return names;
}

std::optional<Method> shaderBake(const std::string& shader) {
    const MethodShader* found = findShader(shader);
    if (!found) return std::nullopt;
    return found->bake;
}

const char* environmentWayName(EnvironmentWay way) {
    return way == EnvironmentWay::Prefiltered ? "prefiltered" : "sh";
}

bool environmentWayFromString(const std::string& name, EnvironmentWay& out) {
    if (name == "prefiltered")
        out = EnvironmentWay::Prefiltered;
    else if (name == "sh")
        out = EnvironmentWay::ShLighting;
    else
        return false;
    return true;
}

const char* environmentTruthName(EnvironmentTruth truth) {
    return truth == EnvironmentTruth::Sampled ? "sampled" : "table";
}

const char* truthFilterName(TruthFilter filter) {
    return filter == TruthFilter::Box ? "box" : "bilinear";
}

bool truthFilterFromString(const std::string& name, TruthFilter& out) {
    if (name == "box")
        out = TruthFilter::Box;
    else if (name == "bilinear")
        out = TruthFilter::Bilinear;
    else
        return false;
    return true;
}

float specularAntiAliasingKernel(const SpecularAntiAliasing& aa, glm::vec3 du, glm::vec3 dv) {
    return glsl().ndfmipSpecularAaKernel(du, dv, aa.variance, aa.threshold);
}

const char* shadeFilterName(ShadeFilter filter) {
    return filter == ShadeFilter::Parameter ? "parameter" : "texel";
}

bool shadeFilterFromString(const std::string& name, ShadeFilter& out) {
    if (name == "parameter")
        out = ShadeFilter::Parameter;
    else if (name == "texel")
        out = ShadeFilter::Texel;
    else
        return false;
    return true;
}

bool exactBoxView(const Scene& scene) {
    // Light from every direction varies per point: integrated exactly only through a table.
    return scene.environment.path.empty() && fixedDirectionsView(scene);
}

bool fixedDirectionsView(const Scene& scene) {
    if (scene.camera.type != CameraType::Orthographic || scene.geometry.type != GeometryType::Plane)
        return false;
    for (const Light& light : scene.lights)
        if (light.type != LightType::Directional) return false;
    const CameraFrame frame = cameraFrame(scene.camera);
    const Geometry& g = scene.geometry;
    // The image's rows along one axis of the texel grid (the camera may tilt about it): each
    // pixel then covers a rectangle of texels, seen from one direction.
    const glm::vec3 normal = glm::normalize(g.normal), tangent = glm::normalize(g.tangent);
    const glm::vec3 bitangent = glm::cross(normal, tangent);
    const float facing = std::abs(glm::dot(frame.forward, normal));
    const float alongTangent = std::abs(glm::dot(frame.right, tangent));
    const float alongBitangent = std::abs(glm::dot(frame.right, bitangent));
    return facing > 1e-3f && (alongTangent > 1.f - 1e-6f || alongBitangent > 1.f - 1e-6f);
}

} // namespace ndfmip
