// Fuzzes image decoding (every format, chosen by the bytes' signature, as loadImage does).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz_limits.h"
#include "ndfmip/io.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    ndfmip::setFuzzLimits();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace ndfmip;
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    Result<SourceImage> image = decodeImage(bytes, "fuzz");
    if (!image) {
        FUZZ_CHECK(image.error().message.rfind("fuzz: ", 0) == 0);
        FUZZ_CHECK(image.error().message.find('\n') == std::string::npos);
        return 0;
    }
    const Image& i = image->image;
    FUZZ_CHECK(i.width > 0 && i.height > 0 && i.channels >= 1 && i.channels <= 4);
    FUZZ_CHECK(int64_t(i.width) * i.height <= inputLimits().maxPixels);
    FUZZ_CHECK(i.pixels.size() == i.texelCount() * size_t(i.channels));
    return 0;
}
