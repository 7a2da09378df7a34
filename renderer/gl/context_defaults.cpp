#include "renderer/gl/context_defaults.h"

#include <GL/glcorearb.h>

namespace omnishadow::gl {

void applyContextDefaults() {
  glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
  glEnable(GL_TEXTURE_CUBE_MAP_SEAMLESS);
}

}  // namespace omnishadow::gl
