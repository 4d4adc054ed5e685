// Turning linear radiance into displayable colours, for looking at renders and references.
#pragma once

#include "ndfmip/image.h"

namespace ndfmip {

// Linear radiance -> display RGB in [0, 1]: multiply by 2^exposureStops, apply Reinhard's
// curve x / (1 + x) to each channel, then the sRGB transfer function. One or two channels
// (grey, grey + alpha) become grey; with three or more, the first three are RGB and the rest
// (alpha) is dropped. Negative values and NaN become 0, +inf becomes 1.
Image toneMap(const Image& linear, float exposureStops = 0.f);

// The exposure (stops) at which toneMap shows a grey pixel at the 99th percentile of luminance
// (Rec. 709 weights) as 0.8. Returns 0 for an image with no positive luminance.
float autoExposure(const Image& linear);

} // namespace ndfmip
