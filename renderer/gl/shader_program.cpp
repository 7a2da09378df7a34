#include "renderer/gl/shader_program.h"

#include <glm/gtc/type_ptr.hpp>
#include <sstream>

#include "renderer/gl/embedded_shaders.h"
#include "renderer/core/errors.h"

namespace omnishadow {
namespace {

std::string_view shaderText(const std::string& file) {
  const auto text = shaders::find(file);
  if (!text) throw RenderError("internal error: shader file " + file + " is not embedded");
  return *text;
}

void appendWithIncludes(const std::string& file, std::string& out, int depth) {
  if (depth > 8) throw RenderError("internal error: shader includes nest too deep in " + file);
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
      continue;
    }
    out += line;
    out += '\n';
  }
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

gl::Shader compile(GLenum stage, const std::string& file, const std::string& source) {
  gl::Shader shader(glCreateShader(stage));
  const char* text = source.c_str();
  glShaderSource(shader.get(), 1, &text, nullptr);
  glCompileShader(shader.get());
  GLint ok = GL_FALSE;
  glGetShaderiv(shader.get(), GL_COMPILE_STATUS, &ok);
  if (!ok)
    throw RenderError("internal error: cannot compile shader " + file + ":\n" +
                      infoLog(shader.get(), glGetShaderiv, glGetShaderInfoLog));
  return shader;
}

}  // namespace

std::string expandShaderSource(const std::string& file, const std::vector<std::string>& defines) {
  std::string source = "#version 450 core\n";
  for (const std::string& define : defines) source += "#define " + define + "\n";
  source += "#line 1\n";
  appendWithIncludes(file, source, 0);
  return source;
}

ShaderProgram::ShaderProgram(const std::string& vertexFile, const std::string& fragmentFile,
                             const std::vector<std::string>& defines,
                             const std::string& geometryFile)
    : program_(glCreateProgram()),
      name_(vertexFile + (geometryFile.empty() ? "" : " + " + geometryFile) + " + " +
            fragmentFile) {
  std::vector<gl::Shader> shaders;
  shaders.push_back(compile(GL_VERTEX_SHADER, vertexFile, expandShaderSource(vertexFile, defines)));
  if (!geometryFile.empty())
    shaders.push_back(
        compile(GL_GEOMETRY_SHADER, geometryFile, expandShaderSource(geometryFile, defines)));
  shaders.push_back(
      compile(GL_FRAGMENT_SHADER, fragmentFile, expandShaderSource(fragmentFile, defines)));
  for (const gl::Shader& shader : shaders) glAttachShader(program_.get(), shader.get());
  glLinkProgram(program_.get());
  for (const gl::Shader& shader : shaders) glDetachShader(program_.get(), shader.get());
  GLint ok = GL_FALSE;
  glGetProgramiv(program_.get(), GL_LINK_STATUS, &ok);
  if (!ok)
    throw RenderError("internal error: cannot link " + name_ + ":\n" +
                      infoLog(program_.get(), glGetProgramiv, glGetProgramInfoLog));
}

void ShaderProgram::use() const {
  glUseProgram(program_.get());
}

GLint ShaderProgram::location(const char* uniform) const {
  return glGetUniformLocation(program_.get(), uniform);
}

void ShaderProgram::set(const char* u, int v) const {
  glProgramUniform1i(id(), location(u), v);
}
void ShaderProgram::set(const char* u, float v) const {
  glProgramUniform1f(id(), location(u), v);
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

}  // namespace omnishadow
