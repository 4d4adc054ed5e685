// A method as one unit: everything the library and the tool need to know about it, in one
// table entry (method_table.cpp) filled from the method's own folder (src/methods/<name>/).
// Adding a method is a folder with its bake, its shading (shaders/<name>.glsl, shared with C++
// through method_shading.h) and its unit, plus one line in each table.
//
// A bake method (naive, toksvig, sh, vmf, lean) makes planes; a shader is one way to render a
// bake's planes (toksvig has two: the closed form and Toksvig's lookup table; a naive bake is
// also read with an engine's roughness mips).
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json_fwd.hpp>

#include "ndfmip/bake.h"
#include "ndfmip/environment_sh_shading.h"
#include "ndfmip/environment_sh_views.h"
#include "ndfmip/environment_splitsum.h"
#include "ndfmip/method_parameters.h"
#include "ndfmip/method_shading.h"
#include "ndfmip/render.h"
#include "ndfmip/sh_brdf.h"

namespace ndfmip {

using BakeParameters = std::map<std::string, double>;

struct InspectOptions {
    bool hasExponent = false; // --exponent given
    float exponent = 0.f;
};

struct MethodUnit {
    Method method;
    const char* name;    // as on the command line and in manifests
    const char* summary; // one line for help texts
    Bake (*bake)(const Pyramid& pyramid, const BakeOptions& options);
    // The planes a bake with these parameters has, in order (names, channel counts, linear);
    // `colours`: a vmf bake with lobe colours.
    std::vector<PlaneInfo> (*planes)(const BakeParameters& parameters, bool colours);
    // The method's own options (method_parameters.h): the commands' flags, their checks, the
    // cache key, the manifest's ranges (those `recorded`) and eval's specs come from it.
    std::vector<MethodParameter> parameters;
    // Rules between the given values that the ranges alone do not say (null: none); a problem
    // names the parameters as `naming` says.
    Status (*checkParameters)(const ParameterValues& values, ParameterNaming naming);
    // Bytes per level-0 texel that the bake holds beyond the decoded normals and the pyramid.
    double (*bakeBytesPerTexel)(const BakeOptions& options);
    // "sh order 7", "vmf with 4 lobes": the bake named in messages.
    std::string (*describe)(const BakeParameters& parameters);
    // inspect: the texel's keys (the level's planes are in `bake.level`).
    void (*inspect)(nlohmann::json& out, const LoadedBake& bake, int x, int y,
                    const InspectOptions& options);
    // The unit normal a level-0 texel holds (`planes` = its planes' values, plane after plane).
    glm::vec3 (*levelZeroNormal)(const float* planes);
    // The texel's NDF density at unit w, for methods that store one (inspect --ndf); else null.
    double (*ndfDensity)(const LoadedBake& bake, int x, int y, glm::dvec3 w);
    // The bake is fitted to the material's own roughness (BakeOptions::baseRoughness): eval bakes
    // it once per GGX roughness it judges.
    bool fitsMaterialRoughness = false;
};

const std::vector<MethodUnit>& methodUnits();
const MethodUnit& methodUnit(Method method);

// What a shader needs besides the texels, set up once per render from the material and bake.
struct ShaderSetup {
    ShShading sh;                  // sh: the material's A_l
    Image lut;                     // toksvig-lut: the table of the material's exponent
    int vmfLobes = 0;              // vmf: J
    bool vmfColors = false;        // vmf: colour planes follow the lobe planes
    bool roughnessIsAlpha = false; // roughness-mips: stored alpha, not perceptual
    RoughnessMapping mapping = RoughnessMapping::Ours;
    float varianceScale = kVarianceScale;
    // Under an environment. The renderer sets environmentView (towards the camera at the image
    // centre, environment frame: the SH lighting's fixed view) before prepare, which fills the
    // lighting its shading reads.
    glm::dvec3 environmentView{0., 0., 1.};
    EnvironmentLod environmentLod = EnvironmentLod::Filament;
    std::shared_ptr<const SplitSumLighting> splitSum; // prefiltered levels (the engine way)
    std::shared_ptr<const ShLighting> shLighting;     // SH lighting (the paper's way), one view
    std::shared_ptr<const ShViewSet> shViews;         // or a set of views (RenderOptions::shViews)
};

// The SH lighting a pixel reads: setup.shLighting, or with a set of views the lighting
// interpolated at the pixel's own view (toEnvironment * v, v towards the camera in the tangent
// frame), held per thread until the next call on that thread.
const ShLighting& shLightingAt(const ShaderSetup& setup, glm::vec3 v,
                               const glm::mat3& toEnvironment);

// The prepare steps the methods share under an environment (nothing without one): the
// prefiltered levels of options.environmentLod's rule, or the SH lighting of order
// options.environmentShOrder for setup.environmentView (the specular cosine options.shCosine,
// environment_sh_shading.h) or, with options.shViews > 0, for the set of views.
Status prepareSplitSumSetup(const Material& material, const RenderTextures& textures,
                            const RenderOptions& options, ShaderSetup& setup);
Status prepareShLightingSetup(const Material& material, const RenderTextures& textures,
                              const RenderOptions& options, ShaderSetup& setup);

// A uniform of the GPU renderer's fragment shader (render_program.h).
struct UniformValue {
    std::string name;
    bool integer = false;
    std::vector<float> values; // 1 to 3 components
};

constexpr int kGpuMaxShOrder = 10; // NDFMIP_SH_MAX_ORDER in shaders/sh.glsl

struct MethodShader {
    const char* name; // render and eval method name
    Method bake;      // the bake it reads
    const char* glsl; // its render glue in shaders/ (render/<name>.glsl: ndfmipShadeTexel for the
                      // GPU renderer)
    // Checks the material (and textures) and fills `setup`; an error names what is wrong.
    Status (*prepare)(const Material& material, const RenderTextures& textures,
                      const RenderOptions& options, ShaderSetup& setup);
    // Radiance per unit irradiance from the filtered (or one texel's) linear plane values, in
    // plane order; roughness-mips' roughness comes last.
    glm::vec3 (*shade)(const ShaderSetup& setup, const Material& material, const float* params,
                       glm::vec3 albedo, glm::vec3 l, glm::vec3 v);
    // The specular lobe alone at half vector h, no cosine (what `ndfmip demo` compares).
    float (*lobe)(const ShaderSetup& setup, const Material& material, const float* params,
                  glm::vec3 h);
    // The radiance the filtered parameters reflect under the whole environment, view v in the
    // tangent frame, `tangentToEnvironment` taking tangent-frame directions to the environment's
    // (environment_lighting.h). Null for a shader that cannot shade under an environment.
    glm::vec3 (*shadeEnvironment)(const ShaderSetup& setup, const Material& material,
                                  const float* params, glm::vec3 albedo, glm::vec3 view,
                                  const glm::mat3& tangentToEnvironment,
                                  const EnvironmentLighting& lighting);
    // The GPU renderer's part (render_program.cpp); null where the glue needs nothing of it.
    // Texture layers the glue reads after the planes' (`levels` of them, one per bake level):
    // roughness-mips' roughness.
    Status (*gpuLayers)(const RenderTextures& textures, size_t levels,
                        std::vector<std::vector<const Image*>>& layers);
    // The glue's #defines (`layers`: the planes' layers and the extra ones).
    std::string (*gpuDefines)(const ShaderSetup& setup, int layers);
    // The glue's uniforms, or why the GPU cannot draw this setup.
    Status (*gpuUniforms)(const ShaderSetup& setup, std::vector<UniformValue>& uniforms);
    // Under SH lighting: the planes hold coefficients in the tangent frame (sh), so the lighting
    // is rotated into it (per hit on a curved surface); otherwise the glue turns its lobes into
    // the environment's frame.
    bool shLightingInTangentFrame;
    // The planes the shader samples where they are not the bake's own: its linear planes encoded
    // as an engine's textures hold them (ggx-aniso-khr), made once per render. Null: the bake's.
    Bake (*planesOf)(const Bake& bake);
    // Specular anti-aliasing (RenderOptions::specularAntiAliasing): adds `kernel` to the squared
    // roughness the shader reads, in the material or in the filtered parameters. Null: the
    // shader's lobe is not an engine's one roughness, and it takes none.
    void (*widenRoughness)(const ShaderSetup& setup, Material& material, float* params,
                           float kernel);
};

// A uniform's value, for the gpuUniforms hooks.
void addUniform(std::vector<UniformValue>& uniforms, const std::string& name, int value);
void addUniform(std::vector<UniformValue>& uniforms, const std::string& name, float value);

const std::vector<MethodShader>& methodShaders();
const MethodShader* findShader(const std::string& name); // null if none

// Each method's unit and shaders (in its folder).
MethodUnit naiveUnit();
MethodUnit toksvigUnit();
MethodUnit shUnit();
MethodUnit vmfUnit();
MethodUnit leanUnit();
MethodUnit ggxFitUnit();
MethodUnit ggxAnisoUnit();
std::vector<MethodShader> naiveShaders();
std::vector<MethodShader> toksvigShaders();
std::vector<MethodShader> shShaders();
std::vector<MethodShader> vmfShaders();
std::vector<MethodShader> leanShaders();
std::vector<MethodShader> ggxFitShaders();
std::vector<MethodShader> ggxAnisoShaders();

// Helpers the units share.
// The material's roughness: an option of every bake (BakeOptions::baseRoughness), not one of a
// method's own, so no command takes it from a table; a bake that depends on it (toksvig's
// roughness planes, ggx-fit) lists it so that its manifest must record it.
MethodParameter materialRoughnessParameter();
// A bake fitted to the material's GGX roughness (ggx-fit, ggx-aniso) shades a GGX material of that
// roughness, or any GGX material when fitted to a roughness map (the map is the material): an
// error names `method` and the --base-roughness to bake with.
Status checkFittedMaterial(const char* method, const Material& m, const RenderTextures& textures);
PlaneInfo planeOf(const std::string& name, int channels, bool linear);
nlohmann::json jsonVec3(const float* v);
int requirePlane(const LoadedBake& bake, const std::string& name); // throws std::runtime_error

} // namespace ndfmip
