// Format-specific pieces of image reading that do not go through a library: our own Radiance
// HDR decoder, and the length checks that run before stb_image sees a TGA, BMP or JPEG file
// (stb fills missing bytes with zeros instead of failing, and loops forever on some truncated
// HDR files).
#pragma once

#include <string>
#include <string_view>

#include "ndfmip/image.h"
#include "ndfmip/result.h"

namespace ndfmip {

// Radiance RGBE (.hdr: "#?RADIANCE" or "#?RGBE", FORMAT=32-bit_rle_rgbe, "-Y H +X W"), flat or
// run-length-encoded scanlines, as 3 float channels (value = byte * 2^(e - 136), 0 for e = 0).
// Every read is bounded: a truncated or inconsistent file is an error naming `name`, and the
// declared size is checked against the input limits before anything is allocated.
Result<Image> decodeRadiance(std::string_view bytes, const std::string& name);

// "" when `bytes` holds every byte its TGA header asks stb_image to read (image id, palette,
// pixels; run-length packets walked up to the declared pixel count), else the problem.
std::string tgaProblem(std::string_view bytes);

// The same for a BMP file's pixel rows (offset + rows x 4-byte-aligned stride).
std::string bmpProblem(std::string_view bytes);

// "" when a JPEG file's segments lead, through its scans, to an end-of-image marker; else the
// problem (a truncated file has none).
std::string jpegProblem(std::string_view bytes);

} // namespace ndfmip
