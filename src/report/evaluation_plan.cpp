// The first steps of `ndfmip eval` (evaluation_steps.h): the options checked and resolved into a
// plan, and the environment's lighting with the rows it cannot light set aside.
#include <cmath>
#include <cstdio>

#include "methods/method_unit.h"
#include "ndfmip/environment.h"
#include "report/evaluation_steps.h"

namespace ndfmip::evaluation {

void fail(std::string message) {
    throw Problem{std::move(message)};
}

namespace {

// The ranges the command line's parser holds the options to, for callers without it.
void checkRanges(const EvalOptions& a) {
    auto range = [](const char* option, double value, double lo, double hi) {
        if (value >= lo && value <= hi) return;
        char text[160];
        std::snprintf(text, sizeof text, "%s %g: expected %g .. %g", option, value, lo, hi);
        fail(text);
    };
    if (a.maps.empty()) fail("no maps to evaluate");
    for (float s : a.exponents) range("--exponents", s, 1e-3, 1e5);
    for (float r : a.roughness) range("--roughness", r, 1e-3, 1.0);
    for (float r : a.calibrationRoughness) range("--calibration-roughness", r, 1e-3, 1.0);
    for (float c : a.calibrationScales) range("calibration scale", c, 1e-3, 1e3);
    range("--pixels", a.maxPixels, 8, 2048);
    range("--specular-aa", a.specularAntiAliasing.variance, 0.0, 1e3);
    range("--specular-aa-threshold", a.specularAntiAliasing.threshold, 0.0, 1.0);
    if (a.spp != 0) range("--spp", a.spp, 1, 1 << 16);
    range("--frames", a.frames, 0, 256);
    if (a.coherence) range("--coherent", *a.coherence, 0.0, 1e6);
    range("--elevation", a.elevation, 5.0, 90.0);
    range("--light-polar", a.lightPolar, 0.0, 85.0);
    if (a.elevation < 90.f && a.lightPolar != 25.f)
        fail("--light-polar: only a straight-down view (--elevation 90) takes it; a tilted view's "
             "light follows the view's mirror direction");
    if (a.taps) range("--taps", *a.taps, 1, 16);
    if (a.lodBias) range("--lod-bias", *a.lodBias, -16.0, 16.0);
    range("--aniso", a.anisotropy, 1, 64);
}

std::vector<Setting> settingsOf(const EvalOptions& a) {
    std::vector<Setting> out;
    for (const std::string& name : a.brdfs) {
        Brdf brdf;
        if (!brdfFromString(name, brdf))
            fail("--brdfs: unknown BRDF " + quote(name) +
                 " (expected lambert, blinnphong, beckmann, ggx)");
        if (brdf == Brdf::Lambert) out.push_back(makeSetting(brdf, 0.f, 0.f));
        if (brdf == Brdf::BlinnPhong)
            for (float s : a.exponents) out.push_back(makeSetting(brdf, s, 0.f));
        if (brdf == Brdf::Beckmann || brdf == Brdf::Ggx)
            for (float r : a.roughness) out.push_back(makeSetting(brdf, 0.f, r));
    }
    return out;
}

MethodSpec methodSpecOf(const std::string& label) {
    if (label == kExact) return {label, kExact, Method::Naive, {}, false, label, {}, {}};
    // A second shader of a bake (toksvig-lut, sggx) is a row of its own, over its own bake.
    if (const MethodShader* shader = findShader(label);
        shader && label != methodName(shader->bake) && label != kRoughnessMips)
        return {label, shader->name, shader->bake, {}, true, label, {}, {}};
    MethodSpec spec{label, "", Method::Naive, {}, true, label, {}, {}};
    std::string name = label, order;
    if (size_t colon = label.find(':'); colon != std::string::npos) {
        name = label.substr(0, colon);
        order = label.substr(colon + 1);
    }
    auto method = methodFromString(name);
    if (!method)
        fail("--methods: unknown method " + quote(label) +
             " (expected naive, toksvig, toksvig-lut, sh[:ORDER], vmf[:LOBES[:BUDGET]], lean, "
             "sggx, ggx-fit, ggx-aniso, ggx-aniso-khr, ggx-aniso-kulla, ggx-aniso-burley, "
             "exact)");
    spec.method = *method;
    spec.render = methodName(*method);
    if (!order.empty()) {
        // sh:ORDER, vmf:J or vmf:J:BUDGET: the values in the method's table's spec order.
        std::vector<std::string> values;
        for (size_t from = 0;;) {
            const size_t colon = order.find(':', from);
            values.push_back(
                order.substr(from, colon == std::string::npos ? std::string::npos : colon - from));
            if (colon == std::string::npos) break;
            from = colon + 1;
        }
        Result<ParameterValues> parsed = parseParameterSpec(*method, label, values);
        if (!parsed) fail(parsed.error().message);
        spec.options.parameters = parsed.value();
    }
    return spec;
}

std::vector<ExternalRoughness> externalRows(const std::vector<std::string>& specs) {
    std::vector<ExternalRoughness> rows;
    for (const std::string& spec : specs) {
        const size_t eq = spec.find('=');
        if (eq == std::string::npos || eq == 0 || eq + 1 == spec.size())
            fail("--external-roughness: " + quote(spec) + " is not NAME=PATTERN");
        if (spec.find("{level}", eq) == std::string::npos)
            fail("--external-roughness: " + quote(spec) + ": the pattern has no {level}");
        rows.push_back({spec.substr(0, eq), spec.substr(eq + 1)});
    }
    return rows;
}

// The options with the view's rule where they leave it open: lab (the renderer's default rule),
// engine (one trilinear lookup, parameters blended, vmf's lobes coherent: H eq. 32, what hardware
// filtering needs) or aligned (one texel per pixel).
EvalOptions withView(EvalOptions a) {
    if (a.view != "lab" && a.view != "engine" && a.view != "aligned")
        fail("--view " + quote(a.view) + ": expected lab, engine or aligned");
    if (a.aligned && a.view == "engine") fail("--aligned and --view engine: give one");
    if ((a.aligned || a.view == "aligned") && a.elevation < 90.f)
        fail("--elevation: an aligned view looks straight down (--elevation 90)");
    if (a.aligned) a.view = "aligned";
    a.aligned = a.view == "aligned";
    if (a.view == "engine") {
        if (!a.taps) a.taps = 1;
        if (!a.lodBias) a.lodBias = 0.f;
        if (!a.lobeFilter) a.lobeFilter = "parameter";
        if (!a.coherence) a.coherence = kEngineViewCoherence;
    }
    if (!a.lobeFilter) a.lobeFilter = "texel";
    return a;
}

} // namespace

std::string Setting::label() const {
    char text[64];
    if (material.brdf == Brdf::BlinnPhong)
        std::snprintf(text, sizeof text, "%s s=%g", brdf.c_str(), exponent);
    else if (material.brdf == Brdf::Lambert)
        std::snprintf(text, sizeof text, "%s", brdf.c_str());
    else
        std::snprintf(text, sizeof text, "%s alpha=%g", brdf.c_str(), roughness);
    return text;
}

Setting makeSetting(Brdf brdf, float exponent, float roughness) {
    Setting s;
    s.brdf = brdfName(brdf);
    s.material.brdf = brdf;
    if (brdf == Brdf::Lambert) {
        s.material.albedo = glm::vec3(1.f);
        s.material.specular = glm::vec3(0.f);
    } else {
        s.material.albedo = glm::vec3(0.f);
        s.material.specular = glm::vec3(1.f);
    }
    if (brdf == Brdf::BlinnPhong) s.material.exponent = s.exponent = exponent;
    if (brdf == Brdf::Beckmann || brdf == Brdf::Ggx) s.material.roughness = s.roughness = roughness;
    return s;
}

MethodSpec methodSpec(const std::string& label) {
    const size_t at = label.find('@');
    if (at == std::string::npos) {
        MethodSpec spec = methodSpecOf(label);
        spec.bakeKey = label;
        return spec;
    }
    MethodSpec spec = methodSpecOf(label.substr(0, at));
    spec.label = label;
    spec.bakeKey = label.substr(0, at);
    const std::string variant = label.substr(at + 1);
    EnvironmentLod lod;
    EnvironmentWay way;
    if (environmentLodFromString(variant, lod) && spec.render != kExact &&
        spec.render != kToksvigLut && spec.method != Method::Sh && spec.method != Method::Lean)
        spec.lod = lod;
    else if (environmentWayFromString(variant, way) && spec.method == Method::Vmf)
        spec.way = way;
    else
        fail("--methods: " + quote(label) +
             ": naive, toksvig and vmf take @log2sigma, @filament, @unity or "
             "@unreal (the prefiltered levels' rule), vmf also @sh or @prefiltered (how it shades "
             "under an "
             "environment)");
    return spec;
}

Plan planEvaluation(const EvalOptions& options) {
    Plan plan;
    plan.options = withView(options);
    const EvalOptions& a = plan.options;
    checkRanges(a);
    plan.settings = settingsOf(a);
    plan.externals = externalRows(a.externalRoughness);
    if (a.externalEncoding != "perceptual" && a.externalEncoding != "alpha")
        fail("--external-encoding: " + quote(a.externalEncoding) + " is not perceptual or alpha");
    RenderOptions& filtering = plan.filtering;
    if (!truthFilterFromString(a.truth, filtering.truth))
        fail("--truth: " + quote(a.truth) + " is not box or bilinear");
    if (!shadeFilterFromString(*a.lobeFilter, filtering.shadeFilter))
        fail("--lobe-filter: " + quote(*a.lobeFilter) + " is not parameter or texel");
    // Aligned: one plain lookup per pixel unless the filtering rule is given.
    filtering.taps = a.taps.value_or(a.aligned ? 1 : filtering.taps);
    filtering.lodBias = a.lodBias.value_or(a.aligned ? 0.f : filtering.lodBias);
    filtering.anisotropy = a.anisotropy;
    filtering.specularAntiAliasing = a.specularAntiAliasing;
    if (a.offset.size() != 2 || !std::isfinite(a.offset[0]) || !std::isfinite(a.offset[1]))
        fail("--offset: two finite numbers X,Y expected");
    // Aligned: each pixel exactly one texel of a level, so every method reads that one texel.
    plan.shift = a.aligned ? glm::vec2(0.f) : glm::vec2(a.offset[0], a.offset[1]);
    if (a.aligned)
        for (int f : a.footprints)
            if ((f & (f - 1)) != 0)
                fail("--aligned: footprint " + std::to_string(f) +
                     " is not a power of two (one texel of a level)");
    std::vector<MethodSpec>& specs = plan.specs;
    for (const std::string& m : a.methods) specs.push_back(methodSpec(m));
    for (MethodSpec& spec : specs)
        if (spec.method == Method::Vmf && spec.baked && a.coherence.value_or(0.f) != 0.f)
            spec.options.parameters["coherent"] = *a.coherence;
    for (const MethodSpec& spec : specs)
        if ((spec.lod || spec.way) && a.environment.empty())
            fail("--methods: " + quote(spec.label) +
                 ": a variant after @ applies under --environment only");
    for (int f : a.footprints)
        if (f < 1 || f > 4096) fail("--footprints: " + std::to_string(f) + " is not in 1 .. 4096");
    return plan;
}

Lighting prepareLighting(Plan& plan) {
    const EvalOptions& a = plan.options;
    Lighting out;
    if (!a.environment.empty()) {
        if (a.calibrate)
            fail("--calibrate: the roughness calibration is made under the directional light, not "
                 "--environment");
        Result<Environment> env = loadEnvironment(a.environment, a.environmentOptions);
        if (!env) fail(env.error().message);
        out.environment = std::make_shared<const EnvironmentLighting>(
            makeEnvironmentLighting(std::move(env.value())));
        const char* reason = "cannot shade under an environment";
        std::vector<MethodSpec> kept;
        for (const MethodSpec& spec : plan.specs) {
            const MethodShader* shader = findShader(spec.render);
            if (shader && shader->shadeEnvironment)
                kept.push_back(spec);
            else
                out.skipped.emplace_back(spec.label, reason);
        }
        plan.specs = std::move(kept);
        const MethodShader* roughnessMips = findShader(kRoughnessMips);
        if (!(roughnessMips && roughnessMips->shadeEnvironment))
            for (const ExternalRoughness& row : plan.externals)
                out.skipped.emplace_back(row.name, reason);
    }
    out.externalRows = !plan.externals.empty() &&
                       (!out.environment || findShader(kRoughnessMips)->shadeEnvironment);
    return out;
}

} // namespace ndfmip::evaluation
