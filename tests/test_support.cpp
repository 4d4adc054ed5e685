#include "test_support.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <random>
#include <sys/wait.h>

#include <gtest/gtest.h>

#include "ndfmip/normal_map.h"
#include "ndfmip/shading.h"

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

Result<Image> sharedMapCrop(const std::filesystem::path& dir, const SharedMap& map, int x0, int y0,
                            int size) {
    DecodeOptions decode;
    decode.greenDown = map.greenDown;
    Result<Image> full = loadNormalMap((dir / map.file).string(), decode, nullptr);
    if (!full) return full;
    if (x0 + size > full->width || y0 + size > full->height)
        return Error{std::string(map.file) + ": smaller than the crop"};
    Image crop(size, size, 3);
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) std::copy_n(full->at(x + x0, y + y0), 3, crop.at(x, y));
    return crop;
}

double ggxReference(double cosH, double alpha) {
    if (cosH <= 0.) return 0.;
    const double a2 = alpha * alpha, d = cosH * cosH * (a2 - 1.) + 1.;
    return a2 / (3.14159265358979323846 * d * d);
}

BakeOptions withBaseRoughness(float alpha) {
    BakeOptions o;
    o.baseRoughness = alpha;
    return o;
}

SharedImage filledNormals(int width, int height, const std::function<glm::vec3(int, int)>& normal) {
    auto image = std::make_shared<Image>(width, height, 3);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const glm::vec3 n = glm::normalize(normal(x, y));
            float* p = image->at(x, y);
            p[0] = n.x, p[1] = n.y, p[2] = n.z;
        }
    return image;
}

std::filesystem::path sharedEnvMaps() {
    auto dir = std::filesystem::path(NDFMIP_SOURCE_DIR) / ".." / "shared" / "data" / "envmaps";
    return std::filesystem::is_directory(dir) ? dir : std::filesystem::path();
}

int runCli(const std::string& args, std::string* output) {
    // runCliWithin's marker: the command runs under timeout(1), killed after that many seconds.
    std::string prefix, rest = args;
    if (args.rfind("__timeout__", 0) == 0) {
        const size_t space = args.find(' ');
        prefix = "timeout -s KILL " + args.substr(11, space - 11) + " ";
        rest = args.substr(space + 1);
    }
    std::string command = prefix + "\"" + NDFMIP_CLI_PATH + "\" " + rest + " 2>&1";
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

int runCliWithin(int seconds, const std::string& args, std::string* output) {
    return runCli("__timeout__" + std::to_string(seconds) + " " + args, output);
}

std::string shellArg(const std::string& text) {
    return "'" + text + "'";
}

void expectOneLineError(int status, const std::string& output,
                        std::initializer_list<std::string> mentions) {
    EXPECT_GT(status, 0) << output;
    EXPECT_LT(status, 128) << "killed by a signal or timed out: " << output;
    EXPECT_EQ(std::count(output.begin(), output.end(), '\n'), 1) << "expected one line:\n"
                                                                 << output;
    for (const std::string& m : mentions)
        EXPECT_NE(output.find(m), std::string::npos) << "'" << m << "' not in: " << output;
}

void expectCliRefuses(const std::string& args, std::initializer_list<std::string> mentions) {
    std::string output;
    int status = runCliWithin(60, args, &output);
    SCOPED_TRACE(args.substr(0, 300));
    expectOneLineError(status, output, mentions);
}

std::vector<std::string> leftovers(const std::filesystem::path& root) {
    std::vector<std::string> found;
    std::error_code ec;
    for (auto it = std::filesystem::recursive_directory_iterator(root, ec);
         !ec && it != std::filesystem::recursive_directory_iterator(); it.increment(ec)) {
        const std::string name = it->path().filename().string();
        for (const char* mark : {".partial-", ".old-", ".tmp-"})
            if (name.find(mark) != std::string::npos) found.push_back(it->path().string());
    }
    return found;
}

std::map<std::string, std::string> snapshot(const std::filesystem::path& dir) {
    std::map<std::string, std::string> files;
    std::error_code ec;
    for (auto it = std::filesystem::recursive_directory_iterator(dir, ec);
         !ec && it != std::filesystem::recursive_directory_iterator(); it.increment(ec))
        if (it->is_regular_file())
            files[std::filesystem::relative(it->path(), dir).string()] = fileBytes(it->path());
    return files;
}

std::string fileBytes(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

void writeBytes(const std::filesystem::path& path, const std::string& text) {
    std::ofstream(path, std::ios::binary).write(text.data(), std::streamsize(text.size()));
}

void setNormal(Image& map, int x, int y, float nx, float ny, float nz) {
    float len = std::sqrt(nx * nx + ny * ny + nz * nz);
    float* t = map.at(x, y);
    t[0] = nx / len;
    t[1] = ny / len;
    t[2] = nz / len;
}

Image blocksAcrossTheVertical(int size) {
    Image map(size, size, 3);
    const float s = std::sin(glm::radians(20.f)), c = std::cos(glm::radians(20.f));
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const float phi = glm::radians(((x / 2 + y / 2) % 2) ? 96.f : 84.f);
            const float side = x % 2 ? s : -s;
            setNormal(map, x, y, side * std::cos(phi), side * std::sin(phi), c);
        }
    return map;
}

Image encodedNormals(Image normals) {
    for (float& v : normals.pixels) v = 0.5f * (v + 1.f);
    return normals;
}

Image randomNormals(int w, int h, float maxTilt, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    Image map(w, h, 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const float t = maxTilt * std::sqrt(u(rng)), p = 2.f * kPi * u(rng);
            setNormal(map, x, y, std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
        }
    return map;
}

} // namespace ndfmip::test
