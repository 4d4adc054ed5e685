// ndfmip._ndfmip: the Python module's native part. Thin by design: every function converts its
// arguments, releases the GIL, calls the library (the same functions the command-line tool
// calls, so results match it bit for bit) and converts the result back. Images leave as numpy
// arrays that own the library's buffer (no copy); float32 C-contiguous arrays come in without a
// conversion, and arrays that ndfmip itself returned go back in without any copy.
#include <cmath>
#include <cstring>
#include <exception>
#include <new>
#include <optional>
#include <stdexcept>
#include <string>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "ndfmip/bake.h"
#include "ndfmip/bake_batch.h"
#include "ndfmip/bake_file.h"
#include "ndfmip/compare.h"
#include "ndfmip/environment_file.h"
#include "ndfmip/evaluate.h"
#include "ndfmip/io.h"
#include "ndfmip/limits.h"
#include "ndfmip/method_parameters.h"
#include "ndfmip/normal_map.h"
#include "ndfmip/paths.h"
#include "ndfmip/render.h"
#include "ndfmip/scene.h"

namespace py = pybind11;
using namespace ndfmip;

namespace {

// Every failure the library reports; Python sees ndfmip.Error (a ValueError) with its one line,
// made printable (a byte that is not UTF-8 could not even become a Python str).
struct NdfmipError : std::runtime_error {
    explicit NdfmipError(const std::string& message)
        : std::runtime_error(printable(message, 4096)) {}
};

template <class T> T take(Result<T> result) {
    if (!result) throw NdfmipError(result.error().message);
    return std::move(result.value());
}

void check(const Status& status) {
    if (!status) throw NdfmipError(status.error);
}

// ---- images <-> arrays ------------------------------------------------------------------------

constexpr const char* kCapsuleName = "ndfmip.image";

// An H x W x C float32 array over the image's pixels; the capsule holds a reference to the
// image, so the buffer lives as long as the array. Read-only where the image may be shared
// (a bake's planes share the pyramid's means).
py::array toArray(SharedImage image, bool writable) {
    auto* holder = new SharedImage(std::move(image));
    py::capsule owner(holder, kCapsuleName, [](PyObject* capsule) {
        delete static_cast<SharedImage*>(PyCapsule_GetPointer(capsule, kCapsuleName));
    });
    const Image& im = **holder;
    const ssize_t c = im.channels, w = im.width;
    py::array array(
        py::dtype::of<float>(), {ssize_t(im.height), w, c},
        {ssize_t(sizeof(float)) * w * c, ssize_t(sizeof(float)) * c, ssize_t(sizeof(float))},
        im.pixels.data(), owner);
    if (!writable)
        py::detail::array_proxy(array.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
    return array;
}

py::array toArray(Image image) {
    return toArray(std::make_shared<const Image>(std::move(image)), true);
}

// A float32 array of `object` shaped H x W or H x W x C (C in [minChannels, maxChannels]);
// made C-contiguous (a copy only where it is not). Errors name `what`.
py::array_t<float, py::array::c_style> floatArray(py::handle object, const std::string& what,
                                                  int minChannels, int maxChannels) {
    if (!py::isinstance<py::array>(object))
        throw NdfmipError(what + ": expected a numpy array, not " +
                          std::string(py::str(py::type::of(object).attr("__name__"))));
    auto array = py::reinterpret_borrow<py::array>(object);
    // Equality, not identity: a float32 dtype with metadata is float32 all the same.
    if (!array.dtype().equal(py::dtype::of<float>())) {
        // Say what differs: a float32 of the other byte order prints as >f4.
        const bool swapped = array.dtype().kind() == 'f' && array.dtype().itemsize() == 4;
        throw NdfmipError(what + ": expected dtype float32" +
                          (swapped ? " in native byte order" : "") + ", not " +
                          std::string(py::str(array.dtype())) +
                          " (convert with .astype(numpy.float32))");
    }
    std::string shape;
    for (ssize_t d = 0; d < array.ndim(); ++d) {
        if (d) shape += ", ";
        shape += std::to_string(array.shape(d));
    }
    const ssize_t channels = array.ndim() == 3 ? array.shape(2) : 1;
    if (array.ndim() < 2 || array.ndim() > 3 || array.shape(0) < 1 || array.shape(1) < 1 ||
        channels < minChannels || channels > maxChannels) {
        const std::string want = minChannels == maxChannels ? std::to_string(minChannels)
                                                            : std::to_string(minChannels) + " .. " +
                                                                  std::to_string(maxChannels);
        throw NdfmipError(what + ": expected shape (H, W, C) with C = " + want +
                          (minChannels == 1 ? " (or (H, W))" : "") + ", not (" + shape + ")");
    }
    // The limits (set_limits) hold before anything is copied: a broadcast view of 12 bytes can
    // stand for gigabytes.
    check(checkImageSize(what, array.shape(1), array.shape(0)));
    const int64_t bytes = int64_t(array.shape(0)) * int64_t(array.shape(1)) * int64_t(channels) * 4;
    if (bytes > inputLimits().maxMemoryBytes)
        throw NdfmipError(what + ": " + std::to_string(array.shape(1)) + "x" +
                          std::to_string(array.shape(0)) + "x" + std::to_string(channels) +
                          " float32 needs " + byteSize(bytes) + ", above the limit of " +
                          byteSize(inputLimits().maxMemoryBytes) +
                          "; set_limits(max_memory_gib=...) raises it");
    auto contiguous = py::array_t<float, py::array::c_style>::ensure(array);
    // ensure() gives an empty handle (and clears the error) when the copy fails.
    if (!contiguous)
        throw NdfmipError(what + ": cannot make a C-contiguous float32 copy of " + byteSize(bytes) +
                          " (out of memory?)");
    return contiguous;
}

// The image an array came from when ndfmip made it and it still covers the whole image.
SharedImage ownImage(const py::array_t<float, py::array::c_style>& array) {
    const py::handle base = array.base();
    if (!base || !PyCapsule_IsValid(base.ptr(), kCapsuleName)) return nullptr;
    const SharedImage& image =
        *static_cast<SharedImage*>(PyCapsule_GetPointer(base.ptr(), kCapsuleName));
    const ssize_t channels = array.ndim() == 3 ? array.shape(2) : 1;
    if (array.data() != image->pixels.data() || array.shape(0) != image->height ||
        array.shape(1) != image->width || channels != image->channels)
        return nullptr;
    return image;
}

// A copy of the array's pixels in a library image. Call with the GIL held.
Image copyToImage(const py::array_t<float, py::array::c_style>& array) {
    const int channels = array.ndim() == 3 ? int(array.shape(2)) : 1;
    Image image(int(array.shape(1)), int(array.shape(0)), channels, Image::Uninitialized{});
    py::gil_scoped_release release;
    std::memcpy(image.pixels.data(), array.data(), image.pixels.size() * sizeof(float));
    return image;
}

// The array as a library image: ndfmip's own without a copy, any other copied once (the
// library's images own their aligned storage). Call with the GIL held.
SharedImage toImage(py::handle object, const std::string& what, int minChannels, int maxChannels) {
    auto array = floatArray(object, what, minChannels, maxChannels);
    if (SharedImage own = ownImage(array)) return own;
    return std::make_shared<const Image>(copyToImage(array));
}

bool isPath(py::handle object) {
    return py::isinstance<py::str>(object) ||
           py::isinstance(object, py::module_::import("os").attr("PathLike"));
}

// A path from Python, refused when it holds NUL or control characters (paths.h).
const std::string& checkedPath(const std::string& path) {
    check(checkUntrustedPath(path));
    return path;
}

std::string pathOf(py::handle object) {
    return checkedPath(py::str(py::module_::import("os").attr("fspath")(object)));
}

// ---- decoding ---------------------------------------------------------------------------------

DecodeOptions decodeOptions(bool greenDown, bool twoChannel, bool signedValues,
                            std::optional<float> height, bool clamp) {
    DecodeOptions d;
    d.greenDown = greenDown;
    d.twoChannel = twoChannel;
    d.signedValues = signedValues;
    // As the command line resolves --height: a scale > 0 makes the input a height map.
    d.height = height.has_value();
    d.heightScale = height.value_or(1.f);
    if (height && !(*height >= 1e-6f && *height <= 1e6f))
        throw NdfmipError("height " + std::to_string(*height) + ": expected 1e-06 .. 1e+06");
    d.address = clamp ? AddressMode::Clamp : AddressMode::Wrap;
    return d;
}

py::array decode(const std::string& path, bool greenDown, bool twoChannel, bool signedValues,
                 std::optional<float> height, bool clamp) {
    const DecodeOptions d = decodeOptions(greenDown, twoChannel, signedValues, height, clamp);
    Result<Image> normals = Error{};
    {
        py::gil_scoped_release release;
        normals = loadNormalMap(checkedPath(path), d, nullptr);
    }
    return toArray(take(std::move(normals)));
}

py::array normalsFromArray(py::handle array, bool greenDown, bool twoChannel, bool signedValues,
                           std::optional<float> height, bool clamp) {
    const DecodeOptions d = decodeOptions(greenDown, twoChannel, signedValues, height, clamp);
    // Decoding writes new normals, so the raw values are read from one copy.
    SourceImage source{copyToImage(floatArray(array, "array", 1, 4)), 32, true, "array"};
    Result<Image> normals = Error{};
    {
        py::gil_scoped_release release;
        normals = decodeNormalMap(source, d, "array", nullptr);
    }
    return toArray(take(std::move(normals)));
}

py::array loadImageArray(const std::string& path) {
    Result<SourceImage> source = Error{};
    {
        py::gil_scoped_release release;
        source = loadImage(checkedPath(path));
    }
    return toArray(take(std::move(source)).image);
}

// Unit normals (or shorter: gloss), finite: what a pyramid is built from.
Status checkNormals(const Image& n) {
    for (size_t i = 0; i < n.texelCount(); ++i) {
        const float* p = &n.pixels[3 * i];
        const float length = length3(p);
        if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]) ||
            !(length > 0.f) || length > 1.001f) {
            char text[200];
            std::snprintf(
                text, sizeof text,
                "normals: texel (%zu, %zu) holds (%g, %g, %g), not a normal of length 1 or less "
                "(decode raw values with ndfmip.normals_from_array)",
                i % size_t(n.width), i / size_t(n.width), p[0], p[1], p[2]);
            return Status::failure(text);
        }
    }
    return Status::success();
}

// ---- bakes ------------------------------------------------------------------------------------

// A bake in memory and where it came from (for its manifest when written).
struct PyBake {
    Bake bake;
    BakeSource source;
};

py::dict planeDict(const PlaneInfo& p) {
    py::dict d;
    d["name"] = p.name;
    d["channels"] = p.channels;
    d["description"] = p.description;
    d["linear"] = p.linear;
    return d;
}

py::dict levelDict(const PyBake& b, int level) {
    if (level < 0 || level >= int(b.bake.levels.size()))
        throw NdfmipError("level " + std::to_string(level) + " out of range (the bake has " +
                          std::to_string(b.bake.levels.size()) + " levels)");
    py::dict planes;
    for (size_t p = 0; p < b.bake.planes.size(); ++p)
        planes[py::str(b.bake.planes[p].name)] = toArray(b.bake.levels[size_t(level)][p], false);
    return planes;
}

// The method parameters given as keywords (lobes=2, max_iterations=5: the keys of the methods'
// tables, method_parameters.h), each a number; Float ones at float precision, as the bake keeps
// them. Which method takes them is checked where they are used.
ParameterValues parameterValues(const py::dict& keywords) {
    ParameterValues values;
    for (const auto& [k, v] : keywords) {
        const std::string key = py::str(k);
        const MethodParameter* p = nullptr;
        for (const auto& [method, parameter] : allMethodParameters())
            if (key == parameter->key && parameter->commands != 0) p = parameter;
        if (!p)
            throw NdfmipError("unknown keyword " + quote(key) + " (method parameters: " + [] {
                std::string keys;
                for (const auto& [method, parameter] : allMethodParameters())
                    if (parameter->commands != 0 && keys.find(parameter->key) == std::string::npos)
                        keys += (keys.empty() ? "" : ", ") + std::string(parameter->key);
                return keys;
            }() + ")");
        if (py::isinstance<py::bool_>(v) ||
            !(py::isinstance<py::int_>(v) || py::isinstance<py::float_>(v)))
            throw NdfmipError(key + ": expected a number, not " +
                              std::string(py::str(py::type::of(v).attr("__name__"))));
        if (p->type == ParameterType::Integer && !py::isinstance<py::int_>(v))
            throw NdfmipError(key + ": expected an integer, not " + std::string(py::str(v)));
        const double value = v.cast<double>();
        values[key] = p->type == ParameterType::Float ? double(float(value)) : value;
    }
    return values;
}

PyBake bake(py::handle normals, const std::string& methodName, const py::dict& parameters,
            float baseRoughness, py::object roughness, py::object albedo, bool greenDown,
            bool twoChannel, bool signedValues, std::optional<float> height, bool clamp) {
    const std::optional<Method> method = methodFromString(methodName);
    if (!method)
        throw NdfmipError("unknown method " + quote(methodName) + " (" + methodNames() + ")");
    PyBake out;
    out.source.decode = decodeOptions(greenDown, twoChannel, signedValues, height, clamp);
    SharedImage map;
    if (isPath(normals)) {
        out.source.path = pathOf(normals);
        py::gil_scoped_release release;
        out.source.sha256 = take(sha256File(out.source.path));
        map = std::make_shared<const Image>(
            take(loadNormalMap(out.source.path, out.source.decode, nullptr)));
    } else {
        map = toImage(normals, "normals", 3, 3);
        py::gil_scoped_release release;
        check(checkNormals(*map));
        // An array has no file: its manifest names the bytes of its normals.
        out.source.sha256 = sha256Text(std::string(
            reinterpret_cast<const char*>(map->pixels.data()), map->pixels.size() * sizeof(float)));
    }
    out.source.width = map->width;
    out.source.height = map->height;
    BakeOptions options;
    options.parameters = parameterValues(parameters);
    options.baseRoughness = baseRoughness;
    if (!roughness.is_none()) options.roughnessMap = toImage(roughness, "roughness", 1, 1);
    if (!albedo.is_none()) options.albedo = toImage(albedo, "albedo", 3, 4);
    py::gil_scoped_release release;
    check(checkBakeOptions(*method, options, map->width, map->height));
    out.bake = bakeMethod(*method, buildPyramid(map), options);
    return out;
}

PyBake readBakeDir(const std::string& dir) {
    checkedPath(dir);
    py::gil_scoped_release release;
    PyBake out;
    out.bake = take(loadBake(dir));
    // The manifest's source, from the 1x1 level (no large plane read twice).
    out.source = take(readBake(dir, int(out.bake.levels.size()) - 1)).source;
    return out;
}

// The export options by their command-line meaning (bake_file.h), for writeBake.
BakeFileOptions exportOptions(const std::string& method, py::object exports,
                              const std::string& exportTextures, const std::string& normalFormat,
                              const std::string& roughnessFormat, int zstd,
                              const std::string& engine, bool half) {
    BakeFileOptions o;
    o.method = method;
    if (py::isinstance<py::str>(exports))
        o.exportFormat = exports.cast<std::string>();
    else if (!exports.is_none())
        for (py::handle e : exports) {
            if (!o.exportFormat.empty()) o.exportFormat += ",";
            o.exportFormat += e.cast<std::string>();
        }
    o.exportTextures = exportTextures;
    o.normalFormat = normalFormat;
    o.roughnessFormat = roughnessFormat;
    o.zstd = zstd;
    o.engine = engine;
    o.half = half;
    return o;
}

void writeBakeDir(const PyBake& b, const std::string& dir, py::object exports, bool half,
                  const std::string& exportTextures, const std::string& normalFormat,
                  const std::string& roughnessFormat, int zstd, const std::string& engine) {
    const BakeFileOptions o = exportOptions(methodName(b.bake.method), exports, exportTextures,
                                            normalFormat, roughnessFormat, zstd, engine, half);
    checkedPath(dir); // before a cleanup beside a path that a NUL would cut short
    py::gil_scoped_release release;
    const BakeWriteOptions write = take(bakeWriteOptions(o));
    recoverInterruptedBake(dir);
    check(writeBake(dir, b.bake, b.source, write));
}

// bake_to's and bake_many's options, as `ndfmip bake` takes them (bake_file.h).
BakeFileOptions
bakeFileOptions(const std::string& method, const py::dict& parameters, const std::string& albedo,
                bool half, const std::string& gloss, float maxExponent, float baseRoughness,
                const std::string& roughnessMap, const std::string& roughnessChannel,
                const std::string& roughnessEncoding, const std::string& engine,
                const std::string& metallicChannel, const std::string& occlusionChannel,
                py::object exports, const std::string& exportTextures,
                const std::string& normalFormat, const std::string& roughnessFormat, int zstd,
                bool force, bool greenDown, bool twoChannel, bool signedValues,
                std::optional<float> height, bool clamp) {
    for (const std::string* path : {&albedo, &gloss, &roughnessMap}) checkedPath(*path);
    BakeFileOptions o = exportOptions(method, exports, exportTextures, normalFormat,
                                      roughnessFormat, zstd, engine, half);
    o.decode = decodeOptions(greenDown, twoChannel, signedValues, height, clamp);
    o.parameters = parameterValues(parameters);
    o.albedo = albedo;
    o.gloss = gloss;
    o.maxExponent = maxExponent;
    o.baseRoughness = baseRoughness;
    o.roughnessMap = roughnessMap;
    o.roughnessChannel = roughnessChannel;
    o.roughnessEncoding = roughnessEncoding;
    o.metallicChannel = metallicChannel;
    o.occlusionChannel = occlusionChannel;
    o.force = force;
    return o;
}

py::dict bakeTo(const std::string& input, const std::string& output,
                const BakeFileOptions& options) {
    for (const std::string* path : {&input, &output}) checkedPath(*path);
    Result<BakeFileReport> result = Error{};
    {
        py::gil_scoped_release release;
        result = bakeFile(input, output, options);
    }
    const BakeFileReport r = take(std::move(result));
    py::dict d;
    d["input"] = input;
    d["output"] = output;
    d["status"] = r.skipped ? "skipped" : "baked";
    d["cache_key"] = r.cacheKey;
    d["method"] = methodName(r.method);
    if (!r.skipped) {
        d["width"] = r.width;
        d["height"] = r.height;
        d["levels"] = r.levels;
        d["parameters"] = r.parameters;
        d["off_unit_length"] = r.decode.offUnitLength;
        d["degenerate"] = r.decode.degenerate;
        d["facing_down"] = r.decode.facingDown;
        d["seconds"] = (r.decodeMs + r.bakeMs + r.writeMs) * 1e-3;
    }
    return d;
}

// `ndfmip bake INPUTS... -o PATTERN --jobs J --shard I/N`: every map of the shard, each one's
// status ("baked", "skipped", "failed" with its error) and seconds; a failed map never stops
// the others, a bad plan (pattern, shard) raises before any bake.
py::list bakeMany(const std::vector<std::string>& inputs, const std::string& pattern,
                  const BakeFileOptions& options, int jobs, int shard, int shards) {
    for (const std::string& input : inputs) checkedPath(input);
    checkedPath(pattern);
    check(checkBakeFileOptions(options));
    if (jobs < 1 || jobs > 256)
        throw NdfmipError("jobs " + std::to_string(jobs) + ": expected 1 to 256");
    std::vector<BakeBatchMap> maps;
    {
        py::gil_scoped_release release;
        const BakeInputs expanded = take(expandBakeInputs(inputs));
        maps = take(planBakeBatch(expanded, pattern, shard, shards));
        runBakeBatch(maps, options, jobs);
    }
    py::list out;
    for (const BakeBatchMap& m : maps) {
        py::dict d;
        d["input"] = m.input;
        d["output"] = m.output;
        d["status"] = m.status;
        d["seconds"] = m.seconds;
        if (!m.error.empty()) d["error"] = m.error;
        out.append(d);
    }
    return out;
}

// `ndfmip envmap INPUT -o OUTPUT` (environment_file.h): what was written and each step's time.
py::dict envmapTo(const std::string& input, const std::string& output, float intensity,
                  float rotation, int shOrder, int size, int levels, int samples,
                  const std::string& layout, const std::string& lodMapping, int dfgSize,
                  int dfgSamples, bool half, bool ktx2, bool dds) {
    for (const std::string* path : {&input, &output}) checkedPath(*path);
    EnvironmentFileOptions o;
    o.environment.intensity = intensity;
    o.environment.rotationDegrees = rotation;
    o.shOrder = shOrder;
    o.size = size;
    o.levels = levels;
    o.samples = samples;
    o.layout = layout;
    o.lodMapping = lodMapping;
    o.dfgSize = dfgSize;
    o.dfgSamples = dfgSamples;
    o.half = half;
    o.ktx2 = ktx2;
    o.dds = dds;
    Result<EnvironmentFileReport> result = Error{};
    {
        py::gil_scoped_release release;
        result = environmentFile(input, output, o);
    }
    const EnvironmentFileReport r = take(std::move(result));
    py::dict d;
    d["input"] = input;
    d["output"] = output;
    d["width"] = r.width;
    d["height"] = r.height;
    d["negative_texels"] = r.negativeTexels;
    d["perceptual_roughness"] = r.perceptualRoughness;
    d["seconds"] = (r.loadMs + r.shMs + r.ggxMs + r.dfgMs + r.writeMs) * 1e-3;
    return d;
}

py::object jsonLoads(const std::string& text) {
    return py::module_::import("json").attr("loads")(text);
}

py::object inspect(const std::string& dir, int level, int x, int y, std::optional<float> exponent) {
    std::string text;
    checkedPath(dir);
    {
        py::gil_scoped_release release;
        const LoadedBake bake = take(readBake(dir, level));
        text = take(inspectTexel(bake, dir, level, x, y, exponent));
    }
    return jsonLoads(text);
}

// The methods' parameter tables as Python sees them: one dict per parameter.
py::list methodParameterTable() {
    py::list table;
    for (const auto& [method, p] : allMethodParameters()) {
        if (p->commands == 0) continue;
        py::list commands;
        for (const auto& [bit, name] : {std::pair{kParameterBake, "bake"},
                                        {kParameterRender, "render"},
                                        {kParameterView, "view"},
                                        {kParameterEval, "eval"}})
            if (p->commands & bit) commands.append(name);
        py::dict d;
        d["method"] = methodName(method);
        d["key"] = p->key;
        d["flag"] = p->flag;
        d["type"] = p->type == ParameterType::Integer ? "int" : "float";
        d["min"] = p->min;
        d["max"] = p->max;
        d["default"] = p->defaultValue;
        d["help"] = p->help;
        d["commands"] = commands;
        table.append(d);
    }
    return table;
}

// ---- render, compare, evaluate ------------------------------------------------------------------

py::array renderScene(py::handle sceneObject, const std::optional<std::string>& methodArg,
                      std::optional<int> spp, const std::string& bakeDir, uint64_t seed,
                      const std::string& truth, int taps, float lodBias,
                      const std::string& lobeFilter, int anisotropy, const py::dict& parameters,
                      const std::string& roughnessMapping, const std::string& baseDir,
                      float specularAa, float specularAaThreshold) {
    checkedPath(bakeDir);
    checkedPath(baseDir);
    Result<Scene> scene = Error{};
    if (py::isinstance<py::dict>(sceneObject)) {
        const std::string text = py::str(py::module_::import("json").attr("dumps")(sceneObject));
        const std::string base =
            baseDir.empty() ? std::string(py::str(py::module_::import("os").attr("getcwd")()))
                            : baseDir;
        scene = parseScene(text, "scene", base);
    } else {
        const std::string path = pathOf(sceneObject);
        py::gil_scoped_release release;
        scene = loadScene(path);
    }
    const Scene s = take(std::move(scene));
    const std::string method = methodArg.value_or(s.method);
    RenderOptions options;
    options.spp = spp.value_or(method == kGroundTruth ? 64 : 1);
    options.seed = seed;
    if (!truthFilterFromString(truth, options.truth))
        throw NdfmipError("truth: " + quote(truth) + " is not box or bilinear");
    if (!shadeFilterFromString(lobeFilter, options.shadeFilter))
        throw NdfmipError("lobe_filter: " + quote(lobeFilter) + " is not parameter or texel");
    options.taps = taps;
    options.lodBias = lodBias;
    options.anisotropy = anisotropy;
    options.specularAntiAliasing = {specularAa, specularAaThreshold};
    if (!roughnessMappingFromString(roughnessMapping, options.roughnessMapping))
        throw NdfmipError("unknown roughness mapping " + quote(roughnessMapping) +
                          " (expected ours, hdrp, filament, godot, unreal)");
    check(checkRenderOptions(options));
    SceneTextureOptions load;
    load.bakeDir = bakeDir;
    load.bakeParameters = parameterValues(parameters);
    check(checkCommandParameterValues(load.bakeParameters, kParameterRender, ParameterNaming::Key));
    Result<Image> image = Error{};
    {
        py::gil_scoped_release release;
        const RenderTextures textures = take(loadSceneTextures(s, method, load));
        image = render(s, textures, method, options);
    }
    return toArray(take(std::move(image)));
}

py::object number(double v) {
    return std::isfinite(v) ? py::object(py::float_(v)) : py::object(py::none());
}

SharedImage imageArgument(py::handle object, const std::string& what) {
    if (isPath(object)) {
        const std::string path = pathOf(object);
        py::gil_scoped_release release;
        return std::make_shared<const Image>(take(loadImage(path)).image);
    }
    return toImage(object, what, 1, 4);
}

SharedImage channelOf(const SharedImage& image, int channel, const std::string& what) {
    if (channel < 0 || channel >= image->channels)
        throw NdfmipError(what + ": channel " + std::to_string(channel) +
                          " is out of range (the image has " + std::to_string(image->channels) +
                          (image->channels == 1 ? " channel)" : " channels)"));
    auto out = std::make_shared<Image>(image->width, image->height, 1);
    for (size_t t = 0; t < image->texelCount(); ++t)
        out->pixels[t] = image->pixels[t * size_t(image->channels) + size_t(channel)];
    return out;
}

py::dict compare(py::handle a, py::handle b, std::optional<int> channel) {
    // Named as the tool names them: the paths, or "a" and "b" for arrays.
    const std::string nameA = isPath(a) ? pathOf(a) : "a", nameB = isPath(b) ? pathOf(b) : "b";
    SharedImage ia = imageArgument(a, nameA), ib = imageArgument(b, nameB);
    if (channel) {
        ia = channelOf(ia, *channel, nameA);
        ib = channelOf(ib, *channel, nameB);
    }
    Result<ImageComparison> compared = Error{};
    {
        py::gil_scoped_release release;
        compared = compareImages(*ia, *ib);
    }
    if (!compared) throw NdfmipError(nameA + " vs " + nameB + ": " + compared.error().message);
    const ImageComparison c = compared.value();
    py::dict d;
    d["width"] = c.width;
    d["height"] = c.height;
    d["channels"] = c.channels;
    d["rmse"] = number(c.rmse);
    d["rel_rmse"] = number(c.relativeRmse);
    d["psnr"] = number(c.psnr);
    d["energy_ratio"] = number(c.energyRatio);
    d["max_abs_error"] = number(c.maxAbsError);
    return d;
}

py::object runEvaluation(EvalOptions o) {
    Result<EvalResult> result = Error{};
    {
        py::gil_scoped_release release;
        result = evaluateMaps(o);
    }
    return jsonLoads(take(std::move(result)).json);
}

void setLimits(std::optional<int64_t> maxPixels, std::optional<double> maxMemoryGib) {
    InputLimits limits = inputLimits();
    if (maxPixels) {
        if (*maxPixels < 1) throw NdfmipError("max_pixels must be at least 1");
        limits.maxPixels = limits.maxCameraPixels = *maxPixels;
    }
    if (maxMemoryGib) {
        if (!(*maxMemoryGib > 0.0 && *maxMemoryGib <= 1e6))
            throw NdfmipError("max_memory_gib: expected 0 .. 1e6");
        limits.maxMemoryBytes = int64_t(*maxMemoryGib * double(int64_t(1) << 30));
    }
    setInputLimits(limits);
}

} // namespace

PYBIND11_MODULE(_ndfmip, m) {
    m.doc() = "ndfmip's native functions; use the ndfmip package, which documents them.";
    m.attr("__version__") = NDFMIP_VERSION;
    static PyObject* error =
        py::register_exception<NdfmipError>(m, "Error", PyExc_ValueError).ptr();
    // An allocation that fails raises ndfmip.Error naming the file being processed, not
    // MemoryError.
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const std::bad_alloc&) {
            PyErr_SetString(error, printable(outOfMemoryMessage(), 4096).c_str());
        }
    });
    m.attr("Error").attr("__module__") = "ndfmip";

    using namespace py::literals;
    m.def("decode", &decode, "path"_a, "green_down"_a, "two_channel"_a, "signed"_a, "height"_a,
          "clamp"_a);
    m.def("normals_from_array", &normalsFromArray, "array"_a, "green_down"_a, "two_channel"_a,
          "signed"_a, "height"_a, "clamp"_a);
    m.def("load_image", &loadImageArray, "path"_a);

    py::class_<PyBake>(m, "Bake")
        .def_property_readonly(
            "method", [](const PyBake& b) { return std::string(methodName(b.bake.method)); })
        .def_property_readonly("parameters", [](const PyBake& b) { return b.bake.parameters; })
        .def_property_readonly("planes",
                               [](const PyBake& b) {
                                   py::list planes;
                                   for (const PlaneInfo& p : b.bake.planes)
                                       planes.append(planeDict(p));
                                   return planes;
                               })
        .def_property_readonly("level_count", [](const PyBake& b) { return b.bake.levels.size(); })
        .def("level", &levelDict, "level"_a)
        .def_property_readonly("source",
                               [](const PyBake& b) {
                                   py::dict d;
                                   d["path"] = b.source.path;
                                   d["sha256"] = b.source.sha256;
                                   d["width"] = b.source.width;
                                   d["height"] = b.source.height;
                                   return d;
                               })
        .def("write", &writeBakeDir, "dir"_a, "exports"_a, "half"_a, "export_textures"_a,
             "normal_format"_a, "roughness_format"_a, "zstd"_a, "engine"_a);

    m.def("bake", &bake, "normals"_a, "method"_a, "parameters"_a, "base_roughness"_a, "roughness"_a,
          "albedo"_a, "green_down"_a, "two_channel"_a, "signed"_a, "height"_a, "clamp"_a);
    m.def("read_bake", &readBakeDir, "dir"_a);
    py::class_<BakeFileOptions>(m, "BakeFileOptions"); // opaque: bake_file_options() makes it
    m.def("bake_file_options", &bakeFileOptions, "method"_a, "parameters"_a, "albedo"_a, "half"_a,
          "gloss"_a, "max_exponent"_a, "base_roughness"_a, "roughness_map"_a, "roughness_channel"_a,
          "roughness_encoding"_a, "engine"_a, "metallic_channel"_a, "occlusion_channel"_a,
          "exports"_a, "export_textures"_a, "normal_format"_a, "roughness_format"_a, "zstd"_a,
          "force"_a, "green_down"_a, "two_channel"_a, "signed"_a, "height"_a, "clamp"_a);
    m.def("bake_to", &bakeTo, "input"_a, "output"_a, "options"_a);
    m.def("bake_many", &bakeMany, "inputs"_a, "output"_a, "options"_a, "jobs"_a, "shard"_a,
          "shards"_a);
    m.def("envmap_to", &envmapTo, "input"_a, "output"_a, "intensity"_a, "rotation"_a, "sh_order"_a,
          "size"_a, "levels"_a, "samples"_a, "layout"_a, "lod_mapping"_a, "dfg_size"_a,
          "dfg_samples"_a, "half"_a, "ktx2"_a, "dds"_a);
    m.def("inspect", &inspect, "dir"_a, "level"_a, "x"_a, "y"_a, "exponent"_a);
    m.def("render", &renderScene, "scene"_a, "method"_a, "spp"_a, "bake"_a, "seed"_a, "truth"_a,
          "taps"_a, "lod_bias"_a, "lobe_filter"_a, "anisotropy"_a, "parameters"_a,
          "roughness_mapping"_a, "base_dir"_a, "specular_aa"_a, "specular_aa_threshold"_a);
    m.def("method_parameters", &methodParameterTable);
    m.def("compare", &compare, "a"_a, "b"_a, "channel"_a);

    py::class_<EvalOptions>(m, "EvalOptions")
        .def(py::init<>())
        .def_readwrite("maps", &EvalOptions::maps)
        .def_readwrite("output", &EvalOptions::output)
        .def_readwrite("footprints", &EvalOptions::footprints)
        .def_readwrite("methods", &EvalOptions::methods)
        .def_readwrite("brdfs", &EvalOptions::brdfs)
        .def_readwrite("exponents", &EvalOptions::exponents)
        .def_readwrite("roughness", &EvalOptions::roughness)
        .def_readwrite("pixels", &EvalOptions::maxPixels)
        .def_readwrite("spp", &EvalOptions::spp)
        .def_readwrite("frames", &EvalOptions::frames)
        .def_readwrite("seed", &EvalOptions::seed)
        .def_readwrite("calibrate", &EvalOptions::calibrate)
        .def_readwrite("all_images", &EvalOptions::allImages)
        .def_readwrite("webgl", &EvalOptions::webgl)
        .def_readwrite("coherent", &EvalOptions::coherence)
        .def_readwrite("aligned", &EvalOptions::aligned)
        .def_readwrite("offset", &EvalOptions::offset)
        .def_readwrite("truth", &EvalOptions::truth)
        .def_readwrite("taps", &EvalOptions::taps)
        .def_readwrite("lod_bias", &EvalOptions::lodBias)
        .def_readwrite("anisotropy", &EvalOptions::anisotropy)
        .def_readwrite("lobe_filter", &EvalOptions::lobeFilter)
        .def_readwrite("view", &EvalOptions::view)
        .def_readwrite("elevation", &EvalOptions::elevation)
        .def_readwrite("light_polar", &EvalOptions::lightPolar)
        .def_property(
            "specular_aa", [](const EvalOptions& o) { return o.specularAntiAliasing.variance; },
            [](EvalOptions& o, float v) { o.specularAntiAliasing.variance = v; })
        .def_property(
            "specular_aa_threshold",
            [](const EvalOptions& o) { return o.specularAntiAliasing.threshold; },
            [](EvalOptions& o, float v) { o.specularAntiAliasing.threshold = v; })
        .def("set_decode", [](EvalOptions& o, bool greenDown, bool twoChannel, bool signedValues,
                              std::optional<float> height, bool clamp) {
            o.decode = decodeOptions(greenDown, twoChannel, signedValues, height, clamp);
        });
    m.def("evaluate", &runEvaluation, "options"_a);
    m.def("set_limits", &setLimits, "max_pixels"_a, "max_memory_gib"_a);
}
