#pragma once

#include <cstdint>
#include <vector>

#include "renderer/camera.h"
#include "renderer/light.h"

namespace omnishadow {

// Screen tiles with the lights that may reach them: a light with a range reaches only the
// tiles its range sphere covers on screen, so a fragment loops over the few lights near it
// rather than all of them (hundreds of lights with ranges cost what their overlap costs).
// Lights without a range (and directional ones) are in every tile.
struct LightTiles {
  int tileSize = 16;  // pixels
  int columns = 0, rows = 0;
  // Per tile (row-major, row 0 at the bottom as gl_FragCoord counts): first index into
  // `lights`, count.
  std::vector<std::uint32_t> ranges;
  std::vector<std::uint32_t> lights;  // light indices, ascending within a tile
};

LightTiles buildLightTiles(const std::vector<const Light*>& lights, const ViewCamera& camera,
                           int tileSize = 16);

}  // namespace omnishadow
