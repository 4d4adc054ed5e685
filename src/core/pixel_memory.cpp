// Pixel allocation (see image.h): huge-page-friendly for large images.
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>

#include <sys/mman.h>

#include "ndfmip/image.h"

namespace ndfmip {

namespace {
constexpr size_t kHugePage = size_t(2) << 20;
constexpr size_t kLarge = size_t(4) << 20; // smaller blocks: plain malloc

bool hugePagesWanted() {
    static const bool wanted = [] {
        const char* v = std::getenv("NDFMIP_HUGE_PAGES");
        return v == nullptr || v[0] != '0';
    }();
    return wanted;
}

} // namespace

size_t freeHugePageBytes(const char* buddyInfo) {
    // Lines "Node 0, zone Normal n0 n1 ... n10": n_k free blocks of 2^k pages of 4 KiB.
    size_t total = 0;
    for (const char* line = buddyInfo; line && *line;) {
        const char* end = std::strchr(line, '\n');
        const char* zone = std::strstr(line, "zone");
        if (zone && (!end || zone < end)) {
            const char* p = zone + 4;
            while (*p == ' ') ++p;
            while (*p && *p != ' ' && *p != '\n') ++p; // the zone's name
            for (int order = 0; *p && *p != '\n'; ++order) {
                char* next = nullptr;
                const unsigned long count = std::strtoul(p, &next, 10);
                if (next == p) break;
                if (order >= 9) total += count * (size_t(4096) << order);
                p = next;
            }
        }
        line = end ? end + 1 : nullptr;
    }
    return total;
}

void* allocatePixels(size_t bytes) {
    if (bytes == 0) bytes = 1;
    void* p = nullptr;
    if (bytes >= kLarge) {
        const size_t rounded = (bytes + kHugePage - 1) / kHugePage * kHugePage;
        p = std::aligned_alloc(kHugePage, rounded);
        if (p && hugePagesWanted()) {
            // Only where the kernel has the 2 MiB pages free already: asking for more than that
            // sends the page faults into compaction, which stalled for seconds when measured.
            char text[4096] = {};
            if (std::FILE* f = std::fopen("/proc/buddyinfo", "r")) {
                text[std::fread(text, 1, sizeof text - 1, f)] = '\0';
                std::fclose(f);
            }
            if (freeHugePageBytes(text) >= 2 * rounded)
                madvise(p, rounded, MADV_HUGEPAGE); // advice only
        }
    } else {
        p = std::malloc(bytes);
    }
    if (!p) throw std::bad_alloc();
    return p;
}

void freePixels(void* pointer) noexcept {
    std::free(pointer);
}

} // namespace ndfmip
