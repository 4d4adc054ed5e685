// Paths and names from outside (the command line, Python, files) before they are used or shown.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

#include "ndfmip/result.h"

namespace ndfmip {

// An error when `path` holds a NUL or another control character (bytes 0x01-0x1F and 0x7F):
// the C library stops at a NUL, so "a.png\0x" would open a.png and "X\0/../y" would write
// beside X; a newline or an escape would break the one-line messages and the logs that hold
// them. Bytes that are not UTF-8 are allowed (Linux file names are bytes). The message names
// the path (shown by `printable`) and the first such byte.
Status checkUntrustedPath(std::string_view path);

// `text` safe to print on one line: control characters as '?', and bytes that are not part of
// valid UTF-8 (a Latin-1 0xFF, a cut sequence) as \xFF; valid UTF-8 is kept. Cut after about
// `maxBytes` bytes of output (at a character) with "…". shortened() and quote() show text so.
std::string printable(std::string_view text, size_t maxBytes = 1024);

} // namespace ndfmip
