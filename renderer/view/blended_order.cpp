#include "renderer/view/blended_order.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "renderer/view/camera.h"

namespace omnishadow {

std::vector<std::size_t> farthestFirst(const std::vector<BlendedDraw>& draws,
                                       const glm::mat4& view) {
  const glm::vec4 depthRow = viewDepthRow(view);
  std::vector<std::pair<float, std::size_t>> keyed;
  keyed.reserve(draws.size());
  for (const BlendedDraw& d : draws) {
    const float depth = glm::dot(depthRow, glm::vec4(d.center, 1.0f));
    // A NaN depth sorts as the nearest, so that the comparison stays a strict weak order.
    keyed.emplace_back(std::isnan(depth) ? -std::numeric_limits<float>::infinity() : depth, d.draw);
  }
  std::stable_sort(keyed.begin(), keyed.end(),
                   [](const auto& a, const auto& b) { return a.first > b.first; });
  std::vector<std::size_t> order;
  order.reserve(keyed.size());
  for (const auto& [depth, draw] : keyed) order.push_back(draw);
  return order;
}

}  // namespace omnishadow
