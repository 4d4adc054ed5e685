// The method table: every bake method and every shader, and the names the tool takes.
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "methods/method_unit.h"

namespace ndfmip {

const std::vector<MethodUnit>& methodUnits() {
    static const std::vector<MethodUnit> units = {
        naiveUnit(), toksvigUnit(), shUnit(), vmfUnit(), leanUnit(), ggxFitUnit(), ggxAnisoUnit()};
    return units;
}

const MethodUnit& methodUnit(Method method) {
    for (const MethodUnit& unit : methodUnits())
        if (unit.method == method) return unit;
    throw std::logic_error("no unit for a method");
}

const std::vector<MethodShader>& methodShaders() {
    static const std::vector<MethodShader> shaders = [] {
        std::vector<MethodShader> all;
        for (auto list : {naiveShaders(), toksvigShaders(), shShaders(), vmfShaders(),
                          leanShaders(), ggxFitShaders(), ggxAnisoShaders()})
            all.insert(all.end(), list.begin(), list.end());
        return all;
    }();
    return shaders;
}

const MethodShader* findShader(const std::string& name) {
    for (const MethodShader& shader : methodShaders())
        if (name == shader.name) return &shader;
    return nullptr;
}

std::optional<Method> methodFromString(std::string_view name) {
    for (const MethodUnit& unit : methodUnits())
        if (name == unit.name) return unit.method;
    return std::nullopt;
}

const char* methodName(Method method) {
    return methodUnit(method).name;
}

glm::vec3 bakeLevelZeroNormal(Method method, const float* planes) {
    return methodUnit(method).levelZeroNormal(planes);
}

std::optional<double> bakeNdfDensity(const LoadedBake& bake, int x, int y, glm::dvec3 w) {
    const auto density = methodUnit(bake.method).ndfDensity;
    if (!density) return std::nullopt;
    return density(bake, x, y, w);
}

std::vector<Method> allMethods() {
    std::vector<Method> methods;
    for (const MethodUnit& unit : methodUnits()) methods.push_back(unit.method);
    return methods;
}

std::string methodNames() {
    std::string names;
    for (const MethodUnit& unit : methodUnits()) {
        if (!names.empty()) names += ", ";
        names += unit.name;
    }
    return names;
}

std::string methodSummaries() {
    std::string text;
    for (const MethodUnit& unit : methodUnits()) {
        if (!text.empty()) text += "\n";
        text += unit.name;
        text += ": ";
        text += unit.summary;
    }
    return text;
}

int findPlane(const std::vector<PlaneInfo>& planes, const std::string& name) {
    for (size_t p = 0; p < planes.size(); ++p)
        if (planes[p].name == name) return int(p);
    return -1;
}

int bakeShOrder(const Bake& bake) {
    auto it = bake.parameters.find("order");
    return bake.method == Method::Sh && it != bake.parameters.end() ? int(it->second) : 0;
}

bool bakeFitsMaterialRoughness(Method method) {
    return methodUnit(method).fitsMaterialRoughness;
}

int bakeVmfLobes(const Bake& bake) {
    auto it = bake.parameters.find("lobes");
    return bake.method == Method::Vmf && it != bake.parameters.end() ? int(it->second) : 0;
}

Bake bakeMethod(Method method, const Pyramid& pyramid, const BakeOptions& options) {
    return methodUnit(method).bake(pyramid, options);
}

MethodParameter materialRoughnessParameter() {
    return {.key = "base_roughness",
            .flag = "--base-roughness",
            .type = ParameterType::Float,
            .min = 0,
            .max = 1,
            .defaultValue = 0,
            .help = "GGX/Beckmann alpha of the material before filtering",
            .commands = 0,
            .recorded = true};
}

PlaneInfo planeOf(const std::string& name, int channels, bool linear) {
    return {name, std::vector<std::string>(size_t(channels)), "", linear};
}

nlohmann::json jsonVec3(const float* v) {
    return {v[0], v[1], v[2]};
}

void addUniform(std::vector<UniformValue>& u, const std::string& name, int value) {
    u.push_back({name, true, {float(value)}});
}

void addUniform(std::vector<UniformValue>& u, const std::string& name, float value) {
    u.push_back({name, false, {value}});
}

int requirePlane(const LoadedBake& bake, const std::string& name) {
    const int p = findPlane(bake.planes, name);
    if (p < 0) throw std::runtime_error("bake has no plane '" + name + "'");
    return p;
}

} // namespace ndfmip
