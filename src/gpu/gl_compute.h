// Runs a GLSL compute kernel over a float array and reads the results back exactly: the way
// tests check a GLSL function against its C++ twin, and a small batch evaluator.
//
// The kernel is the body of a compute shader: no #version and no buffer declarations, those
// come from the prelude put in front of it (computeShaderHead()):
//
//     layout(local_size_x = 64) in;
//     layout(std430, binding = 0) readonly buffer NdfmipInputBuffer { float ndfmipInput[]; };
//     layout(std430, binding = 1) buffer NdfmipOutputBuffer { float ndfmipOutput[]; };
//     uniform uint ndfmipItems; // the item count
//
// One invocation per item, item index gl_GlobalInvocationID.x; the last work group runs past
// the end, so main() must return when the index is not below ndfmipItems:
//
//     void main() {
//         uint i = gl_GlobalInvocationID.x;
//         if (i >= ndfmipItems) return;
//         float x = ndfmipInput[i];
//         ndfmipOutput[2 * i] = x * x + 1.0;
//         ndfmipOutput[2 * i + 1] = exp(x);
//     }
#pragma once

#include "gpu/gl_context.h"
#include "gpu/gl_program.h"

#include <string>
#include <vector>

namespace ndfmip {

constexpr int kComputeLocalSize = 64; // local_size_x of every kernel run here

// "#version 450 core" and the prelude above, as segments "<version header>" and "<compute
// prelude>"; append the kernel's files to it (appendShaderText, or loadShaderFiles(folder, files,
// computeShaderHead())).
ShaderSource computeShaderHead();

// Compiles `source` (which must start with computeShaderHead()) as a compute program.
Result<GlProgram> compileCompute(const GlContext& gl, const ShaderSource& source);

// Uploads `input` to binding 0, runs `program` over `items` invocations and returns the
// `outputFloatsPerItem * items` floats of binding 1 (zero where the kernel wrote nothing).
// Fails when the buffers exceed the driver's storage-block size or `items` its work-group count
// (at least 65535 * 64 items everywhere).
Result<std::vector<float>> runComputeProgram(const GlContext& gl, const GlProgram& program,
                                             const std::vector<float>& input,
                                             int outputFloatsPerItem, int items);

// Compile and run in one call; `source` is the kernel alone, `name` names it in error messages.
Result<std::vector<float>> runCompute(const GlContext& gl, const std::string& source,
                                      const std::vector<float>& input, int outputFloatsPerItem,
                                      int items, const std::string& name = "<kernel>");

// The same for a kernel concatenated from files: `source` must start with computeShaderHead().
Result<std::vector<float>> runCompute(const GlContext& gl, const ShaderSource& source,
                                      const std::vector<float>& input, int outputFloatsPerItem,
                                      int items);

} // namespace ndfmip
