#include "renderer/mesh_topology.h"

#include <algorithm>
#include <numeric>
#include <tuple>

namespace omnishadow {
namespace {

// One id per distinct position: split vertices (flat shading, UV seams) share an id.
std::vector<std::uint32_t> weldedIds(const std::vector<glm::vec3>& positions) {
  std::vector<std::uint32_t> order(positions.size());
  std::iota(order.begin(), order.end(), 0u);
  auto key = [&](std::uint32_t i) {
    return std::make_tuple(positions[i].x, positions[i].y, positions[i].z);
  };
  std::sort(order.begin(), order.end(),
            [&](std::uint32_t a, std::uint32_t b) { return key(a) < key(b); });
  std::vector<std::uint32_t> ids(positions.size());
  std::uint32_t id = 0;
  for (std::size_t k = 0; k < order.size(); ++k) {
    if (k > 0 && key(order[k]) != key(order[k - 1])) ++id;
    ids[order[k]] = id;
  }
  return ids;
}

std::uint32_t findRoot(std::vector<std::uint32_t>& parent, std::uint32_t i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

}  // namespace

bool isClosedSolid(const std::vector<glm::vec3>& positions,
                   const std::vector<std::uint32_t>& indices) {
  const std::vector<std::uint32_t> ids = weldedIds(positions);
  std::vector<std::uint64_t> edges;
  edges.reserve(indices.size());
  std::vector<std::uint32_t> parent(positions.size());
  std::iota(parent.begin(), parent.end(), 0u);
  std::vector<std::size_t> triangles;  // first index of each non-degenerate triangle
  for (std::size_t t = 0; t + 2 < indices.size(); t += 3) {
    const std::uint32_t v[3] = {ids[indices[t]], ids[indices[t + 1]], ids[indices[t + 2]]};
    // A triangle with two welded corners covers no area and bounds nothing.
    if (v[0] == v[1] || v[1] == v[2] || v[2] == v[0]) continue;
    triangles.push_back(t);
    for (int e = 0; e < 3; ++e) {
      edges.push_back(std::uint64_t{v[e]} << 32 | v[(e + 1) % 3]);
      const std::uint32_t a = findRoot(parent, v[e]), b = findRoot(parent, v[(e + 1) % 3]);
      if (a != b) parent[a] = b;
    }
  }
  if (triangles.empty()) return false;

  // Each directed edge once, and its reverse once: every edge joins exactly two triangles that
  // agree on which side is out.
  std::sort(edges.begin(), edges.end());
  if (std::adjacent_find(edges.begin(), edges.end()) != edges.end()) return false;
  for (const std::uint64_t e : edges)
    if (!std::binary_search(edges.begin(), edges.end(), e << 32 | e >> 32)) return false;

  // Signed volume per connected piece, relative to a point of the piece (less cancellation
  // than relative to the origin). A piece turned inside out has a negative volume.
  std::vector<double> volume(positions.size(), 0.0);
  std::vector<int> origin(positions.size(), -1);
  for (const std::size_t t : triangles) {
    const std::uint32_t root = findRoot(parent, ids[indices[t]]);
    if (origin[root] < 0) origin[root] = static_cast<int>(indices[t]);
    const glm::dvec3 o(positions[static_cast<std::size_t>(origin[root])]);
    const glm::dvec3 a = glm::dvec3(positions[indices[t]]) - o;
    const glm::dvec3 b = glm::dvec3(positions[indices[t + 1]]) - o;
    const glm::dvec3 c = glm::dvec3(positions[indices[t + 2]]) - o;
    volume[root] += glm::dot(a, glm::cross(b, c));
  }
  for (std::size_t root = 0; root < positions.size(); ++root)
    if (origin[root] >= 0 && !(volume[root] > 0.0)) return false;
  return true;
}

}  // namespace omnishadow
