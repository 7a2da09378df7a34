#pragma once

#include <cstdint>

#include "renderer/scene/scene.h"

namespace omnishadow {

// A 64-bit hash of everything in a scene that shapes its shadow maps: the triangles,
// where instances are, and the alpha of casters that are not opaque. Two loads of the same file
// give the same value; any change to a caster changes it (barring hash collisions).
std::uint64_t shadowFingerprint(const Scene& scene);

// A 64-bit hash of everything the GPU geometry of a scene is made from (GpuGeometry): every
// mesh array, each mesh's material and bounds, the instances and the number of materials.
// Materials themselves, textures and images do not count.
std::uint64_t geometryFingerprint(const Scene& scene);

}  // namespace omnishadow
