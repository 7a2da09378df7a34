#pragma once

#include <glm/glm.hpp>

#include "renderer/verify/shadow_reference.h"

namespace omnishadow {

// The ray-traced counterpart of the screen-space ambient occlusion (AmbientOcclusion): the
// cosine-weighted share of the hemisphere above `normal` at `point` whose rays meet no surface
// (as ShadowReference casts them: cut-outs let them through) within `reach`, from `samples`
// stratified rays (rounded down to a square grid), leaving the surface at point + normal x
// epsilon(). The same every call. Every surface occludes, seen by the camera or not.
float ambientVisibility(const ShadowReference& reference, const glm::vec3& point,
                        const glm::vec3& normal, float reach, int samples = 64);

}  // namespace omnishadow
