// Radiance RGBE (.hdr) decoding, bounded at every read. Debian's stb_image 2.27 loops forever on
// some truncated files (CVE-2021-42715), so HDR files never reach it.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "io/image_formats.h"
#include "ndfmip/limits.h"

namespace ndfmip {
namespace {

struct Cursor {
    std::string_view bytes;
    size_t pos = 0;

    size_t left() const { return bytes.size() - pos; }
    uint8_t byte() { return static_cast<uint8_t>(bytes[pos++]); }
    // The next '\n'-terminated line without its '\n' (and a trailing '\r'); false at the end.
    bool line(std::string_view& out) {
        size_t end = bytes.find('\n', pos);
        if (end == std::string_view::npos) return false;
        out = bytes.substr(pos, end - pos);
        if (!out.empty() && out.back() == '\r') out.remove_suffix(1);
        pos = end + 1;
        return true;
    }
};

// A decimal integer of up to 9 digits at the start of `text`, consumed; -1 if there is none.
int64_t leadingInteger(std::string_view& text) {
    int64_t value = 0;
    size_t digits = 0;
    while (digits < text.size() && digits < 10 && text[digits] >= '0' && text[digits] <= '9')
        value = 10 * value + (text[digits++] - '0');
    if (digits == 0 || digits == 10) return -1;
    text.remove_prefix(digits);
    return value;
}

bool skipWord(std::string_view& text, std::string_view word) {
    while (!text.empty() && text.front() == ' ') text.remove_prefix(1);
    if (text.substr(0, word.size()) != word) return false;
    text.remove_prefix(word.size());
    while (!text.empty() && text.front() == ' ') text.remove_prefix(1);
    return true;
}

// "-Y H +X W": rows from the top, pixels left to right (the only layout stb and most tools
// write); anything else is refused rather than shown transposed or mirrored.
bool parseResolution(std::string_view text, int64_t& width, int64_t& height) {
    if (!skipWord(text, "-Y")) return false;
    height = leadingInteger(text);
    if (height < 0 || !skipWord(text, "+X")) return false;
    width = leadingInteger(text);
    return width >= 0 && text.empty();
}

void toFloat(const uint8_t* rgbe, int stride, float* out) {
    // Radiance's convention: the shared exponent e scales the mantissas by 2^(e - 128 - 8).
    const uint8_t e = rgbe[3 * stride];
    const float scale = e == 0 ? 0.f : std::ldexp(1.f, int(e) - 136);
    for (int c = 0; c < 3; ++c) out[c] = float(rgbe[c * stride]) * scale;
}

// New-style run-length scanline: four components one after another, each as packets of a run
// (count > 128: count - 128 copies of one byte) or literal bytes (count <= 128).
bool readRleScanline(Cursor& in, int width, std::vector<uint8_t>& planar) {
    for (int c = 0; c < 4; ++c) {
        uint8_t* component = planar.data() + size_t(c) * size_t(width);
        int x = 0;
        while (x < width) {
            if (in.left() < 1) return false;
            int count = in.byte();
            if (count > 128) {
                count -= 128;
                if (count > width - x || in.left() < 1) return false;
                const uint8_t value = in.byte();
                for (int i = 0; i < count; ++i) component[x++] = value;
            } else {
                if (count == 0 || count > width - x || in.left() < size_t(count)) return false;
                for (int i = 0; i < count; ++i) component[x++] = in.byte();
            }
        }
    }
    return true;
}

} // namespace

Result<Image> decodeRadiance(std::string_view bytes, const std::string& name) {
    auto fail = [&](const std::string& problem) { return Error{name + ": " + problem}; };
    Cursor in{bytes};
    std::string_view line;
    if (!in.line(line) || (line != "#?RADIANCE" && line != "#?RGBE"))
        return fail("not a Radiance HDR file");
    bool rgbe = false;
    while (true) {
        if (!in.line(line)) return fail("truncated Radiance HDR header");
        if (line.empty()) break;
        if (line.substr(0, 7) == "FORMAT=") {
            if (line != "FORMAT=32-bit_rle_rgbe")
                return fail("unsupported Radiance pixel format " + quote(line.substr(7)));
            rgbe = true;
        }
    }
    if (!rgbe) return fail("Radiance HDR header without FORMAT=32-bit_rle_rgbe");
    int64_t width = 0, height = 0;
    if (!in.line(line)) return fail("truncated Radiance HDR header (no resolution line)");
    if (!parseResolution(line, width, height))
        return fail("unsupported Radiance resolution line " + quote(line) +
                    " (expected '-Y height +X width')");
    if (Status size = checkDecodedSize(name, width, height); !size) return Error{size.error};

    // The least a scanline can take (flat: 4 bytes a pixel; run-length: a 4-byte marker and a
    // 2-byte run per 127 pixels of each component), so a short file fails before allocating.
    const bool rleWidth = width >= 8 && width <= 0x7FFF;
    const int64_t leastPerRow =
        rleWidth ? std::min<int64_t>(4 * width, 4 + 8 * ((width + 126) / 127)) : 4 * width;
    if (int64_t(in.left()) < leastPerRow * height)
        return fail("truncated Radiance HDR (" + std::to_string(in.left()) +
                    " bytes of pixel data cannot hold " + std::to_string(width) + "x" +
                    std::to_string(height) + " pixels)");

    Image image(int(width), int(height), 3);
    std::vector<uint8_t> planar(size_t(4 * width));
    for (int y = 0; y < int(height); ++y) {
        float* row = image.at(0, y);
        const bool rle = rleWidth && in.left() >= 4 && bytes[in.pos] == 2 &&
                         bytes[in.pos + 1] == 2 &&
                         !(static_cast<uint8_t>(bytes[in.pos + 2]) & 0x80);
        if (rle) {
            const int declared = (static_cast<uint8_t>(bytes[in.pos + 2]) << 8) |
                                 static_cast<uint8_t>(bytes[in.pos + 3]);
            if (declared != width)
                return fail("corrupt Radiance HDR: scanline " + std::to_string(y) + " is " +
                            std::to_string(declared) + " pixels wide, not " +
                            std::to_string(width));
            in.pos += 4;
            if (!readRleScanline(in, int(width), planar))
                return fail("truncated or corrupt Radiance HDR (run-length data of scanline " +
                            std::to_string(y) + ")");
            for (int x = 0; x < int(width); ++x)
                toFloat(planar.data() + x, int(width), row + 3 * x);
        } else {
            if (int64_t(in.left()) < 4 * width)
                return fail("truncated Radiance HDR (scanline " + std::to_string(y) + ")");
            for (int x = 0; x < int(width); ++x) {
                toFloat(reinterpret_cast<const uint8_t*>(bytes.data() + in.pos), 1, row + 3 * x);
                in.pos += 4;
            }
        }
    }
    return image;
}

} // namespace ndfmip
