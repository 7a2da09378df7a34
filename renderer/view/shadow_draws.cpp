#include "renderer/view/shadow_draws.h"

#include <algorithm>
#include <array>

namespace omnishadow {
namespace {

// The instances a caster is drawn with in a pass over `view`.
unsigned instancesIn(ShadowLayering layering, int view, unsigned viewMask) {
  return view < 0 && layering == ShadowLayering::Instanced ? viewMask : 1u;
}

bool drawnIn(int view, unsigned viewMask) {
  return viewMask != 0 && (view < 0 || (viewMask & (1u << view)));
}

}  // namespace

int firstPassView(ShadowLayering layering) {
  return layering == ShadowLayering::PerView ? 0 : -1;
}

int passViewEnd(ShadowLayering layering, int views) {
  return layering == ShadowLayering::PerView ? views : 0;
}

ShadowDrawList buildShadowDraws(const std::vector<ShadowCaster>& casters,
                                const std::vector<CasterGeometry>& geometry,
                                const CasterCulling& culling, int views, ShadowLayering layering,
                                bool streamOrder) {
  // Only casters some view keeps: a light with a range usually reaches few of a large scene's
  // casters, and every pass below walks the list again. Sorting the kept ones alone gives them
  // the order they have in the sorted whole (a stable sort's order is a total one).
  std::vector<std::size_t> casterOrder, masked;
  for (std::size_t c = 0; c < casters.size(); ++c)
    if (culling.viewMask[c] != 0) (casters[c].masked ? masked : casterOrder).push_back(c);
  std::vector<std::size_t> worldOrder = casterOrder;
  if (streamOrder)
    std::stable_sort(worldOrder.begin(), worldOrder.end(), [&](std::size_t a, std::size_t b) {
      return geometry[a].casterFirstIndex < geometry[b].casterFirstIndex;
    });
  // Each (culling state, vertex source) batch's casters, in its order, found once rather than
  // in every view's pass: a light's 36 passes each walked all its casters.
  std::array<std::array<std::vector<std::size_t>, 2>, kCullBucketCount> batched;
  for (const bool world : {true, false})
    for (const std::size_t c : world ? worldOrder : casterOrder)
      if ((geometry[c].casterFirstIndex >= 0) == world)
        batched[static_cast<std::size_t>(culling.bucket[c])][world ? 0 : 1].push_back(c);
  ShadowDrawList list;
  for (int view = firstPassView(layering); view < passViewEnd(layering, views); ++view)
    for (int bucket = 0; bucket < kCullBucketCount; ++bucket)
      for (const bool world : {true, false}) {
        const int first = static_cast<int>(list.objects.size());
        for (const std::size_t c : batched[static_cast<std::size_t>(bucket)][world ? 0 : 1]) {
          const CasterGeometry& g = geometry[c];
          if (!drawnIn(view, culling.viewMask[c])) continue;
          // Runs of consecutive faces become one command each.
          forEachFaceRun(
              instancesIn(layering, view, culling.viewMask[c]), views,
              [&](int firstInstance, int count) {
                const IndirectDrawCommand command{
                    g.indexCount, static_cast<std::uint32_t>(count),
                    world ? static_cast<std::uint32_t>(g.casterFirstIndex) : g.firstIndex,
                    world ? 0 : g.baseVertex, static_cast<std::uint32_t>(firstInstance)};
                // World-space copies that follow each other in the stream, for the same faces,
                // extend the batch's last command: llvmpipe spends microseconds per command.
                if (world && static_cast<int>(list.objects.size()) > first) {
                  IndirectDrawCommand& last = list.commands.back();
                  if (last.firstIndex + last.count == command.firstIndex &&
                      last.instanceCount == command.instanceCount &&
                      last.baseInstance == command.baseInstance) {
                    last.count += command.count;
                    return;
                  }
                }
                list.commands.push_back(command);
                list.objects.push_back(static_cast<std::uint32_t>(c));
              });
        }
        const int count = static_cast<int>(list.objects.size()) - first;
        if (count > 0)
          list.opaque.push_back({static_cast<CullBucket>(bucket), view, world, first, count});
      }

  for (int view = firstPassView(layering); view < passViewEnd(layering, views); ++view)
    for (const std::size_t c : masked)
      if (drawnIn(view, culling.viewMask[c]))
        list.masked.push_back(
            {view, static_cast<int>(c), instancesIn(layering, view, culling.viewMask[c])});
  return list;
}

}  // namespace omnishadow
