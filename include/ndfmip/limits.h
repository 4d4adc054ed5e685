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

// checkImageSize for an image about to be decoded, and the memory its decoding leads to against
// maxMemoryBytes: the PlannedPeak alive on this thread, else the decoded image's own bytes.
// Every decoder calls it with its header's size before it allocates.
Status checkDecodedSize(const std::string& name, int64_t width, int64_t height);

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

// "a toksvig bake", "a sh bake of order 8": what a bake is, for messages.
std::string bakeDescription(Method method, const BakeOptions& options);

// Bytes a bake of `method` holds per texel of its map (bakeMemoryEstimate's factor).
double bakeBytesPerTexel(Method method, const BakeOptions& options);

// The peak memory a pipeline will hold, known from its options before it decodes its image:
// `bytesPerTexel` per texel of that image plus `fixedBytes`. While one is alive on a thread,
// checkDecodedSize (which every decoder calls with its header's size before allocating) checks
// that peak against maxMemoryBytes, so a small file that decodes to a huge map is refused from
// its header: "NAME: <what> of a WxH map needs about N, above the limit of L". Without one, a
// decoder's own output (16 bytes per texel at most) is held to maxMemoryBytes.
class PlannedPeak {
  public:
    PlannedPeak(std::string what, double bytesPerTexel, int64_t fixedBytes = 0);
    ~PlannedPeak();
    PlannedPeak(const PlannedPeak&) = delete;
    PlannedPeak& operator=(const PlannedPeak&) = delete;

    std::string what;
    double bytesPerTexel;
    int64_t fixedBytes;

  private:
    const PlannedPeak* outer_;
};

// The line for an allocation that failed (std::bad_alloc) while `name` was processed on this
// thread: "NAME: out of memory (needs about 6.3 GiB)", the figure being the last estimate
// checked on this thread for `name` (left out when there is none). Without a name: the file
// of the last size checked on this thread, the one being processed when memory ran out.
std::string outOfMemoryMessage(const std::string& name);
std::string outOfMemoryMessage();

// Bytes as a short human-readable figure ("86.0 GiB").
std::string byteSize(int64_t bytes);

} // namespace ndfmip
