// A method's own options as data: each method declares the parameters its bake takes (key,
// command-line flag, type, range, default, help, the commands that take it) in one table in its
// folder. The command line's options, their checks and "applies to --method X only" rules, the
// cache key, the manifest's ranges, Python's keywords and eval's method specs (`vmf:8:0.01`) are
// read from it, so a new option is one table row beside the code that uses it.
#pragma once

#include <limits>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "ndfmip/bake.h"
#include "ndfmip/result.h"

namespace ndfmip {

enum class ParameterType {
    Integer, // a whole number in [min, max]
    Float,   // a number kept at float precision (what the bake stores it as)
    Double,  // a number kept at double precision
};

// The commands a parameter reaches (bit set): bake it, or bake on the fly for a render, the
// viewer or an evaluation.
enum ParameterCommand : unsigned {
    kParameterBake = 1u << 0,
    kParameterRender = 1u << 1,
    kParameterView = 1u << 2,
    kParameterEval = 1u << 3,
};

struct MethodParameter {
    const char* key;  // in manifests, cache keys, JSON and as Python's keyword: "lobes"
    const char* flag; // on the command line: "--lobes"
    ParameterType type;
    double min, max;
    double defaultValue;   // what the bake uses when the parameter is not given
    const char* help;      // one line for the option's help, without the method's name
    unsigned commands;     // ParameterCommand bits
    bool recorded = false; // a bake records it in its parameters: a manifest must hold it in range
    int specPosition = -1; // its place in eval's METHOD:A:B specs (0 = A), -1 = not there
    // The value the cache key records when the parameter is not given: the default for most; 0
    // for those whose default the bake chooses ("0 = the default"), as bakes have always keyed.
    bool keyedZeroWhenUnset = false;
    // A bake written to files (bakeFile: `ndfmip bake`, Python's bake_to), which engines and the
    // GPU read through hardware filtering, uses this instead of defaultValue when the parameter
    // is not given and the method's rules allow it beside the values given; NaN: defaultValue.
    double fileDefault = std::numeric_limits<double>::quiet_NaN();
};

// The values a bake written to files uses: `values` and, for each parameter of `method` not in
// it with a fileDefault, that value where checkParameterValues still passes with it.
ParameterValues fileParameterValues(Method method, const ParameterValues& values);

// The method's table (empty for a method without parameters of its own).
const std::vector<MethodParameter>& methodParameters(Method method);

// The parameter of `method` called `key`, or null.
const MethodParameter* findMethodParameter(Method method, const std::string& key);

// Every parameter of every method, as (method, parameter): the flags the commands register.
std::vector<std::pair<Method, const MethodParameter*>> allMethodParameters();

// `values[key]` when given, else the parameter's default (the table of `method` must have it).
double parameterValue(Method method, const ParameterValues& values, const std::string& key);

// The values of `values` that `method`'s table has (a command's options reach every method it
// may bake; each bake takes its own).
ParameterValues parametersOf(Method method, const ParameterValues& values);

// How messages name a parameter: by its flag ("--lobes 9: expected 1 .. 8") or by its key
// ("lobes 9: ..."), as the caller's user spelled it.
enum class ParameterNaming { Flag, Key };

// Each given value known to `method`, of its type and in its range, and the method's own rules
// between them (e.g. --lobe-budget does not apply to coherent lobes). A value no parameter of
// `method` takes fails as "--lobes applies to --method vmf only" (the methods that take it), or
// as unknown. The first problem as one line.
Status checkParameterValues(Method method, const ParameterValues& values, ParameterNaming naming);

// Each given value a parameter of some method that `use` (a ParameterCommand bit) takes, of its
// type and in its range: the check of a command whose values reach whichever method it bakes.
Status checkCommandParameterValues(const ParameterValues& values, unsigned use,
                                   ParameterNaming naming);

// eval's spec of a method with parameters, e.g. "vmf:8:0.01": the values after the name in
// their specPosition order. An error names the spec and what it takes.
Result<ParameterValues> parseParameterSpec(Method method, const std::string& spec,
                                           const std::vector<std::string>& values);
// "a lobe count 1 .. 8 and optionally :lobe_budget (0 .. 10)": what a spec of `method` takes.
std::string parameterSpecHelp(Method method);

} // namespace ndfmip
