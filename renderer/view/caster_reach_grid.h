#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

#include "renderer/view/caster_culling.h"

namespace omnishadow {

// A scene's shadow casters binned in a uniform grid by the box within which a point light can
// reach them (cullCasters' bound: a sphere of radius r that any cube face keeps lies within
// far + 2.5 r of the light on every axis), so that a light with a range tests the casters of
// the cells around it instead of every caster of the scene. Built once per frame and shared,
// read-only, by every light and both shadow contexts' threads.
//
// Why: with 256 lights on 2006 casters, walking every caster per light was 513k bound tests a
// frame, about 9 ms on this project's 2-core machine, on the thread that then submits the draws.
class CasterReachGrid {
 public:
  explicit CasterReachGrid(const std::vector<ShadowCaster>& casters);

  // Replaces `out` with, ascending and each once, every caster that a point light at
  // `position` with depth range end `far` may reach: a superset of those whose bound
  // (cullCasters) lets them through, with margins far above float rounding.
  void candidates(const glm::vec3& position, float far, std::vector<std::uint32_t>& out) const;

  // The casters with a plane (shadowsNoReceiver may leave them out), ascending.
  const std::vector<std::uint32_t>& flat() const { return flat_; }
  std::size_t casterCount() const { return casterCount_; }

 private:
  glm::ivec3 cellOf(const glm::vec3& point) const;

  std::size_t casterCount_ = 0;
  glm::vec3 origin_{0.0f};
  float inverseCell_ = 0.0f;
  glm::ivec3 dims_{0};
  std::vector<std::uint32_t> cellStart_;  // per cell, into entries_; one more at the end
  std::vector<std::uint32_t> entries_;
  // Casters whose box spans many cells, is not finite, or all of them when the grid would not
  // help: candidates of every query.
  std::vector<std::uint32_t> everywhere_;
  std::vector<std::uint32_t> flat_;
};

}  // namespace omnishadow
