#pragma once

#include <glm/glm.hpp>
#include <vector>

#include "renderer/view/camera.h"

namespace omnishadow {

// Camera sets for multi-view renders: each view is an eye looking at `center` (+Y up), to be
// applied to a CameraRequest as --eye/--target would be.
struct CameraView {
  glm::vec3 eye{0.0f};
  glm::vec3 target{0.0f};
};

// `count` eyes on the horizontal circle around `center` through `eye` (its elevation and
// distance kept), 360/count degrees apart, starting at `eye`. An eye straight above or below
// the center gets the circle at 30 degrees elevation at its distance.
std::vector<CameraView> orbitViews(const glm::vec3& eye, const glm::vec3& center, int count);

// `count` eyes spread evenly over the upper hemisphere around `center` at `distance` (a
// Fibonacci lattice: equal areas per view, heights (k + 0.5) / count apart from the top).
std::vector<CameraView> hemisphereViews(const glm::vec3& center, float distance, int count);

}  // namespace omnishadow
