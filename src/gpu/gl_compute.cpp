#include "gpu/gl_compute.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <cassert>
#include <cstdio>

namespace ndfmip {

namespace {

// After the local size line, which comes from kComputeLocalSize.
const char* kComputeBuffers =
    R"(layout(std430, binding = 0) readonly buffer NdfmipInputBuffer { float ndfmipInput[]; };
layout(std430, binding = 1) buffer NdfmipOutputBuffer { float ndfmipOutput[]; };
uniform uint ndfmipItems;
)";

std::string glErrorText(GLenum code) {
    char hex[48];
    std::snprintf(hex, sizeof hex, "GL error 0x%04x", unsigned(code));
    return hex;
}

// A buffer object deleted on every return path.
struct GlBuffer {
    GLuint id = 0;
    GlBuffer() { glCreateBuffers(1, &id); }
    ~GlBuffer() { glDeleteBuffers(1, &id); }
    GlBuffer(const GlBuffer&) = delete;
    GlBuffer& operator=(const GlBuffer&) = delete;
};

} // namespace

ShaderSource computeShaderHead() {
    ShaderSource source = glslVersionHeader();
    appendShaderText(source, "<compute prelude>",
                     "layout(local_size_x = " + std::to_string(kComputeLocalSize) + ") in;\n" +
                         kComputeBuffers);
    return source;
}

Result<GlProgram> compileCompute(const GlContext& gl, const ShaderSource& source) {
    if (Status current = makeCurrent(gl); !current) return Error{current.error};
    return compileProgram({{ShaderStage::Compute, source}});
}

Result<std::vector<float>> runComputeProgram(const GlContext& gl, const GlProgram& program,
                                             const std::vector<float>& input,
                                             int outputFloatsPerItem, int items) {
    assert(outputFloatsPerItem >= 1 && items >= 0);
    if (Status current = makeCurrent(gl); !current) return Error{current.error};
    if (items == 0) return std::vector<float>();

    GLint maxGroups = 0;
    glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, 0, &maxGroups);
    const GLint64 groups = (GLint64(items) + kComputeLocalSize - 1) / kComputeLocalSize;
    if (groups > maxGroups)
        return Error{"GPU: " + std::to_string(items) +
                     " compute items exceed the driver's limit of " +
                     std::to_string(GLint64(maxGroups) * kComputeLocalSize)};
    GLint64 maxBlock = 0;
    glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &maxBlock);
    const GLint64 inputBytes = GLint64(input.size()) * GLint64(sizeof(float));
    const GLint64 outputBytes = GLint64(items) * outputFloatsPerItem * GLint64(sizeof(float));
    if (inputBytes > maxBlock || outputBytes > maxBlock)
        return Error{
            "GPU: compute buffers of " + std::to_string(std::max(inputBytes, outputBytes)) +
            " bytes exceed the driver's shader storage block size of " + std::to_string(maxBlock)};

    while (glGetError() != GL_NO_ERROR) {
    } // errors left by earlier callers are not ours

    // A zero-sized buffer cannot back a binding, so an empty input gets one unused float.
    GlBuffer in, out;
    const float unused = 0;
    glNamedBufferStorage(in.id, std::max<GLint64>(inputBytes, sizeof(float)),
                         input.empty() ? &unused : input.data(), 0);
    glNamedBufferStorage(out.id, outputBytes, nullptr, 0);
    const float zero = 0;
    glClearNamedBufferData(out.id, GL_R32F, GL_RED, GL_FLOAT, &zero);

    glUseProgram(program.id());
    glProgramUniform1ui(program.id(), glGetUniformLocation(program.id(), "ndfmipItems"),
                        GLuint(items));
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, in.id);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, out.id);
    glDispatchCompute(GLuint(groups), 1, 1);
    // Shader writes must land before glGetBufferSubData reads the buffer.
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);

    std::vector<float> result(size_t(items) * size_t(outputFloatsPerItem));
    glGetNamedBufferSubData(out.id, 0, outputBytes, result.data());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, 0);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, 0);
    glUseProgram(0);

    if (GLenum error = glGetError(); error != GL_NO_ERROR)
        return Error{"GPU: compute dispatch failed (" + glErrorText(error) + ")"};
    return result;
}

Result<std::vector<float>> runCompute(const GlContext& gl, const ShaderSource& source,
                                      const std::vector<float>& input, int outputFloatsPerItem,
                                      int items) {
    Result<GlProgram> program = compileCompute(gl, source);
    if (!program) return program.error();
    return runComputeProgram(gl, program.value(), input, outputFloatsPerItem, items);
}

Result<std::vector<float>> runCompute(const GlContext& gl, const std::string& source,
                                      const std::vector<float>& input, int outputFloatsPerItem,
                                      int items, const std::string& name) {
    ShaderSource full = computeShaderHead();
    appendShaderText(full, name, source);
    return runCompute(gl, full, input, outputFloatsPerItem, items);
}

} // namespace ndfmip
