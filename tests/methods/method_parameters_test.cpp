// The methods' parameter tables: well formed, the one source of the checks, the cache key and
// eval's specs.
#include <fstream>
#include <iterator>
#include <set>
#include <tuple>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "methods/method_unit.h"
#include "ndfmip/bake_file.h"
#include "ndfmip/io.h"
#include "ndfmip/method_parameters.h"
#include "ndfmip/vmf.h"

using namespace ndfmip;

TEST(MethodParameters, TablesAreWellFormed) {
    for (const MethodUnit& unit : methodUnits()) {
        SCOPED_TRACE(unit.name);
        std::set<std::string> keys, flags;
        for (const MethodParameter& p : unit.parameters) {
            SCOPED_TRACE(p.key);
            EXPECT_TRUE(keys.insert(p.key).second);
            EXPECT_TRUE(flags.insert(p.flag).second);
            EXPECT_EQ(std::string(p.flag).rfind("--", 0), 0u);
            EXPECT_LE(p.min, p.defaultValue);
            EXPECT_GE(p.max, p.defaultValue);
            EXPECT_TRUE(
                checkParameterValues(unit.method, {{p.key, p.defaultValue}}, ParameterNaming::Key));
            EXPECT_NE(std::string(p.help), "");
        }
    }
    // A key shared by two methods means the same option: one type and range.
    for (const auto& [m1, p1] : allMethodParameters())
        for (const auto& [m2, p2] : allMethodParameters())
            if (std::string(p1->key) == p2->key) {
                EXPECT_EQ(std::string(p1->flag), p2->flag);
                EXPECT_EQ(p1->type, p2->type);
            }
}

TEST(MethodParameters, TheLobeLimitIsTheShadersArrays) {
    const MethodParameter* lobes = findMethodParameter(Method::Vmf, "lobes");
    ASSERT_NE(lobes, nullptr);
    EXPECT_EQ(lobes->max, kMaxVmfBakeLobes);
    EXPECT_LE(kMaxVmfBakeLobes, kMaxVmfLobes);
    EXPECT_EQ(parameterValue(Method::Vmf, {}, "lobes"), 4.0);
    EXPECT_EQ(parameterValue(Method::Vmf, {{"lobes", 6}}, "lobes"), 6.0);
}

TEST(MethodParameters, ChecksNameTheParameterAsTheCallerSpellsIt) {
    auto error = [](Method m, const ParameterValues& v, ParameterNaming n) {
        Status s = checkParameterValues(m, v, n);
        return s ? std::string() : s.error;
    };
    EXPECT_EQ(error(Method::Vmf, {{"lobes", 9}}, ParameterNaming::Flag),
              "--lobes 9: expected a whole number 1 .. 8");
    EXPECT_EQ(error(Method::Vmf, {{"lobes", 2.5}}, ParameterNaming::Key),
              "lobes 2.5: expected a whole number 1 .. 8");
    EXPECT_EQ(error(Method::Vmf, {{"tolerance", 2}}, ParameterNaming::Key),
              "tolerance 2: expected 0 .. 1");
    EXPECT_EQ(error(Method::Toksvig, {{"lobes", 2}}, ParameterNaming::Flag),
              "--lobes applies to --method vmf only");
    EXPECT_EQ(error(Method::Vmf, {{"order", 3}}, ParameterNaming::Key),
              "order applies to method sh only");
    EXPECT_EQ(error(Method::Vmf, {{"max_iterations", 5}, {"lobes", 2}}, ParameterNaming::Key), "");
    EXPECT_EQ(error(Method::Sh, {{"bands", 3}}, ParameterNaming::Key), "unknown parameter 'bands'");
    // vmf's own rule between two of its values.
    EXPECT_EQ(error(Method::Vmf, {{"coherent", 1}, {"lobe_budget", 0.01}}, ParameterNaming::Flag),
              "--lobe-budget does not apply to coherent lobes");
    EXPECT_EQ(error(Method::Vmf, {{"coherent", 1}, {"lobe_budget", 0}}, ParameterNaming::Flag), "");
    // A command's values reach whichever method it bakes: ranges only.
    EXPECT_TRUE(checkCommandParameterValues({{"lobes", 2}, {"order", 3}}, kParameterRender,
                                            ParameterNaming::Key));
    EXPECT_FALSE(
        checkCommandParameterValues({{"order", 31}}, kParameterRender, ParameterNaming::Key));
    EXPECT_FALSE(
        checkCommandParameterValues({{"coherent", 1}}, kParameterRender, ParameterNaming::Key));
}

TEST(MethodParameters, EvalSpecsReadTheTablesPositions) {
    Result<ParameterValues> vmf = parseParameterSpec(Method::Vmf, "vmf:8:0.01", {"8", "0.01"});
    ASSERT_TRUE(vmf) << vmf.error().message;
    EXPECT_EQ(vmf->at("lobes"), 8.0);
    EXPECT_EQ(vmf->at("lobe_budget"), double(0.01f)); // kept as the bake keeps it
    Result<ParameterValues> sh = parseParameterSpec(Method::Sh, "sh:12", {"12"});
    ASSERT_TRUE(sh);
    EXPECT_EQ(sh->at("order"), 12.0);
    for (const auto& [method, spec, values] :
         {std::tuple{Method::Vmf, "vmf:9", std::vector<std::string>{"9"}},
          {Method::Vmf, "vmf:x", {"x"}},
          {Method::Vmf, "vmf:4:11", {"4", "11"}},
          {Method::Vmf, "vmf:4:0:1", {"4", "0", "1"}},
          {Method::Sh, "sh:2.5", {"2.5"}},
          {Method::Sh, "sh:", {""}},
          {Method::Toksvig, "toksvig:3", {"3"}}}) {
        Result<ParameterValues> parsed = parseParameterSpec(method, spec, values);
        ASSERT_FALSE(parsed) << spec;
        EXPECT_NE(parsed.error().message.find(spec), std::string::npos) << parsed.error().message;
    }
    EXPECT_EQ(parameterSpecHelp(Method::Vmf), "lobes 1 .. 8 and optionally :lobe_budget (0 .. 10)");
    EXPECT_EQ(parameterSpecHelp(Method::Toksvig), "nothing");
}

// The cache key from the tables is the key earlier versions wrote for the same options (their
// fixed list of keys, written out here), so bakes made by them stay up to date.
// The project's version as CMakeLists.txt's project() line gives it (what the library is built
// with).
std::string projectVersion() {
    std::ifstream in(std::string(NDFMIP_SOURCE_DIR) + "/CMakeLists.txt");
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string key = "project(ndfmip VERSION ";
    const size_t at = text.find(key);
    if (at == std::string::npos) return "";
    const size_t from = at + key.size();
    return text.substr(from, text.find_first_not_of("0123456789.", from) - from);
}

// A bake written to files: vmf's lobes coherent unless --coherent or --lobe-budget (which plain
// lobes take) is given; nothing else changes.
TEST(MethodParameters, FileBakesTakeTheFileDefaultsTheMethodsRulesAllow) {
    EXPECT_EQ(fileParameterValues(Method::Vmf, {}),
              (ParameterValues{{"coherent", kHardwareFilteringCoherence}}));
    EXPECT_EQ(fileParameterValues(Method::Vmf, {{"lobes", 6}}),
              (ParameterValues{{"lobes", 6}, {"coherent", kHardwareFilteringCoherence}}));
    EXPECT_EQ(fileParameterValues(Method::Vmf, {{"coherent", 0}}),
              (ParameterValues{{"coherent", 0}}));
    EXPECT_EQ(fileParameterValues(Method::Vmf, {{"lobe_budget", 0.01}}),
              (ParameterValues{{"lobe_budget", 0.01}}));
    EXPECT_EQ(fileParameterValues(Method::Vmf, {{"lobe_budget", 0}}),
              (ParameterValues{{"lobe_budget", 0}, {"coherent", kHardwareFilteringCoherence}}));
    EXPECT_EQ(fileParameterValues(Method::Sh, {}), ParameterValues{});
    // The library's own default (bakes on the fly, shaded texel by texel) stays plain.
    EXPECT_EQ(parameterValue(Method::Vmf, {}, "coherent"), 0.0);
}

TEST(MethodParameters, CacheKeysAreThoseOfTheFixedOptionList) {
    const std::string version = projectVersion();
    ASSERT_NE(version, "");
    auto earlierKey = [&](int order, int lobes, float coherent, float budget, int iterations,
                          double tolerance) {
        const nlohmann::json options = {{"method", "vmf"},
                                        {"order", order},
                                        {"lobes", lobes},
                                        {"coherent", coherent},
                                        {"lobe_budget", budget},
                                        {"max_iterations", iterations},
                                        {"tolerance", tolerance},
                                        {"half", false},
                                        {"max_exponent", 0.f},
                                        {"base_roughness", 0.f},
                                        {"roughness_channel", "r"},
                                        {"roughness_encoding", "perceptual"},
                                        {"engine", ""},
                                        {"metallic_channel", ""},
                                        {"occlusion_channel", ""},
                                        {"export", ""},
                                        {"export_textures", BakeFileOptions{}.exportTextures},
                                        {"normal_format", "bc5"},
                                        {"roughness_format", "bc4"},
                                        {"zstd", 0},
                                        {"green_down", false},
                                        {"two_channel", false},
                                        {"signed", false},
                                        {"height", false},
                                        {"height_scale", 1.f},
                                        {"clamp", false}};
        return sha256Text("ndfmip " + version + "\n" + options.dump() + "\nsource abc");
    };
    BakeFileOptions o;
    o.method = "vmf";
    // A vmf bake written to files has coherent lobes unless told otherwise: its key is that of
    // --coherent 0.03, and the earlier default's (plain lobes) is --coherent 0's.
    Result<std::string> coherent = bakeCacheKey(o, "abc");
    ASSERT_TRUE(coherent) << coherent.error().message;
    EXPECT_EQ(coherent.value(), earlierKey(0, 0, kHardwareFilteringCoherence, 0.f, 50, 1e-5));
    o.parameters = {{"coherent", 0.0}};
    Result<std::string> plain = bakeCacheKey(o, "abc");
    ASSERT_TRUE(plain) << plain.error().message;
    EXPECT_EQ(plain.value(), earlierKey(0, 0, 0.f, 0.f, 50, 1e-5));
    o.parameters = {{"lobe_budget", 0.01}}; // a budget applies to plain lobes
    EXPECT_EQ(bakeCacheKey(o, "abc").value(), earlierKey(0, 0, 0.f, 0.01f, 50, 1e-5));
    o.parameters = {
        {"lobes", 6}, {"coherent", double(0.3f)}, {"max_iterations", 7}, {"tolerance", 1e-3}};
    Result<std::string> given = bakeCacheKey(o, "abc");
    ASSERT_TRUE(given);
    EXPECT_EQ(given.value(), earlierKey(0, 6, 0.3f, 0.f, 7, 1e-3));
    EXPECT_NE(given.value(), plain.value());
}
