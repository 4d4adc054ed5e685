// Helpers shared by the tests: temporary folders, the shared real-data folder, running the CLI.
#pragma once

#include <filesystem>
#include <functional>
#include <initializer_list>
#include <map>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "ndfmip/bake.h"
#include "ndfmip/image.h"
#include "ndfmip/result.h"

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

// The two shared maps fits are checked against independent references on: one per green
// convention and bit depth (8-bit, +Y up; 16-bit, DirectX).
struct SharedMap {
    const char* file;
    bool greenDown;
};
inline constexpr SharedMap kReferenceMaps[2] = {{"stktex_generic_rockA_Normal.png", false},
                                                {"Ground010_1K_Normal.png", true}};

// The size x size crop at (x0, y0) of `map` in `dir`, decoded as its convention says.
Result<Image> sharedMapCrop(const std::filesystem::path& dir, const SharedMap& map, int x0, int y0,
                            int size);

// GGX over half vectors written out in double, apart from the shading library: alpha^2 / (pi
// (c^2 (alpha^2 - 1) + 1)^2), 0 for c <= 0.
double ggxReference(double cosH, double alpha);

// A width x height map of the unit normals normal(x, y) (normalised).
SharedImage filledNormals(int width, int height, const std::function<glm::vec3(int, int)>& normal);

// A bake's options with the material's base GGX roughness `alpha`, everything else the default.
BakeOptions withBaseRoughness(float alpha);

// ../shared/data/envmaps beside the checkout (equirectangular HDR maps), or empty.
std::filesystem::path sharedEnvMaps();

// Runs the built CLI with `args` (a shell-quoted string); returns the exit status and
// fills `output` with stdout and stderr together.
int runCli(const std::string& args, std::string* output);

// The same, killed (and reported as status 137) when it runs longer than `seconds`.
int runCliWithin(int seconds, const std::string& args, std::string* output);

// `text` single-quoted for the shell (it must hold no single quote).
std::string shellArg(const std::string& text);

// A clean refusal: a non-zero status below 128 (no crash, no timeout) and exactly one line of
// output that names each of `mentions`.
void expectOneLineError(int status, const std::string& output,
                        std::initializer_list<std::string> mentions);

// Runs the CLI with `args` (at most 60 s) and expects a clean refusal.
void expectCliRefuses(const std::string& args, std::initializer_list<std::string> mentions);

// Paths below `root` that interrupted writes leave (names holding .partial-, .old- or .tmp-).
std::vector<std::string> leftovers(const std::filesystem::path& root);

// Every file below `dir` (relative path -> bytes); empty when dir does not exist.
std::map<std::string, std::string> snapshot(const std::filesystem::path& dir);

std::string fileBytes(const std::filesystem::path& path);
void writeBytes(const std::filesystem::path& path, const std::string& text);

// Stores (nx, ny, nz) normalised to unit length at texel (x, y).
void setNormal(Image& map, int x, int y, float nx, float ny, float nz);

// Random unit normals within `maxTilt` radians of +z, uniform over that cap's projected disc.
Image randomNormals(int w, int h, float maxTilt, unsigned seed);

// Unit normals in 2 x 2 blocks, each block's columns at +-20 degrees along 84 or 96 degrees from
// x, in a checkerboard of blocks: level 1's anisotropic lobes lie near the y axis, each
// neighbour's on the other side of it (where a direction stored with x >= 0 changes sign).
Image blocksAcrossTheVertical(int size);

// Unit normals (values in [-1, 1]) as a normal map's file holds them, (n + 1) / 2.
Image encodedNormals(Image normals);

} // namespace ndfmip::test
