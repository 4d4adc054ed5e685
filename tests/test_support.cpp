#include "test_support.h"

#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <sys/wait.h>

namespace ndfmip::test {

TempDir::TempDir(const std::string& tag) {
    std::random_device rd;
    path = std::filesystem::temp_directory_path() /
           ("ndfmip_" + tag + "_" + std::to_string(rd()) + std::to_string(rd()));
    std::filesystem::create_directories(path);
}

TempDir::~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
}

std::filesystem::path sharedNormalMaps() {
    auto dir = std::filesystem::path(NDFMIP_SOURCE_DIR) / ".." / "shared" / "data" / "normalmaps";
    return std::filesystem::is_directory(dir) ? dir : std::filesystem::path();
}

int runCli(const std::string& args, std::string* output) {
    std::string command = std::string("\"") + NDFMIP_CLI_PATH + "\" " + args + " 2>&1";
    FILE* pipe = popen(command.c_str(), "r");
    if (!pipe) return -1;
    std::array<char, 4096> buffer;
    std::string text;
    size_t n;
    while ((n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0) text.append(buffer.data(), n);
    int status = pclose(pipe);
    if (output) *output = text;
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

void setNormal(Image& map, int x, int y, float nx, float ny, float nz) {
    float len = std::sqrt(nx * nx + ny * ny + nz * nz);
    float* t = map.at(x, y);
    t[0] = nx / len;
    t[1] = ny / len;
    t[2] = nz / len;
}

} // namespace ndfmip::test
