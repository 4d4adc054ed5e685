// Reading and writing image files. The only place file formats live.
// Every error message is one line that starts with the file's path.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "ndfmip/image.h"
#include "ndfmip/result.h"

namespace ndfmip {

// An image as read from disk. Integer formats are scaled to [0,1] (by 255 or 65535);
// float formats (OpenEXR half/float) are returned as stored.
struct SourceImage {
    Image image;            // 1 to 4 channels, top row first
    int bitsPerChannel = 8; // 8 or 16 for integer formats, 16 (half) or 32 for EXR
    bool isFloat = false;   // true for OpenEXR
    std::string format;     // "png", "jpeg", "tga", "exr", ...
};

// Reads PNG (8/16-bit), JPEG, TGA, BMP, OpenEXR (half/float) and Radiance HDR, recognised by
// their first bytes. Grey+alpha is returned with 2 channels, RGBA with 4; alpha is never dropped
// here. Only regular files are read (a FIFO, device or folder is an error), and the size a header
// declares is checked against the input limits (limits.h) before anything is allocated.
Result<SourceImage> loadImage(const std::string& path);

// The same from bytes in memory; `name` starts error messages.
Result<SourceImage> decodeImage(std::string_view bytes, const std::string& name);

// Writes a float OpenEXR file (FLOAT pixels, or HALF with `half`; ZIP compression).
// channelNames, when given, has one name per channel; the default is R,G,B,A (Y for one
// channel). Written to a temporary file beside `path` and renamed, so a failure leaves no
// partial file.
Status saveExr(const std::string& path, const Image& image,
               const std::vector<std::string>& channelNames = {}, bool half = false);

// Encodes an 8- or 16-bit PNG (1 to 4 channels, values clamped to [0,1]) in memory.
Result<std::string> encodePng(const Image& image, int bitsPerChannel);

// Writes encodePng's bytes to `path`; atomic as above.
Status savePng(const std::string& path, const Image& image, int bitsPerChannel);

// An EXR and its 8-bit PNG preview as a pair (no PNG when `pngPath` is empty): both are written to
// temporaries beside their names (PATH.tmp-TAG-render, which a later call removes once their
// writer is gone) and renamed only once both are written, the preview first and the EXR, the
// data, last; a failure leaves the earlier pair and its message names the file asked for.
Status saveExrWithPreview(const std::string& exrPath, const Image& image,
                          const std::string& pngPath, const Image& preview);

// Writes bytes to `path` through a temporary file and a rename.
Status writeFileAtomic(const std::string& path, const std::string& bytes);

// Lower-case hex SHA-256 of a file's bytes, and of bytes in memory.
Result<std::string> sha256File(const std::string& path);
std::string sha256Text(const std::string& bytes);

} // namespace ndfmip
