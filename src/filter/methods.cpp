// Method names and dispatch.
#include "ndfmip/bake.h"

namespace ndfmip {

std::optional<Method> methodFromString(std::string_view name) {
    for (Method m : allMethods())
        if (name == methodName(m)) return m;
    return std::nullopt;
}

const char* methodName(Method method) {
    switch (method) {
    case Method::Naive: return "naive";
    case Method::Toksvig: return "toksvig";
    case Method::Sh: return "sh";
    case Method::Vmf: return "vmf";
    case Method::Lean: return "lean";
    }
    return "?";
}

std::vector<Method> allMethods() {
    return {Method::Naive, Method::Toksvig, Method::Sh, Method::Vmf, Method::Lean};
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

int bakeVmfLobes(const Bake& bake) {
    auto it = bake.parameters.find("lobes");
    return bake.method == Method::Vmf && it != bake.parameters.end() ? int(it->second) : 0;
}

Bake bakeMethod(Method method, const Pyramid& pyramid, const BakeOptions& options) {
    switch (method) {
    case Method::Naive: return bakeNaive(pyramid, options);
    case Method::Toksvig: return bakeToksvig(pyramid, options);
    case Method::Sh: return bakeSh(pyramid, options);
    case Method::Vmf: return bakeVmf(pyramid, options);
    case Method::Lean: return bakeLean(pyramid, options);
    }
    return {};
}

} // namespace ndfmip
