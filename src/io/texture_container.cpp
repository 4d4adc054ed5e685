// KTX2 and DDS files (see texture_container.h). KTX2: Khronos KTX 2.0 specification (header,
// level index, data format descriptor per the Khronos Data Format specification 1.3); DDS:
// Microsoft's DDS_HEADER + DDS_HEADER_DXT10.
#include "ndfmip/texture_container.h"

#include "io/basisu_encoder.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include <Imath/half.h>
#include <zstd.h>

extern "C" {
// Debian's libstb.so holds stb_dxt's block encoders (stb_dxt.h declares them).
void stb_compress_bc4_block(unsigned char* dest, const unsigned char* src);
void stb_compress_bc5_block(unsigned char* dest, const unsigned char* src);
}

namespace ndfmip {

namespace {

struct FormatInfo {
    TextureFormat format;
    const char* name;
    uint32_t vkFormat;   // VkFormat
    uint32_t dxgiFormat; // DXGI_FORMAT
    int channels;
    int bytesPerTexel; // uncompressed; 0 for block formats
    int bytesPerBlock; // block formats
    int typeSize;      // KTX2: the size of the data type, for endianness conversion
};

const FormatInfo kFormats[] = {
    {TextureFormat::Rgba32F, "rgba32f", 109, 2, 4, 16, 0, 4}, // VK_FORMAT_R32G32B32A32_SFLOAT
    {TextureFormat::Rgba16F, "rgba16f", 97, 10, 4, 8, 0, 2},  // VK_FORMAT_R16G16B16A16_SFLOAT
    {TextureFormat::R16F, "r16f", 76, 54, 1, 2, 0, 2},        // VK_FORMAT_R16_SFLOAT
    {TextureFormat::Rg16Unorm, "rg16", 77, 35, 2, 4, 0, 2},   // VK_FORMAT_R16G16_UNORM
    {TextureFormat::Rgba8Unorm, "rgba8", 37, 28, 4, 4, 0, 1}, // VK_FORMAT_R8G8B8A8_UNORM
    {TextureFormat::Bc4Unorm, "bc4", 139, 80, 1, 0, 8, 1},    // VK_FORMAT_BC4_UNORM_BLOCK
    {TextureFormat::Bc5Unorm, "bc5", 141, 83, 2, 0, 16, 1},   // VK_FORMAT_BC5_UNORM_BLOCK
    {TextureFormat::Uastc, "uastc", 0, 0, 4, 0, 16, 1}, // VK_FORMAT_UNDEFINED: the DFD says UASTC
};

const FormatInfo& info(TextureFormat format) {
    for (const FormatInfo& f : kFormats)
        if (f.format == format) return f;
    return kFormats[0];
}

bool isBlock(TextureFormat f) {
    return info(f).bytesPerBlock > 0;
}

template <typename T> void put(std::string& out, T value) {
    out.append(reinterpret_cast<const char*>(&value), sizeof value);
}

template <typename T> void putAt(std::string& out, size_t offset, T value) {
    std::memcpy(&out[offset], &value, sizeof value);
}

uint8_t unorm8(float v) {
    return uint8_t(std::clamp(v, 0.f, 1.f) * 255.f + 0.5f);
}
uint16_t unorm16(float v) {
    return uint16_t(std::clamp(v, 0.f, 1.f) * 65535.f + 0.5f);
}

// In a BC4 block's 8-level mode (r0 > r1) level p, counted from r1 (p = 0) to r0 (p = 7), is
// ((7 - p) r1 + p r0 + 3) / 7 as decoders round it, and has code kCodeOfLevel[p].
constexpr int kCodeOfLevel[8] = {1, 7, 6, 5, 4, 3, 2, 0};

// The squared error of the 16 values at their nearest levels between r1 < r0, and those levels.
// The levels are evenly spaced (to rounding), so the nearest is one of the two that bracket the
// value, found by a multiply (a rounding at an exact level only moves it to the bracket below,
// which still holds that level). Branch-free, so the compiler can run the 16 values together; an
// AVX2 clone is picked at load time where the CPU has it (twice the lanes of SSE2).
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
__attribute__((target_clones("avx2", "default")))
#endif
int nearestLevels(const int values[16], int r0, int r1, int level[16]) {
    const float scale = 7.f / float(r0 - r1);
    int total = 0;
    for (int i = 0; i < 16; ++i) {
        const int below = std::clamp(int(float(values[i] - r1) * scale), 0, 6);
        const int d0 = values[i] - ((7 - below) * r1 + below * r0 + 3) / 7;
        const int d1 = values[i] - ((6 - below) * r1 + (below + 1) * r0 + 3) / 7;
        const int up = d1 * d1 < d0 * d0 ? 1 : 0;
        level[i] = below + up;
        total += up ? d1 * d1 : d0 * d0;
    }
    return total;
}

// stb_dxt takes each block's maximum and minimum as the endpoints, which spends the eight levels
// poorly where the values cluster. Starting there, the endpoints are refitted by least squares to
// the values given their levels, and the levels reassigned, while the error falls: on real
// roughness mips this gains 1-3 dB, to within 0.6 dB of the best any 8-level block can do (a grid
// search over endpoint pairs gained nothing more at 3x the time). Layout: r0, r1, 16 3-bit codes.
void refineBc4Block(unsigned char* block, const unsigned char* bytes, int stride) {
    // stb_dxt writes r0 = max >= r1 = min; equal only for a constant block, which is exact.
    if (block[0] <= block[1]) return;
    int values[16], level[16], bestLevel[16];
    for (int i = 0; i < 16; ++i) values[i] = bytes[i * stride];
    int r0 = block[0], r1 = block[1], best0 = r0, best1 = r1;
    int bestError = nearestLevels(values, r0, r1, bestLevel);
    if (bestError <= 16) return; // within one level per texel on average: nothing to gain
    std::copy(bestLevel, bestLevel + 16, level);
    for (int iteration = 0, last = bestError; iteration < 2; ++iteration) {
        // value ~ w r0 + (1 - w) r1 with w = level / 7.
        float sww = 0.f, sw = 0.f, swv = 0.f, sv = 0.f;
        for (int i = 0; i < 16; ++i) {
            const float w = float(level[i]) * (1.f / 7.f), v = float(values[i]);
            sww += w * w, sw += w, swv += w * v, sv += v;
        }
        // Normal equations in (r0, r1): [sww, sw - sww; sw - sww, 16 - 2 sw + sww].
        const float a = sww, b = sw - sww, c = 16.f - 2.f * sw + sww, det = a * c - b * b;
        if (std::abs(det) < 1e-6f) break;
        const float y0 = swv, y1 = sv - swv;
        const int n0 = std::clamp(int((y0 * c - y1 * b) / det + 0.5f), 0, 255);
        const int n1 = std::clamp(int((y1 * a - y0 * b) / det + 0.5f), 0, 255);
        if ((n0 == r0 && n1 == r1) || n0 <= n1) break; // settled, or out of the 8-level mode
        r0 = n0, r1 = n1;
        const int error = nearestLevels(values, r0, r1, level);
        if (error < bestError)
            bestError = error, best0 = r0, best1 = r1, std::copy(level, level + 16, bestLevel);
        if (error >= last) break; // the fit has settled
        last = error;
    }
    if (best0 == block[0] && best1 == block[1]) return;
    block[0] = uint8_t(best0);
    block[1] = uint8_t(best1);
    uint64_t bits = 0;
    for (int i = 0; i < 16; ++i) bits |= uint64_t(kCodeOfLevel[bestLevel[i]]) << (3 * i);
    for (int b = 0; b < 6; ++b) block[2 + b] = uint8_t(bits >> (8 * b));
}

std::string encodeLevel(const LevelRows& level, const FormatInfo& f) {
    const int width = level.width, height = level.height, channels = level.channels;
    auto value = [channels](const float* texel, int c) { return c < channels ? texel[c] : 0.f; };
    std::string out;
    if (!isBlock(f.format)) {
        const size_t rowBytes = size_t(width) * size_t(f.bytesPerTexel);
        out.resize(rowBytes * size_t(height));
#pragma omp parallel for schedule(static) if (size_t(width) * size_t(height) >= 65536)
        for (int y = 0; y < height; ++y) {
            std::vector<float> row(size_t(width) * size_t(channels));
            level.row(y, row.data());
            char* dst = &out[size_t(y) * rowBytes];
            for (int x = 0; x < width; ++x)
                for (int c = 0; c < f.channels; ++c) {
                    const float v = value(&row[size_t(x) * size_t(channels)], c);
                    if (f.format == TextureFormat::Rgba32F)
                        std::memcpy(dst, &v, 4), dst += 4;
                    else if (f.format == TextureFormat::Rg16Unorm) {
                        const uint16_t u = unorm16(v);
                        std::memcpy(dst, &u, 2), dst += 2;
                    } else if (f.format == TextureFormat::Rgba8Unorm)
                        *dst++ = char(unorm8(v));
                    else {
                        const uint16_t bits = Imath::half(v).bits();
                        std::memcpy(dst, &bits, 2), dst += 2;
                    }
                }
        }
        return out;
    }
    // 4x4 blocks, rows of blocks from the top; texels past an edge repeat the edge. Rows of
    // blocks are independent: each thread reads its four rows and encodes them into their place.
    const int bw = (width + 3) / 4, bh = (height + 3) / 4;
    const size_t rowBytes = size_t(bw) * size_t(f.bytesPerBlock);
    out.resize(rowBytes * size_t(bh));
#pragma omp parallel if (bh >= 64)
    {
        std::vector<float> rows(4 * size_t(width) * size_t(channels));
        std::vector<unsigned char> bytes(4 * size_t(width) * size_t(f.channels));
#pragma omp for schedule(dynamic, 4)
        for (int by = 0; by < bh; ++by) {
            for (int j = 0; j < 4; ++j) {
                float* row = &rows[size_t(j) * size_t(width) * size_t(channels)];
                if (4 * by + j < height)
                    level.row(4 * by + j, row);
                else
                    std::copy_n(row - size_t(width) * size_t(channels),
                                size_t(width) * size_t(channels), row);
                unsigned char* b = &bytes[size_t(j) * size_t(width) * size_t(f.channels)];
                if (channels == f.channels) {
                    for (size_t i = 0; i < size_t(width) * size_t(channels); ++i)
                        b[i] = unorm8(row[i]);
                } else {
                    for (int x = 0; x < width; ++x)
                        for (int c = 0; c < f.channels; ++c)
                            *b++ = unorm8(value(row + size_t(x) * size_t(channels), c));
                }
            }
            const size_t blockRow = 4 * size_t(f.channels); // bytes of one block's row of 4 texels
            for (int bx = 0; bx < bw; ++bx) {
                unsigned char src[32];
                for (int j = 0; j < 4; ++j) {
                    const unsigned char* line =
                        &bytes[size_t(j) * size_t(width) * size_t(f.channels)];
                    if (4 * bx + 3 < width) {
                        std::memcpy(src + size_t(j) * blockRow, line + size_t(bx) * blockRow,
                                    blockRow);
                        continue;
                    }
                    for (int i = 0; i < 4; ++i) {
                        const int x = std::min(4 * bx + i, width - 1);
                        for (int c = 0; c < f.channels; ++c)
                            src[(4 * j + i) * f.channels + c] =
                                line[size_t(x) * size_t(f.channels) + size_t(c)];
                    }
                }
                auto* block = reinterpret_cast<unsigned char*>(
                    &out[size_t(by) * rowBytes + size_t(bx) * size_t(f.bytesPerBlock)]);
                if (f.format == TextureFormat::Bc4Unorm) {
                    stb_compress_bc4_block(block, src);
                    refineBc4Block(block, src, 1);
                } else { // BC5: a BC4 block for red, then one for green
                    stb_compress_bc5_block(block, src);
                    refineBc4Block(block, src, 2);
                    refineBc4Block(block + 8, src + 1, 2);
                }
            }
        }
    }
    return out;
}

// The KTX2 basic data format descriptor (Khronos Data Format 1.3, section 5) of a format.
std::string dataFormatDescriptor(const FormatInfo& f) {
    std::string samples;
    auto sample = [&](uint32_t bitOffset, uint32_t bitLength, uint32_t channelType, uint32_t lower,
                      uint32_t upper) {
        put(samples, uint16_t(bitOffset));
        put(samples, uint8_t(bitLength - 1));
        put(samples, uint8_t(channelType));
        put(samples, uint32_t(0)); // sample positions
        put(samples, lower);
        put(samples, upper);
    };
    const uint32_t floatSigned = 0x80u | 0x40u; // KHR_DF_SAMPLE_DATATYPE_FLOAT | SIGNED
    uint8_t model = 1;                          // KHR_DF_MODEL_RGBSDA
    uint8_t dims[4] = {0, 0, 0, 0};
    uint8_t bytesPlane0 = 0;
    switch (f.format) {
    case TextureFormat::Rgba32F:
        for (uint32_t c = 0; c < 4; ++c)
            sample(32 * c, 32, (c == 3 ? 15u : c) | floatSigned, 0xBF800000u, 0x3F800000u);
        bytesPlane0 = 16;
        break;
    case TextureFormat::Rgba16F:
        for (uint32_t c = 0; c < 4; ++c)
            sample(16 * c, 16, (c == 3 ? 15u : c) | floatSigned, 0xBF800000u, 0x3F800000u);
        bytesPlane0 = 8;
        break;
    case TextureFormat::R16F:
        sample(0, 16, 0u | floatSigned, 0xBF800000u, 0x3F800000u);
        bytesPlane0 = 2;
        break;
    case TextureFormat::Rgba8Unorm:
        for (uint32_t c = 0; c < 4; ++c) sample(8 * c, 8, c == 3 ? 15u : c, 0u, 255u);
        bytesPlane0 = 4;
        break;
    case TextureFormat::Rg16Unorm:
        sample(0, 16, 0u, 0u, 65535u);
        sample(16, 16, 1u, 0u, 65535u);
        bytesPlane0 = 4;
        break;
    case TextureFormat::Bc4Unorm:
        model = 131; // KHR_DF_MODEL_BC4
        dims[0] = dims[1] = 3;
        sample(0, 64, 0u, 0u, 0xFFFFFFFFu);
        bytesPlane0 = 8;
        break;
    case TextureFormat::Bc5Unorm:
        model = 132; // KHR_DF_MODEL_BC5
        dims[0] = dims[1] = 3;
        sample(0, 64, 0u, 0u, 0xFFFFFFFFu);
        sample(64, 64, 1u, 0u, 0xFFFFFFFFu);
        bytesPlane0 = 16;
        break;
    case TextureFormat::Uastc: // the encoder's descriptor is written instead (EncodedTexture)
        break;
    }
    std::string block;
    put(block, uint32_t(0));                   // vendorId 0 (Khronos), descriptorType 0 (basic)
    put(block, uint16_t(2));                   // versionNumber (1.3)
    put(block, uint16_t(24 + samples.size())); // descriptorBlockSize
    put(block, model);
    put(block, uint8_t(1)); // colorPrimaries: BT709
    put(block, uint8_t(1)); // transferFunction: linear
    put(block, uint8_t(0)); // flags: alpha straight
    block.append(reinterpret_cast<const char*>(dims), 4);
    const uint8_t planes[8] = {bytesPlane0, 0, 0, 0, 0, 0, 0, 0};
    block.append(reinterpret_cast<const char*>(planes), 8);
    block += samples;
    std::string dfd;
    put(dfd, uint32_t(4 + block.size())); // dfdTotalSize
    return dfd + block;
}

constexpr unsigned char kKtx2Identifier[12] = {0xAB, 'K',  'T',  'X',  ' ',  '2',
                                               '0',  0xBB, '\r', '\n', 0x1A, '\n'};

// KTX2 key/value data (KTX 2.0 section 3.11): each entry its byte length, then the key and the
// value each NUL-terminated, padded to 4 bytes; entries sorted by key (std::map's order is the
// keys' bytes, unsigned: UTF-8's code point order, as the specification asks).
Result<std::string> keyValueData(Ktx2KeyValues keyValues) {
    keyValues.emplace("KTXwriter", std::string("ndfmip ") + NDFMIP_VERSION); // kept when given
    std::string out;
    for (const auto& [key, value] : keyValues) {
        if (key.empty() || key.find('\0') != std::string::npos)
            return Error{"ktx2: key " + quote(key) + " is empty or holds a NUL byte"};
        put(out, uint32_t(key.size() + 1 + value.size() + 1));
        out += key;
        out += '\0';
        out += value;
        out += '\0';
        while (out.size() % 4) out += '\0';
    }
    return out;
}

} // namespace

const char* textureFormatName(TextureFormat format) {
    return info(format).name;
}

std::optional<TextureFormat> textureFormatFromName(const std::string& name) {
    for (const FormatInfo& f : kFormats)
        if (name == f.name) return f.format;
    return std::nullopt;
}

Result<EncodedTexture> encodeTexture(const std::vector<LevelRows>& levels, TextureFormat format) {
    if (levels.empty() || levels.front().width <= 0 || levels.front().height <= 0 ||
        levels.front().channels <= 0)
        return Error{"texture: no levels to encode"};
    EncodedTexture t;
    t.format = format;
    t.width = levels.front().width;
    t.height = levels.front().height;
    for (size_t k = 0; k < levels.size(); ++k) {
        if (format == TextureFormat::Uastc) break; // checked and encoded together below
        const LevelRows& level = levels[k];
        const int w = std::max(t.width >> k, 1), h = std::max(t.height >> k, 1);
        if (level.width != w || level.height != h)
            return Error{"texture: level " + std::to_string(k) + " is " +
                         std::to_string(level.width) + "x" + std::to_string(level.height) +
                         ", the mip rule gives " + std::to_string(w) + "x" + std::to_string(h)};
        if (level.channels <= 0 || !level.row)
            return Error{"texture: level " + std::to_string(k) + " has no texels"};
        t.levels.push_back(encodeLevel(level, info(format)));
    }
    if (format == TextureFormat::Uastc) {
        for (size_t k = 0; k < levels.size(); ++k) {
            const int w = std::max(t.width >> k, 1), h = std::max(t.height >> k, 1);
            if (levels[k].width != w || levels[k].height != h || levels[k].channels <= 0 ||
                !levels[k].row)
                return Error{"texture: level " + std::to_string(k) + " is not the " +
                             std::to_string(w) + "x" + std::to_string(h) + " the mip rule gives"};
        }
        Result<std::vector<std::string>> blocks = encodeUastcLevels(levels, t.dataFormatDescriptor);
        if (!blocks) return blocks.error();
        t.levels = std::move(blocks.value());
    }
    return t;
}

Result<EncodedTexture> encodeCubeTexture(const std::vector<std::vector<LevelRows>>& faces,
                                         TextureFormat format) {
    if (faces.empty()) return Error{"texture: no levels to encode"};
    EncodedTexture cube;
    for (int f = 0; f < 6; ++f) {
        std::vector<LevelRows> chain;
        for (size_t k = 0; k < faces.size(); ++k) {
            if (faces[k].size() != 6)
                return Error{"texture: level " + std::to_string(k) + " has " +
                             std::to_string(faces[k].size()) + " cube faces, not 6"};
            chain.push_back(faces[k][size_t(f)]);
        }
        if (chain.front().width != chain.front().height)
            return Error{"texture: cube faces must be square, level 0 is " +
                         std::to_string(chain.front().width) + "x" +
                         std::to_string(chain.front().height)};
        Result<EncodedTexture> face = encodeTexture(chain, format);
        if (!face) return face;
        if (f == 0) {
            cube = face.value();
            cube.faces = 6;
            continue;
        }
        for (size_t k = 0; k < faces.size(); ++k) cube.levels[k] += face->levels[k];
    }
    return cube;
}

LevelRows rowsOf(const Image& image, int channels, float fill) {
    const int n = channels > 0 ? channels : image.channels;
    return {image.width, image.height, n, [&image, n, fill](int y, float* out) {
                const float* row = image.at(0, y);
                if (n == image.channels) {
                    std::copy(row, row + size_t(image.width) * size_t(n), out);
                    return;
                }
                for (int x = 0; x < image.width; ++x)
                    for (int c = 0; c < n; ++c)
                        out[size_t(x) * size_t(n) + size_t(c)] =
                            c < image.channels ? row[size_t(x) * size_t(image.channels) + size_t(c)]
                                               : fill;
            }};
}

LevelRows rowsOf(std::shared_ptr<const Image> image, int channels, float fill) {
    LevelRows rows = rowsOf(*image, channels, fill);
    rows.row = [read = std::move(rows.row), image = std::move(image)](int y, float* out) {
        read(y, out);
    };
    return rows;
}

Result<EncodedTexture> encodeTexture(const std::vector<const Image*>& levels,
                                     TextureFormat format) {
    std::vector<LevelRows> rows;
    for (const Image* image : levels) {
        if (!image || image->empty()) return Error{"texture: no levels to encode"};
        rows.push_back(rowsOf(*image));
    }
    return encodeTexture(rows, format);
}

Result<std::string> ktx2File(const EncodedTexture& t, int zstdLevel,
                             const Ktx2KeyValues& keyValues) {
    const FormatInfo& f = info(t.format);
    if (zstdLevel < 0 || zstdLevel > ZSTD_maxCLevel())
        return Error{"ktx2: zstd level " + std::to_string(zstdLevel) + " out of range 0 to " +
                     std::to_string(ZSTD_maxCLevel())};
    // Zstandard supercompression (scheme 2) compresses each level on its own, so a reader can
    // inflate only the levels it uploads.
    std::vector<std::string> stored;
    if (zstdLevel > 0) {
        stored.resize(t.levels.size());
        for (size_t k = 0; k < t.levels.size(); ++k) {
            std::string& z = stored[k];
            z.resize(ZSTD_compressBound(t.levels[k].size()));
            const size_t n = ZSTD_compress(z.data(), z.size(), t.levels[k].data(),
                                           t.levels[k].size(), zstdLevel);
            if (ZSTD_isError(n)) return Error{std::string("ktx2: zstd: ") + ZSTD_getErrorName(n)};
            z.resize(n);
        }
    }
    const std::vector<std::string>& levels = zstdLevel > 0 ? stored : t.levels;
    const uint32_t levelCount = uint32_t(t.levels.size());
    std::string dfd =
        t.dataFormatDescriptor.empty() ? dataFormatDescriptor(f) : t.dataFormatDescriptor;
    if (t.format == TextureFormat::Uastc) {
        if (dfd.size() < 44)
            return Error{"ktx2: UASTC levels without the encoder's data format descriptor"};
        // bytesPlane0: a UASTC block's 16 bytes, 0 once supercompressed (the levels are then
        // byte streams of no fixed block size), as libktx writes it.
        dfd[20] = char(zstdLevel > 0 ? 0 : 16);
    }
    Result<std::string> kvd = keyValueData(keyValues);
    if (!kvd) return kvd.error();
    // Header (80 bytes), level index (24 bytes a level), then the DFD, the key/value data (both
    // a multiple of 4 bytes long), then the levels, smallest first, each aligned to
    // lcm(texel block size, 4).
    const size_t indexAt = 80, dfdAt = indexAt + 24 * size_t(levelCount),
                 kvdAt = dfdAt + dfd.size();
    // Levels aligned to lcm(texel block size, 4): every block or texel size here is 2 or a
    // multiple of 4. Supercompressed levels are byte streams, aligned to 1.
    const size_t blockSize = size_t(isBlock(t.format) ? f.bytesPerBlock : f.bytesPerTexel);
    const size_t alignment = zstdLevel > 0 ? 1 : blockSize % 4 == 0 ? blockSize : 4;
    size_t total = kvdAt + kvd->size();
    for (const std::string& level : levels) total += level.size() + alignment;
    std::string out;
    out.reserve(total); // one allocation: the levels of a 4096² map are tens of MB
    out.append(reinterpret_cast<const char*>(kKtx2Identifier), 12);
    put(out, f.vkFormat);
    put(out, uint32_t(f.typeSize));
    put(out, uint32_t(t.width));
    put(out, uint32_t(t.height));
    put(out, uint32_t(0));       // pixelDepth
    put(out, uint32_t(0));       // layerCount
    put(out, uint32_t(t.faces)); // faceCount
    put(out, levelCount);
    put(out, uint32_t(zstdLevel > 0 ? 2 : 0)); // supercompressionScheme: none or Zstandard
    put(out, uint32_t(dfdAt));
    put(out, uint32_t(dfd.size()));
    put(out, uint32_t(kvdAt));
    put(out, uint32_t(kvd->size()));
    put(out, uint64_t(0));   // sgdByteOffset
    put(out, uint64_t(0));   // sgdByteLength
    out.resize(dfdAt, '\0'); // the level index, filled below
    out += dfd;
    out += kvd.value();
    std::vector<uint64_t> offsets(levelCount);
    for (int k = int(levelCount) - 1; k >= 0; --k) {
        while (out.size() % alignment) out += '\0';
        offsets[size_t(k)] = out.size();
        out += levels[size_t(k)];
    }
    for (uint32_t k = 0; k < levelCount; ++k) {
        putAt(out, indexAt + 24 * k, offsets[k]);
        putAt(out, indexAt + 24 * k + 8, uint64_t(levels[k].size()));
        putAt(out, indexAt + 24 * k + 16, uint64_t(t.levels[k].size())); // uncompressedByteLength
    }
    return out;
}

Result<Ktx2KeyValues> readKtx2KeyValues(const std::string& file) {
    if (file.size() < 80 || std::memcmp(file.data(), kKtx2Identifier, 12) != 0)
        return Error{"ktx2: not a KTX2 file (no KTX 2.0 identifier)"};
    uint32_t offset = 0, length = 0;
    std::memcpy(&offset, &file[56], 4);
    std::memcpy(&length, &file[60], 4);
    if (uint64_t(offset) + length > file.size())
        return Error{"ktx2: the key/value data (" + std::to_string(length) + " bytes at " +
                     std::to_string(offset) + ") runs past the end of the file (" +
                     std::to_string(file.size()) + " bytes)"};
    Ktx2KeyValues out;
    const size_t end = size_t(offset) + length;
    for (size_t at = offset; at < end;) {
        uint32_t n = 0;
        if (end - at < 4)
            return Error{"ktx2: key/value entry at " + std::to_string(at) + " is cut short"};
        std::memcpy(&n, &file[at], 4);
        at += 4;
        if (n > end - at)
            return Error{"ktx2: key/value entry at " + std::to_string(at - 4) +
                         " runs past the data"};
        const std::string entry = file.substr(at, n);
        const size_t nul = entry.find('\0');
        if (nul == 0 || nul == std::string::npos)
            return Error{"ktx2: key/value entry at " + std::to_string(at - 4) +
                         " has no NUL-terminated key"};
        std::string value = entry.substr(nul + 1);
        if (!value.empty() && value.back() == '\0') value.pop_back();
        if (!out.emplace(entry.substr(0, nul), std::move(value)).second)
            return Error{"ktx2: key " + quote(entry.substr(0, nul)) + " appears twice"};
        at += n;
        at += (4 - n % 4) % 4; // valuePadding
    }
    return out;
}

namespace {

// The bytes a level of `f` holds at w x h, per face (0 where a 4 GiB guard is passed).
uint64_t levelBytes(const FormatInfo& f, uint64_t w, uint64_t h) {
    const uint64_t n = isBlock(f.format) ? ((w + 3) / 4) * ((h + 3) / 4) * uint64_t(f.bytesPerBlock)
                                         : w * h * uint64_t(f.bytesPerTexel);
    return n > (uint64_t(1) << 32) ? 0 : n;
}

} // namespace

Result<EncodedTexture> readKtx2(const std::string& file) {
    if (file.size() < 80 || std::memcmp(file.data(), kKtx2Identifier, 12) != 0)
        return Error{"ktx2: not a KTX2 file (no KTX 2.0 identifier)"};
    uint32_t h[13];
    std::memcpy(h, &file[12], sizeof h);
    const uint32_t vkFormat = h[0], width = h[2], height = h[3], depth = h[4], layers = h[5],
                   faces = h[6], scheme = h[8], dfdAt = h[9], dfdLength = h[10];
    const uint32_t levelCount = std::max(h[7], 1u); // 0: "generate the mips", one level stored
    if (width == 0 || height == 0 || depth > 0 || layers > 0 || (faces != 1 && faces != 6))
        return Error{"ktx2: only 2D textures and cube maps are read (this one is " +
                     std::to_string(width) + "x" + std::to_string(height) + "x" +
                     std::to_string(depth) + ", " + std::to_string(layers) + " layers, " +
                     std::to_string(faces) + " faces)"};
    if (scheme != 0 && scheme != 2)
        return Error{"ktx2: supercompression scheme " + std::to_string(scheme) +
                     " (only none and Zstandard are read)"};
    if (levelCount > 32 || ((width >> (levelCount - 1)) == 0 && (height >> (levelCount - 1)) == 0))
        return Error{"ktx2: " + std::to_string(levelCount) + " levels do not fit " +
                     std::to_string(width) + "x" + std::to_string(height)};
    if (uint64_t(dfdAt) + dfdLength > file.size() || dfdLength < 28 ||
        80 + 24 * uint64_t(levelCount) > file.size())
        return Error{
            "ktx2: the level index or data format descriptor runs past the end of the file"};
    EncodedTexture t;
    t.width = int(width), t.height = int(height), t.faces = int(faces);
    const std::string dfd = file.substr(dfdAt, dfdLength);
    const FormatInfo* f = nullptr;
    for (const FormatInfo& candidate : kFormats)
        if (candidate.vkFormat == vkFormat && vkFormat != 0) f = &candidate;
    if (vkFormat == 0 && uint8_t(dfd[12]) == 166) { // KHR_DF_MODEL_UASTC
        f = &info(TextureFormat::Uastc);
        t.dataFormatDescriptor = dfd;
    }
    if (!f) return Error{"ktx2: vkFormat " + std::to_string(vkFormat) + " is not one ndfmip reads"};
    t.format = f->format;
    for (uint32_t k = 0; k < levelCount; ++k) {
        uint64_t index[3];
        std::memcpy(index, &file[80 + 24 * size_t(k)], sizeof index);
        const uint64_t expect =
            levelBytes(*f, std::max(width >> k, 1u), std::max(height >> k, 1u)) * uint64_t(faces);
        if (index[0] > file.size() || index[1] > file.size() - index[0])
            return Error{"ktx2: level " + std::to_string(k) + " runs past the end of the file"};
        if (expect == 0 || index[2] != expect)
            return Error{"ktx2: level " + std::to_string(k) + " holds " + std::to_string(index[2]) +
                         " bytes, its size " + "and format need " + std::to_string(expect)};
        std::string level;
        if (scheme == 0) {
            if (index[1] != expect)
                return Error{"ktx2: level " + std::to_string(k) + " is cut short"};
            level = file.substr(size_t(index[0]), size_t(index[1]));
        } else {
            level.resize(size_t(expect));
            const size_t n = ZSTD_decompress(level.data(), level.size(), &file[size_t(index[0])],
                                             size_t(index[1]));
            if (ZSTD_isError(n) || n != expect)
                return Error{
                    "ktx2: level " + std::to_string(k) + " does not inflate to its " +
                    std::to_string(expect) + " bytes" +
                    (ZSTD_isError(n) ? std::string(" (") + ZSTD_getErrorName(n) + ")" : "")};
        }
        t.levels.push_back(std::move(level));
    }
    return t;
}

namespace {

// The levels after the header: face by face, each with all its levels.
void appendDdsData(std::string& out, const EncodedTexture& t) {
    size_t total = out.size();
    for (const std::string& level : t.levels) total += level.size();
    out.reserve(total);
    for (int f = 0; f < t.faces; ++f)
        for (const std::string& level : t.levels) {
            const size_t faceBytes = level.size() / size_t(t.faces);
            out.append(level, size_t(f) * faceBytes, faceBytes);
        }
}

std::string ddsHeader(const EncodedTexture& t, const char fourCC[4]) {
    const FormatInfo& f = info(t.format);
    std::string out = "DDS ";
    const bool block = isBlock(t.format);
    const uint32_t pitchOrLinearSize =
        block ? uint32_t(((t.width + 3) / 4) * ((t.height + 3) / 4) * f.bytesPerBlock)
              : uint32_t(t.width * f.bytesPerTexel);
    put(out, uint32_t(124)); // dwSize
    put(out,
        uint32_t(0x1 | 0x2 | 0x4 | 0x1000 | 0x20000 |
                 (block ? 0x80000
                        : 0x8))); // CAPS HEIGHT WIDTH PIXELFORMAT MIPMAPCOUNT, LINEARSIZE or PITCH
    put(out, uint32_t(t.height));
    put(out, uint32_t(t.width));
    put(out, pitchOrLinearSize);
    put(out, uint32_t(0));                              // depth
    put(out, uint32_t(t.levels.size()));                // mip map count
    for (int i = 0; i < 11; ++i) put(out, uint32_t(0)); // reserved
    put(out, uint32_t(32));                             // pixel format size
    put(out, uint32_t(0x4));                            // DDPF_FOURCC
    out.append(fourCC, 4);
    for (int i = 0; i < 5; ++i) put(out, uint32_t(0));     // bit count and masks
    put(out, uint32_t(0x1000 | 0x8 | 0x400000));           // caps: TEXTURE, COMPLEX, MIPMAP
    put(out, uint32_t(t.faces == 6 ? 0x200 | 0xFC00 : 0)); // caps2: CUBEMAP and its six faces
    for (int i = 0; i < 3; ++i) put(out, uint32_t(0));     // caps3, caps4, reserved2
    return out;
}

} // namespace

std::string ddsFile(const EncodedTexture& t) {
    std::string out = ddsHeader(t, "DX10");
    put(out, info(t.format).dxgiFormat);
    put(out, uint32_t(3));                      // D3D10_RESOURCE_DIMENSION_TEXTURE2D
    put(out, uint32_t(t.faces == 6 ? 0x4 : 0)); // misc flags: D3D11_RESOURCE_MISC_TEXTURECUBE
    put(out, uint32_t(1));                      // array size (of cubes, for a cube map)
    put(out, uint32_t(0));                      // misc flags 2: alpha mode unknown
    appendDdsData(out, t);
    return out;
}

Result<std::string> ddsFileLegacy(const EncodedTexture& t) {
    if (t.format != TextureFormat::Bc4Unorm && t.format != TextureFormat::Bc5Unorm)
        return Error{std::string("dds: no legacy FourCC for ") + textureFormatName(t.format)};
    std::string out = ddsHeader(t, t.format == TextureFormat::Bc4Unorm ? "ATI1" : "ATI2");
    appendDdsData(out, t);
    return out;
}

} // namespace ndfmip
