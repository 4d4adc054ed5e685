#include <string>

#include <gtest/gtest.h>

#include "gpu/gl_program.h"
#include "gpu_test_support.h"
#include "test_support.h"

namespace ndfmip {
namespace {

ShaderSource twoFiles() {
    ShaderSource source = glslVersionHeader();
    appendShaderText(source, "common.glsl", "float half_(float x) {\n    return 0.5 * x;\n}\n");
    appendShaderText(source, "main.glsl",
                     "out vec4 colour;\nvoid main() {\n    colour = vec4(half_(2.0));\n}");
    return source;
}

TEST(GlProgram, SegmentsStartWhereEachFileStarts) {
    ShaderSource source = twoFiles();
    ASSERT_EQ(source.segments.size(), 3u);
    EXPECT_EQ(source.segments[0].firstLine, 1); // #version
    EXPECT_EQ(source.segments[1].firstLine, 2);
    EXPECT_EQ(source.segments[2].firstLine, 5);
    EXPECT_EQ(source.text.back(), '\n'); // main.glsl had no final newline
}

// Concatenated line 6 is main.glsl's line 2, whatever the driver's log format.
TEST(GlProgram, MapsDriverLogLinesToFiles) {
    ShaderSource source = twoFiles();
    EXPECT_EQ(firstShaderError("0:6(5): error: `foo' undeclared\n0:7(1): error: more\n", source),
              "main.glsl:2: error: `foo' undeclared");
    EXPECT_EQ(firstShaderError("0(6) : error C1008: undefined variable \"foo\"\n", source),
              "main.glsl:2: error C1008: undefined variable \"foo\"");
    EXPECT_EQ(
        firstShaderError("ERROR: 0:3: 'foo' : undeclared identifier\nERROR: 1 compilation errors.",
                         source),
        "common.glsl:2: error: 'foo' : undeclared identifier");
    // A warning before the error is passed over.
    EXPECT_EQ(firstShaderError("0:2(1): warning: unused\n0:9(3): error: bad\n", source),
              "main.glsl:5: error: bad");
    EXPECT_EQ(firstShaderError("error: unresolved reference to function `g'\n", source),
              "error: unresolved reference to function `g'");
    EXPECT_EQ(firstShaderError("", source), "no message from the driver");
}

TEST(GlProgram, LoaderRefusesVersionAndInclude) {
    test::TempDir dir("gl_program");
    test::writeBytes(dir.path / "a.glsl", "float a() { return 1.0; }\n");
    test::writeBytes(dir.path / "b.glsl", "// b\n#version 450 core\n");
    test::writeBytes(dir.path / "c.glsl", "  #include \"a.glsl\"\n");

    Result<ShaderSource> ok = loadShaderFiles(dir.path, {"a.glsl"});
    ASSERT_TRUE(ok.ok()) << ok.error().message;
    EXPECT_EQ(ok->text, "#version 450 core\nfloat a() { return 1.0; }\n");

    Result<ShaderSource> version = loadShaderFiles(dir.path, {"a.glsl", "b.glsl"});
    ASSERT_FALSE(version.ok());
    EXPECT_NE(version.error().message.find("b.glsl:2"), std::string::npos)
        << version.error().message;
    Result<ShaderSource> include = loadShaderFiles(dir.path, {"c.glsl"});
    ASSERT_FALSE(include.ok());
    EXPECT_NE(include.error().message.find("#include"), std::string::npos)
        << include.error().message;
    Result<ShaderSource> missing = loadShaderFiles(dir.path, {"nope.glsl"});
    ASSERT_FALSE(missing.ok());
    EXPECT_NE(missing.error().message.find("nope.glsl"), std::string::npos)
        << missing.error().message;
}

// The real driver's message for a shader broken in its second file names that file and the
// line within it.
TEST(GlProgram, CompileErrorNamesSecondFileAndItsLine) {
    NDFMIP_GL_OR_SKIP(gl);
    test::TempDir dir("gl_program");
    test::writeBytes(dir.path / "common.glsl", "float half_(float x) {\n    return 0.5 * x;\n}\n");
    test::writeBytes(dir.path / "broken.glsl",
                     "out vec4 colour;\nvoid main() {\n    float y = half_(1.0);\n    colour = "
                     "vec4(y, notDeclared, 0.0, 1.0);\n}\n");
    Result<ShaderSource> source = loadShaderFiles(dir.path, {"common.glsl", "broken.glsl"});
    ASSERT_TRUE(source.ok()) << source.error().message;

    Result<GlProgram> program = compileProgram({{ShaderStage::Fragment, source.value()}});
    ASSERT_FALSE(program.ok());
    const std::string& message = program.error().message;
    EXPECT_NE(message.find("fragment shader"), std::string::npos) << message;
    EXPECT_NE(message.find("broken.glsl:4:"), std::string::npos) << message;
    EXPECT_NE(message.find("notDeclared"), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

TEST(GlProgram, LinkErrorIsOneLine) {
    NDFMIP_GL_OR_SKIP(gl);
    ShaderSource fragment = glslVersionHeader();
    appendShaderText(fragment, "declared_only.glsl",
                     "float missing(float x);\nout vec4 colour;\nvoid main() { colour = "
                     "vec4(missing(1.0)); }\n");
    Result<GlProgram> program = compileProgram({{ShaderStage::Fragment, fragment}});
    ASSERT_FALSE(program.ok());
    const std::string& message = program.error().message;
    EXPECT_NE(message.find("declared_only.glsl"), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

TEST(GlProgram, VertexAndFragmentLink) {
    NDFMIP_GL_OR_SKIP(gl);
    ShaderSource vertex = glslVersionHeader();
    appendShaderText(vertex, "triangle.vert",
                     "void main() { gl_Position = vec4(float(gl_VertexID & 1) * 4.0 - 1.0, "
                     "float(gl_VertexID >> 1) * 4.0 - 1.0, 0.0, 1.0); }\n");
    ShaderSource fragment = glslVersionHeader();
    appendShaderText(fragment, "white.frag",
                     "out vec4 colour;\nvoid main() { colour = vec4(1.0); }\n");
    Result<GlProgram> program =
        compileProgram({{ShaderStage::Vertex, vertex}, {ShaderStage::Fragment, fragment}});
    ASSERT_TRUE(program.ok()) << program.error().message;
    EXPECT_NE(program->id(), 0u);
}

} // namespace
} // namespace ndfmip
