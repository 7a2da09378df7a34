#pragma once

#include <cstddef>

#include "renderer/scene/scene.h"
#include "renderer/view/camera.h"

namespace omnishadow {

// The number of pixels whose centers a mesh instance would cover if it were the only thing
// drawn: its triangles clipped to the camera's near (and far) plane and rasterized on the CPU
// at pixel centers, back faces of single-sided materials culled like the GPU does. A center
// exactly on a triangle's edge counts as covered (the GPU's fill rule would give it to
// one of the two triangles sharing that edge), so the count is never below what the renderer
// draws of the instance alone. Textures are not read: alpha-masked cut-outs count as covered.
std::size_t coveredPixelCount(const Scene& scene, const MeshInstance& instance,
                              const ViewCamera& camera);

}  // namespace omnishadow
