#include "renderer/scene/mesh_deform.h"

#include <cmath>
#include <cstddef>

#include "renderer/scene/tangents.h"

namespace omnishadow {
namespace {

glm::vec3 normalizedOr(const glm::vec3& v, const glm::vec3& fallback) {
  const float length = glm::length(v);
  return length > 0.0f && std::isfinite(length) ? v / length : fallback;
}

// The matrix that carries normals along with `m`: its inverse transpose, up to a positive
// factor. The cofactor matrix is that times det(m); it stays finite when a joint is scaled to
// zero, and the sign of det keeps mirrored joints' normals facing out.
glm::mat3 normalMatrix(const glm::mat4& m) {
  const glm::vec3 a(m[0]), b(m[1]), c(m[2]);
  const glm::mat3 cofactor(glm::cross(b, c), glm::cross(c, a), glm::cross(a, b));
  return glm::dot(a, glm::cross(b, c)) < 0.0f ? -cofactor : cofactor;
}

}  // namespace

DeformedVertices morph(const DeformedInstance& source, const std::vector<float>& weights) {
  DeformedVertices out{source.positions, source.normals, source.tangents};
  for (std::size_t t = 0; t < source.targets.size() && t < weights.size(); ++t) {
    const float w = weights[t];
    if (w == 0.0f) continue;
    const MorphTarget& target = source.targets[t];
    if (!target.positions.empty())
      for (std::size_t v = 0; v < out.positions.size(); ++v)
        out.positions[v] += w * target.positions[v];
    if (!target.normals.empty() && !out.normals.empty())
      for (std::size_t v = 0; v < out.normals.size(); ++v) out.normals[v] += w * target.normals[v];
    if (!target.tangents.empty() && !out.tangents.empty())
      for (std::size_t v = 0; v < out.tangents.size(); ++v)
        out.tangents[v] += glm::vec4(w * target.tangents[v], 0.0f);
  }
  for (std::size_t v = 0; v < out.normals.size(); ++v)
    out.normals[v] = normalizedOr(out.normals[v], source.normals[v]);
  for (std::size_t v = 0; v < out.tangents.size(); ++v)
    out.tangents[v] =
        glm::vec4(normalizedOr(glm::vec3(out.tangents[v]), glm::vec3(source.tangents[v])),
                  source.tangents[v].w);
  return out;
}

void skin(const DeformedInstance& source, const std::vector<glm::mat4>& jointMatrices,
          const glm::mat4& fallback, DeformedVertices& vertices) {
  std::vector<glm::mat3> normalMatrices;
  normalMatrices.reserve(jointMatrices.size());
  for (const glm::mat4& m : jointMatrices) normalMatrices.push_back(normalMatrix(m));
  const glm::mat3 fallbackNormal = normalMatrix(fallback);
  const auto k = static_cast<std::size_t>(source.influences);
  for (std::size_t v = 0; v < vertices.positions.size(); ++v) {
    float sum = 0.0f;
    for (std::size_t i = 0; i < k; ++i) sum += source.weights[v * k + i];
    glm::mat4 m(0.0f);
    glm::mat3 n(0.0f);
    if (sum > 0.0f && std::isfinite(sum)) {
      for (std::size_t i = 0; i < k; ++i) {
        const float w = source.weights[v * k + i];
        if (w == 0.0f) continue;
        const std::size_t joint = source.joints[v * k + i];
        m += (w / sum) * jointMatrices[joint];
        n += (w / sum) * normalMatrices[joint];
      }
    } else {
      m = fallback;
      n = fallbackNormal;
    }
    vertices.positions[v] = glm::vec3(m * glm::vec4(vertices.positions[v], 1.0f));
    if (!vertices.normals.empty())
      vertices.normals[v] = normalizedOr(n * vertices.normals[v], vertices.normals[v]);
    if (!vertices.tangents.empty()) {
      const glm::vec4 t = vertices.tangents[v];
      vertices.tangents[v] =
          glm::vec4(normalizedOr(glm::mat3(m) * glm::vec3(t), glm::vec3(t)), t.w);
    }
  }
}

void writeDeformedMesh(const DeformedInstance& source, const DeformedVertices& vertices,
                       Mesh& mesh) {
  const std::size_t n = source.vertexSource.size();
  mesh.positions.resize(n);
  for (std::size_t i = 0; i < n; ++i)
    mesh.positions[i] = vertices.positions[source.vertexSource[i]];
  if (source.flatNormals) {
    generateNormals(mesh);
  } else {
    for (std::size_t i = 0; i < n; ++i) mesh.normals[i] = vertices.normals[source.vertexSource[i]];
  }
  if (!vertices.tangents.empty() && mesh.tangents.size() == n) {
    for (std::size_t i = 0; i < n; ++i)
      mesh.tangents[i] = vertices.tangents[source.vertexSource[i]];
  } else if (source.generatedTangentUv >= 0) {
    generateTangents(mesh, source.generatedTangentUv == 0 ? mesh.uv0 : mesh.uv1);
  }
  mesh.bounds = Bounds{};
  for (const glm::vec3& p : mesh.positions) mesh.bounds.extend(p);
}

}  // namespace omnishadow
