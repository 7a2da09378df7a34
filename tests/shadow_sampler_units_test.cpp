// The texture units of the lighting pass's shadow sampler arrays (shadowSamplerUnits): only the
// families a frame's filters read, SHADOW_SLOTS units each, after the material's units, never
// overlapping each other or the material's, and within the 32 units a fragment shader has
// (the material extensions' textures take the units after them, per material variant).
#include <gtest/gtest.h>

#include <set>
#include <vector>

#include "renderer/passes/lighting_pass.h"
#include "renderer/passes/shader_contract.h"

namespace omnishadow::shadow_sampler_units_test {
namespace {

unsigned bit(ShadowFilter filter) {
  return 1u << static_cast<unsigned>(filter);
}

// The units each declared array takes, checked for overlaps on the way.
std::set<int> unitsTaken(const ShadowSamplerUnits& u, int slots) {
  std::set<int> taken;
  for (const int first : {u.cubeCompare, u.planarCompare, u.cubeDepth, u.planarDepth, u.cubeMoments,
                          u.planarMoments}) {
    if (first < 0) continue;
    for (int s = 0; s < slots; ++s) EXPECT_TRUE(taken.insert(first + s).second) << first + s;
  }
  return taken;
}

TEST(ShadowSamplerUnits, OnePcfLayoutTakesOneUnitAfterTheMaterials) {
  LightingFeatures f;
  f.cubeShadows = true;
  f.filters = bit(ShadowFilter::Pcf);
  f.shadowSlots = 1;
  const ShadowSamplerUnits u = shadowSamplerUnits(f);
  EXPECT_EQ(u.cubeCompare, contract::kFirstShadowUnit);
  EXPECT_EQ(u.cubeDepth, -1);
  EXPECT_EQ(u.planarCompare, -1);
  EXPECT_EQ(u.cubeMoments, -1);
  EXPECT_EQ(u.end, contract::kFirstShadowUnit + 1);
  // No shadowed light: nothing declared.
  EXPECT_EQ(shadowSamplerUnits(LightingFeatures{}).end, contract::kFirstShadowUnit);
}

TEST(ShadowSamplerUnits, EachFilterDeclaresTheFamiliesItReads) {
  const struct {
    ShadowFilter filter;
    bool compare, depth, moments;
  } filters[] = {
      {ShadowFilter::Hard, false, true, false},    {ShadowFilter::Pcf, true, false, false},
      {ShadowFilter::PcfDisk, true, false, false}, {ShadowFilter::Poisson, true, false, false},
      {ShadowFilter::Pcss, true, true, false},     {ShadowFilter::Vsm, false, false, true}};
  for (const auto& f : filters) {
    LightingFeatures features;
    features.cubeShadows = features.planarShadows = true;
    features.filters = bit(f.filter);
    features.shadowSlots = 2;
    const ShadowSamplerUnits u = shadowSamplerUnits(features);
    EXPECT_EQ(u.cubeCompare >= 0, f.compare);
    EXPECT_EQ(u.planarCompare >= 0, f.compare);
    EXPECT_EQ(u.cubeDepth >= 0, f.depth);
    EXPECT_EQ(u.planarDepth >= 0, f.depth);
    EXPECT_EQ(u.cubeMoments >= 0, f.moments);
    EXPECT_EQ(u.planarMoments >= 0, f.moments);
  }
  // The depth debug view reads raw depth whatever the filter.
  LightingFeatures debug;
  debug.cubeShadows = true;
  debug.filters = bit(ShadowFilter::Pcf);
  debug.debugDepth = true;
  EXPECT_GE(shadowSamplerUnits(debug).cubeDepth, 0);
}

TEST(ShadowSamplerUnits, EveryFrameFitsAfterTheMaterialsUnits) {
  const unsigned all = bit(ShadowFilter::Hard) | bit(ShadowFilter::Pcf) | bit(ShadowFilter::Vsm);
  for (int slots = 1; slots <= contract::kMaxShadowGroups; ++slots)
    for (unsigned filters = 0; filters <= all; ++filters)
      for (int layouts = 1; layouts <= 3; ++layouts) {
        LightingFeatures f;
        f.cubeShadows = layouts & 1;
        f.planarShadows = layouts & 2;
        f.filters = filters & all;
        f.debugDepth = filters & 1;
        f.shadowSlots = slots;
        const ShadowSamplerUnits u = shadowSamplerUnits(f);
        const std::set<int> taken = unitsTaken(u, slots);
        EXPECT_LE(u.end, contract::kTextureUnits);
        if (!taken.empty()) {
          EXPECT_EQ(*taken.begin(), contract::kFirstShadowUnit);
          EXPECT_EQ(*taken.rbegin(), u.end - 1);
        } else {
          EXPECT_EQ(u.end, contract::kFirstShadowUnit);
        }
      }
}

}  // namespace
}  // namespace omnishadow::shadow_sampler_units_test
