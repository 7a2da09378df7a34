#include "renderer/gl/gl_debug.h"

#include <GL/glcorearb.h>

#include <cstdio>

#include "renderer/core/errors.h"
#include "renderer/gl/enum_names.h"

namespace omnishadow::gl {
namespace {

const char* severityName(GLenum severity) {
  switch (severity) {
    case GL_DEBUG_SEVERITY_HIGH:
      return "high";
    case GL_DEBUG_SEVERITY_MEDIUM:
      return "medium";
    case GL_DEBUG_SEVERITY_LOW:
      return "low";
    default:
      return "note";
  }
}

void APIENTRY printMessage(GLenum, GLenum, GLuint, GLenum severity, GLsizei length,
                           const GLchar* message, const void*) {
  std::fprintf(stderr, "omnishadow: GL (%s): %.*s\n", severityName(severity),
               static_cast<int>(length), message);
}

const char* errorName(GLenum error) {
  static constexpr EnumName<GLenum> kNames[] = {
      OMNISHADOW_ENUM_NAME(GL_INVALID_ENUM),
      OMNISHADOW_ENUM_NAME(GL_INVALID_VALUE),
      OMNISHADOW_ENUM_NAME(GL_INVALID_OPERATION),
      OMNISHADOW_ENUM_NAME(GL_INVALID_FRAMEBUFFER_OPERATION),
      OMNISHADOW_ENUM_NAME(GL_OUT_OF_MEMORY),
      OMNISHADOW_ENUM_NAME(GL_STACK_OVERFLOW),
      OMNISHADOW_ENUM_NAME(GL_STACK_UNDERFLOW),
  };
  return nameOf(error, kNames, "unknown GL error");
}

}  // namespace

void enableDebugOutput() {
  glEnable(GL_DEBUG_OUTPUT);
  glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
  glDebugMessageCallback(printMessage, nullptr);
  glDebugMessageControl(GL_DONT_CARE, GL_DONT_CARE, GL_DEBUG_SEVERITY_NOTIFICATION, 0, nullptr,
                        GL_FALSE);
}

void checkErrors(const std::string& stage) {
  if (glGetGraphicsResetStatus() != GL_NO_ERROR)
    throw RenderError("the OpenGL context was lost during " + stage);
  const GLenum error = glGetError();
  if (error == GL_NO_ERROR) return;
  while (glGetError() != GL_NO_ERROR) {
  }
  throw RenderError(std::string("OpenGL error during ") + stage + ": " + errorName(error));
}

}  // namespace omnishadow::gl
