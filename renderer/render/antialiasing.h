#pragma once

#include <glm/glm.hpp>
#include <vector>

#include "renderer/view/camera.h"

namespace omnishadow {

// Anti-aliased beauty (--aa N): the beauty is rendered N times, each time with the projection
// shifted by a sub-pixel offset, and averaged; AOVs, ids, masks, depth and visibility are still
// rendered once through the pixel centers, so they stay exact. Offsets are the standard
// multisample positions (Direct3D's, also what most GL drivers use), in pixels from the pixel
// center, x right and y down. Only 1, 4, 8 and 16 have a pattern.
bool isAntialiasingSampleCount(int samples);
// InputError "--aa N: expected 1, 4, 8 or 16" for any other count.
void checkAntialiasingSampleCount(int samples);
std::vector<glm::vec2> antialiasingOffsets(int samples);

// The camera with its image shifted by `offset` pixels (the projection translated in clip space),
// so that pixel centers sample the scene at center + offset.
ViewCamera jitteredCamera(const ViewCamera& camera, glm::vec2 offset);

}  // namespace omnishadow
