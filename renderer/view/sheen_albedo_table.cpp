#include "renderer/view/sheen_albedo_table.h"

#include <algorithm>
#include <cmath>

namespace omnishadow {

const std::array<float, kSheenAlbedoEntries>& sheenAlbedoTable() {
  static constexpr std::array<float, kSheenAlbedoEntries> kTable = {
#include "sheen_albedo_table.inc"
  };
  return kTable;
}

float sheenAlbedo(float mu, float roughness) {
  const std::array<float, kSheenAlbedoEntries>& table = sheenAlbedoTable();
  const float x = std::clamp(mu, 0.0f, 1.0f) * (kSheenAlbedoCosines - 1);
  const float y = std::clamp(roughness, 0.0f, 1.0f) * (kSheenAlbedoRoughnesses - 1);
  const int x0 = std::min(static_cast<int>(x), kSheenAlbedoCosines - 2);
  const int y0 = std::min(static_cast<int>(y), kSheenAlbedoRoughnesses - 2);
  const float fx = x - static_cast<float>(x0), fy = y - static_cast<float>(y0);
  const auto at = [&](int i, int j) { return table[j * kSheenAlbedoCosines + i]; };
  const float low = at(x0, y0) + (at(x0 + 1, y0) - at(x0, y0)) * fx;
  const float high = at(x0, y0 + 1) + (at(x0 + 1, y0 + 1) - at(x0, y0 + 1)) * fx;
  return low + (high - low) * fy;
}

}  // namespace omnishadow
