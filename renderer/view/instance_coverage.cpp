#include "renderer/view/instance_coverage.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace omnishadow {
namespace {

// A polygon in view space clipped by the plane dot(plane, (p, 1)) >= 0 (Sutherland-Hodgman).
std::vector<glm::vec3> clip(const std::vector<glm::vec3>& polygon, const glm::vec4& plane) {
  std::vector<glm::vec3> out;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const glm::vec3& a = polygon[i];
    const glm::vec3& b = polygon[(i + 1) % polygon.size()];
    const float da = glm::dot(plane, glm::vec4(a, 1.0f));
    const float db = glm::dot(plane, glm::vec4(b, 1.0f));
    if (da >= 0) out.push_back(a);
    if ((da >= 0) != (db >= 0)) out.push_back(a + (b - a) * (da / (da - db)));
  }
  return out;
}

// A block of pixels [x0, x1) x [y0, y1) of the frame, one byte each: 1 = covered.
struct PixelBlock {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  std::vector<std::uint8_t> covered;
};

// The pixel centers [x0, x1] x [y0, y1] (inclusive) a triangle's box may hold, in the frame.
struct CenterRange {
  int x0, x1, y0, y1;
};

CenterRange centerRange(const std::array<glm::dvec2, 3>& v, int width, int height) {
  const double minX = std::min({v[0].x, v[1].x, v[2].x});
  const double maxX = std::max({v[0].x, v[1].x, v[2].x});
  const double minY = std::min({v[0].y, v[1].y, v[2].y});
  const double maxY = std::max({v[0].y, v[1].y, v[2].y});
  // Clamped before the conversion: a vertex far outside the frame is no int.
  auto toInt = [](double value, int limit) {
    return static_cast<int>(std::clamp(value, -1.0, static_cast<double>(limit)));
  };
  return {std::max(0, toInt(std::floor(minX - 0.5), width)),
          std::min(width - 1, toInt(std::ceil(maxX - 0.5), width)),
          std::max(0, toInt(std::floor(minY - 0.5), height)),
          std::min(height - 1, toInt(std::ceil(maxY - 0.5), height))};
}

// Marks the pixel centers inside the screen-space triangle (x right, y down, in pixels).
// `v` has a finite area other than 0.
void rasterize(const std::array<glm::dvec2, 3>& v, int width, int height, PixelBlock& block) {
  const double area = (v[1].x - v[0].x) * (v[2].y - v[0].y) - (v[2].x - v[0].x) * (v[1].y - v[0].y);
  const double sign = area > 0 ? 1.0 : -1.0;
  const CenterRange r = centerRange(v, width, height);
  auto edge = [](const glm::dvec2& a, const glm::dvec2& b, double x, double y) {
    return (b.x - a.x) * (y - a.y) - (b.y - a.y) * (x - a.x);
  };
  const auto stride = static_cast<std::size_t>(block.x1 - block.x0);
  for (int y = r.y0; y <= r.y1; ++y) {
    const double py = y + 0.5;
    // Along a row an edge's value only falls or only rises with x, also as rounded (each
    // subtraction and product rounds monotonically), so the centers inside an edge are the
    // row's first or last ones and those inside all three one run. Its ends are found by
    // bisection with the same expression a test of every center would use: the same pixels.
    int x0 = r.x0, x1 = r.x1;
    for (int k = 0; k < 3 && x0 <= x1; ++k) {
      const glm::dvec2& a = v[static_cast<std::size_t>(k)];
      const glm::dvec2& b = v[static_cast<std::size_t>((k + 1) % 3)];
      auto inside = [&](int x) { return sign * edge(a, b, x + 0.5, py) >= 0; };
      const double falls = sign * (b.y - a.y);  // > 0: the value falls as x grows
      if (falls > 0) {
        if (!inside(x0)) {
          x1 = x0 - 1;
          continue;
        }
        int lo = x0, hi = x1;  // the last center inside: inside(lo) holds
        while (lo < hi) {
          const int mid = lo + (hi - lo + 1) / 2;
          if (inside(mid)) {
            lo = mid;
          } else {
            hi = mid - 1;
          }
        }
        x1 = lo;
      } else if (falls < 0) {
        if (!inside(x1)) {
          x0 = x1 + 1;
          continue;
        }
        int lo = x0, hi = x1;  // the first center inside: inside(hi) holds
        while (lo < hi) {
          const int mid = lo + (hi - lo) / 2;
          if (inside(mid)) {
            hi = mid;
          } else {
            lo = mid + 1;
          }
        }
        x0 = hi;
      } else if (!inside(x0)) {
        x1 = x0 - 1;
      }
    }
    if (x0 > x1) continue;
    std::uint8_t* row = block.covered.data() + static_cast<std::size_t>(y - block.y0) * stride;
    std::fill(row + (x0 - block.x0), row + (x1 + 1 - block.x0), std::uint8_t{1});
  }
}

}  // namespace

std::size_t coveredPixelCount(const Scene& scene, const MeshInstance& instance,
                              const ViewCamera& camera) {
  const int w = camera.width, h = camera.height;
  const Mesh& mesh = scene.meshes[static_cast<std::size_t>(instance.mesh)];
  const bool doubleSided =
      mesh.material >= 0 && scene.materials[static_cast<std::size_t>(mesh.material)].doubleSided;
  // A mirroring transform turns the winding over; the GPU flips its front face for it too.
  const bool mirrored = glm::determinant(glm::mat3(instance.world)) < 0.0f;
  const glm::mat4 modelView = camera.view * instance.world;
  // View space looks down -Z: keep znear <= -z (<= zfar when the far plane is finite).
  std::vector<glm::vec4> planes = {{0, 0, -1, -camera.znear}};
  if (camera.zfar > 0) planes.push_back({0, 0, 1, camera.zfar});
  auto toScreen = [&](const glm::vec3& p) {
    const glm::vec4 clipped = camera.projection * glm::vec4(p, 1.0f);
    const double x = double(clipped.x) / clipped.w, y = double(clipped.y) / clipped.w;
    return glm::dvec2((x + 1.0) * 0.5 * w, (1.0 - y) * 0.5 * h);
  };
  // Each vertex once (meshes share most vertices between triangles): in view space, whether
  // every clip plane keeps it, and where it lands on screen. A triangle whose vertices all stay
  // is the polygon clipping would give back unchanged, so it takes these as they are.
  struct ViewVertex {
    glm::vec3 view;
    glm::dvec2 screen;
    bool kept;
  };
  std::vector<ViewVertex> vertices(mesh.positions.size());
  for (std::size_t v = 0; v < vertices.size(); ++v) {
    ViewVertex& out = vertices[v];
    out.view = glm::vec3(modelView * glm::vec4(mesh.positions[v], 1.0f));
    out.kept = std::all_of(planes.begin(), planes.end(), [&](const glm::vec4& plane) {
      return glm::dot(plane, glm::vec4(out.view, 1.0f)) >= 0;
    });
    if (out.kept) out.screen = toScreen(out.view);
  }
  // The screen triangles that face the camera (or need not), then the block of pixels their
  // boxes span: an instance small on screen fills and counts that block, not the frame.
  std::vector<std::array<glm::dvec2, 3>> triangles;
  PixelBlock block{w, h, 0, 0, {}};
  auto add = [&](const std::array<glm::dvec2, 3>& triangle) {
    // Counter-clockwise on screen with y up is front facing; y runs down here.
    const double area = (triangle[1].x - triangle[0].x) * (triangle[2].y - triangle[0].y) -
                        (triangle[2].x - triangle[0].x) * (triangle[1].y - triangle[0].y);
    if (area == 0.0 || !std::isfinite(area)) return;  // covers no pixel center
    const bool front = (area < 0) != mirrored;
    if (!doubleSided && !front) return;
    triangles.push_back(triangle);
    const CenterRange r = centerRange(triangle, w, h);
    if (r.x0 > r.x1 || r.y0 > r.y1) return;
    block.x0 = std::min(block.x0, r.x0);
    block.y0 = std::min(block.y0, r.y0);
    block.x1 = std::max(block.x1, r.x1 + 1);
    block.y1 = std::max(block.y1, r.y1 + 1);
  };
  std::vector<glm::vec3> polygon;
  std::vector<glm::dvec2> screen;
  for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    const ViewVertex& a = vertices[mesh.indices[t]];
    const ViewVertex& b = vertices[mesh.indices[t + 1]];
    const ViewVertex& c = vertices[mesh.indices[t + 2]];
    if (a.kept && b.kept && c.kept) {
      add({a.screen, b.screen, c.screen});
      continue;
    }
    polygon = {a.view, b.view, c.view};
    for (const glm::vec4& plane : planes) polygon = clip(polygon, plane);
    if (polygon.size() < 3) continue;
    screen.clear();
    for (const glm::vec3& p : polygon) screen.push_back(toScreen(p));
    for (std::size_t k = 1; k + 1 < screen.size(); ++k) add({screen[0], screen[k], screen[k + 1]});
  }
  if (block.x0 >= block.x1 || block.y0 >= block.y1) return 0;
  block.covered.assign(
      static_cast<std::size_t>(block.x1 - block.x0) * static_cast<std::size_t>(block.y1 - block.y0),
      0);
  for (const auto& triangle : triangles) rasterize(triangle, w, h, block);
  return static_cast<std::size_t>(std::count(block.covered.begin(), block.covered.end(), 1));
}

}  // namespace omnishadow
