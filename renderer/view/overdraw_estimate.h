#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

#include "renderer/scene/scene.h"

namespace omnishadow {

// What a frame's opaque surfaces would draw, estimated on the CPU before anything is drawn, so
// that the frame can choose the depth pre-pass by its overdraw (Renderer::Impl::choosePrepass).

// An opaque draw: its mesh's triangles placed by `world`; back faces culled unless the
// material is double-sided, front faces clockwise where `world` mirrors.
struct OverdrawSurface {
  const Mesh* mesh = nullptr;
  glm::mat4 world{1.0f};
  bool cullBackFaces = true;
  bool mirrored = false;
};

// Counts at sample points, scaled to pixels, as GL's occlusion queries would count them around
// the pre-pass and the shading after it: the fragments that pass the pre-pass's depth test with
// depth writes (`passed`: what it lets through, and what shading without it would shade, ties
// aside), the pixels covered at the end (`covered`: what shading after it shades, ties aside),
// and every triangle (`triangles`: what it draws).
struct OverdrawCounts {
  std::uint64_t passed = 0;
  std::uint64_t covered = 0;
  std::uint64_t triangles = 0;
};

// Rasterizes `inDrawOrder` at the centres of a grid of at most `maxSamples` samples, about
// square cells, over a width x height frame seen through `viewProjection`, with the frame's
// conventions:
// reversed depth (GL_ZERO_TO_ONE, nearer is greater, cleared to 0) and the pre-pass's
// GL_GREATER. Triangles are clipped to the near and far planes, not to the frame's sides.
// Small triangles between sample points count nothing, as they count little on screen.
OverdrawCounts estimateOverdraw(const std::vector<OverdrawSurface>& inDrawOrder,
                                const glm::mat4& viewProjection, int width, int height,
                                int maxSamples);

}  // namespace omnishadow
