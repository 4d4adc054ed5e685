// From decoded pixels to unit tangent-space normals (OpenGL convention, +Y towards the top
// row), checking the input looks like a normal map and counting what looks wrong.
#include "ndfmip/normal_map.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>

#include "io/input_file.h"

namespace ndfmip {
namespace {

// Row-major scan so the message names the first bad texel a user would look at.
Result<bool> checkFinite(const Image& image, int usedChannels, const std::string& name) {
    for (int y = 0; y < image.height; ++y) {
        for (int x = 0; x < image.width; ++x) {
            const float* t = image.at(x, y);
            for (int c = 0; c < usedChannels; ++c) {
                if (!std::isfinite(t[c]))
                    return fileError(name, "texel (" + std::to_string(x) + ", " +
                                               std::to_string(y) +
                                               ") is not a finite number (NaN or Inf)");
            }
        }
    }
    return true;
}

struct RawNormal {
    float x, y, z;
};

// The stored value of one texel as a (not yet unit) normal.
RawNormal rawNormal(const float* t, bool twoChannel, bool stored) {
    auto decode = [stored](float c) { return stored ? c : 2.f * c - 1.f; };
    float x = decode(t[0]);
    float y = decode(t[1]);
    if (twoChannel) return {x, y, std::sqrt(std::max(0.f, 1.f - x * x - y * y))};
    return {x, y, decode(t[2])};
}

// Unit-normalises every texel of `raw` (3 channels) in place, filling the counts. Returns the
// index of the first texel whose length overflows a float (a component near 1e19 or more:
// dividing by an infinite length would leave a silent zero normal), or -1.
int64_t renormalise(Image& raw, DecodeReport& report) {
    const int64_t count = int64_t(raw.texelCount());
    size_t offUnit = 0, degenerate = 0, facingDown = 0;
    int64_t firstOverflow = count;
    float* p = raw.pixels.data();
#pragma omp parallel for reduction(+ : offUnit, degenerate, facingDown) \
    reduction(min : firstOverflow) schedule(static)
    for (int64_t i = 0; i < count; ++i) {
        float* n = p + 3 * i;
        float length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (!std::isfinite(length)) {
            firstOverflow = std::min(firstOverflow, i);
            continue;
        }
        if (std::abs(length - 1.f) > 0.1f) ++offUnit;
        if (length < 1e-3f) {
            ++degenerate;
            n[0] = 0.f, n[1] = 0.f, n[2] = 1.f;
            continue;
        }
        n[0] /= length, n[1] /= length, n[2] /= length;
        if (n[2] < 0.f) ++facingDown;
    }
    report = {size_t(count), offUnit, degenerate, facingDown};
    return firstOverflow < count ? firstOverflow : -1;
}

// Channel 0 of `image` as a one-channel height field.
Image firstChannel(const Image& image) {
    Image height(image.width, image.height, 1);
    for (size_t i = 0; i < height.pixels.size(); ++i)
        height.pixels[i] = image.pixels[i * size_t(image.channels)];
    return height;
}

Result<Image> decodeHeight(const SourceImage& source, const DecodeOptions& options,
                           const std::string& name) {
    if (auto finite = checkFinite(source.image, 1, name); !finite) return finite.error();
    // greenDown does not apply: a height map has no green convention, and the normals
    // built from it are already +Y up.
    return heightToNormals(firstChannel(source.image), options.heightScale, options.address);
}

Result<Image> decodeVectors(const SourceImage& source, const DecodeOptions& options,
                            const std::string& name) {
    const Image& in = source.image;
    int used = options.twoChannel ? 2 : 3;
    if (in.channels < used) {
        std::string count = std::to_string(in.channels);
        if (options.twoChannel)
            return fileError(name, "has " + count + " channel(s); --two-channel needs at least 2");
        return fileError(name, "has " + count + " channel(s); a normal map needs 3 (use " +
                                   "--two-channel for RG maps or --height for height maps)");
    }
    if (auto finite = checkFinite(in, used, name); !finite) return finite.error();
    // Integer formats cannot hold negative values, so signedValues only applies to floats.
    bool stored = source.isFloat && options.signedValues;
    float ySign = options.greenDown ? -1.f : 1.f;
    Image out(in.width, in.height, 3);
    const int64_t count = int64_t(in.texelCount());
#pragma omp parallel for schedule(static)
    for (int64_t i = 0; i < count; ++i) {
        RawNormal n = rawNormal(in.pixels.data() + i * in.channels, options.twoChannel, stored);
        float* o = out.pixels.data() + 3 * i;
        o[0] = n.x, o[1] = ySign * n.y, o[2] = n.z;
    }
    return out;
}

// Derivative along one axis at index i of n samples, `at(j)` giving the sample at j.
template <class Sample> double derivative(int i, int n, AddressMode address, Sample at) {
    auto difference = [&](int a, int b) { return double(at(a)) - double(at(b)); };
    if (n < 2) return 0.0; // nothing to difference along a 1-texel dimension
    if (address == AddressMode::Wrap) return 0.5 * difference((i + 1) % n, (i + n - 1) % n);
    if (i == 0) return difference(1, 0); // one-sided at the edges: nothing exists outside
    if (i == n - 1) return difference(n - 1, n - 2);
    return 0.5 * difference(i + 1, i - 1);
}

} // namespace

Image heightToNormals(const Image& height, float scale, AddressMode address) {
    Image out(height.width, height.height, 3);
    const int w = height.width, h = height.height;
#pragma omp parallel for schedule(static)
    for (int row = 0; row < h; ++row) {
        auto alongRow = [&](int x) { return height.at(x, row)[0]; };
        for (int x = 0; x < w; ++x) {
            // Rows run downwards, y runs up: dh/dy_up = -dh/drow.
            auto alongColumn = [&](int r) { return height.at(x, r)[0]; };
            // In double: huge heights (1e30) times the scale would overflow a float's square
            // and leave a zero normal; in double they give the steep normal they mean.
            double dx = derivative(x, w, address, alongRow);
            double dyUp = -derivative(row, h, address, alongColumn);
            double nx = -double(scale) * dx, ny = -double(scale) * dyUp;
            double length = std::sqrt(nx * nx + ny * ny + 1.0);
            float* n = out.at(x, row);
            n[0] = float(nx / length), n[1] = float(ny / length), n[2] = float(1.0 / length);
        }
    }
    return out;
}

Result<Image> decodeNormalMap(const SourceImage& source, const DecodeOptions& options,
                              const std::string& name, DecodeReport* report) {
    const Image& in = source.image;
    if (in.empty()) return fileError(name, "image is empty (0x0)");
    if (in.pixels.size() != in.texelCount() * size_t(in.channels))
        return fileError(name, "pixel buffer does not match the image size");
    auto decoded =
        options.height ? decodeHeight(source, options, name) : decodeVectors(source, options, name);
    if (!decoded) return decoded;
    DecodeReport counts;
    if (int64_t bad = renormalise(decoded.value(), counts); bad >= 0) {
        const float* t = in.pixels.data() + size_t(bad) * size_t(in.channels);
        char values[96];
        std::snprintf(values, sizeof values, "%g, %g, %g", t[0], t[std::min(1, in.channels - 1)],
                      t[std::min(2, in.channels - 1)]);
        return fileError(name, "texel (" + std::to_string(bad % in.width) + ", " +
                                   std::to_string(bad / in.width) + ") holds (" + values +
                                   "), too large for a normal (its length overflows a float)");
    }
    if (counts.degenerate == counts.texels)
        return fileError(name, "every normal is zero-length (not a normal map?)");
    if (report) *report = counts;
    return decoded;
}

Result<Image> loadNormalMap(const std::string& path, const DecodeOptions& options,
                            DecodeReport* report) {
    auto source = loadImage(path);
    if (!source) return source.error();
    return decodeNormalMap(source.value(), options, path, report);
}

} // namespace ndfmip
