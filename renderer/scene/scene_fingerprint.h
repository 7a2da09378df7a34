#pragma once

#include <cstdint>

#include "renderer/scene/scene.h"

namespace omnishadow {

// A 64-bit hash of everything in a scene that shapes its shadow maps: the triangles,
// where instances are, and the alpha of casters that are not opaque. Two loads of the same file
// give the same value; any change to a caster changes it (barring hash collisions).
std::uint64_t shadowFingerprint(const Scene& scene);

}  // namespace omnishadow
