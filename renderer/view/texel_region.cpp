#include "renderer/view/texel_region.h"

#include <algorithm>
#include <optional>
#include <tuple>
#include <utility>

namespace omnishadow {

namespace {

// Up to this many rectangles the exact union is tried first: its sweep visits every rectangle
// once per band of rows between two of their edges. On the coarse grid, whose bands are at
// least kCoarseGrid rows, up to kCoarseInputs distinct ones are swept; beyond that a region is
// its bounds.
constexpr std::size_t kExactInputs = 512;
constexpr std::size_t kCoarseInputs = 4096;

bool byRowThenColumn(const TexelRect& a, const TexelRect& b) {
  return a.y0 != b.y0 ? a.y0 < b.y0 : a.x0 < b.x0;
}

// The union of `rects` (none empty) as disjoint rectangles, or nothing where it takes more than
// `maxRects`. The rows are cut where some rectangle starts or ends; in each band of rows between
// two cuts every rectangle covers all rows or none, and the columns of those covering it merge
// into spans. A span that continues the band above with the same columns grows down into it.
std::optional<std::vector<TexelRect>> exactUnion(const std::vector<TexelRect>& rects,
                                                 std::size_t maxRects) {
  std::vector<int> cuts;
  cuts.reserve(rects.size() * 2);
  for (const TexelRect& r : rects) {
    cuts.push_back(r.y0);
    cuts.push_back(r.y1);
  }
  std::sort(cuts.begin(), cuts.end());
  cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());
  std::vector<TexelRect> closed, open, band;
  std::vector<std::pair<int, int>> columns;
  for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
    const int y0 = cuts[i], y1 = cuts[i + 1];
    columns.clear();
    for (const TexelRect& r : rects)
      if (r.y0 <= y0 && r.y1 >= y1) columns.emplace_back(r.x0, r.x1);
    std::sort(columns.begin(), columns.end());
    band.clear();
    for (const auto& [x0, x1] : columns) {
      if (!band.empty() && x0 <= band.back().x1)
        band.back().x1 = std::max(band.back().x1, x1);
      else
        band.push_back({x0, y0, x1, y1});
    }
    const bool continues =
        band.size() == open.size() && std::equal(band.begin(), band.end(), open.begin(),
                                                 [](const TexelRect& a, const TexelRect& b) {
                                                   return a.x0 == b.x0 && a.x1 == b.x1;
                                                 });
    if (continues) {
      for (TexelRect& r : open) r.y1 = y1;
    } else {
      closed.insert(closed.end(), open.begin(), open.end());
      open = band;
    }
    if (closed.size() + open.size() > maxRects) return std::nullopt;
  }
  closed.insert(closed.end(), open.begin(), open.end());
  std::sort(closed.begin(), closed.end(), byRowThenColumn);
  return closed;
}

// The multiple of `grid` at or below `value`, and at or above it.
int downTo(int value, int grid) {
  return value >= 0 ? value / grid * grid : -((-value + grid - 1) / grid * grid);
}
int upTo(int value, int grid) {
  return -downTo(-value, grid);
}

}  // namespace

TexelRegion::TexelRegion(const TexelRect& rect) {
  if (!rect.empty()) rects_.push_back(rect);
}

TexelRegion TexelRegion::unionOf(const std::vector<TexelRect>& rects, const TexelRect& clip,
                                 std::size_t maxRects) {
  std::vector<TexelRect> inside;
  TexelRect bounding;
  for (const TexelRect& r : rects) {
    const TexelRect within = r.intersected(clip);
    if (within.empty()) continue;
    inside.push_back(within);
    bounding = bounding.united(within);
  }
  TexelRegion region;
  if (inside.empty()) return region;
  if (maxRects <= 1 || inside.size() == 1) return TexelRegion(bounding);
  if (inside.size() <= kExactInputs) {
    if (std::optional<std::vector<TexelRect>> exact = exactUnion(inside, maxRects)) {
      region.rects_ = std::move(*exact);
      return region;
    }
  }
  for (TexelRect& r : inside) {
    r = TexelRect{downTo(r.x0, kCoarseGrid), downTo(r.y0, kCoarseGrid), upTo(r.x1, kCoarseGrid),
                  upTo(r.y1, kCoarseGrid)}
            .intersected(clip);
  }
  std::sort(inside.begin(), inside.end(), [](const TexelRect& a, const TexelRect& b) {
    return std::tie(a.y0, a.x0, a.y1, a.x1) < std::tie(b.y0, b.x0, b.y1, b.x1);
  });
  inside.erase(std::unique(inside.begin(), inside.end()), inside.end());
  if (inside.size() > kCoarseInputs) return TexelRegion(bounding);
  if (std::optional<std::vector<TexelRect>> coarse = exactUnion(inside, maxRects)) {
    region.rects_ = std::move(*coarse);
    return region;
  }
  return TexelRegion(bounding);
}

TexelRect TexelRegion::bounds() const {
  TexelRect all;
  for (const TexelRect& r : rects_) all = all.united(r);
  return all;
}

std::int64_t TexelRegion::texels() const {
  std::int64_t sum = 0;
  for (const TexelRect& r : rects_) sum += r.texels();
  return sum;
}

std::int64_t TexelRegion::largestRectTexels() const {
  std::int64_t largest = 0;
  for (const TexelRect& r : rects_) largest = std::max(largest, r.texels());
  return largest;
}

TexelRegion TexelRegion::clipped(const TexelRect& clip) const {
  TexelRegion region;
  for (const TexelRect& r : rects_) {
    const TexelRect within = r.intersected(clip);
    if (!within.empty()) region.rects_.push_back(within);
  }
  return region;
}

}  // namespace omnishadow
