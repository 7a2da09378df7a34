#include "renderer/view/draw_order.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "renderer/view/camera.h"

namespace omnishadow {
namespace {

// The draws' indices by the depth of their centres moved `farSide` radii along the view axis,
// farthest first or nearest first.
std::vector<std::size_t> byDepth(const std::vector<DrawCenter>& draws, const glm::mat4& view,
                                 float farSide, bool farthest) {
  const glm::vec4 depthRow = viewDepthRow(view);
  std::vector<std::pair<float, std::size_t>> keyed;
  keyed.reserve(draws.size());
  for (const DrawCenter& d : draws) {
    const float depth = glm::dot(depthRow, glm::vec4(d.center, 1.0f)) + farSide * d.radius;
    // A NaN depth sorts as the nearest, so that the comparison stays a strict weak order.
    keyed.emplace_back(std::isnan(depth) ? -std::numeric_limits<float>::infinity() : depth, d.draw);
  }
  std::stable_sort(keyed.begin(), keyed.end(), [farthest](const auto& a, const auto& b) {
    return farthest ? a.first > b.first : a.first < b.first;
  });
  std::vector<std::size_t> order;
  order.reserve(keyed.size());
  for (const auto& [depth, draw] : keyed) order.push_back(draw);
  return order;
}

}  // namespace

std::vector<std::size_t> farthestFirst(const std::vector<DrawCenter>& draws,
                                       const glm::mat4& view) {
  return byDepth(draws, view, 0.0f, true);
}

std::vector<std::size_t> nearestFirst(const std::vector<DrawCenter>& draws, const glm::mat4& view) {
  return byDepth(draws, view, 1.0f, false);
}

}  // namespace omnishadow
