#include "renderer/light_tiles.h"

#include <algorithm>
#include <cmath>

namespace omnishadow {
namespace {

struct TileRect {
  int x0, y0, x1, y1;  // inclusive tile coordinates
};

// Tiles the light's range sphere may cover: its view-space bounding box projected, or every
// tile when the sphere reaches the camera's near plane (or there is no range).
TileRect coveredTiles(const Light& light, const ViewCamera& camera, const LightTiles& tiles) {
  const TileRect all{0, 0, tiles.columns - 1, tiles.rows - 1};
  if (light.type == LightType::Directional || light.range <= 0.0f) return all;
  const glm::vec3 c = glm::vec3(camera.view * glm::vec4(light.position, 1.0f));
  const float r = light.range;
  if (-c.z + r < camera.znear) return {0, 0, -1, -1};  // wholly behind the camera
  if (!camera.orthographic && -c.z - r < camera.znear) return all;
  glm::vec2 lo(1e30f), hi(-1e30f);
  for (int i = 0; i < 8; ++i) {
    const glm::vec3 corner =
        c + r * glm::vec3((i & 1) ? 1 : -1, (i & 2) ? 1 : -1, (i & 4) ? 1 : -1);
    const glm::vec4 clip = camera.projection * glm::vec4(corner, 1.0f);
    const glm::vec2 ndc = glm::vec2(clip) / clip.w;
    lo = glm::min(lo, ndc);
    hi = glm::max(hi, ndc);
  }
  if (hi.x < -1.0f || hi.y < -1.0f || lo.x > 1.0f || lo.y > 1.0f) return {0, 0, -1, -1};
  const auto tile = [&](float ndc, int pixels, int count) {
    const float pixel = (ndc * 0.5f + 0.5f) * static_cast<float>(pixels);
    return std::clamp(static_cast<int>(std::floor(pixel / static_cast<float>(tiles.tileSize))), 0,
                      count - 1);
  };
  return {tile(lo.x, camera.width, tiles.columns), tile(lo.y, camera.height, tiles.rows),
          tile(hi.x, camera.width, tiles.columns), tile(hi.y, camera.height, tiles.rows)};
}

}  // namespace

LightTiles buildLightTiles(const std::vector<const Light*>& lights, const ViewCamera& camera,
                           int tileSize) {
  LightTiles tiles;
  tiles.tileSize = tileSize;
  tiles.columns = (camera.width + tileSize - 1) / tileSize;
  tiles.rows = (camera.height + tileSize - 1) / tileSize;
  const std::size_t count = static_cast<std::size_t>(tiles.columns) * tiles.rows;
  std::vector<std::vector<std::uint32_t>> perTile(count);
  for (std::size_t i = 0; i < lights.size(); ++i) {
    const TileRect rect = coveredTiles(*lights[i], camera, tiles);
    for (int y = rect.y0; y <= rect.y1; ++y)
      for (int x = rect.x0; x <= rect.x1; ++x)
        perTile[static_cast<std::size_t>(y) * tiles.columns + x].push_back(
            static_cast<std::uint32_t>(i));
  }
  tiles.ranges.reserve(2 * count);
  for (const auto& list : perTile) {
    tiles.ranges.push_back(static_cast<std::uint32_t>(tiles.lights.size()));
    tiles.ranges.push_back(static_cast<std::uint32_t>(list.size()));
    tiles.lights.insert(tiles.lights.end(), list.begin(), list.end());
  }
  return tiles;
}

}  // namespace omnishadow
