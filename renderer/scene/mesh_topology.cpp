#include "renderer/scene/mesh_topology.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>

namespace omnishadow {
namespace {

// One id per distinct position: split vertices (flat shading, UV seams) share an id. An open
// addressing hash of the coordinates' bits (-0 and +0 are the same position) keeps this linear.
std::vector<std::uint32_t> weldedIds(const std::vector<glm::vec3>& positions) {
  auto bits = [](float f) {
    std::uint32_t b = 0;
    f = f == 0.0f ? 0.0f : f;
    std::memcpy(&b, &f, sizeof b);
    return b;
  };
  std::size_t size = 16;
  while (size < 2 * positions.size()) size *= 2;
  constexpr std::uint32_t kEmpty = 0xffffffffu;
  std::vector<std::uint32_t> table(size, kEmpty);  // vertex index of each slot's first copy
  std::vector<std::uint32_t> ids(positions.size());
  std::uint32_t next = 0;
  for (std::size_t i = 0; i < positions.size(); ++i) {
    const std::uint32_t x = bits(positions[i].x), y = bits(positions[i].y),
                        z = bits(positions[i].z);
    std::uint64_t h =
        (x * 0x9E3779B97F4A7C15ull) ^ (y * 0xC2B2AE3D27D4EB4Full) ^ (z * 0x165667B19E3779F9ull);
    h ^= h >> 29;
    for (std::size_t slot = h & (size - 1);; slot = (slot + 1) & (size - 1)) {
      const std::uint32_t j = table[slot];
      if (j == kEmpty) {
        table[slot] = static_cast<std::uint32_t>(i);
        ids[i] = next++;
        break;
      }
      if (bits(positions[j].x) == x && bits(positions[j].y) == y && bits(positions[j].z) == z) {
        ids[i] = ids[j];
        break;
      }
    }
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
  std::vector<std::uint32_t> parent(positions.size());
  std::iota(parent.begin(), parent.end(), 0u);
  std::vector<std::size_t> triangles;  // first index of each non-degenerate triangle
  // Directed edges grouped by their first corner (counting sort): edgeStart[a] .. edgeStart[a+1]
  // hold the second corners of the edges leaving a.
  std::vector<std::uint32_t> edgeStart(positions.size() + 1, 0);
  for (std::size_t t = 0; t + 2 < indices.size(); t += 3) {
    const std::uint32_t v[3] = {ids[indices[t]], ids[indices[t + 1]], ids[indices[t + 2]]};
    // A triangle with two welded corners covers no area and bounds nothing.
    if (v[0] == v[1] || v[1] == v[2] || v[2] == v[0]) continue;
    triangles.push_back(t);
    for (int e = 0; e < 3; ++e) {
      ++edgeStart[v[e] + 1];
      const std::uint32_t a = findRoot(parent, v[e]), b = findRoot(parent, v[(e + 1) % 3]);
      if (a != b) parent[a] = b;
    }
  }
  if (triangles.empty()) return false;
  std::partial_sum(edgeStart.begin(), edgeStart.end(), edgeStart.begin());
  std::vector<std::uint32_t> edgeEnd(edgeStart.back());
  std::vector<std::uint32_t> filled(edgeStart.begin(), edgeStart.end() - 1);
  for (const std::size_t t : triangles) {
    const std::uint32_t v[3] = {ids[indices[t]], ids[indices[t + 1]], ids[indices[t + 2]]};
    for (int e = 0; e < 3; ++e) edgeEnd[filled[v[e]]++] = v[(e + 1) % 3];
  }
  // Each directed edge once, and its reverse once: every edge joins exactly two triangles that
  // agree on which side is out. (Sorted lists keep a vertex shared by thousands of triangles
  // from costing its degree squared.)
  const auto list = [&](std::uint32_t a) {
    return std::make_pair(edgeEnd.begin() + edgeStart[a], edgeEnd.begin() + edgeStart[a + 1]);
  };
  for (std::uint32_t a = 0; a + 1 < edgeStart.size(); ++a) {
    const auto [first, last] = list(a);
    std::sort(first, last);
    if (std::adjacent_find(first, last) != last) return false;
  }
  for (std::uint32_t a = 0; a + 1 < edgeStart.size(); ++a)
    for (std::uint32_t k = edgeStart[a]; k < edgeStart[a + 1]; ++k) {
      const auto [first, last] = list(edgeEnd[k]);
      if (!std::binary_search(first, last, a)) return false;
    }

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

std::optional<MeshPlane> flatMeshPlane(const std::vector<glm::vec3>& positions,
                                       const std::vector<std::uint32_t>& indices) {
  // The largest triangle's normal decides which way is up; then the area-weighted mean of the
  // triangles' normals (turned that way, so that a two-sided sheet does not cancel out)
  // through their area-weighted centroid, in double. Over one triangle's plane this spreads a
  // raised corner's tilt across the mesh instead of taking it whole.
  glm::dvec3 up(0.0), low(1e300), high(-1e300);
  double largest = 0.0;
  for (std::size_t t = 0; t + 2 < indices.size(); t += 3) {
    const glm::dvec3 a(positions[indices[t]]), b(positions[indices[t + 1]]),
        c(positions[indices[t + 2]]);
    const glm::dvec3 n = glm::cross(b - a, c - a);
    const double area = glm::length(n);
    if (area > largest) {
      largest = area;
      up = n;
    }
    for (const glm::dvec3& p : {a, b, c}) {
      low = glm::min(low, p);
      high = glm::max(high, p);
    }
  }
  if (!(largest > 0.0) || !std::isfinite(largest)) return std::nullopt;
  glm::dvec3 sum(0.0), centroid(0.0);
  double area = 0.0;
  for (std::size_t t = 0; t + 2 < indices.size(); t += 3) {
    const glm::dvec3 a(positions[indices[t]]), b(positions[indices[t + 1]]),
        c(positions[indices[t + 2]]);
    const glm::dvec3 n = glm::cross(b - a, c - a);
    sum += glm::dot(n, up) < 0.0 ? -n : n;
    const double weight = glm::length(n);
    centroid += weight * (a + b + c) / 3.0;
    area += weight;
  }
  const double length = glm::length(sum);
  if (!(length > 0.0) || !std::isfinite(length)) return std::nullopt;
  const glm::dvec3 normal = sum / length;
  const double offset = -glm::dot(normal, centroid / area);
  const double tolerance = 1e-5 * glm::length(high - low);
  double thickness = 0.0;
  const std::size_t corners = indices.size() - indices.size() % 3;
  for (std::size_t k = 0; k < corners; ++k) {
    thickness =
        std::max(thickness, std::abs(glm::dot(normal, glm::dvec3(positions[indices[k]])) + offset));
    if (!(thickness <= tolerance)) return std::nullopt;  // curved: no need to look further
  }
  return MeshPlane{glm::vec3(normal), static_cast<float>(offset), static_cast<float>(thickness)};
}

std::optional<MeshPlane> transformedPlane(const MeshPlane& plane, const glm::mat4& transform) {
  // A point q of the plane's slab moves to M q, and dot(n', M q) = dot(n, q) with the normal
  // n' = M^-T n (unnormalized): distances shrink by |n'|.
  const glm::dmat4 m(transform);
  const glm::dmat3 linear(m);
  const double det = glm::determinant(linear);
  if (!(std::abs(det) > 0.0) || !std::isfinite(det)) return std::nullopt;
  const glm::dvec3 n = glm::transpose(glm::inverse(linear)) * glm::dvec3(plane.normal);
  const double scale = glm::length(n);
  if (!(scale > 0.0) || !std::isfinite(scale)) return std::nullopt;
  const glm::dvec3 onPlane = -static_cast<double>(plane.offset) * glm::dvec3(plane.normal);
  const glm::dvec3 moved = glm::dvec3(m * glm::dvec4(onPlane, 1.0));
  const glm::dvec3 normal = n / scale;
  return MeshPlane{glm::vec3(normal), static_cast<float>(-glm::dot(normal, moved)),
                   static_cast<float>(plane.thickness / scale)};
}

}  // namespace omnishadow
