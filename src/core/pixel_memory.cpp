// Pixel allocation (see image.h): huge-page-friendly for large images.
#include <cstdlib>
#include <new>

#include <sys/mman.h>

#include "ndfmip/image.h"

namespace ndfmip {

namespace {
constexpr size_t kHugePage = size_t(2) << 20;
constexpr size_t kLarge = size_t(4) << 20; // smaller blocks: plain malloc
} // namespace

void* allocatePixels(size_t bytes) {
    if (bytes == 0) bytes = 1;
    void* p = nullptr;
    if (bytes >= kLarge) {
        const size_t rounded = (bytes + kHugePage - 1) / kHugePage * kHugePage;
        p = std::aligned_alloc(kHugePage, rounded);
        static const bool huge = [] {
            const char* v = std::getenv("NDFMIP_HUGE_PAGES");
            return v != nullptr && v[0] == '1';
        }();
        if (p && huge) madvise(p, rounded, MADV_HUGEPAGE); // advice only: failure changes nothing
    } else {
        p = std::malloc(bytes);
    }
    if (!p) throw std::bad_alloc();
    return p;
}

void freePixels(void* pointer) noexcept { std::free(pointer); }

} // namespace ndfmip
