// Helpers shared by the tests: temporary folders, the shared real-data folder, running the CLI.
#pragma once

#include <filesystem>
#include <string>

#include "ndfmip/image.h"

namespace ndfmip::test {

// A fresh empty folder under the system temp dir, removed when the object dies.
struct TempDir {
    std::filesystem::path path;
    explicit TempDir(const std::string& tag);
    ~TempDir();
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    std::string file(const std::string& name) const { return (path / name).string(); }
};

// ../shared/data/normalmaps beside the checkout, or empty when it does not exist
// (tests that need it call GTEST_SKIP()).
std::filesystem::path sharedNormalMaps();

// Runs the built CLI with `args` (a shell-quoted string); returns the exit status and
// fills `output` with stdout and stderr together.
int runCli(const std::string& args, std::string* output);

// Stores (nx, ny, nz) normalised to unit length at texel (x, y).
void setNormal(Image& map, int x, int y, float nx, float ny, float nz);

} // namespace ndfmip::test
