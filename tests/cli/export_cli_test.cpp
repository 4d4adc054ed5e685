// bake --export ktx2,dds: the files every level in one container each, listed in the manifest,
// the bake still read back; DDS headers as an independent reader (nvddsinfo) sees them.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "test_support.h"

namespace ndfmip {
namespace {

const std::string kMap = std::string(NDFMIP_SOURCE_DIR) + "/data/normalmaps/pyramidwall_256.png";

nlohmann::json manifestOf(const std::string& dir) {
    std::ifstream in(dir + "/manifest.json");
    return nlohmann::json::parse(in);
}

TEST(ExportCli, ToksvigWritesNormalRoughnessAndPlaneContainers) {
    test::TempDir dir("ndfmip_export");
    const std::string out = dir.file("wall.bake");
    std::string output;
    ASSERT_EQ(test::runCli("bake " + test::shellArg(kMap) + " --green-down --method toksvig --export ktx2,dds,png16 -o " +
                           test::shellArg(out), &output),
              0)
        << output;
    const nlohmann::json m = manifestOf(out);
    for (const char* container : {"ktx2", "dds"}) {
        ASSERT_TRUE(m["exports"].contains(container)) << m["exports"].dump();
        const auto names = m["exports"][container].get<std::vector<std::string>>();
        for (const char* stem : {"normal_bc5", "roughness_bc4", "mean"})
            EXPECT_NE(std::find(names.begin(), names.end(), std::string(container) + "/" + stem + "." + container), names.end())
                << stem;
        for (const std::string& name : names) EXPECT_TRUE(std::filesystem::exists(out + "/" + name)) << name;
    }
    EXPECT_TRUE(m["exports"].contains("png16"));
    // The bake is still a bake: inspect reads it, and a rebake replaces it.
    ASSERT_EQ(test::runCli("inspect " + test::shellArg(out) + " --level 3 --texel 1,1", &output), 0) << output;
    ASSERT_EQ(test::runCli("bake " + test::shellArg(kMap) + " --green-down --method vmf --lobes 2 --export ktx2 -o " +
                           test::shellArg(out), &output),
              0)
        << output;
    const auto names = manifestOf(out)["exports"]["ktx2"].get<std::vector<std::string>>();
    EXPECT_EQ(names, (std::vector<std::string>{"ktx2/lobe0.ktx2", "ktx2/lobe1.ktx2"}));
    EXPECT_FALSE(std::filesystem::exists(out + "/dds"));
}

TEST(ExportCli, DdsHeaderAsNvddsinfoReadsIt) {
    if (!std::filesystem::exists("/usr/bin/nvddsinfo")) GTEST_SKIP() << "nvddsinfo (libnvtt-bin) not installed";
    test::TempDir dir("ndfmip_export_dds");
    const std::string out = dir.file("wall.bake");
    std::string output;
    ASSERT_EQ(test::runCli("bake " + test::shellArg(kMap) + " --green-down --method toksvig --export dds -o " + test::shellArg(out),
                           &output),
              0)
        << output;
    const std::string info = dir.file("info.txt");
    ASSERT_EQ(std::system(("nvddsinfo " + test::shellArg(out + "/dds/normal_bc5.dds") + " > " + test::shellArg(info)).c_str()), 0);
    std::ifstream in(info);
    const std::string text((std::istreambuf_iterator<char>(in)), {});
    EXPECT_NE(text.find("Width: 256"), std::string::npos) << text;
    EXPECT_NE(text.find("Mipmap count: 9"), std::string::npos) << text;
    EXPECT_NE(text.find("DXGI Format: 83"), std::string::npos) << text; // BC5_UNORM
}

TEST(ExportCli, UnknownExportsAndForeignPathsAreRefused) {
    test::TempDir dir("ndfmip_export_bad");
    test::expectCliRefuses("bake " + test::shellArg(kMap) + " --export ktx3 -o " + test::shellArg(dir.file("x")),
                           {"--export", "ktx3"});
    const std::string out = dir.file("wall.bake");
    std::string output;
    ASSERT_EQ(test::runCli("bake " + test::shellArg(kMap) + " --export ktx2 -o " + test::shellArg(out), &output), 0) << output;
    nlohmann::json m = manifestOf(out);
    m["exports"]["ktx2"][0] = "../../etc/passwd";
    std::ofstream(out + "/manifest.json") << m.dump(2);
    test::expectCliRefuses("inspect " + test::shellArg(out) + " --texel 0,0", {"exports.ktx2", "not ktx2/"});
}

} // namespace
} // namespace ndfmip
