#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <limits>
#include <vector>

#include "renderer/scene/light.h"
#include "renderer/view/camera.h"

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

// A cluster's view-space bounding box.
struct ClusterBox {
  glm::vec3 lo{std::numeric_limits<float>::max()};
  glm::vec3 hi{std::numeric_limits<float>::lowest()};
};

// The view-space bounding boxes of a grid's clusters, and of each of its rows of clusters.
struct ClusterBoxes {
  std::vector<ClusterBox> clusters;  // indexed as LightClusters::ranges
  // Per (slice, row), at index slice * rows + row: the box around the row's clusters. A sphere
  // that misses it misses every cluster of the row, so a light's rows it misses are skipped.
  std::vector<ClusterBox> rows;
};

// The bounding boxes of every cluster of the last grid asked for: they depend on the camera's
// projection and size and the grid's slices alone, and frames of one camera (batch jobs of one
// scene, --repeat) ask for the same ones again (86k boxes at 1280x720).
class ClusterBoxCache {
 public:
  const ClusterBoxes& boxes(const LightClusters& grid, const ViewCamera& camera);

 private:
  struct Key {
    glm::mat4 projection{0.0f};
    bool orthographic = false;
    int width = 0, height = 0, tileSize = 0, slices = 0;
    float sliceNear = 0.0f, sliceScale = 0.0f;
    bool operator==(const Key&) const = default;
  };
  Key key_;
  ClusterBoxes boxes_;
};

// `farthestDepth`: the largest view depth of any geometry (the slices end there). `cache`:
// the boxes of an earlier frame's grid, reused when this grid's are the same.
LightClusters buildLightClusters(const std::vector<const Light*>& lights, const ViewCamera& camera,
                                 float farthestDepth, int tileSize = 16, int slices = 24,
                                 ClusterBoxCache* cache = nullptr);

// The slice of view depth `depth`, as shaders/lighting.frag computes it.
int clusterSlice(const LightClusters& clusters, float depth);

}  // namespace omnishadow
