#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "renderer/scene/scene.h"

namespace omnishadow {

// Per mesh of a scene, a 64-bit hash of each of its arrays: what both fingerprints below are
// made of, so that a render that needs both hashes each array once (GeometryCache and the
// shadow cache: the 1M-triangle bench room's 26 MB were hashed 1.7 times a frame). From 4 MiB
// on, on two threads.
struct MeshDigests {
  std::uint64_t positions = 0, normals = 0, tangents = 0, uv0 = 0, uv1 = 0, colors = 0, indices = 0,
                lineIndices = 0, pointIndices = 0;
};
std::vector<MeshDigests> meshDigests(const Scene& scene);

// Per image of a scene, a 64-bit hash of its pixels where shadowFingerprint() took one
// (the images of casters that are not opaque), by image index.
using ImageHashes = std::vector<std::optional<std::uint64_t>>;

// A 64-bit hash of everything in a scene that shapes its shadow maps: the triangles,
// where instances are, and the alpha of casters that are not opaque. Two loads of the same file
// give the same value; any change to a caster changes it (barring hash collisions).
std::uint64_t shadowFingerprint(const Scene& scene);
// The same from the scene's meshDigests(). With `images` (sized to the scene's images), an
// image's hash found there is taken as it is, and one taken is left there: a caller keeps them
// for the next fingerprint of the same Scene::revision, as it keeps the mesh digests (a
// masked caster's 2048^2 texture is 16 MB to hash).
std::uint64_t shadowFingerprint(const Scene& scene, const std::vector<MeshDigests>& meshes,
                                ImageHashes* images = nullptr);

// A 64-bit hash of everything the GPU geometry of a scene is made from (GpuGeometry): every
// mesh array, each mesh's material and bounds, the instances and the number of materials.
// Materials themselves, textures and images do not count.
std::uint64_t geometryFingerprint(const Scene& scene);
std::uint64_t geometryFingerprint(const Scene& scene, const std::vector<MeshDigests>& meshes);

}  // namespace omnishadow
