#include "renderer/gl/raster_state.h"

namespace omnishadow::gl {
namespace {

void setEnabled(GLenum capability, bool enabled) {
  if (enabled)
    glEnable(capability);
  else
    glDisable(capability);
}

GLboolean glBool(bool value) {
  return value ? GL_TRUE : GL_FALSE;
}

}  // namespace

void DepthState::apply() const {
  setEnabled(GL_DEPTH_TEST, test);
  glDepthFunc(func);
  glDepthMask(glBool(write));
}

void CullState::apply() const {
  setEnabled(GL_CULL_FACE, enabled);
  if (enabled) glCullFace(face);
  glFrontFace(front);
}

void PolygonOffset::apply() const {
  setEnabled(GL_POLYGON_OFFSET_FILL, enabled);
  if (enabled) glPolygonOffset(factor, units);
}

void ColorWrites::apply() const {
  glColorMask(glBool(rgba[0]), glBool(rgba[1]), glBool(rgba[2]), glBool(rgba[3]));
  for (GLuint i = 0; i < 32; ++i)
    if (offBuffers & (1u << i)) glColorMaski(i, GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
  for (GLuint i = 0; i < 32; ++i)
    if (greenOnlyBuffers & (1u << i)) glColorMaski(i, GL_FALSE, GL_TRUE, GL_FALSE, GL_FALSE);
}

void BlendState::apply() const {
  glDisable(GL_BLEND);
  for (GLuint i = 0; i < 32; ++i) {
    if (!(buffers & (1u << i))) continue;
    glEnablei(GL_BLEND, i);
    glBlendFuncSeparatei(i, sourceColor, destinationColor, sourceAlpha, destinationAlpha);
    glBlendEquationSeparatei(i, colorEquation, alphaEquation);
  }
}

void Viewport::apply() const {
  glViewport(x, y, width, height);
}

void Scissor::apply() const {
  setEnabled(GL_SCISSOR_TEST, enabled);
  if (enabled) glScissor(x, y, width, height);
}

void RasterState::apply() const {
  depth.apply();
  cull.apply();
  offset.apply();
  color.apply();
  blend.apply();
  viewport.apply();
  scissor.apply();
}

void RasterState::restoreDefaults() {
  const RasterState defaults;
  defaults.depth.apply();
  defaults.cull.apply();
  defaults.offset.apply();
  defaults.color.apply();
  defaults.blend.apply();
  defaults.scissor.apply();
}

}  // namespace omnishadow::gl
