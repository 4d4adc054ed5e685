// Owning float image, rows stored top row first (the order of the image file), channels
// interleaved. Every stage of ndfmip works on these; file formats live in io.h.
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

namespace ndfmip {

struct Image {
    int width = 0;
    int height = 0;
    int channels = 0;
    std::vector<float> pixels; // width * height * channels values

    Image() = default;
    Image(int w, int h, int c) : width(w), height(h), channels(c), pixels(size_t(w) * h * c, 0.f) {}

    bool empty() const { return width <= 0 || height <= 0 || channels <= 0; }
    size_t texelCount() const { return size_t(width) * size_t(height); }
    size_t index(int x, int y) const { return (size_t(y) * width + x) * channels; }
    float* at(int x, int y) { return pixels.data() + index(x, y); }
    const float* at(int x, int y) const { return pixels.data() + index(x, y); }
};

// Images handed between stages without copies (a pyramid's means are a Toksvig bake's plane).
using SharedImage = std::shared_ptr<const Image>;

} // namespace ndfmip
