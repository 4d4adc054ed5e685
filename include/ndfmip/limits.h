// The input-size policy: how large an image file, a rendered image, a bake or a text file may be
// before ndfmip allocates anything for it. Every loader checks the sizes a file declares (image
// headers, manifests, scenes) against one process-wide set of limits before it allocates, so a
// 69-byte PNG header cannot ask for gigabytes. docs/SECURITY.md lists the defaults; the CLI
// raises them with --max-pixels and --max-memory.
#pragma once

#include <cstdint>
#include <string>

#include "ndfmip/bake.h"
#include "ndfmip/result.h"

namespace ndfmip {

struct InputLimits {
    int64_t maxSide = 32768;                      // either side of an image file, in texels
    int64_t maxPixels = int64_t(1) << 28;         // texels of an image file (16384 x 16384)
    int64_t maxCameraPixels = int64_t(1) << 26;   // pixels of a rendered image (8192 x 8192)
    int64_t maxMemoryBytes = int64_t(16) << 30;   // estimated peak memory of a bake or bake folder
    int64_t maxImageFileBytes = int64_t(4) << 30; // bytes of an image file
    int64_t maxTextFileBytes = int64_t(16) << 20; // scene, manifest and BRDF-table files
    int maxJsonDepth = 64; // arrays and objects nested in scene/manifest JSON
};

// The limits in force. setInputLimits is meant for the start of a program, before any work.
const InputLimits& inputLimits();
void setInputLimits(const InputLimits& limits);

// A width x height image declared by `name` (a file's header, a manifest): an error naming it
// when a side is not positive or above maxSide, or the texel count above maxPixels.
Status checkImageSize(const std::string& name, int64_t width, int64_t height);

// A rendered image of width x height pixels against maxCameraPixels.
Status checkCameraSize(const std::string& name, int64_t width, int64_t height);

// Bytes a bake of `method` over a width x height map holds at its peak (the decoded normals,
// the pyramid and every plane of every level; for sh, 16 ceil((l*+1)^2 / 4) bytes per texel per
// level). An estimate, good to a small factor, for refusing hopeless bakes before they start.
int64_t bakeMemoryEstimate(Method method, const BakeOptions& options, int64_t width,
                           int64_t height);

// bakeMemoryEstimate against maxMemoryBytes; the error names `name` and both numbers.
Status checkBakeMemory(const std::string& name, Method method, const BakeOptions& options,
                       int64_t width, int64_t height);

// Bytes as a short human-readable figure ("86.0 GiB").
std::string byteSize(int64_t bytes);

} // namespace ndfmip
