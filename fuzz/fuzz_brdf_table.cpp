// Fuzzes the tabulated-BRDF parser and the table's evaluation.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_limits.h"
#include "ndfmip/sh_brdf.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    ndfmip::setFuzzLimits();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace ndfmip;
    const std::string text(reinterpret_cast<const char*>(data), size);
    Result<TabulatedTransfer> table = parseTabulatedTransfer(text, "table.txt");
    if (!table) {
        FUZZ_CHECK(table.error().message.rfind("table.txt", 0) == 0);
        FUZZ_CHECK(table.error().message.find('\n') == std::string::npos);
        FUZZ_CHECK(table.error().message.size() < 512);
        return 0;
    }
    FUZZ_CHECK(table->anglesDegrees.size() == table->values.size() && table->values.size() >= 2);
    for (double t : {-1.0, 0.0, 0.25, 0.7071, 0.999, 1.0, std::nan("")}) {
        const double v = evaluate(table.value(), t);
        FUZZ_CHECK(std::isfinite(v) && v >= 0.0);
        FUZZ_CHECK(
            std::isfinite(tabulatedFactor(table.value(), std::acos(std::fabs(t) <= 1 ? t : 1))));
    }
    return 0;
}
