// Fuzzes the scene parser: JSON text in, a checked Scene or a one-line error out.
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_limits.h"
#include "ndfmip/scene.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    ndfmip::setFuzzLimits();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace ndfmip;
    const std::string text(reinterpret_cast<const char*>(data), size);
    // Relative table paths resolve against a folder that does not exist.
    Result<Scene> scene = parseScene(text, "scene.json", "/nonexistent-fuzz-dir");
    if (!scene) {
        const std::string& m = scene.error().message;
        FUZZ_CHECK(m.rfind("scene.json: ", 0) == 0);
        FUZZ_CHECK(m.find('\n') == std::string::npos);
        FUZZ_CHECK(m.size() < 8192);
        return 0;
    }
    FUZZ_CHECK(!scene->lights.empty());
    FUZZ_CHECK(int64_t(scene->camera.width) * scene->camera.height <=
               inputLimits().maxCameraPixels);
    return 0;
}
