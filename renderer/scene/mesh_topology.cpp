#include "renderer/scene/mesh_topology.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <unordered_map>

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

// Open corners checkSolid() welds in any mesh (a box open by an ulp has all its corners open);
// beyond this, at most a quarter of the mesh's distinct positions.
constexpr std::size_t kMaxWeldedCornersAlways = 1024;

std::uint32_t findRoot(std::vector<std::uint32_t>& parent, std::uint32_t i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

// A mesh's non-degenerate triangles between bit-welded positions (weldedIds), their connected
// pieces, and their directed edges grouped by first corner: edgeStart[a] .. edgeStart[a + 1] of
// edgeEnd hold, sorted, the second corners of the edges leaving a.
struct Surface {
  std::vector<std::uint32_t> ids;
  std::vector<std::size_t> triangles;  // first index of each
  std::vector<std::uint32_t> parent;   // union-find over ids: the pieces
  std::vector<std::uint32_t> edgeStart, edgeEnd;
  bool repeatedEdge = false;  // an edge run twice the same way: no consistent surface
};

Surface surfaceOf(const std::vector<glm::vec3>& positions,
                  const std::vector<std::uint32_t>& indices) {
  Surface s;
  s.ids = weldedIds(positions);
  s.parent.resize(positions.size());
  std::iota(s.parent.begin(), s.parent.end(), 0u);
  s.edgeStart.assign(positions.size() + 1, 0);
  for (std::size_t t = 0; t + 2 < indices.size(); t += 3) {
    const std::uint32_t v[3] = {s.ids[indices[t]], s.ids[indices[t + 1]], s.ids[indices[t + 2]]};
    // A triangle with two welded corners covers no area and bounds nothing.
    if (v[0] == v[1] || v[1] == v[2] || v[2] == v[0]) continue;
    s.triangles.push_back(t);
    for (int e = 0; e < 3; ++e) {
      ++s.edgeStart[v[e] + 1];
      const std::uint32_t a = findRoot(s.parent, v[e]), b = findRoot(s.parent, v[(e + 1) % 3]);
      if (a != b) s.parent[a] = b;
    }
  }
  std::partial_sum(s.edgeStart.begin(), s.edgeStart.end(), s.edgeStart.begin());
  s.edgeEnd.resize(s.edgeStart.back());
  std::vector<std::uint32_t> filled(s.edgeStart.begin(), s.edgeStart.end() - 1);
  for (const std::size_t t : s.triangles) {
    const std::uint32_t v[3] = {s.ids[indices[t]], s.ids[indices[t + 1]], s.ids[indices[t + 2]]};
    for (int e = 0; e < 3; ++e) s.edgeEnd[filled[v[e]]++] = v[(e + 1) % 3];
  }
  // Sorted lists keep a vertex shared by thousands of triangles from costing its degree squared.
  for (std::size_t a = 0; a + 1 < s.edgeStart.size(); ++a) {
    const auto first = s.edgeEnd.begin() + s.edgeStart[a];
    const auto last = s.edgeEnd.begin() + s.edgeStart[a + 1];
    std::sort(first, last);
    if (std::adjacent_find(first, last) != last) s.repeatedEdge = true;
  }
  return s;
}

// Whether every directed edge has its reverse: each edge joins exactly two triangles that agree
// on which side is out. With `open`, the corners (ids) of the edges that have none are added to
// it, and every edge is looked at; without, the first such edge ends the search.
bool everyEdgeHasItsReverse(const Surface& s, std::vector<std::uint32_t>* open) {
  bool all = true;
  for (std::uint32_t a = 0; a + 1 < s.edgeStart.size(); ++a)
    for (std::uint32_t k = s.edgeStart[a]; k < s.edgeStart[a + 1]; ++k) {
      const std::uint32_t b = s.edgeEnd[k];
      if (std::binary_search(s.edgeEnd.begin() + s.edgeStart[b],
                             s.edgeEnd.begin() + s.edgeStart[b + 1], a))
        continue;
      if (!open) return false;
      all = false;
      open->push_back(a);
      open->push_back(b);
    }
  return all;
}

// Signed volume per connected piece, relative to a point of the piece (less cancellation than
// relative to the origin): a piece turned inside out has a negative volume.
bool everyPieceEnclosesAVolume(Surface& s, const std::vector<glm::vec3>& positions,
                               const std::vector<std::uint32_t>& indices) {
  std::vector<double> volume(positions.size(), 0.0);
  std::vector<int> origin(positions.size(), -1);
  for (const std::size_t t : s.triangles) {
    const std::uint32_t root = findRoot(s.parent, s.ids[indices[t]]);
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

}  // namespace

bool isClosedSolid(const std::vector<glm::vec3>& positions,
                   const std::vector<std::uint32_t>& indices) {
  Surface s = surfaceOf(positions, indices);
  if (s.triangles.empty() || s.repeatedEdge || !everyEdgeHasItsReverse(s, nullptr)) return false;
  return everyPieceEnclosesAVolume(s, positions, indices);
}

std::vector<glm::vec3> weldedWithin(const std::vector<glm::vec3>& positions, float tolerance) {
  std::vector<glm::vec3> welded = positions;
  if (!(tolerance > 0.0f) || positions.empty()) return welded;
  // Cells twice the tolerance wide: the positions within it of p lie in at most two cells along
  // each axis, those of p - tolerance and p + tolerance. Coordinates too large for a cell index
  // are left alone.
  const double cell = 2.0 * static_cast<double>(tolerance);
  const auto cellOf = [&](const glm::dvec3& p, glm::i64vec3& index) {
    const glm::dvec3 c = glm::floor(p / cell);
    if (!glm::all(glm::lessThan(glm::abs(c), glm::dvec3(1e15)))) return false;
    index = glm::i64vec3(c);
    return true;
  };
  const auto key = [](const glm::i64vec3& c) {
    std::uint64_t h = static_cast<std::uint64_t>(c.x) * 0x9E3779B97F4A7C15ull;
    h ^= static_cast<std::uint64_t>(c.y) * 0xC2B2AE3D27D4EB4Full;
    h ^= static_cast<std::uint64_t>(c.z) * 0x165667B19E3779F9ull;
    return h ^ (h >> 29);
  };
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> firsts;  // per cell key
  firsts.reserve(positions.size());
  const glm::dvec3 reach(static_cast<double>(tolerance));
  for (std::size_t i = 0; i < positions.size(); ++i) {
    const glm::dvec3 p(positions[i]);
    glm::i64vec3 low, high, own;
    if (!cellOf(p - reach, low) || !cellOf(p + reach, high) || !cellOf(p, own)) continue;
    // The earliest first position within the tolerance (hash collisions only cost a test).
    std::uint32_t found = 0xffffffffu;
    for (std::int64_t z = low.z; z <= high.z; ++z)
      for (std::int64_t y = low.y; y <= high.y; ++y)
        for (std::int64_t x = low.x; x <= high.x; ++x) {
          const auto it = firsts.find(key({x, y, z}));
          if (it == firsts.end()) continue;
          for (const std::uint32_t j : it->second)
            if (j < found && glm::all(glm::lessThanEqual(glm::abs(positions[j] - positions[i]),
                                                         glm::vec3(tolerance))))
              found = j;
        }
    if (found != 0xffffffffu) {
      welded[i] = positions[found];
    } else {
      firsts[key(own)].push_back(static_cast<std::uint32_t>(i));
    }
  }
  return welded;
}

SolidCheck checkSolid(const std::vector<glm::vec3>& positions,
                      const std::vector<std::uint32_t>& indices) {
  SolidCheck check;
  Surface s = surfaceOf(positions, indices);
  std::vector<std::uint32_t> open;
  if (s.triangles.empty() || s.repeatedEdge) return check;  // no surface welding could close
  if (everyEdgeHasItsReverse(s, &open)) {
    check.closed = everyPieceEnclosesAVolume(s, positions, indices);
    return check;  // closed, or inside out: nothing to weld either way
  }
  glm::vec3 low(INFINITY), high(-INFINITY);
  for (const glm::vec3& p : positions) {
    low = glm::min(low, p);
    high = glm::max(high, p);
  }
  const glm::vec3 extent = high - low;
  const float tolerance = 1e-6f * std::max({extent.x, extent.y, extent.z});
  if (!std::isfinite(tolerance) || !(tolerance > 0.0f)) return check;
  // Only the open edges' corners can close a crack: they are welded among themselves, each id
  // at the position of its first vertex, in the order the ids were given (vertex order).
  std::sort(open.begin(), open.end());
  open.erase(std::unique(open.begin(), open.end()), open.end());
  // A mesh open by rounding is open along a seam or at a pole; one mostly made of open corners
  // (leaves as separate cards, a triangle soup) is open by design, and a weld would cost time
  // in proportion to its size for nothing.
  const std::size_t distinct =
      s.ids.empty() ? 0 : std::size_t{*std::max_element(s.ids.begin(), s.ids.end())} + 1;
  if (open.size() > std::max<std::size_t>(kMaxWeldedCornersAlways, distinct / 4)) return check;
  std::vector<std::uint32_t> firstVertex(positions.size(), 0xffffffffu);
  for (std::size_t v = positions.size(); v-- > 0;)
    firstVertex[s.ids[v]] = static_cast<std::uint32_t>(v);
  std::vector<glm::vec3> corners;
  corners.reserve(open.size());
  for (const std::uint32_t id : open) corners.push_back(positions[firstVertex[id]]);
  const std::vector<glm::vec3> moved = weldedWithin(corners, tolerance);
  if (moved == corners) return check;
  std::vector<glm::vec3> to(positions.size());
  std::vector<bool> changed(positions.size(), false);
  for (std::size_t k = 0; k < open.size(); ++k)
    if (moved[k] != corners[k]) {
      changed[open[k]] = true;
      to[open[k]] = moved[k];
    }
  std::vector<glm::vec3> welded = positions;
  for (std::size_t v = 0; v < positions.size(); ++v)
    if (changed[s.ids[v]]) welded[v] = to[s.ids[v]];
  if (isClosedSolid(welded, indices)) check.welded = std::move(welded);
  return check;
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
