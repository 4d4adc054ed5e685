// Fuzzes the glTF path: each input is written as a file and filtered as `ndfmip gltf` does
// (container and JSON read, every material's images decoded and baked, the GLB assembled).
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include "fuzz_limits.h"
#include "ndfmip/gltf.h"

namespace fs = std::filesystem;

namespace {

fs::path gRoot;

void removeRoot() {
    std::error_code ec;
    fs::remove_all(gRoot, ec);
}

} // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    ndfmip::setFuzzLimits();
    char pattern[] = "/tmp/ndfmip-fuzz-gltf-XXXXXX";
    if (!::mkdtemp(pattern)) std::abort();
    gRoot = pattern;
    std::atexit(removeRoot);
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    // Read as a .gltf (JSON with uris resolved beside it) and, when it starts like one, a .glb.
    const fs::path path = gRoot / "asset.gltf";
    {
        std::ofstream out(path, std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
    }
    ndfmip::GltfOptions options;
    options.textureFormat = ndfmip::GltfTextureFormat::Dds; // no encoder processes per input
    ndfmip::Result<ndfmip::GltfFiltered> filtered = ndfmip::filterGltf(path.string(), options);
    if (filtered && filtered->glb.empty()) std::abort(); // success always has a file to write
    return 0;
}
