#include "renderer/gl/shader_program.h"

#include <algorithm>
#include <cctype>
#include <glm/gtc/type_ptr.hpp>
#include <sstream>

#include "renderer/core/errors.h"
#include "renderer/gl/embedded_shaders.h"

namespace omnishadow {
namespace {

std::string_view shaderText(const std::string& file) {
  const auto text = shaders::find(file);
  if (!text) throw RenderError("internal error: shader file " + file + " is not embedded");
  return *text;
}

// The source string number of a file, numbering it on first use.
int sourceNumber(const std::string& file, std::vector<std::string>& files) {
  const auto found = std::find(files.begin(), files.end(), file);
  if (found != files.end()) return static_cast<int>(found - files.begin());
  files.push_back(file);
  return static_cast<int>(files.size()) - 1;
}

// `#line N S`: the next line is line N of source string S (GLSL 4.50, like C's #line).
std::string lineDirective(int line, int source) {
  return "#line " + std::to_string(line) + " " + std::to_string(source) + "\n";
}

void appendWithIncludes(const std::string& file, ShaderSource& out, int depth) {
  if (depth > 8) throw RenderError("internal error: shader includes nest too deep in " + file);
  const int source = sourceNumber(file, out.files);
  out.text += lineDirective(1, source);
  std::istringstream lines{std::string(shaderText(file))};
  std::string line;
  int number = 0;
  while (std::getline(lines, line)) {
    ++number;
    const auto start = line.find("#include \"");
    if (start != std::string::npos && line.find_first_not_of(" \t") == start) {
      const auto nameStart = start + 10;
      const auto nameEnd = line.find('"', nameStart);
      appendWithIncludes(line.substr(nameStart, nameEnd - nameStart), out, depth + 1);
      // Back in this file: without this, errors below an include would count on from the
      // included file's lines.
      out.text += lineDirective(number + 1, source);
      continue;
    }
    out.text += line;
    out.text += '\n';
  }
}

// "S:L(" at the start of a log line (Mesa), as source string S and the length of "S:".
bool mesaLocation(const std::string& line, std::size_t& source, std::size_t& prefix) {
  std::size_t i = 0;
  while (i < line.size() && std::isdigit(static_cast<unsigned char>(line[i]))) ++i;
  if (i == 0 || i >= line.size() || line[i] != ':') return false;
  std::size_t j = i + 1;
  while (j < line.size() && std::isdigit(static_cast<unsigned char>(line[j]))) ++j;
  if (j == i + 1 || j >= line.size() || line[j] != '(') return false;
  source = std::stoul(line.substr(0, i));
  prefix = i + 1;
  return true;
}

// The driver's compile or link log of a shader or program.
template <typename GetIv, typename GetLog>
std::string infoLog(GLuint object, GetIv getIv, GetLog getLog) {
  GLint length = 0;
  getIv(object, GL_INFO_LOG_LENGTH, &length);
  std::string log(static_cast<std::size_t>(std::max(length, 1)), '\0');
  getLog(object, length, nullptr, log.data());
  return log;
}

gl::Shader compile(GLenum stage, const std::string& file, const ShaderSource& source) {
  gl::Shader shader(glCreateShader(stage));
  const char* text = source.text.c_str();
  glShaderSource(shader.get(), 1, &text, nullptr);
  glCompileShader(shader.get());
  GLint ok = GL_FALSE;
  glGetShaderiv(shader.get(), GL_COMPILE_STATUS, &ok);
  if (!ok)
    throw RenderError(
        "internal error: cannot compile shader " + file + ":\n" +
        describeShaderLog(infoLog(shader.get(), glGetShaderiv, glGetShaderInfoLog), source.files));
  return shader;
}

}  // namespace

ShaderSource expandShader(const std::string& file, const std::vector<std::string>& defines) {
  ShaderSource source;
  source.text = "#version 450 core\n";
  for (const std::string& define : defines) source.text += "#define " + define + "\n";
  appendWithIncludes(file, source, 0);
  return source;
}

std::string expandShaderSource(const std::string& file, const std::vector<std::string>& defines) {
  return expandShader(file, defines).text;
}

std::string describeShaderLog(const std::string& log, const std::vector<std::string>& files) {
  std::istringstream lines{log.substr(0, log.find('\0'))};
  std::string out, line;
  while (std::getline(lines, line)) {
    std::size_t source = 0, prefix = 0;
    if (mesaLocation(line, source, prefix) && source < files.size())
      line = files[source] + ":" + line.substr(prefix);
    out += line + "\n";
  }
  out += "(source strings:";
  for (std::size_t i = 0; i < files.size(); ++i)
    out += (i ? ", " : " ") + std::to_string(i) + " = " + files[i];
  return out + ")";
}

ShaderProgram::ShaderProgram(const std::string& vertexFile, const std::string& fragmentFile,
                             const std::vector<std::string>& defines,
                             const std::string& geometryFile)
    : program_(glCreateProgram()),
      name_(vertexFile + (geometryFile.empty() ? "" : " + " + geometryFile) + " + " +
            fragmentFile) {
  std::vector<gl::Shader> shaders;
  shaders.push_back(compile(GL_VERTEX_SHADER, vertexFile, expandShader(vertexFile, defines)));
  if (!geometryFile.empty())
    shaders.push_back(
        compile(GL_GEOMETRY_SHADER, geometryFile, expandShader(geometryFile, defines)));
  shaders.push_back(compile(GL_FRAGMENT_SHADER, fragmentFile, expandShader(fragmentFile, defines)));
  for (const gl::Shader& shader : shaders) glAttachShader(program_.get(), shader.get());
  glLinkProgram(program_.get());
  for (const gl::Shader& shader : shaders) glDetachShader(program_.get(), shader.get());
  GLint ok = GL_FALSE;
  glGetProgramiv(program_.get(), GL_LINK_STATUS, &ok);
  if (!ok)
    throw RenderError("internal error: cannot link " + name_ + ":\n" +
                      infoLog(program_.get(), glGetProgramiv, glGetProgramInfoLog));

  // Every active uniform once; arrays are listed as "name[0]" and set by their plain name too.
  GLint count = 0, longest = 0;
  glGetProgramiv(program_.get(), GL_ACTIVE_UNIFORMS, &count);
  glGetProgramiv(program_.get(), GL_ACTIVE_UNIFORM_MAX_LENGTH, &longest);
  std::string name(static_cast<std::size_t>(std::max(longest, 1)), '\0');
  for (GLint i = 0; i < count; ++i) {
    GLsizei length = 0;
    GLint size = 0;
    GLenum type = 0;
    glGetActiveUniform(program_.get(), static_cast<GLuint>(i), longest, &length, &size, &type,
                       name.data());
    const std::string uniform = name.substr(0, static_cast<std::size_t>(length));
    const GLint at = glGetUniformLocation(program_.get(), uniform.c_str());
    if (at < 0) continue;  // a member of a uniform block
    locations_.emplace(uniform, at);
    if (uniform.ends_with("[0]")) locations_.emplace(uniform.substr(0, uniform.size() - 3), at);
  }
}

void ShaderProgram::use() const {
  glUseProgram(program_.get());
}

GLint ShaderProgram::location(std::string_view uniform) const {
  const auto found = locations_.find(uniform);
  return found == locations_.end() ? -1 : found->second;
}

void ShaderProgram::set(const char* u, int v) const {
  glProgramUniform1i(id(), location(u), v);
}
void ShaderProgram::set(const char* u, float v) const {
  glProgramUniform1f(id(), location(u), v);
}
void ShaderProgram::set(const char* u, const glm::vec2& v) const {
  glProgramUniform2fv(id(), location(u), 1, glm::value_ptr(v));
}
void ShaderProgram::set(const char* u, const glm::vec3& v) const {
  glProgramUniform3fv(id(), location(u), 1, glm::value_ptr(v));
}
void ShaderProgram::set(const char* u, const glm::vec4& v) const {
  glProgramUniform4fv(id(), location(u), 1, glm::value_ptr(v));
}
void ShaderProgram::set(const char* u, const glm::mat3& v) const {
  glProgramUniformMatrix3fv(id(), location(u), 1, GL_FALSE, glm::value_ptr(v));
}
void ShaderProgram::set(const char* u, const glm::mat4& v) const {
  glProgramUniformMatrix4fv(id(), location(u), 1, GL_FALSE, glm::value_ptr(v));
}
void ShaderProgram::set(const char* u, const glm::mat4* values, int count) const {
  glProgramUniformMatrix4fv(id(), location(u), count, GL_FALSE, glm::value_ptr(values[0]));
}
void ShaderProgram::set(const char* u, const glm::vec4* values, int count) const {
  glProgramUniform4fv(id(), location(u), count, glm::value_ptr(values[0]));
}
void ShaderProgram::set(const char* u, const float* values, int count) const {
  glProgramUniform1fv(id(), location(u), count, values);
}

}  // namespace omnishadow
