#include "renderer/view/shadow_draws.h"

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
                                const CasterCulling& culling, int views, ShadowLayering layering) {
  ShadowDrawList list;
  for (int view = firstPassView(layering); view < passViewEnd(layering, views); ++view)
    for (int bucket = 0; bucket < kCullBucketCount; ++bucket)
      for (const bool world : {true, false}) {
        const int first = static_cast<int>(list.objects.size());
        for (std::size_t c = 0; c < casters.size(); ++c) {
          const CasterGeometry& g = geometry[c];
          if (casters[c].masked || culling.bucket[c] != static_cast<CullBucket>(bucket) ||
              (g.casterBaseVertex >= 0) != world || !drawnIn(view, culling.viewMask[c]))
            continue;
          // Runs of consecutive faces become one command each.
          forEachFaceRun(
              instancesIn(layering, view, culling.viewMask[c]), views,
              [&](int firstInstance, int count) {
                list.commands.push_back({g.indexCount, static_cast<std::uint32_t>(count),
                                         g.firstIndex, world ? g.casterBaseVertex : g.baseVertex,
                                         static_cast<std::uint32_t>(firstInstance)});
                list.objects.push_back(static_cast<std::uint32_t>(c));
              });
        }
        const int count = static_cast<int>(list.objects.size()) - first;
        if (count > 0)
          list.opaque.push_back({static_cast<CullBucket>(bucket), view, world, first, count});
      }

  for (int view = firstPassView(layering); view < passViewEnd(layering, views); ++view)
    for (std::size_t c = 0; c < casters.size(); ++c)
      if (casters[c].masked && drawnIn(view, culling.viewMask[c]))
        list.masked.push_back(
            {view, static_cast<int>(c), instancesIn(layering, view, culling.viewMask[c])});
  return list;
}

}  // namespace omnishadow
