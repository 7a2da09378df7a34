#pragma once

#include <GL/glcorearb.h>

#include <array>
#include <cstdint>

namespace omnishadow::gl {

// The fixed-function state a pass draws with, filled in one place and applied in one call, so
// that no pass depends on what the one before it happened to leave behind.
//
// The defaults are what passes leave between them (restoreDefaults). They matter beyond the
// draws: glClear* obeys the depth and color write masks, so a pass that clears before it
// applies its own state relies on writes being on.

struct DepthState {
  bool test = true;
  GLenum func = GL_GREATER;  // reversed depth: nearer is larger
  bool write = true;
  void apply() const;
};

struct CullState {
  bool enabled = false;
  GLenum face = GL_BACK;  // what is culled, when enabled
  GLenum front = GL_CCW;  // also decides gl_FrontFacing where nothing is culled
  void apply() const;
};

// Applied to filled polygons only (GL_POLYGON_OFFSET_FILL).
struct PolygonOffset {
  bool enabled = false;
  float factor = 0.0f, units = 0.0f;
  void apply() const;
};

struct ColorWrites {
  std::array<bool, 4> rgba{true, true, true, true};  // every draw buffer
  std::uint32_t offBuffers = 0;                      // bit i: draw buffer i writes no color at all
  std::uint32_t greenOnlyBuffers = 0;                // bit i: draw buffer i writes green alone
  void apply() const;
};

struct BlendState {
  std::uint32_t buffers = 0;  // bit i: draw buffer i blends; none by default
  GLenum sourceColor = GL_ONE, destinationColor = GL_ZERO;
  GLenum sourceAlpha = GL_ONE, destinationAlpha = GL_ZERO;
  GLenum colorEquation = GL_FUNC_ADD, alphaEquation = GL_FUNC_ADD;
  void apply() const;
};

struct Viewport {
  int x = 0, y = 0, width = 0, height = 0;
  void apply() const;
};

// Off by default; clears obey it too.
struct Scissor {
  bool enabled = false;
  int x = 0, y = 0, width = 0, height = 0;
  void apply() const;
};

struct RasterState {
  DepthState depth;
  CullState cull;
  PolygonOffset offset;
  ColorWrites color;
  BlendState blend;
  Viewport viewport;
  Scissor scissor;

  void apply() const;
  // The defaults above, viewport aside (every pass sets its own).
  static void restoreDefaults();
};

}  // namespace omnishadow::gl
