#pragma once

#include <functional>
#include <glm/glm.hpp>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "renderer/gl/gl_resources.h"

namespace omnishadow {

// A linked GL program built from files in shaders/ (embedded at build time). Sources get
// "#version 450 core", then one "#define" per entry of `defines`, and `#include "file"` lines
// replaced by that file's text. Compile or link errors throw RenderError with the driver's log.
// Uniform locations are looked up once, after linking; set() with a name the program does not
// use (or the compiler optimised away) does nothing.
class ShaderProgram {
 public:
  ShaderProgram(const std::string& vertexFile, const std::string& fragmentFile,
                const std::vector<std::string>& defines = {}, const std::string& geometryFile = {});

  GLuint id() const { return program_.get(); }
  void use() const;
  GLint location(std::string_view uniform) const;  // -1 when the uniform is unused

  void set(const char* uniform, int value) const;
  void set(const char* uniform, float value) const;
  void set(const char* uniform, const glm::vec2& value) const;
  void set(const char* uniform, const glm::vec3& value) const;
  void set(const char* uniform, const glm::vec4& value) const;
  void set(const char* uniform, const glm::mat3& value) const;
  void set(const char* uniform, const glm::mat4& value) const;
  void set(const char* uniform, const glm::mat4* values, int count) const;  // uniform arrays
  void set(const char* uniform, const glm::vec4* values, int count) const;
  void set(const char* uniform, const float* values, int count) const;

 private:
  // Transparent, so set("uName") finds its entry without building a std::string.
  struct NameHash {
    using is_transparent = void;
    std::size_t operator()(std::string_view name) const {
      return std::hash<std::string_view>{}(name);
    }
  };

  gl::Program program_;
  std::string name_;
  std::unordered_map<std::string, GLint, NameHash, std::equal_to<>> locations_;
};

// A shader file expanded for the driver. GLSL's `#line N S` names a source string by number,
// not by file, so the expansion numbers its files: `files[S]` is the file of source string S,
// the expanded file itself being 0. Every line of the text then reports its own file and line.
struct ShaderSource {
  std::string text;
  std::vector<std::string> files;
};
ShaderSource expandShader(const std::string& file, const std::vector<std::string>& defines);

// Just the text of expandShader().
std::string expandShaderSource(const std::string& file, const std::vector<std::string>& defines);

// A driver's compile log made readable: "S:L(C)" locations (Mesa's format) become
// "file:L(C)", and a legend lists every source string number with its file for drivers that
// write locations differently.
std::string describeShaderLog(const std::string& log, const std::vector<std::string>& files);

}  // namespace omnishadow
