#include "renderer/scene/tangents.h"

#include <cmath>
#include <cstddef>

namespace omnishadow {

namespace {

template <typename T>
std::vector<T> unindexed(const std::vector<T>& values, const std::vector<std::uint32_t>& indices) {
  if (values.empty()) return {};
  std::vector<T> out;
  out.reserve(indices.size());
  for (std::uint32_t index : indices) out.push_back(values[index]);
  return out;
}

}  // namespace

glm::vec3 anyPerpendicular(const glm::vec3& n) {
  const glm::vec3 axis =
      std::abs(n.x) < 0.9f ? glm::vec3(1.0f, 0.0f, 0.0f) : glm::vec3(0.0f, 1.0f, 0.0f);
  const glm::vec3 t = glm::cross(axis, n);
  const float length = glm::length(t);
  return length > 0.0f && std::isfinite(length) ? t / length : axis;  // n was zero or NaN
}

void generateNormals(Mesh& mesh) {
  const std::size_t triangles = mesh.indices.size() / 3;
  mesh.indices.resize(triangles * 3);
  mesh.positions = unindexed(mesh.positions, mesh.indices);
  mesh.tangents = unindexed(mesh.tangents, mesh.indices);
  mesh.uv0 = unindexed(mesh.uv0, mesh.indices);
  mesh.uv1 = unindexed(mesh.uv1, mesh.indices);
  mesh.colors = unindexed(mesh.colors, mesh.indices);

  mesh.normals.assign(mesh.positions.size(), glm::vec3(0.0f, 0.0f, 1.0f));
  for (std::size_t t = 0; t < triangles; ++t) {
    const glm::vec3& p0 = mesh.positions[3 * t];
    const glm::vec3 n = glm::cross(mesh.positions[3 * t + 1] - p0, mesh.positions[3 * t + 2] - p0);
    const float length = glm::length(n);
    // A zero-area triangle draws nothing, so the +Z fallback is never seen; it only keeps the
    // "normals are unit length" promise.
    if (length > 0.0f && std::isfinite(length)) {
      for (std::size_t k = 0; k < 3; ++k) mesh.normals[3 * t + k] = n / length;
    }
  }
  for (std::size_t i = 0; i < mesh.indices.size(); ++i) {
    mesh.indices[i] = static_cast<std::uint32_t>(i);
  }
}

void generateTangents(Mesh& mesh, const std::vector<glm::vec2>& uvs) {
  const std::size_t n = mesh.positions.size();
  if (mesh.normals.size() != n || uvs.size() != n) {
    mesh.tangents.clear();
    return;
  }
  // Per vertex: sum of dP/du and of dP/dv over its triangles.
  std::vector<glm::vec3> dpdu(n, glm::vec3(0.0f)), dpdv(n, glm::vec3(0.0f));
  for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    const std::uint32_t i0 = mesh.indices[t], i1 = mesh.indices[t + 1], i2 = mesh.indices[t + 2];
    const glm::vec3 e1 = mesh.positions[i1] - mesh.positions[i0];
    const glm::vec3 e2 = mesh.positions[i2] - mesh.positions[i0];
    const glm::vec2 d1 = uvs[i1] - uvs[i0];
    const glm::vec2 d2 = uvs[i2] - uvs[i0];
    const float det = d1.x * d2.y - d2.x * d1.y;
    if (std::abs(det) < 1e-20f || !std::isfinite(det)) continue;  // UVs collapsed: no gradient
    const glm::vec3 u = (e1 * d2.y - e2 * d1.y) / det;
    const glm::vec3 v = (e2 * d1.x - e1 * d2.x) / det;
    for (std::uint32_t i : {i0, i1, i2}) {
      dpdu[i] += u;
      dpdv[i] += v;
    }
  }

  mesh.tangents.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const glm::vec3& normal = mesh.normals[i];
    glm::vec3 t = dpdu[i] - normal * glm::dot(normal, dpdu[i]);
    const float length = glm::length(t);
    t = length > 1e-20f && std::isfinite(length) ? t / length : anyPerpendicular(normal);
    // glTF's v runs down the image while a normal map's +Y points up it, so the bitangent
    // cross(N, T) * w must follow -dP/dv.
    const float w = glm::dot(glm::cross(normal, t), -dpdv[i]) < 0.0f ? -1.0f : 1.0f;
    mesh.tangents[i] = glm::vec4(t, w);
  }
}

}  // namespace omnishadow
