// The grid that lets a point light cull only the casters near it must give every light exactly
// the culling that walking every caster gives: masks, buckets and the count of flat casters
// left out, for scenes and lights nobody tuned it for.
#include "renderer/view/caster_reach_grid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "renderer/view/caster_culling.h"
#include "tests/support/cube_culling_light.h"

namespace caster_reach_grid_test {

using namespace omnishadow;

namespace {

struct Random {
  std::uint32_t state;
  float uniform(float lo, float hi) {
    state = state * 1664525u + 1013904223u;
    return lo + (hi - lo) * static_cast<float>(state >> 8) / 16777216.0f;
  }
};

ShadowCullingLight pointLight(const glm::vec3& position, float far, CullFace cullFace) {
  return test::cubeCullingLight(position, cullFace, far * 0.01f, far);
}

// Casters of many sizes spread over a box of `size` around `middle`: spheres from a
// millimetre to a tenth of the scene, a few larger than the scene, flat ones among them, and
// closed, mirrored, double-sided and masked ones.
std::vector<ShadowCaster> scatter(Random& random, int count, const glm::vec3& middle, float size) {
  std::vector<ShadowCaster> casters;
  for (int c = 0; c < count; ++c) {
    ShadowCaster caster;
    const float kind = random.uniform(0.0f, 1.0f);
    caster.radius = kind < 0.1f    ? random.uniform(0.0f, 0.001f * size)
                    : kind < 0.97f ? random.uniform(0.0f, 0.1f * size)
                                   : random.uniform(0.5f * size, 2.0f * size);
    caster.center = middle + glm::vec3(random.uniform(-size, size), random.uniform(-size, size),
                                       random.uniform(-size, size)) *
                                 0.5f;
    caster.closed = random.uniform(0.0f, 1.0f) < 0.5f;
    caster.mirrored = random.uniform(0.0f, 1.0f) < 0.2f;
    caster.doubleSided = random.uniform(0.0f, 1.0f) < 0.2f;
    caster.masked = random.uniform(0.0f, 1.0f) < 0.1f;
    if (random.uniform(0.0f, 1.0f) < 0.05f)
      caster.plane = MeshPlane{{0.0f, 1.0f, 0.0f}, -caster.center.y, 0.0f};
    casters.push_back(caster);
  }
  return casters;
}

void expectSameCulling(const std::vector<ShadowCaster>& casters, const CasterReachGrid& grid,
                       const ShadowCullingLight& light, const Bounds& receivers,
                       const std::string& what) {
  const CasterCulling all = cullCasters(casters, light, receivers);
  const CasterCulling near = cullCasters(casters, light, receivers, &grid);
  ASSERT_EQ(near.viewMask, all.viewMask) << what;
  ASSERT_EQ(near.bucket, all.bucket) << what;
  ASSERT_EQ(near.flatLeftOut, all.flatLeftOut) << what;
}

}  // namespace

TEST(CasterReachGrid, EveryLightCullsAsIfItWalkedEveryCaster) {
  Random random{2024u};
  int kept = 0, total = 0;
  for (int scene = 0; scene < 12; ++scene) {
    const float size = std::pow(10.0f, random.uniform(-2.0f, 3.0f));
    const glm::vec3 middle(random.uniform(-1e3f, 1e3f), random.uniform(-1e3f, 1e3f),
                           random.uniform(-1e3f, 1e3f));
    const std::vector<ShadowCaster> casters =
        scatter(random, static_cast<int>(random.uniform(64.0f, 3000.0f)), middle, size);
    const CasterReachGrid grid(casters);
    Bounds receivers;
    receivers.extend(middle - glm::vec3(0.5f * size, 0.0f, 0.5f * size));
    receivers.extend(middle + glm::vec3(0.5f * size));
    for (int l = 0; l < 40; ++l) {
      // Ranges from a hundredth of the scene to beyond it, lights inside it and outside.
      const float far = size * std::pow(10.0f, random.uniform(-2.0f, 0.5f));
      const glm::vec3 at =
          middle + glm::vec3(random.uniform(-size, size), random.uniform(-size, size),
                             random.uniform(-size, size)) *
                       0.6f;
      const CullFace face = l % 3 == 0 ? CullFace::Back : CullFace::None;
      const ShadowCullingLight light = pointLight(at, far, face);
      const std::string what = "scene " + std::to_string(scene) + " light " + std::to_string(l);
      expectSameCulling(casters, grid, light, receivers, what);
      expectSameCulling(casters, grid, light, Bounds{}, what + " without receivers");
      const CasterCulling culling = cullCasters(casters, light, receivers, &grid);
      for (const unsigned mask : culling.viewMask) kept += mask != 0u;
      total += static_cast<int>(casters.size());
    }
  }
  // The lights kept some casters and rejected most, so both kinds were compared.
  EXPECT_GT(kept, total / 100);
  EXPECT_LT(kept, total / 2);
}

TEST(CasterReachGrid, CastersOnTheBoundOfALightsReachAreStillFound) {
  // Spheres placed just inside and just outside the bound along each axis, at coordinates far
  // from the origin where float spacing is coarse, among 20,000 specks that make the cells
  // small beside the spheres (so that a box a fifth too small would miss some).
  Random random{7u};
  const glm::vec3 at(4096.5f, -2048.25f, 1024.125f);
  const float far = 3.0f;
  std::vector<ShadowCaster> casters;
  for (int c = 0; c < 20000; ++c) {
    ShadowCaster speck;
    speck.radius = 0.001f;
    speck.center =
        at + glm::vec3(random.uniform(-5, 5), random.uniform(-5, 5), random.uniform(-5, 5));
    casters.push_back(speck);
  }
  for (int c = 0; c < 600; ++c) {
    ShadowCaster caster;
    caster.radius = random.uniform(0.1f, 0.45f);
    const float bound = far + 2.5f * caster.radius + 1e-3f * (far + caster.radius);
    glm::vec3 offset(random.uniform(-bound, bound), random.uniform(-bound, bound),
                     random.uniform(-bound, bound));
    const int axis = c % 3;
    offset[axis] = (c % 2 ? 1.0f : -1.0f) * bound * random.uniform(0.999f, 1.001f);
    caster.center = at + offset;
    casters.push_back(caster);
  }
  const CasterReachGrid grid(casters);
  expectSameCulling(casters, grid, pointLight(at, far, CullFace::None), Bounds{}, "on the bound");
  // The grid's own promise, tighter than the masks can tell: every caster within the bound
  // on every axis is a candidate.
  std::vector<std::uint32_t> found;
  grid.candidates(at, far, found);
  int within = 0;
  for (std::size_t c = 0; c < casters.size(); ++c) {
    const float bound = far + 2.5f * casters[c].radius + 1e-3f * (far + casters[c].radius);
    const glm::vec3 d = glm::abs(casters[c].center - at);
    if (d.x > bound || d.y > bound || d.z > bound) continue;
    ++within;
    ASSERT_TRUE(std::binary_search(found.begin(), found.end(), static_cast<std::uint32_t>(c))) << c;
  }
  EXPECT_GT(within, 200);
  EXPECT_LT(found.size(), casters.size());
}

TEST(CasterReachGrid, CandidatesAreAscendingOnceEachAndHoldEveryCasterTheBoundKeeps) {
  Random random{99u};
  std::vector<ShadowCaster> casters;
  for (int c = 0; c < 500; ++c) {
    ShadowCaster caster;
    caster.radius = random.uniform(0.0f, 0.2f);
    caster.center = {random.uniform(-10, 10), random.uniform(-10, 10), random.uniform(-10, 10)};
    casters.push_back(caster);
  }
  const CasterReachGrid grid(casters);
  std::vector<std::uint32_t> found;
  grid.candidates({1.0f, 2.0f, -3.0f}, 2.0f, found);
  for (std::size_t i = 1; i < found.size(); ++i) ASSERT_LT(found[i - 1], found[i]);
  // Far fewer than all of them (the bound's box is 1/50 of the scene's): the grid does cull.
  EXPECT_LT(found.size(), casters.size() / 10);
  const ShadowCullingLight light = pointLight({1.0f, 2.0f, -3.0f}, 2.0f, CullFace::None);
  const CasterCulling culling = cullCasters(casters, light, Bounds{});
  int kept = 0;
  for (std::size_t c = 0; c < casters.size(); ++c) {
    if (culling.viewMask[c] == 0u) continue;
    ++kept;
    EXPECT_TRUE(std::binary_search(found.begin(), found.end(), static_cast<std::uint32_t>(c)));
  }
  EXPECT_GT(kept, 0);
  // The query is replaced, not appended to.
  std::vector<std::uint32_t> again = {12345u};
  grid.candidates({1.0f, 2.0f, -3.0f}, 2.0f, again);
  EXPECT_EQ(again, found);
}

TEST(CasterReachGrid, FewOrUnboundedCastersAreCandidatesOfEveryLight) {
  Random random{5u};
  // Under the size where a grid pays, and with spheres no box holds: every caster, in order.
  const std::vector<ShadowCaster> few = scatter(random, 10, glm::vec3(0.0f), 1.0f);
  std::vector<std::uint32_t> found;
  CasterReachGrid(few).candidates(glm::vec3(100.0f), 0.1f, found);
  EXPECT_EQ(found.size(), few.size());

  std::vector<ShadowCaster> casters = scatter(random, 300, glm::vec3(0.0f), 10.0f);
  casters[17].radius = std::numeric_limits<float>::infinity();
  casters[40].center.x = std::numeric_limits<float>::quiet_NaN();
  const CasterReachGrid grid(casters);
  grid.candidates(glm::vec3(1000.0f), 1.0f, found);
  EXPECT_LT(found.size(), casters.size() / 4);
  EXPECT_TRUE(std::binary_search(found.begin(), found.end(), 17u));
  EXPECT_TRUE(std::binary_search(found.begin(), found.end(), 40u));
  // A light that is not finite tests every caster.
  grid.candidates(glm::vec3(std::numeric_limits<float>::infinity()), 1.0f, found);
  EXPECT_EQ(found.size(), casters.size());
  expectSameCulling(casters, grid, pointLight(glm::vec3(0.5f), 3.0f, CullFace::None), Bounds{},
                    "with an infinite and a NaN caster");
}

}  // namespace caster_reach_grid_test
