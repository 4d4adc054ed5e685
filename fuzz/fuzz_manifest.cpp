// Fuzzes the bake reader: each input is written as the manifest.json of a folder that holds the
// plane files of a small bake of every method, then read the way inspect and render read it.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <unistd.h>

#include "fuzz_bakes.h"
#include "fuzz_limits.h"
#include "ndfmip/bake.h"
#include "ndfmip/io.h"

namespace fs = std::filesystem;

namespace {

fs::path gRoot, gBake;

void removeRoot() {
    std::error_code ec;
    fs::remove_all(gRoot, ec);
}

} // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    ndfmip::setFuzzLimits();
    char pattern[] = "/tmp/ndfmip-fuzz-manifest-XXXXXX";
    if (!::mkdtemp(pattern)) std::abort();
    gRoot = pattern;
    std::atexit(removeRoot);
    if (!ndfmip::writeFuzzBakes(gRoot)) std::abort();
    // Every method's planes side by side (their names differ), plus each bake's exports.
    gBake = gRoot / "bake";
    fs::create_directories(gBake);
    for (const char* method : {"naive", "toksvig", "sh", "vmf"})
        for (const auto& entry : fs::recursive_directory_iterator(gRoot / method)) {
            const fs::path relative = fs::relative(entry.path(), gRoot / method);
            if (entry.is_directory())
                fs::create_directories(gBake / relative);
            else if (relative != "manifest.json")
                fs::copy_file(entry.path(), gBake / relative, fs::copy_options::overwrite_existing);
        }
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace ndfmip;
    const std::string text(reinterpret_cast<const char*>(data), size);
    Result<LoadedBake> parsed = parseBakeManifest(text, "manifest.json");
    if (!parsed) {
        FUZZ_CHECK(parsed.error().message.rfind("manifest.json: ", 0) == 0);
        FUZZ_CHECK(parsed.error().message.find('\n') == std::string::npos);
        return 0;
    }
    FUZZ_CHECK(!parsed->planes.empty() && !parsed->levelSizes.empty());
    FUZZ_CHECK(parsed->levelFiles.size() == parsed->levelSizes.size());
    // Valid manifests go on to the files.
    if (!writeFileAtomic((gBake / "manifest.json").string(), text)) std::abort();
    for (int level : {0, 1, 99}) {
        Result<LoadedBake> read = readBake(gBake.string(), level);
        if (!read) continue;
        FUZZ_CHECK(read->level.size() == read->planes.size());
        for (size_t p = 0; p < read->level.size(); ++p) {
            FUZZ_CHECK(read->level[p].width == read->levelSizes[size_t(level)].first);
            FUZZ_CHECK(read->level[p].height == read->levelSizes[size_t(level)].second);
            FUZZ_CHECK(read->level[p].channels == int(read->planes[p].channels.size()));
        }
    }
    Result<Bake> bake = loadBake(gBake.string());
    if (bake) FUZZ_CHECK(bake->levels.size() == parsed->levelSizes.size());
    return 0;
}
