// Owning float image, rows stored top row first (the order of the image file), channels
// interleaved. Every stage of ndfmip works on these; file formats live in io.h.
#pragma once

#include <cmath>
#include <cstddef>
#include <memory>
#include <utility>
#include <vector>

namespace ndfmip {

// Pixel storage. Large blocks are aligned to 2 MiB and offered to the kernel as transparent
// huge pages when it has that many 2 MiB pages free (first touching fresh memory in 4 KiB pages
// is the largest cost of a big bake on a VM; NDFMIP_HUGE_PAGES=0 in the environment turns the
// offer off). Asking while the kernel has none free would stall the faults on compaction.
void* allocatePixels(size_t bytes);
void freePixels(void* pointer) noexcept;
// Bytes free in blocks of 2 MiB or more, from the text of /proc/buddyinfo.
size_t freeHugePageBytes(const char* buddyInfo);

template <class T> struct PixelAllocator {
    using value_type = T;
    PixelAllocator() = default;
    template <class U> PixelAllocator(const PixelAllocator<U>&) noexcept {}
    T* allocate(size_t n) { return static_cast<T*>(allocatePixels(n * sizeof(T))); }
    // Elements made without a value are left uninitialised (Image's Uninitialized
    // constructor): a pass that writes every pixel then touches the memory first, in parallel.
    template <class U> void construct(U* p) noexcept { ::new (static_cast<void*>(p)) U; }
    template <class U, class... Args> void construct(U* p, Args&&... args) {
        ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
    void deallocate(T* p, size_t) noexcept { freePixels(p); }
    template <class U> bool operator==(const PixelAllocator<U>&) const noexcept { return true; }
};

using PixelVector = std::vector<float, PixelAllocator<float>>;

struct Image {
    int width = 0;
    int height = 0;
    int channels = 0;
    PixelVector pixels; // width * height * channels values

    Image() = default;
    Image(int w, int h, int c) : width(w), height(h), channels(c), pixels(size_t(w) * h * c, 0.f) {}
    // Pixels left unset, for code that writes every one of them.
    struct Uninitialized {};
    Image(int w, int h, int c, Uninitialized)
        : width(w), height(h), channels(c), pixels(size_t(w) * h * c) {}

    bool empty() const { return width <= 0 || height <= 0 || channels <= 0; }
    size_t texelCount() const { return size_t(width) * size_t(height); }
    size_t index(int x, int y) const { return (size_t(y) * width + x) * channels; }
    float* at(int x, int y) { return pixels.data() + index(x, y); }
    const float* at(int x, int y) const { return pixels.data() + index(x, y); }
};

// Length of the 3-vector stored at p (a texel of a normal or mean-normal image).
inline float length3(const float* p) {
    return std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
}

// p / |p|, or (0, 0, 1) where p is zero: normals that cancel out exactly leave no direction,
// so take the flat one.
inline void normalizeOrFlat(const float* p, float* out) {
    float length = length3(p);
    for (int c = 0; c < 3; ++c) out[c] = length > 0.f ? p[c] / length : (c == 2 ? 1.f : 0.f);
}

// Images handed between stages without copies (a pyramid's means are a Toksvig bake's plane).
using SharedImage = std::shared_ptr<const Image>;

} // namespace ndfmip
