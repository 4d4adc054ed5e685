// Length checks run before stb_image decodes a TGA, BMP or JPEG file. stb reads missing bytes
// as zeros, so a file cut short would otherwise load "successfully" as garbage rows. Each check
// reads the header the way stb 2.27 does and walks only as far as the file goes.
#include <algorithm>
#include <cstdint>

#include "io/image_formats.h"

namespace ndfmip {
namespace {

uint32_t le16(std::string_view b, size_t at) {
    return uint32_t(uint8_t(b[at])) | uint32_t(uint8_t(b[at + 1])) << 8;
}
uint32_t le32(std::string_view b, size_t at) {
    return le16(b, at) | le16(b, at + 2) << 16;
}

std::string shortBy(const char* format, uint64_t need, size_t have) {
    return std::string("truncated ") + format + " (" + std::to_string(have) +
           " bytes where the header needs " + std::to_string(need) + ")";
}

// stb's stbi__tga_get_comp: channels for a bit depth, and whether pixels are packed 5:5:5.
int tgaChannels(int bits, bool grey, bool& rgb16) {
    rgb16 = false;
    switch (bits) {
    case 8:
        return 1;
    case 16:
        if (grey) return 2;
        rgb16 = true;
        return 3;
    case 15:
        rgb16 = true;
        return 3;
    case 24:
    case 32:
        return bits / 8;
    default:
        return 0;
    }
}

} // namespace

std::string tgaProblem(std::string_view b) {
    if (b.size() < 18) return shortBy("TGA header", 18, b.size());
    const uint32_t idLength = uint8_t(b[0]), indexed = uint8_t(b[1]), type = uint8_t(b[2]);
    const uint32_t paletteStart = le16(b, 3), paletteLength = le16(b, 5);
    const int paletteBits = uint8_t(b[7]), bits = uint8_t(b[16]);
    const uint64_t pixels = uint64_t(le16(b, 12)) * le16(b, 14);
    const bool rle = type >= 8;
    bool rgb16 = false;
    const int channels = indexed ? tgaChannels(paletteBits, false, rgb16)
                                 : tgaChannels(bits, (rle ? type - 8 : type) == 3, rgb16);
    if (channels == 0) return ""; // stb refuses the pixel format itself

    uint64_t need = 18 + idLength;
    if (indexed) need += paletteStart + uint64_t(paletteLength) * (rgb16 ? 2 : channels);
    const uint64_t pixelBytes = indexed ? (bits == 8 ? 1 : 2) : rgb16 ? 2 : uint64_t(channels);
    if (!rle) {
        need += pixels * pixelBytes;
        return b.size() >= need ? "" : shortBy("TGA", need, b.size());
    }
    // Run-length packets: a count byte, then one pixel (a run) or `count` pixels (literal).
    // Each packet takes at least one byte, so the walk ends within the file's length.
    uint64_t at = need, left = pixels;
    while (left > 0) {
        if (at >= b.size()) return "truncated TGA (run-length data ends before the last pixel)";
        const uint8_t command = uint8_t(b[at++]);
        const uint64_t count = std::min<uint64_t>(1 + (command & 127), left);
        at += command & 128 ? pixelBytes : count * pixelBytes;
        left -= count;
    }
    return at <= b.size() ? "" : "truncated TGA (run-length data ends before the last pixel)";
}

std::string bmpProblem(std::string_view b) {
    if (b.size() < 26) return shortBy("BMP header", 26, b.size());
    const uint64_t offset = le32(b, 10), headerSize = le32(b, 14);
    uint64_t width = 0, height = 0, bits = 0;
    if (headerSize == 12) {
        width = le16(b, 18), height = le16(b, 20), bits = le16(b, 24);
    } else {
        if (b.size() < 34) return shortBy("BMP header", 34, b.size());
        width = le32(b, 18), bits = le16(b, 28);
        const auto signedHeight = int32_t(le32(b, 22)); // negative: rows stored top down
        height = signedHeight < 0 ? 0 - uint64_t(int64_t(signedHeight)) : uint64_t(signedHeight);
        const uint32_t compression = le32(b, 30);
        if (compression != 0 && compression != 3) return ""; // stb refuses RLE/JPEG/PNG BMPs
    }
    if (width == 0 || height == 0 || width > (1u << 24) || height > (1u << 24)) return "";
    const uint64_t stride = (width * bits + 31) / 32 * 4; // rows are padded to 4 bytes
    const uint64_t need = std::max(offset, 14 + headerSize) + height * stride;
    return b.size() >= need ? "" : shortBy("BMP", need, b.size());
}

std::string jpegProblem(std::string_view b) {
    const char* truncated = "truncated JPEG (no end-of-image marker)";
    size_t at = b.find_first_not_of('\xFF'); // the start-of-image marker, after fill bytes
    if (at == std::string_view::npos || uint8_t(b[at]) != 0xD8) return "not a JPEG file";
    ++at;
    while (true) {
        // Segments may be padded; stb scans forward to the next marker too.
        while (at < b.size() && uint8_t(b[at]) != 0xFF) ++at;
        while (at < b.size() && uint8_t(b[at]) == 0xFF) ++at;
        if (at >= b.size()) return truncated;
        const uint8_t marker = uint8_t(b[at++]);
        if (marker == 0xD9) return "";                                      // end of image
        if (marker == 0x01 || (marker >= 0xD0 && marker <= 0xD8)) continue; // no length
        if (b.size() - at < 2) return truncated;
        const size_t length = size_t(uint8_t(b[at])) << 8 | uint8_t(b[at + 1]);
        if (length < 2 || b.size() - at < length) return truncated;
        at += length;
        if (marker != 0xDA) continue;
        // Entropy-coded data after a scan header: 0xFF is followed by a stuffed 0x00, a
        // restart marker or fill bytes; any other marker ends the scan.
        while (at < b.size()) {
            if (uint8_t(b[at]) != 0xFF) {
                ++at;
                continue;
            }
            if (at + 1 >= b.size()) return truncated;
            const uint8_t next = uint8_t(b[at + 1]);
            if (next == 0x00 || (next >= 0xD0 && next <= 0xD7))
                at += 2;
            else if (next == 0xFF)
                ++at;
            else
                break;
        }
    }
}

} // namespace ndfmip
