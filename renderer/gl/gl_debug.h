#pragma once

#include <string>

namespace omnishadow::gl {

// Routes KHR_debug messages to stderr (only meaningful on a debug context). Notifications are
// dropped: drivers emit them for every buffer placement.
void enableDebugOutput();

// Throws RenderError("GL error after <stage>: GL_INVALID_...") if the GL error flag is set,
// and RenderError on context loss (glGetGraphicsResetStatus).
void checkErrors(const std::string& stage);

}  // namespace omnishadow::gl
