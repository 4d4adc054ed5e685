// `ndfmip view`: a one-line error without a display; under a virtual X server (Xvfb) it opens
// its window, draws frames of every mode and quits.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>

#include <gtest/gtest.h>

#include "test_support.h"

namespace ndfmip {
namespace {

const std::string kScene = std::string(NDFMIP_SOURCE_DIR) + "/scenes/sphere.json";

// Unsets an environment variable for the scope, restoring it after.
struct Unset {
    std::string name;
    std::optional<std::string> saved;
    explicit Unset(const char* variable) : name(variable) {
        if (const char* v = std::getenv(variable)) saved = v;
        unsetenv(variable);
    }
    ~Unset() {
        if (saved) setenv(name.c_str(), saved->c_str(), 1);
    }
};

TEST(ViewCli, WithoutADisplayIsAOneLineError) {
    Unset display("DISPLAY"), wayland("WAYLAND_DISPLAY");
    std::string output;
    const int status = test::runCli("view " + test::shellArg(kScene), &output);
    if (output.find("built without a window system") != std::string::npos) GTEST_SKIP() << output;
    test::expectOneLineError(status, output, {"no display"});
}

TEST(ViewCli, DrawsEveryModeInAVirtualXServer) {
    if (!std::filesystem::exists("/usr/bin/xvfb-run"))
        GTEST_SKIP() << "xvfb-run (xvfb) not installed";
    test::TempDir dir("ndfmip_view");
    for (const std::string& mode : {std::string("--method vmf --lobes 3 --split --mip-levels"),
                                    std::string("--method toksvig --taps 1 --lod-bias 0"),
                                    std::string("--method sh --order 4")}) {
        const std::string log = dir.file("view.log");
        const std::string command = "timeout 120 xvfb-run -a " + test::shellArg(NDFMIP_CLI_PATH) +
                                    " view " + test::shellArg(kScene) + " --frames 2 " + mode +
                                    " > " + test::shellArg(log) + " 2>&1";
        const int status = std::system(command.c_str());
        std::ifstream in(log);
        const std::string output((std::istreambuf_iterator<char>(in)), {});
        if (output.find("built without a window system") != std::string::npos)
            GTEST_SKIP() << output;
        EXPECT_EQ(status, 0) << mode << ": " << output;
        EXPECT_NE(output.find("view: 2 frames of"), std::string::npos) << mode << ": " << output;
    }
}

} // namespace
} // namespace ndfmip
