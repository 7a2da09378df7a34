// Shader source expansion: `#include` pasting and the `#line` directives that keep compile
// errors pointing at the right file and line. No GL context needed.
#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "renderer/gl/embedded_shaders.h"
#include "renderer/gl/shader_program.h"

namespace omnishadow::shader_source_test {
namespace {

std::vector<std::string> splitLines(std::string_view text) {
  std::vector<std::string> lines;
  std::istringstream in{std::string(text)};
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// A line of the expanded text with where a compiler says it is, following `#line N S` as
// GLSL 4.50 (and C) define it: the next line is line N of source string S.
struct Located {
  std::string text;
  int source = -1;
  int line = 0;
};

std::vector<Located> locate(const std::string& expanded) {
  std::vector<Located> located;
  int source = -1, line = 0;
  for (const std::string& text : splitLines(expanded)) {
    if (text.rfind("#line ", 0) == 0) {
      std::istringstream directive(text.substr(6));
      directive >> line >> source;
      continue;
    }
    if (source >= 0) located.push_back({text, source, line});
    ++line;
  }
  return located;
}

std::string fileLine(const std::string& file, int line) {
  const auto lines = splitLines(*shaders::find(file));
  return line >= 1 && line <= static_cast<int>(lines.size()) ? lines[line - 1] : "<no such line>";
}

TEST(ShaderSource, ALineAfterAnIncludeMapsBackToItsFileAndLine) {
  const ShaderSource source = expandShader("lighting.frag", {"WRITE_AOVS"});
  ASSERT_GE(source.files.size(), 4u);
  EXPECT_EQ(source.files[0], "lighting.frag");

  // "in VertexData {" follows the three includes of lighting.frag.
  bool found = false;
  for (const Located& l : locate(source.text)) {
    if (l.text != "in VertexData {") continue;
    found = true;
    EXPECT_EQ(source.files[l.source], "lighting.frag");
    EXPECT_EQ(fileLine("lighting.frag", l.line), "in VertexData {");
    EXPECT_GT(l.line, 3);  // not counted from the start of an included file
  }
  EXPECT_TRUE(found);
}

TEST(ShaderSource, EveryExpandedLineIsTheLineItClaimsToBe) {
  for (const char* file : {"lighting.frag", "scene.vert", "shadow_depth.vert", "vsm_blur.frag"}) {
    const ShaderSource source = expandShader(file, {"SOME_DEFINE 1"});
    const auto located = locate(source.text);
    ASSERT_FALSE(located.empty()) << file;
    for (const Located& l : located) {
      ASSERT_GE(l.source, 0);
      ASSERT_LT(l.source, static_cast<int>(source.files.size()));
      EXPECT_EQ(fileLine(source.files[l.source], l.line), l.text)
          << file << ": " << source.files[l.source] << ":" << l.line;
    }
  }
}

TEST(ShaderSource, IncludedFilesGetTheirOwnSourceNumbers) {
  const ShaderSource source = expandShader("lighting.frag", {});
  bool lightsSeen = false;
  for (const Located& l : locate(source.text))
    if (l.text == "struct Light {") {
      lightsSeen = true;
      EXPECT_EQ(source.files[l.source], "lights.glsl");
      EXPECT_EQ(fileLine("lights.glsl", l.line), "struct Light {");
    }
  EXPECT_TRUE(lightsSeen);
}

TEST(ShaderSource, CompileLogsNameTheFiles) {
  const std::vector<std::string> files = {"lighting.frag", "lights.glsl"};
  const std::string log = describeShaderLog(
      "1:12(5): error: `foo' undeclared\n0:40(3): warning: unused\nno location here\n", files);
  EXPECT_NE(log.find("lights.glsl:12(5): error: `foo' undeclared"), std::string::npos) << log;
  EXPECT_NE(log.find("lighting.frag:40(3): warning: unused"), std::string::npos) << log;
  EXPECT_NE(log.find("no location here"), std::string::npos) << log;
  EXPECT_NE(log.find("0 = lighting.frag, 1 = lights.glsl"), std::string::npos) << log;
}

}  // namespace
}  // namespace omnishadow::shader_source_test
