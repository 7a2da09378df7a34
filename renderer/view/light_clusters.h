#pragma once

#include <cstdint>
#include <vector>

#include "renderer/view/camera.h"
#include "renderer/scene/light.h"

namespace omnishadow {

// The view frustum cut into clusters (16x16-pixel screen tiles times depth slices), each with
// the lights that may reach it: a light with a range is listed only in the clusters its range
// sphere touches, so a fragment loops over the few lights near it in space rather than every
// light whose sphere covers its pixel on screen (clustered shading, Olsson et al. 2012).
// Lights without a range and directional lights reach every point: they are listed once, in
// `lights` before all clusters, and every fragment loops over them first.
struct LightClusters {
  int tileSize = 16;  // pixels
  int columns = 0, rows = 0;
  int slices = 1;
  // A point at view depth z (distance along the view axis) is in slice
  // clamp(floor(log(z / sliceNear) * sliceScale), 0, slices - 1) (clusterSlice()).
  float sliceNear = 1.0f, sliceScale = 0.0f;
  std::uint32_t globalCount = 0;  // lights[0, globalCount): the lights reaching everywhere
  // Per cluster, at index (slice * rows + row) * columns + column, row 0 at the bottom as
  // gl_FragCoord counts: first index into `lights`, count.
  std::vector<std::uint32_t> ranges;
  std::vector<std::uint32_t> lights;  // light indices, ascending within each list
};

// `farthestDepth`: the largest view depth of any geometry (the slices end there).
LightClusters buildLightClusters(const std::vector<const Light*>& lights, const ViewCamera& camera,
                                 float farthestDepth, int tileSize = 16, int slices = 24);

// The slice of view depth `depth`, as shaders/lighting.frag computes it.
int clusterSlice(const LightClusters& clusters, float depth);

}  // namespace omnishadow
