#include "renderer/view/caster_reach_grid.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <numeric>

namespace omnishadow {
namespace {

// Below this many casters every query returns them all: walking them is as cheap as the grid.
constexpr std::size_t kGridFrom = 64;
// A caster whose box spans more cells than this on an axis is a candidate of every query
// rather than an entry in each of its cells (a room's floor and walls).
constexpr int kMaxSpan = 8;
constexpr std::size_t kMaxCells = std::size_t{1} << 20;

// The bound's half extents (cullCasters: far + 2.5 r + 1e-3 (far + r), split between the light
// and the caster), grown by a relative 1e-4 and by 1e-5 of the coordinates' magnitude: the
// float rounding of the bound and of the boxes' corners is below 1e-6 of either.
float casterHalfExtent(const glm::vec3& center, float radius) {
  const float magnitude = std::max({std::abs(center.x), std::abs(center.y), std::abs(center.z)});
  return (2.5f * radius + 1e-3f * radius) * 1.0001f + 1e-5f * (magnitude + radius);
}

float lightHalfExtent(const glm::vec3& position, float far) {
  const float magnitude =
      std::max({std::abs(position.x), std::abs(position.y), std::abs(position.z)});
  return (far + 1e-3f * far) * 1.0001f + 1e-5f * (magnitude + far);
}

bool finite(const glm::vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

}  // namespace

CasterReachGrid::CasterReachGrid(const std::vector<ShadowCaster>& casters)
    : casterCount_(casters.size()) {
  for (std::size_t c = 0; c < casters.size(); ++c)
    if (casters[c].plane) flat_.push_back(static_cast<std::uint32_t>(c));

  // The boxes, and the bounds of the finite ones.
  std::vector<glm::vec3> low(casters.size()), high(casters.size());
  std::vector<bool> placed(casters.size(), false);
  glm::vec3 lo(INFINITY), hi(-INFINITY);
  for (std::size_t c = 0; c < casters.size(); ++c) {
    const ShadowCaster& caster = casters[c];
    const float h = casterHalfExtent(caster.center, caster.radius);
    if (!finite(caster.center) || !std::isfinite(h)) continue;
    low[c] = caster.center - h;
    high[c] = caster.center + h;
    if (!finite(low[c]) || !finite(high[c])) continue;
    placed[c] = true;
    lo = glm::min(lo, low[c]);
    hi = glm::max(hi, high[c]);
  }
  const glm::vec3 extent = hi - lo;
  const float largest = std::max({extent.x, extent.y, extent.z});
  if (casters.size() < kGridFrom || !(largest > 0.0f) || !std::isfinite(largest)) {
    everywhere_.resize(casters.size());
    std::iota(everywhere_.begin(), everywhere_.end(), 0u);
    return;
  }
  // About two cells per caster, none thinner than a 64th of the largest extent.
  const glm::vec3 sides = glm::max(extent, glm::vec3(largest / 64.0f));
  float cell = std::cbrt(sides.x * sides.y * sides.z / (2.0f * static_cast<float>(casters.size())));
  for (;;) {
    dims_ = glm::clamp(glm::ivec3(glm::ceil(extent / cell)), glm::ivec3(1), glm::ivec3(128));
    if (static_cast<std::size_t>(dims_.x) * dims_.y * dims_.z <= kMaxCells) break;
    cell *= 1.25f;
  }
  origin_ = lo;
  inverseCell_ = 1.0f / cell;

  // Count, then fill, each caster's cells (a compressed row per cell).
  const std::size_t cells = static_cast<std::size_t>(dims_.x) * dims_.y * dims_.z;
  std::vector<std::pair<glm::ivec3, glm::ivec3>> ranges(casters.size());
  cellStart_.assign(cells + 1, 0u);
  const auto cellIndex = [this](int x, int y, int z) {
    return (static_cast<std::size_t>(z) * dims_.y + y) * dims_.x + x;
  };
  const auto forCells = [&](const std::pair<glm::ivec3, glm::ivec3>& r, auto visit) {
    for (int z = r.first.z; z <= r.second.z; ++z)
      for (int y = r.first.y; y <= r.second.y; ++y)
        for (int x = r.first.x; x <= r.second.x; ++x) visit(cellIndex(x, y, z));
  };
  for (std::size_t c = 0; c < casters.size(); ++c) {
    if (!placed[c]) {
      everywhere_.push_back(static_cast<std::uint32_t>(c));
      continue;
    }
    ranges[c] = {cellOf(low[c]), cellOf(high[c])};
    const glm::ivec3 span = ranges[c].second - ranges[c].first;
    if (span.x >= kMaxSpan || span.y >= kMaxSpan || span.z >= kMaxSpan) {
      placed[c] = false;
      everywhere_.push_back(static_cast<std::uint32_t>(c));
      continue;
    }
    forCells(ranges[c], [&](std::size_t i) { ++cellStart_[i + 1]; });
  }
  std::partial_sum(cellStart_.begin(), cellStart_.end(), cellStart_.begin());
  entries_.resize(cellStart_.back());
  std::vector<std::uint32_t> next(cellStart_.begin(), cellStart_.end() - 1);
  for (std::size_t c = 0; c < casters.size(); ++c)
    if (placed[c])
      forCells(ranges[c],
               [&](std::size_t i) { entries_[next[i]++] = static_cast<std::uint32_t>(c); });
}

glm::ivec3 CasterReachGrid::cellOf(const glm::vec3& point) const {
  // Monotonic in each coordinate (float subtraction and scaling are), so that boxes that
  // overlap get cell ranges that overlap.
  const glm::vec3 scaled = glm::floor((point - origin_) * inverseCell_);
  return glm::ivec3(glm::clamp(scaled, glm::vec3(0.0f), glm::vec3(dims_ - 1)));
}

void CasterReachGrid::candidates(const glm::vec3& position, float far,
                                 std::vector<std::uint32_t>& out) const {
  out.clear();
  const float q = lightHalfExtent(position, far);
  if (everywhere_.size() == casterCount_ || !finite(position) || !std::isfinite(q)) {
    out.resize(casterCount_);
    std::iota(out.begin(), out.end(), 0u);
    return;
  }
  // A bit per caster: a caster in several of the cells comes out once, and in order.
  std::vector<std::uint64_t> bits((casterCount_ + 63) / 64, 0u);
  const auto mark = [&bits](std::uint32_t c) { bits[c / 64] |= std::uint64_t{1} << (c % 64); };
  const glm::ivec3 first = cellOf(position - q), last = cellOf(position + q);
  for (int z = first.z; z <= last.z; ++z)
    for (int y = first.y; y <= last.y; ++y)
      for (int x = first.x; x <= last.x; ++x) {
        const std::size_t cell = (static_cast<std::size_t>(z) * dims_.y + y) * dims_.x + x;
        for (std::uint32_t i = cellStart_[cell]; i < cellStart_[cell + 1]; ++i) mark(entries_[i]);
      }
  for (const std::uint32_t c : everywhere_) mark(c);
  for (std::size_t word = 0; word < bits.size(); ++word)
    for (std::uint64_t w = bits[word]; w != 0u; w &= w - 1)
      out.push_back(
          static_cast<std::uint32_t>(word * 64 + static_cast<std::size_t>(std::countr_zero(w))));
}

}  // namespace omnishadow
