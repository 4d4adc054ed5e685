// The equirectangular map: its direction convention, loading checks and area-weighted resampling.
#include "ndfmip/environment.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdio>

#include "ndfmip/io.h"

namespace ndfmip {

glm::dvec3 equirectDirection(double u, double v) {
    const double phi = 2. * M_PI * (u - 0.5);
    const double lat = M_PI * (0.5 - v);
    return {-std::cos(lat) * std::sin(phi), std::sin(lat), std::cos(lat) * std::cos(phi)};
}

glm::dvec2 equirectCoordinates(glm::dvec3 d) {
    double u = 0.5 + std::atan2(-d.x, d.z) / (2. * M_PI);
    if (u >= 1.) u -= 1.; // atan2 returns pi for -0 as well as 0
    const double v = 0.5 - std::asin(std::clamp(d.y / glm::length(d), -1., 1.)) / M_PI;
    return {u, v};
}

glm::dvec3 rotateAboutY(glm::dvec3 d, double angle) {
    const double c = std::cos(angle), s = std::sin(angle);
    return {c * d.x + s * d.z, d.y, -s * d.x + c * d.z};
}

double equirectTexelSolidAngle(int width, int height, int y) {
    // theta from +Y: row y spans [pi y / h, pi (y + 1) / h].
    const double c0 = std::cos(M_PI * y / height), c1 = std::cos(M_PI * (y + 1) / height);
    return 2. * M_PI / width * (c0 - c1);
}

void sampleEquirect(const Image& map, glm::dvec3 d, float* out) {
    const glm::dvec2 uv = equirectCoordinates(d);
    const double sx = uv.x * map.width - 0.5, sy = uv.y * map.height - 0.5;
    const int x0 = int(std::floor(sx)), y0 = int(std::floor(sy));
    const double fx = sx - x0, fy = sy - y0;
    for (int c = 0; c < map.channels; ++c) out[c] = 0.f;
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 2; ++i) {
            int x = x0 + i, y = y0 + j;
            // Past a pole the row continues on the far side of the sphere.
            if (y < 0 || y >= map.height) {
                y = y < 0 ? -1 - y : 2 * map.height - 1 - y;
                x += map.width / 2;
            }
            x = ((x % map.width) + map.width) % map.width;
            const float w = float((i ? fx : 1. - fx) * (j ? fy : 1. - fy));
            const float* p = map.at(x, y);
            for (int c = 0; c < map.channels; ++c) out[c] += w * p[c];
        }
}

namespace {

std::string texelName(size_t i, int width) {
    return std::string("(") + std::to_string(i % size_t(width)) + ", " +
           std::to_string(i / size_t(width)) + ")";
}

} // namespace

Result<Environment> makeEnvironment(Image image, const std::string& name,
                                    const EnvironmentOptions& options, EnvironmentReport* report) {
    if (!std::isfinite(options.intensity) || options.intensity <= 0.f || options.intensity > 1e6f)
        return Error{name + ": intensity " + std::to_string(options.intensity) +
                     " is not in (0, 1e6]"};
    if (!std::isfinite(options.rotationDegrees) || std::abs(options.rotationDegrees) > 360.f)
        return Error{name + ": rotation " + std::to_string(options.rotationDegrees) +
                     " degrees is not in [-360, 360]"};
    const std::string size = std::to_string(image.width) + "x" + std::to_string(image.height);
    if (image.width != 2 * image.height)
        return Error{name + ": " + size +
                     " is not an equirectangular map (its width must be twice its height)"};
    if (image.height < 2)
        return Error{name + ": " + size + " is too small for an environment map (at least 4x2)"};
    if (image.channels == 2)
        return Error{name + ": has 2 channels; an environment map is RGB, RGBA or grey"};
    Environment env;
    env.rotation = double(options.rotationDegrees) * M_PI / 180.;
    env.radiance = Image(image.width, image.height, 3, Image::Uninitialized{});
    EnvironmentReport counted;
    const size_t texels = image.texelCount();
    for (size_t i = 0; i < texels; ++i) {
        const float* in = &image.pixels[i * size_t(image.channels)];
        float* out = &env.radiance.pixels[3 * i];
        bool negative = false;
        for (int c = 0; c < 3; ++c) {
            const float value = in[image.channels == 1 ? 0 : c];
            if (!std::isfinite(value))
                return Error{name + ": texel " + texelName(i, image.width) +
                             " is not a finite number"};
            negative |= value < 0.f;
            out[c] = std::max(value, 0.f) * options.intensity;
            // Checked after the scale too: 1e33 times an intensity of 1e6 is no float.
            if (!std::isfinite(out[c])) {
                char times[64];
                std::snprintf(times, sizeof times, " (%g) times intensity %g", double(value),
                              double(options.intensity));
                return Error{name + ": texel " + texelName(i, image.width) + times +
                             " is not a finite number"};
            }
        }
        counted.negativeTexels += negative;
    }
    if (report) *report = counted;
    return env;
}

Result<Environment> loadEnvironment(const std::string& path, const EnvironmentOptions& options,
                                    EnvironmentReport* report) {
    Result<SourceImage> source = loadImage(path);
    if (!source) return source.error();
    return makeEnvironment(std::move(source->image), path, options, report);
}

namespace {

// One output texel's overlap with input texels along one axis: input index and weight (the
// weights of a texel sum to 1).
struct Tap {
    int index;
    double weight;
};

// Columns: the output texel x covers [x, x + 1) / outWidth in world u, which is file u plus
// rotation / 2 pi (Environment::rotation); the overlaps with the file's columns, wrapped.
std::vector<std::vector<Tap>> columnTaps(int inWidth, int outWidth, double rotation) {
    std::vector<std::vector<Tap>> taps(static_cast<size_t>(outWidth));
    const double shift = rotation / (2. * M_PI) * inWidth; // in input texels
    const double scale = double(inWidth) / outWidth;
    for (int x = 0; x < outWidth; ++x) {
        const double a = x * scale + shift, b = (x + 1) * scale + shift;
        for (double start = std::floor(a); start < b; start += 1.) {
            const double overlap = std::min(b, start + 1.) - std::max(a, start);
            if (overlap <= 0.) continue;
            int index = int(std::fmod(start, double(inWidth)));
            if (index < 0) index += inWidth;
            taps[size_t(x)].push_back({index, overlap / scale});
        }
    }
    return taps;
}

// Rows: overlaps in cos(theta), i.e. solid angle per unit of longitude.
std::vector<std::vector<Tap>> rowTaps(int inHeight, int outHeight) {
    std::vector<std::vector<Tap>> taps(static_cast<size_t>(outHeight));
    for (int y = 0; y < outHeight; ++y) {
        const double a = double(y) * inHeight / outHeight, b = double(y + 1) * inHeight / outHeight;
        const double total = std::cos(M_PI * y / outHeight) - std::cos(M_PI * (y + 1) / outHeight);
        for (int row = int(std::floor(a)); row < b && row < inHeight; ++row) {
            const double lo = std::max(a, double(row)), hi = std::min(b, double(row + 1));
            if (hi <= lo) continue;
            const double overlap = std::cos(M_PI * lo / inHeight) - std::cos(M_PI * hi / inHeight);
            taps[size_t(y)].push_back({row, overlap / total});
        }
    }
    return taps;
}

} // namespace

Image resampleEquirect(const Image& map, int width, double rotation) {
    assert(width >= 2 && width % 2 == 0 && map.width == 2 * map.height);
    const int height = width / 2, channels = map.channels;
    const auto columns = columnTaps(map.width, width, rotation);
    const auto rows = rowTaps(map.height, height);
    Image out(width, height, channels, Image::Uninitialized{});
#pragma omp parallel for schedule(static)
    for (int y = 0; y < height; ++y) {
        std::vector<double> line(size_t(map.width) * size_t(channels));
        std::fill(line.begin(), line.end(), 0.);
        for (const Tap& row : rows[size_t(y)]) {
            const float* in = map.at(0, row.index);
            for (size_t i = 0; i < line.size(); ++i) line[i] += row.weight * in[i];
        }
        for (int x = 0; x < width; ++x) {
            float* o = out.at(x, y);
            for (int c = 0; c < channels; ++c) {
                double sum = 0.;
                for (const Tap& column : columns[size_t(x)])
                    sum +=
                        column.weight * line[size_t(column.index) * size_t(channels) + size_t(c)];
                o[c] = float(sum);
            }
        }
    }
    return out;
}

} // namespace ndfmip
