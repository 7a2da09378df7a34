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

// Marks the pixel centers inside the screen-space triangle (x right, y down, in pixels).
void rasterize(const std::array<glm::dvec2, 3>& v, int width, int height,
               std::vector<std::uint8_t>& covered) {
  const double area = (v[1].x - v[0].x) * (v[2].y - v[0].y) - (v[2].x - v[0].x) * (v[1].y - v[0].y);
  if (area == 0.0 || !std::isfinite(area)) return;
  const double sign = area > 0 ? 1.0 : -1.0;
  const double minX = std::min({v[0].x, v[1].x, v[2].x});
  const double maxX = std::max({v[0].x, v[1].x, v[2].x});
  const double minY = std::min({v[0].y, v[1].y, v[2].y});
  const double maxY = std::max({v[0].y, v[1].y, v[2].y});
  const int x0 = std::max(0, static_cast<int>(std::floor(minX - 0.5)));
  const int x1 = std::min(width - 1, static_cast<int>(std::ceil(maxX - 0.5)));
  const int y0 = std::max(0, static_cast<int>(std::floor(minY - 0.5)));
  const int y1 = std::min(height - 1, static_cast<int>(std::ceil(maxY - 0.5)));
  auto edge = [](const glm::dvec2& a, const glm::dvec2& b, double x, double y) {
    return (b.x - a.x) * (y - a.y) - (b.y - a.y) * (x - a.x);
  };
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) {
      const double px = x + 0.5, py = y + 0.5;
      if (sign * edge(v[0], v[1], px, py) >= 0 && sign * edge(v[1], v[2], px, py) >= 0 &&
          sign * edge(v[2], v[0], px, py) >= 0)
        covered[static_cast<std::size_t>(y) * width + x] = 1;
    }
}

}  // namespace

std::vector<std::uint8_t> instanceCoverage(const Scene& scene, const MeshInstance& instance,
                                           const ViewCamera& camera) {
  const int w = camera.width, h = camera.height;
  std::vector<std::uint8_t> covered(static_cast<std::size_t>(w) * h, 0);
  const Mesh& mesh = scene.meshes[static_cast<std::size_t>(instance.mesh)];
  const bool doubleSided =
      mesh.material >= 0 && scene.materials[static_cast<std::size_t>(mesh.material)].doubleSided;
  // A mirroring transform turns the winding over; the GPU flips its front face for it too.
  const bool mirrored = glm::determinant(glm::mat3(instance.world)) < 0.0f;
  const glm::mat4 modelView = camera.view * instance.world;
  // View space looks down -Z: keep znear <= -z (<= zfar when the far plane is finite).
  std::vector<glm::vec4> planes = {{0, 0, -1, -camera.znear}};
  if (camera.zfar > 0) planes.push_back({0, 0, 1, camera.zfar});
  for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    std::vector<glm::vec3> polygon;
    for (int k = 0; k < 3; ++k)
      polygon.emplace_back(modelView * glm::vec4(mesh.positions[mesh.indices[t + k]], 1.0f));
    for (const glm::vec4& plane : planes) polygon = clip(polygon, plane);
    if (polygon.size() < 3) continue;
    std::vector<glm::dvec2> screen;
    for (const glm::vec3& p : polygon) {
      const glm::vec4 clipped = camera.projection * glm::vec4(p, 1.0f);
      const double x = double(clipped.x) / clipped.w, y = double(clipped.y) / clipped.w;
      screen.emplace_back((x + 1.0) * 0.5 * w, (1.0 - y) * 0.5 * h);
    }
    for (std::size_t k = 1; k + 1 < screen.size(); ++k) {
      const std::array<glm::dvec2, 3> triangle = {screen[0], screen[k], screen[k + 1]};
      // Counter-clockwise on screen with y up is front facing; y runs down here.
      const double area = (triangle[1].x - triangle[0].x) * (triangle[2].y - triangle[0].y) -
                          (triangle[2].x - triangle[0].x) * (triangle[1].y - triangle[0].y);
      const bool front = (area < 0) != mirrored;
      if (!doubleSided && !front) continue;
      rasterize(triangle, w, h, covered);
    }
  }
  return covered;
}

}  // namespace omnishadow
