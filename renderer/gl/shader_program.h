#pragma once

#include <glm/glm.hpp>
#include <string>
#include <vector>

#include "renderer/gl/gl_resources.h"

namespace omnishadow {

// A linked GL program built from files in shaders/ (embedded at build time). Sources get
// "#version 450 core", then one "#define" per entry of `defines`, and `#include "file"` lines
// replaced by that file's text. Compile or link errors throw RenderError with the driver's log.
class ShaderProgram {
 public:
  ShaderProgram(const std::string& vertexFile, const std::string& fragmentFile,
                const std::vector<std::string>& defines = {}, const std::string& geometryFile = {});

  GLuint id() const { return program_.get(); }
  void use() const;
  GLint location(const char* uniform) const;  // -1 when the uniform is unused

  void set(const char* uniform, int value) const;
  void set(const char* uniform, float value) const;
  void set(const char* uniform, const glm::vec3& value) const;
  void set(const char* uniform, const glm::vec4& value) const;
  void set(const char* uniform, const glm::mat3& value) const;
  void set(const char* uniform, const glm::mat4& value) const;
  void set(const char* uniform, const glm::mat4* values, int count) const;  // uniform arrays

 private:
  gl::Program program_;
  std::string name_;
};

// The full source text a shader file expands to (for tests and error messages).
std::string expandShaderSource(const std::string& file, const std::vector<std::string>& defines);

}  // namespace omnishadow
