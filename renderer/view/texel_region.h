#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "renderer/view/caster_culling.h"

namespace omnishadow {

// A set of texels held as disjoint rectangles: the pixels a frame may have drawn, which its
// readback visits (FrameTargets::drawn()). One bounding rectangle holds the gaps between a
// scene's objects too: Sundial's 14 draws at 1280x720 reach 292,066 pixels in 43 rectangles,
// their bounding rectangle 465,504, and the readback copies and converts each pixel it reads.
class TexelRegion {
 public:
  // Disjoint rectangles a region keeps at most, since each is a read of its own in every band
  // of rows it crosses; beyond that it is coarsened (unionOf()).
  static constexpr std::size_t kMaxRects = 64;
  // The grid a region's edges move out to when its exact union needs more rectangles.
  static constexpr int kCoarseGrid = 32;

  TexelRegion() = default;
  // The texels of `rect`; none for an empty one.
  explicit TexelRegion(const TexelRect& rect);

  // The texels of `rects` within `clip`, as at most `maxRects` disjoint rectangles: exactly their
  // union where that takes no more; else with every edge moved out to a multiple of kCoarseGrid
  // (within `clip`); else their bounding rectangle. Each holds every texel of `rects` in `clip`.
  static TexelRegion unionOf(const std::vector<TexelRect>& rects, const TexelRect& clip,
                             std::size_t maxRects = kMaxRects);

  // Ordered by their lowest row, then their left column; none empty, none overlapping.
  const std::vector<TexelRect>& rects() const { return rects_; }
  bool empty() const { return rects_.empty(); }
  // The smallest rectangle holding the region (empty for an empty region).
  TexelRect bounds() const;
  std::int64_t texels() const;
  // The texels of its largest rectangle.
  std::int64_t largestRectTexels() const;
  // The region's texels within `clip`.
  TexelRegion clipped(const TexelRect& clip) const;
  bool operator==(const TexelRegion& other) const = default;

 private:
  std::vector<TexelRect> rects_;
};

}  // namespace omnishadow
