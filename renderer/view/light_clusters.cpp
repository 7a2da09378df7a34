#include "renderer/view/light_clusters.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>

#include "renderer/core/in_parts.h"
#include "renderer/view/sphere_projection.h"

namespace omnishadow {
namespace {

struct TileRect {
  int x0, y0, x1, y1;  // inclusive tile coordinates
};

// Tiles the light's range sphere may cover: its view-space bounding box projected, or every
// tile when the sphere reaches the camera's near plane.
TileRect coveredTiles(const glm::vec3& c, float r, const ViewCamera& camera,
                      const LightClusters& clusters) {
  const TileRect all{0, 0, clusters.columns - 1, clusters.rows - 1};
  if (!camera.orthographic && -c.z - r < camera.znear) return all;
  // In front of the near plane (perspective) or any plane (orthographic), every corner's w > 0.
  const std::optional<NdcBounds> box = projectedSphereBox(camera.projection, c, r);
  if (!box) return all;
  const glm::vec2 lo = box->low, hi = box->high;
  if (hi.x < -1.0f || hi.y < -1.0f || lo.x > 1.0f || lo.y > 1.0f) return {0, 0, -1, -1};
  const auto tile = [&](float ndc, int pixels, int count) {
    const float pixel = (ndc * 0.5f + 0.5f) * static_cast<float>(pixels);
    return std::clamp(static_cast<int>(std::floor(pixel / static_cast<float>(clusters.tileSize))),
                      0, count - 1);
  };
  return {tile(lo.x, camera.width, clusters.columns), tile(lo.y, camera.height, clusters.rows),
          tile(hi.x, camera.width, clusters.columns), tile(hi.y, camera.height, clusters.rows)};
}

void extend(ClusterBox& box, const glm::vec3& p) {
  box.lo = glm::min(box.lo, p);
  box.hi = glm::max(box.hi, p);
}

bool touchesSphere(const ClusterBox& box, const glm::vec3& c, float r) {
  const glm::vec3 d = glm::max(glm::max(box.lo - c, c - box.hi), glm::vec3(0.0f));
  return glm::dot(d, d) <= r * r;
}

// View-space bounding boxes of every cluster. Depth bounds are widened a little so that a
// fragment whose slice rounds to a neighbour still finds its lights there; the first slice
// starts at the camera and the last one reaches well past the farthest geometry.
ClusterBoxes clusterBoxes(const LightClusters& clusters, const ViewCamera& camera) {
  const glm::mat4 inverse = glm::inverse(camera.projection);
  // The view-space point of normalized device coordinates (x, y) at view depth d.
  auto at = [&](float x, float y, float d) {
    const glm::vec4 h = inverse * glm::vec4(x, y, camera.orthographic ? 0.5f : 1.0f, 1.0f);
    glm::vec3 p = glm::vec3(h) / h.w;
    if (camera.orthographic) return glm::vec3(p.x, p.y, -d);
    return p * (d / -p.z);
  };
  std::vector<float> bounds(static_cast<std::size_t>(clusters.slices) + 1);
  for (int s = 0; s <= clusters.slices; ++s)
    bounds[s] = clusters.sliceNear * std::exp(static_cast<float>(s) / clusters.sliceScale);
  ClusterBoxes boxes;
  boxes.clusters.resize(static_cast<std::size_t>(clusters.columns) * clusters.rows *
                        clusters.slices);
  boxes.rows.resize(static_cast<std::size_t>(clusters.rows) * clusters.slices);
  // Normalized device coordinates spanned by tile `i` along an axis of `pixels`, half a pixel
  // wider on each side.
  const float tile = static_cast<float>(clusters.tileSize);
  auto ndcSpan = [&](int i, int pixels) {
    const auto ndc = [&](float pixel) { return 2.0f * pixel / static_cast<float>(pixels) - 1.0f; };
    return std::array<float, 2>{ndc(std::max(0.0f, static_cast<float>(i) * tile - 0.5f)),
                                ndc(static_cast<float>(i + 1) * tile + 0.5f)};
  };
  for (int s = 0; s < clusters.slices; ++s) {
    const float d0 = s == 0 ? 0.0f : bounds[s] * 0.999f;
    const float d1 = s == clusters.slices - 1 ? 2.0f * bounds[s + 1] : bounds[s + 1] * 1.001f;
    for (int y = 0; y < clusters.rows; ++y) {
      const std::array<float, 2> ys = ndcSpan(y, camera.height);
      for (int x = 0; x < clusters.columns; ++x) {
        const std::array<float, 2> xs = ndcSpan(x, camera.width);
        const std::size_t row = static_cast<std::size_t>(s) * clusters.rows + y;
        ClusterBox& box = boxes.clusters[row * clusters.columns + x];
        for (const float d : {d0, d1})
          for (const float nx : xs)
            for (const float ny : ys) extend(box, at(nx, ny, d));
        extend(boxes.rows[row], box.lo);
        extend(boxes.rows[row], box.hi);
      }
    }
  }
  return boxes;
}

}  // namespace

const ClusterBoxes& ClusterBoxCache::boxes(const LightClusters& grid, const ViewCamera& camera) {
  const Key key{camera.projection, camera.orthographic, camera.width,   camera.height,
                grid.tileSize,     grid.slices,         grid.sliceNear, grid.sliceScale};
  if (boxes_.clusters.empty() || !(key == key_)) {
    boxes_ = clusterBoxes(grid, camera);
    key_ = key;
  }
  return boxes_;
}

int clusterSlice(const LightClusters& clusters, float depth) {
  const float s =
      std::floor(std::log(std::max(depth, 1e-30f) / clusters.sliceNear) * clusters.sliceScale);
  return static_cast<int>(std::clamp(s, 0.0f, static_cast<float>(clusters.slices - 1)));
}

LightClusters buildLightClusters(const std::vector<const Light*>& lights, const ViewCamera& camera,
                                 float farthestDepth, int tileSize, int slices,
                                 ClusterBoxCache* cache) {
  LightClusters clusters;
  clusters.tileSize = tileSize;
  clusters.columns = (camera.width + tileSize - 1) / tileSize;
  clusters.rows = (camera.height + tileSize - 1) / tileSize;
  clusters.slices = slices;
  // Logarithmic slices (clusters about as deep as they are wide) from a thousandth of the
  // scene's depth, or the near plane, to its far end; nearer points share the first slice.
  const float far = std::max({farthestDepth, camera.znear * 2.0f, 1e-3f});
  clusters.sliceNear = std::max(camera.znear, far * 1e-3f);
  clusters.sliceScale =
      static_cast<float>(slices) / std::log(std::max(far / clusters.sliceNear, 1.0001f));

  // Where each ranged light may reach: its tiles and slices.
  struct Reach {
    std::uint32_t light;
    glm::vec3 center;  // view space
    float radius;
    TileRect tiles;
    int firstSlice, lastSlice;
  };
  std::vector<Reach> reaches;
  for (std::size_t i = 0; i < lights.size(); ++i) {
    const Light& light = *lights[i];
    if (light.type == LightType::Directional || light.range <= 0.0f) {
      clusters.lights.push_back(static_cast<std::uint32_t>(i));
      continue;
    }
    const glm::vec3 c = glm::vec3(camera.view * glm::vec4(light.position, 1.0f));
    const float r = light.range;
    if (-c.z + r < camera.znear) continue;  // wholly behind the camera
    const TileRect rect = coveredTiles(c, r, camera, clusters);
    if (rect.x1 < rect.x0) continue;
    const int s0 = clusterSlice(clusters, -c.z - r), s1 = clusterSlice(clusters, -c.z + r);
    reaches.push_back({static_cast<std::uint32_t>(i), c, r, rect, std::max(0, s0 - 1),
                       std::min(slices - 1, s1 + 1)});
  }
  clusters.globalCount = static_cast<std::uint32_t>(clusters.lights.size());

  // Each cluster's list of ranged lights, in light order. The (slice, row)s of clusters go in
  // blocks of a few rows to several threads from 16 lights on, dealt out in turn (the lights
  // crowd some depths), and each block's lists go into a buffer of its own, their ranges as
  // offsets into it; the buffers are then copied into place after one another, by the same
  // threads. No pass over all the (cluster, light) pairs runs on one thread (256 lights at
  // 1920x1080 list 1.55M): on the H200's host the counting sort over them that did took 9.5 ms
  // a frame (docs/performance.md).
  ClusterBoxCache ownCache;
  ClusterBoxCache& boxCache = cache ? *cache : ownCache;
  const ClusterBoxes* boxes = reaches.empty() ? nullptr : &boxCache.boxes(clusters, camera);
  const std::size_t columns = static_cast<std::size_t>(clusters.columns);
  const std::size_t rowCount = static_cast<std::size_t>(clusters.rows) * clusters.slices;
  constexpr std::size_t kBlockRows = 4;
  const std::size_t blocks = (rowCount + kBlockRows - 1) / kBlockRows;
  const std::size_t parts = std::max<std::size_t>(1, std::min(partsFor(reaches.size()), blocks));
  // Part p takes blocks p, p + parts, p + 2 parts, ...
  const auto forBlocksOf = [&](std::size_t part, const auto& work) {
    for (std::size_t block = part; block < blocks; block += parts)
      work(block, block * kBlockRows, std::min(rowCount, (block + 1) * kBlockRows));
  };
  clusters.ranges.assign(2 * rowCount * columns, 0);
  std::vector<std::vector<std::uint32_t>> blockLights(blocks);
  inParts(parts, parts, [&](std::size_t part, std::size_t, std::size_t) {
    std::vector<std::pair<std::uint32_t, std::uint32_t>> rowPairs;  // (column, light)
    std::vector<std::uint32_t> inColumn(columns);
    forBlocksOf(part, [&](std::size_t block, std::size_t firstRow, std::size_t endRow) {
      std::vector<std::uint32_t>& listed = blockLights[block];
      for (std::size_t row = firstRow; row < endRow; ++row) {
        const int s = static_cast<int>(row / static_cast<std::size_t>(clusters.rows));
        const int y = static_cast<int>(row % static_cast<std::size_t>(clusters.rows));
        rowPairs.clear();
        for (const Reach& reach : reaches) {
          if (s < reach.firstSlice || s > reach.lastSlice || y < reach.tiles.y0 ||
              y > reach.tiles.y1)
            continue;
          // The row's box holds each cluster's: touchesSphere computes a distance to it no
          // larger than to any of them, rounding included, so no cluster it misses is lost.
          if (!touchesSphere(boxes->rows[row], reach.center, reach.radius)) continue;
          for (int x = reach.tiles.x0; x <= reach.tiles.x1; ++x)
            if (touchesSphere(boxes->clusters[row * columns + x], reach.center, reach.radius))
              rowPairs.emplace_back(static_cast<std::uint32_t>(x), reach.light);
        }
        // Counting sort of the row's pairs by column keeps the light order within each cluster.
        std::fill(inColumn.begin(), inColumn.end(), 0u);
        for (const auto& [x, light] : rowPairs) ++inColumn[x];
        auto next = static_cast<std::uint32_t>(listed.size());
        for (std::size_t x = 0; x < columns; ++x) {
          clusters.ranges[2 * (row * columns + x)] = next;  // into `listed` until moved
          next += inColumn[x];
        }
        listed.resize(next);
        for (const auto& [x, light] : rowPairs) {
          std::uint32_t* range = &clusters.ranges[2 * (row * columns + x)];
          listed[range[0] + range[1]++] = light;
        }
      }
    });
  });
  std::vector<std::uint32_t> blockStart(blocks);
  std::size_t total = clusters.globalCount;
  for (std::size_t block = 0; block < blocks; ++block) {
    blockStart[block] = static_cast<std::uint32_t>(total);
    total += blockLights[block].size();
  }
  clusters.lights.resize(total);
  inParts(parts, parts, [&](std::size_t part, std::size_t, std::size_t) {
    forBlocksOf(part, [&](std::size_t block, std::size_t firstRow, std::size_t endRow) {
      std::copy(blockLights[block].begin(), blockLights[block].end(),
                clusters.lights.begin() + blockStart[block]);
      for (std::size_t cluster = firstRow * columns; cluster < endRow * columns; ++cluster)
        clusters.ranges[2 * cluster] += blockStart[block];
    });
  });
  return clusters;
}

}  // namespace omnishadow
