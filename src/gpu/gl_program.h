// GLSL programs built from sources concatenated out of several files, with compile and link
// errors reported as one line against the file the error is in, not the concatenation.
#pragma once

#include "ndfmip/result.h"

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace ndfmip {

enum class ShaderStage { Vertex, Fragment, Compute };

// Where one input file starts in a concatenated source.
struct ShaderSegment {
    std::string name; // file name as it should appear in messages
    int firstLine;    // 1-based line of the concatenation holding the file's line 1
};

// Source text plus the files it was made of, in order.
struct ShaderSource {
    std::string text;
    std::vector<ShaderSegment> segments;
};

// Appends `text` as a segment called `name`, ending it with a newline if it lacks one.
void appendShaderText(ShaderSource& source, std::string_view name, std::string_view text);

// A source holding only "#version 450 core" (segment "<version header>"); append the files to it.
ShaderSource glslVersionHeader();

// Reads `files` (names relative to `folder`, in order) and appends them to `head`, by default
// glslVersionHeader(). The files must have no #version (the head gives it) and no #include
// (GLSL has none).
Result<ShaderSource> loadShaderFiles(const std::filesystem::path& folder,
                                     const std::vector<std::string>& files,
                                     ShaderSource head = glslVersionHeader());

// The first error of a driver's info log as one line, its line number mapped through
// `source.segments` ("b.glsl:3: error: `foo' undeclared"). Understands Mesa's "0:LINE(COL):",
// NVIDIA's "0(LINE) :" and the "ERROR: 0:LINE:" of other drivers and glslang.
std::string firstShaderError(std::string_view log, const ShaderSource& source);

struct ShaderPart {
    ShaderStage stage;
    ShaderSource source;
};

// A linked program object; deletes it when destroyed (the context it came from must be current).
class GlProgram {
  public:
    GlProgram() = default;
    explicit GlProgram(unsigned id) : id_(id) {}
    GlProgram(GlProgram&& other) noexcept : id_(other.id_) { other.id_ = 0; }
    GlProgram& operator=(GlProgram&& other) noexcept;
    GlProgram(const GlProgram&) = delete;
    GlProgram& operator=(const GlProgram&) = delete;
    ~GlProgram();

    unsigned id() const { return id_; } // the GLuint name

  private:
    unsigned id_ = 0;
};

// Compiles each part and links them, in the current context. Errors are one line:
// "GPU: compute shader does not compile: kernel.glsl:12: error: ...".
Result<GlProgram> compileProgram(const std::vector<ShaderPart>& parts);

} // namespace ndfmip
