#pragma once

// In-memory test scenes: a builder mesh placed once in a Scene, with its bounds, and meshes
// as other tools make them.

#include <cmath>
#include <cstdint>
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

// A UV sphere as three.js's SphereGeometry makes it: the seam's second column computed at
// phi = 2 pi and the south pole's row at theta = pi, whose float sines and cosines differ from
// the first column's and from 0 by an ulp, so that the seam and the pole do not close. Normals
// point outwards.
inline builder::MeshData ulpSeamSphere(float radius, int segments, int rings) {
  builder::MeshData m;
  constexpr float kPi = 3.14159265358979f;
  for (int iy = 0; iy <= rings; ++iy) {
    const float theta = static_cast<float>(iy) / static_cast<float>(rings) * kPi;
    for (int ix = 0; ix <= segments; ++ix) {
      const float phi = static_cast<float>(ix) / static_cast<float>(segments) * 2.0f * kPi;
      const glm::vec3 unit(-std::cos(phi) * std::sin(theta), std::cos(theta),
                           std::sin(phi) * std::sin(theta));
      m.positions.push_back(radius * unit);
      m.normals.push_back(unit);
    }
  }
  const auto at = [&](int iy, int ix) {
    return static_cast<std::uint32_t>(iy * (segments + 1) + ix);
  };
  for (int iy = 0; iy < rings; ++iy)
    for (int ix = 0; ix < segments; ++ix) {
      const std::uint32_t a = at(iy, ix + 1), b = at(iy, ix), c = at(iy + 1, ix),
                          d = at(iy + 1, ix + 1);
      if (iy != 0) m.indices.insert(m.indices.end(), {a, b, d});
      if (iy != rings - 1) m.indices.insert(m.indices.end(), {b, c, d});
    }
  return m;
}

}  // namespace omnishadow::test
