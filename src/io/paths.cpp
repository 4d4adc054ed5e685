// The untrusted-path policy and printable text (paths.h).
#include "ndfmip/paths.h"

#include <cstdio>

namespace ndfmip {
namespace {

unsigned char byteAt(std::string_view text, size_t i) {
    return static_cast<unsigned char>(text[i]);
}

// The length of the valid UTF-8 sequence that starts at text[i], or 0 where none does
// (a stray continuation byte, an overlong form, a surrogate, a cut sequence).
size_t utf8Length(std::string_view text, size_t i) {
    const unsigned char c = byteAt(text, i);
    if (c < 0x80) return 1;
    size_t n = 0;
    unsigned char lo = 0x80, hi = 0xBF; // the second byte's range
    if (c >= 0xC2 && c <= 0xDF) {
        n = 2;
    } else if (c >= 0xE0 && c <= 0xEF) {
        n = 3;
        if (c == 0xE0) lo = 0xA0;
        if (c == 0xED) hi = 0x9F;
    } else if (c >= 0xF0 && c <= 0xF4) {
        n = 4;
        if (c == 0xF0) lo = 0x90;
        if (c == 0xF4) hi = 0x8F;
    } else {
        return 0;
    }
    if (i + n > text.size() || byteAt(text, i + 1) < lo || byteAt(text, i + 1) > hi) return 0;
    for (size_t k = 2; k < n; ++k)
        if ((byteAt(text, i + k) & 0xC0) != 0x80) return 0;
    return n;
}

} // namespace

std::string printable(std::string_view text, size_t maxBytes) {
    std::string out;
    for (size_t i = 0; i < text.size();) {
        const unsigned char c = byteAt(text, i);
        const size_t n = utf8Length(text, i);
        std::string_view piece = text.substr(i, n);
        char hex[8];
        if (n == 0) {
            std::snprintf(hex, sizeof hex, "\\x%02X", c);
            piece = hex;
            ++i;
        } else {
            // C0 controls, DEL and the C1 controls (U+0080-U+009F, which some terminals obey).
            if (c < 0x20 || c == 0x7F || (c == 0xC2 && byteAt(text, i + 1) < 0xA0)) piece = "?";
            i += n;
        }
        if (out.size() + piece.size() > maxBytes) {
            out += "\xE2\x80\xA6"; // U+2026 HORIZONTAL ELLIPSIS
            break;
        }
        out += piece;
    }
    return out;
}

Status checkUntrustedPath(std::string_view path) {
    for (size_t i = 0; i < path.size(); ++i) {
        const unsigned char c = byteAt(path, i);
        if (c >= 0x20 && c != 0x7F) continue;
        char what[40];
        if (c == 0)
            std::snprintf(what, sizeof what, "a NUL character");
        else
            std::snprintf(what, sizeof what, "the control character 0x%02X", c);
        return Status::failure(quote(path) + ": not a usable path: it holds " + what + " (byte " +
                               std::to_string(i) +
                               "); paths may not hold NUL or control characters");
    }
    return Status::success();
}

} // namespace ndfmip
