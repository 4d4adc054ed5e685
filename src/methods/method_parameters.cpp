// The methods' parameter tables read as one: lookups, defaults, the checks every command and
// Python share, and eval's METHOD:A:B specs.
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "methods/method_unit.h"
#include "ndfmip/method_parameters.h"

namespace ndfmip {
namespace {

std::string number(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", value);
    return text;
}

std::string nameOf(const MethodParameter& p, ParameterNaming naming) {
    return naming == ParameterNaming::Flag ? p.flag : p.key;
}

// "vmf" or "sh and vmf": the methods whose tables have `key`.
std::string methodsTaking(const std::string& key) {
    std::vector<std::string> names;
    for (const MethodUnit& unit : methodUnits())
        for (const MethodParameter& p : unit.parameters)
            if (key == p.key) names.push_back(unit.name);
    std::string text;
    for (size_t i = 0; i < names.size(); ++i)
        text += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + names[i];
    return text;
}

// The flag of the first parameter called `key` in any table, or the key itself.
std::string anyName(const std::string& key, ParameterNaming naming) {
    for (const auto& [method, p] : allMethodParameters())
        if (key == p->key) return nameOf(*p, naming);
    return key;
}

} // namespace

const std::vector<MethodParameter>& methodParameters(Method method) {
    return methodUnit(method).parameters;
}

const MethodParameter* findMethodParameter(Method method, const std::string& key) {
    for (const MethodParameter& p : methodParameters(method))
        if (key == p.key) return &p;
    return nullptr;
}

std::vector<std::pair<Method, const MethodParameter*>> allMethodParameters() {
    std::vector<std::pair<Method, const MethodParameter*>> all;
    for (const MethodUnit& unit : methodUnits())
        for (const MethodParameter& p : unit.parameters) all.emplace_back(unit.method, &p);
    return all;
}

double parameterValue(Method method, const ParameterValues& values, const std::string& key) {
    const MethodParameter* p = findMethodParameter(method, key);
    if (!p) throw std::logic_error(std::string(methodName(method)) + " has no parameter " + key);
    auto it = values.find(key);
    return it == values.end() ? p->defaultValue : it->second;
}

ParameterValues parametersOf(Method method, const ParameterValues& values) {
    ParameterValues own;
    for (const auto& [key, value] : values)
        if (findMethodParameter(method, key)) own[key] = value;
    return own;
}

// `value` of p's type and in its range, or the problem.
static Status checkValue(const MethodParameter& p, double value, ParameterNaming naming) {
    const bool whole = p.type != ParameterType::Integer || value == std::floor(value);
    if (value >= p.min && value <= p.max && whole) return Status::success();
    return Status::failure(nameOf(p, naming) + " " + number(value) + ": expected " +
                           (p.type == ParameterType::Integer ? "a whole number " : "") +
                           number(p.min) + " .. " + number(p.max));
}

Status checkParameterValues(Method method, const ParameterValues& values, ParameterNaming naming) {
    const char* methodWord = naming == ParameterNaming::Flag ? "--method " : "method ";
    for (const auto& [key, value] : values) {
        const MethodParameter* p = findMethodParameter(method, key);
        if (!p) {
            const std::string takers = methodsTaking(key);
            if (takers.empty()) return Status::failure("unknown parameter " + quote(key));
            return Status::failure(anyName(key, naming) + " applies to " + methodWord + takers +
                                   " only");
        }
        if (Status s = checkValue(*p, value, naming); !s) return s;
    }
    if (const MethodUnit& unit = methodUnit(method); unit.checkParameters)
        return unit.checkParameters(values, naming);
    return Status::success();
}

ParameterValues fileParameterValues(Method method, const ParameterValues& values) {
    ParameterValues out = values;
    for (const MethodParameter& p : methodParameters(method)) {
        if (std::isnan(p.fileDefault) || out.count(p.key)) continue;
        ParameterValues with = out;
        with[p.key] = p.fileDefault;
        if (checkParameterValues(method, with, ParameterNaming::Key)) out = std::move(with);
    }
    return out;
}

Status checkCommandParameterValues(const ParameterValues& values, unsigned use,
                                   ParameterNaming naming) {
    for (const auto& [key, value] : values) {
        const MethodParameter* taker = nullptr;
        for (const auto& [method, p] : allMethodParameters())
            if (key == p->key && (p->commands & use)) taker = p;
        if (!taker) return Status::failure("unknown parameter " + quote(key));
        if (Status s = checkValue(*taker, value, naming); !s) return s;
    }
    return Status::success();
}

Result<ParameterValues> parseParameterSpec(Method method, const std::string& spec,
                                           const std::vector<std::string>& texts) {
    std::vector<const MethodParameter*> positions;
    for (const MethodParameter& p : methodParameters(method))
        if (p.specPosition >= 0) {
            if (positions.size() <= size_t(p.specPosition))
                positions.resize(size_t(p.specPosition) + 1);
            positions[size_t(p.specPosition)] = &p;
        }
    auto refuse = [&] {
        return Error{"--methods: " + quote(spec) + ": " + std::string(methodName(method)) +
                     " takes " + parameterSpecHelp(method)};
    };
    if (texts.size() > positions.size()) return refuse();
    ParameterValues values;
    for (size_t i = 0; i < texts.size(); ++i) {
        const MethodParameter& p = *positions[i];
        char* end = nullptr;
        const double value = p.type == ParameterType::Integer
                                 ? double(std::strtol(texts[i].c_str(), &end, 10))
                                 : std::strtod(texts[i].c_str(), &end);
        if (texts[i].empty() || *end != '\0' || !std::isfinite(value)) return refuse();
        values[p.key] = p.type == ParameterType::Float ? double(float(value)) : value;
    }
    if (!checkParameterValues(method, values, ParameterNaming::Key)) return refuse();
    return values;
}

std::string parameterSpecHelp(Method method) {
    std::string text;
    int position = 0;
    for (bool found = true; found; ++position) {
        found = false;
        for (const MethodParameter& p : methodParameters(method))
            if (p.specPosition == position) {
                const std::string range = number(p.min) + " .. " + number(p.max);
                text += position == 0
                            ? std::string(p.key) + " " + range
                            : " and optionally :" + std::string(p.key) + " (" + range + ")";
                found = true;
            }
    }
    return text.empty() ? "nothing" : text;
}

} // namespace ndfmip
