#pragma once

#include <cstdint>
#include <vector>

#include "renderer/view/caster_culling.h"

namespace omnishadow {

// The shadow pass's draws of one light, batched from the casters' culling: opaque casters as
// multi-draw indirect commands, alpha-tested ones one by one. No GL here: the pass uploads
// the commands as they are and walks the batches.

// How the views of one light are reached.
enum class ShadowLayering {
  PerView,    // one pass per view (layer attached alone)
  Instanced,  // one pass; the instance index picks the layer, one instance per view
  Geometry,   // one pass; a geometry shader picks the layers (one instance)
};

// Calls visit(first, count) for each run of consecutive set bits among the low `views` bits of
// `mask`: the faces one instanced draw can cover.
template <typename Visit>
void forEachFaceRun(unsigned mask, int views, Visit visit) {
  for (int v = 0; v < views;) {
    if (!(mask & (1u << v))) {
      ++v;
      continue;
    }
    int end = v;
    while (end < views && (mask & (1u << end))) ++end;
    visit(v, end - v);
    v = end;
  }
}

// glMultiDrawElementsIndirect's command layout (DrawElementsIndirectCommand).
struct IndirectDrawCommand {
  std::uint32_t count;
  std::uint32_t instanceCount;
  std::uint32_t firstIndex;
  std::int32_t baseVertex;
  std::uint32_t baseInstance;
};
static_assert(sizeof(IndirectDrawCommand) == 20);

// Where a caster's triangles are in the scene's buffers.
struct CasterGeometry {
  std::uint32_t indexCount = 0;
  std::uint32_t firstIndex = 0;  // in indices
  std::int32_t baseVertex = 0;
  // First index of the caster's copy in the world-space caster stream, whose indices need no
  // base vertex; -1 when it has none.
  std::int32_t casterFirstIndex = -1;
};

// One multi-draw: commands [first, first + count) of one culling state, view and vertex source.
struct OpaqueShadowBatch {
  CullBucket bucket = CullBucket::None;
  int view = 0;        // -1: all views at once (layered)
  bool world = false;  // from the world-space caster stream
  int first = 0, count = 0;
};

// One alpha-tested caster in one pass. Each run of set bits in `instances` is one instanced
// draw whose instance index picks the layer; PerView and Geometry draw a single instance.
struct MaskedShadowDraw {
  int view = 0;  // -1: all views at once (layered)
  int caster = 0;
  unsigned instances = 1u;
};

struct ShadowDrawList {
  // The shader finds a command's caster (its transform) at objects[batch.first + drawID]; a
  // command of a world batch may cover several casters (the first is named), which the shader
  // needs no transform for.
  std::vector<IndirectDrawCommand> commands;
  std::vector<std::uint32_t> objects;
  std::vector<OpaqueShadowBatch> opaque;  // in drawing order
  std::vector<MaskedShadowDraw> masked;   // in drawing order, after the opaque batches
};

// The views a pass loops over: 0..views-1, or -1 alone for a layered strategy.
int firstPassView(ShadowLayering layering);
int passViewEnd(ShadowLayering layering, int views);

// Casters from the world-space stream are drawn in the stream's order when `streamOrder` (the
// GpuScene keeps neighbours in space together there), else in the casters' order; either way
// copies that follow each other in the stream, for the same faces, share one command. A depth
// map does not depend on the order its triangles are drawn in; moments do, where two casters
// tie for the nearest depth.
ShadowDrawList buildShadowDraws(const std::vector<ShadowCaster>& casters,
                                const std::vector<CasterGeometry>& geometry,
                                const CasterCulling& culling, int views, ShadowLayering layering,
                                bool streamOrder = false);

}  // namespace omnishadow
