// Turning a decoded image into unit tangent-space normals, under the conventions users'
// normal maps come in. A normal map is an Image with 3 channels (x, y, z), OpenGL
// convention (+Y up, i.e. towards the top row of the file).
#pragma once

#include <cstddef>
#include <string>

#include "ndfmip/image.h"
#include "ndfmip/io.h"
#include "ndfmip/result.h"

namespace ndfmip {

// How texels outside the map are addressed (sampling, height-map differences).
enum class AddressMode {
    Wrap,  // tileable texture: coordinates wrap around (default)
    Clamp, // non-tiling texture: nothing exists outside the map
};

struct DecodeOptions {
    bool greenDown = false;  // DirectX-style map (green points down): flip Y after decoding
    bool twoChannel = false; // use R,G only and rebuild z = sqrt(max(0, 1 - x^2 - y^2)) (BC5 style)
    bool signedValues = false; // float maps already holding n in [-1,1] (else n = 2c - 1)
    bool height = false;       // input is a height map (first channel), turned into normals
    float heightScale = 1.f;   // with `height`: height of value 1.0, in texels
    AddressMode address = AddressMode::Wrap;
};

// What decoding found; the CLI prints it so a wrong convention is noticed.
struct DecodeReport {
    size_t texels = 0;
    size_t offUnitLength = 0; // | |n| - 1 | > 0.1 before renormalisation
    size_t degenerate = 0;    // |n| < 1e-3: replaced by (0,0,1)
    size_t facingDown = 0;    // z < 0 after renormalisation
};

// Decodes `source` into unit normals. Errors (one line, starting with `name`): 0x0 image,
// a 1- or 2-channel image without `height`/`twoChannel`, NaN/Inf values, every normal
// degenerate. The report may be null.
Result<Image> decodeNormalMap(const SourceImage& source, const DecodeOptions& options,
                              const std::string& name, DecodeReport* report);

// Height field (one channel) to unit normals by central differences, n ∝ (-s dh/dx, -s dh/dy, 1),
// y up. Wrap differences across the edges; Clamp uses one-sided differences at the edges.
Image heightToNormals(const Image& height, float scale, AddressMode address);

// loadImage + decodeNormalMap.
Result<Image> loadNormalMap(const std::string& path, const DecodeOptions& options,
                            DecodeReport* report);

} // namespace ndfmip
