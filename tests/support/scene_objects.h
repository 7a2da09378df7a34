#pragma once

// In-memory test scenes: a builder mesh placed once in a Scene, with its bounds.

#include <glm/glm.hpp>

#include "renderer/scene/scene.h"
#include "scenes/builder/gltf_builder.h"

namespace omnishadow::test {

inline void placeMesh(Scene& scene, const builder::MeshData& data, const glm::mat4& world,
                      int material) {
  Mesh mesh;
  mesh.positions = data.positions;
  mesh.normals = data.normals;
  mesh.uv0 = data.uvs;
  mesh.indices = data.indices;
  mesh.material = material;
  for (const glm::vec3& p : mesh.positions) mesh.bounds.extend(p);
  scene.meshes.push_back(mesh);
  scene.instances.push_back({static_cast<int>(scene.meshes.size()) - 1, world, -1, {}, {}});
  scene.bounds.extend(mesh.bounds.transformed(world));
}

}  // namespace omnishadow::test
