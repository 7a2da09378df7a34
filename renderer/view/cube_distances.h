#pragma once

#include <array>
#include <vector>

#include "renderer/view/cube_faces.h"

namespace omnishadow {

// A point light's shadow cube map read back as distances to the light (world units) along each
// texel center's ray. Faces in GL order; rows in GL texel order (row 0 = t 0, column 0 = s 0).
// Texels where nothing was rendered hold +infinity.
struct CubeDistances {
  int resolution = 0;
  std::array<std::vector<float>, kCubeFaceCount> faces;
  float at(CubeFace face, int column, int row) const {
    return faces[static_cast<int>(face)][static_cast<std::size_t>(row) * resolution + column];
  }
};

}  // namespace omnishadow
