#include "gpu/gl_program.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <sstream>

namespace ndfmip {

namespace {

const char* stageName(ShaderStage stage) {
    switch (stage) {
    case ShaderStage::Vertex:
        return "vertex shader";
    case ShaderStage::Fragment:
        return "fragment shader";
    case ShaderStage::Compute:
        return "compute shader";
    }
    return "shader";
}

GLenum stageEnum(ShaderStage stage) {
    switch (stage) {
    case ShaderStage::Vertex:
        return GL_VERTEX_SHADER;
    case ShaderStage::Fragment:
        return GL_FRAGMENT_SHADER;
    case ShaderStage::Compute:
        return GL_COMPUTE_SHADER;
    }
    return GL_NONE;
}

std::string trimmed(std::string_view text) {
    size_t begin = text.find_first_not_of(" \t\r\n");
    if (begin == std::string_view::npos) return {};
    size_t end = text.find_last_not_of(" \t\r\n");
    return std::string(text.substr(begin, end - begin + 1));
}

std::string lowered(std::string_view text) {
    std::string lower(text);
    std::transform(lower.begin(), lower.end(), lower.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return lower;
}

bool startsWithError(std::string_view text) {
    return lowered(text.substr(0, 5)) == "error";
}

// "name:line" for a line of the concatenation: the last segment starting at or before it.
std::string sourceLocation(int line, const ShaderSource& source) {
    const ShaderSegment* segment = nullptr;
    for (const ShaderSegment& s : source.segments)
        if (s.firstLine <= line) segment = &s;
    if (segment == nullptr) return "<source>:" + std::to_string(line);
    return segment->name + ":" + std::to_string(line - segment->firstLine + 1);
}

std::string names(const std::vector<ShaderPart>& parts) {
    std::string list;
    for (const ShaderPart& part : parts)
        for (const ShaderSegment& s : part.source.segments)
            if (s.name.empty() || s.name.front() != '<')
                list += (list.empty() ? "" : ", ") + s.name;
    return list;
}

std::string shaderLog(GLuint shader) {
    GLint length = 0;
    glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
    std::string log(size_t(std::max(length, 1)), '\0');
    glGetShaderInfoLog(shader, length, nullptr, log.data());
    return log;
}

std::string programLog(GLuint program) {
    GLint length = 0;
    glGetProgramiv(program, GL_INFO_LOG_LENGTH, &length);
    std::string log(size_t(std::max(length, 1)), '\0');
    glGetProgramInfoLog(program, length, nullptr, log.data());
    return log;
}

// One line of a driver's info log: Mesa "0:12(5): error: ...", NVIDIA "0(12) : error C0000: ...",
// glslang and AMD "ERROR: 0:12: ...". `line` is 0 when the line has none of these shapes.
struct LogLine {
    int line = 0;
    bool isError = false; // the "ERROR:" prefix said so; otherwise `text` starts with the severity
    std::string text;
};

// Reads the digits at `at`, advancing it; -1 when there are none.
int readNumber(std::string_view text, size_t& at) {
    size_t begin = at;
    long value = 0;
    while (at < text.size() && std::isdigit(static_cast<unsigned char>(text[at])) &&
           value < 1000000)
        value = value * 10 + (text[at++] - '0');
    return at == begin ? -1 : int(value);
}

bool skip(std::string_view text, size_t& at, char c) {
    while (at < text.size() && text[at] == ' ') ++at;
    if (at >= text.size() || text[at] != c) return false;
    ++at;
    return true;
}

LogLine parseLogLine(std::string_view line) {
    LogLine out;
    size_t at = line.find_first_not_of(" \t");
    if (at == std::string_view::npos) return out;
    if (line.substr(at, 6) == "ERROR:") {
        at += 6;
        while (at < line.size() && line[at] == ' ') ++at;
        out.isError = true;
    }
    if (readNumber(line, at) < 0) return out; // source string number
    int number = -1;
    if (skip(line, at, ':')) {
        number = readNumber(line, at);
        if (number < 0) return out;
        if (!out.isError &&
            !(skip(line, at, '(') && readNumber(line, at) >= 0 && skip(line, at, ')')))
            return out; // Mesa's column
    } else if (!out.isError && skip(line, at, '(')) {
        number = readNumber(line, at);
        if (number < 0 || !skip(line, at, ')')) return out;
    } else {
        return out;
    }
    if (!skip(line, at, ':')) return out;
    out.line = number;
    out.text = trimmed(line.substr(at));
    return out;
}

} // namespace

void appendShaderText(ShaderSource& source, std::string_view name, std::string_view text) {
    int firstLine = 1 + int(std::count(source.text.begin(), source.text.end(), '\n'));
    source.segments.push_back({std::string(name), firstLine});
    source.text += text;
    if (text.empty() || text.back() != '\n') source.text += '\n';
}

ShaderSource glslVersionHeader() {
    ShaderSource source;
    appendShaderText(source, "<version header>", "#version 450 core\n");
    return source;
}

Result<ShaderSource> loadShaderFiles(const std::filesystem::path& folder,
                                     const std::vector<std::string>& files, ShaderSource head) {
    ShaderSource source = std::move(head);
    for (const std::string& file : files) {
        std::filesystem::path path = folder / file;
        std::ifstream in(path, std::ios::binary);
        std::ostringstream text;
        text << in.rdbuf();
        if (!in) return Error{"GPU: cannot read shader file " + quote(path.string())};
        std::string body = text.str();

        std::istringstream lines(body);
        std::string line;
        for (int number = 1; std::getline(lines, line); ++number) {
            std::string directive = trimmed(line);
            if (directive.rfind("#version", 0) == 0 || directive.rfind("#include", 0) == 0)
                return Error{"GPU: shader file " + quote(file + ":" + std::to_string(number)) +
                             " has " + directive.substr(0, 8) +
                             " (files are concatenated after '#version 450 core')"};
        }
        appendShaderText(source, file, body);
    }
    return source;
}

std::string firstShaderError(std::string_view log, const ShaderSource& source) {
    std::string fallback;
    std::istringstream lines{std::string(log)};
    for (std::string line; std::getline(lines, line);) {
        LogLine parsed = parseLogLine(line);
        if (parsed.line > 0 && (parsed.isError || startsWithError(parsed.text)))
            return sourceLocation(parsed.line, source) + ": " + (parsed.isError ? "error: " : "") +
                   parsed.text;
        if (fallback.empty() && lowered(line).find("error") != std::string::npos)
            fallback = trimmed(line);
    }
    if (!fallback.empty()) return fallback;
    std::string first = trimmed(log.substr(0, log.find('\n')));
    return first.empty() ? "no message from the driver" : first;
}

GlProgram& GlProgram::operator=(GlProgram&& other) noexcept {
    if (this != &other) {
        if (id_ != 0) glDeleteProgram(id_);
        id_ = other.id_;
        other.id_ = 0;
    }
    return *this;
}

GlProgram::~GlProgram() {
    if (id_ != 0) glDeleteProgram(id_);
}

Result<GlProgram> compileProgram(const std::vector<ShaderPart>& parts) {
    GlProgram program(glCreateProgram());
    if (program.id() == 0) return Error{"GPU: glCreateProgram failed (no current OpenGL context?)"};

    std::vector<GLuint> shaders;
    auto deleteShaders = [&] {
        for (GLuint shader : shaders)
            glDeleteShader(shader); // deferred until detached or the program dies
    };
    for (const ShaderPart& part : parts) {
        GLuint shader = glCreateShader(stageEnum(part.stage));
        shaders.push_back(shader);
        const GLchar* text = part.source.text.c_str();
        const GLint length = GLint(part.source.text.size());
        glShaderSource(shader, 1, &text, &length);
        glCompileShader(shader);
        GLint compiled = GL_FALSE;
        glGetShaderiv(shader, GL_COMPILE_STATUS, &compiled);
        if (compiled != GL_TRUE) {
            std::string message = firstShaderError(shaderLog(shader), part.source);
            deleteShaders();
            return Error{std::string("GPU: ") + stageName(part.stage) +
                         " does not compile: " + message};
        }
        glAttachShader(program.id(), shader);
    }
    glLinkProgram(program.id());
    for (GLuint shader : shaders) glDetachShader(program.id(), shader);
    deleteShaders();

    GLint linked = GL_FALSE;
    glGetProgramiv(program.id(), GL_LINK_STATUS, &linked);
    if (linked != GL_TRUE) {
        // Link errors rarely carry a line; map one when they do (against the first part).
        ShaderSource none;
        std::string message =
            firstShaderError(programLog(program.id()), parts.empty() ? none : parts.front().source);
        return Error{"GPU: program (" + names(parts) + ") does not link: " + message};
    }
    return program;
}

} // namespace ndfmip
