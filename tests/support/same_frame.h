#pragma once
// Whether two frames hold the same pictures, byte for byte: the 8-bit and float beauty, the AOVs
// and the object ids, each where the frames have it (both or neither).
#include <gtest/gtest.h>

#include <string>

#include "renderer/render/frame.h"

namespace omnishadow::test_support {

inline void expectSameFrame(const Frame& a, const Frame& b, const std::string& what) {
  ASSERT_EQ(a.srgb8.has_value(), b.srgb8.has_value()) << what;
  if (a.srgb8) {
    EXPECT_TRUE(a.srgb8->rgb == b.srgb8->rgb) << what << ": the 8-bit beauty differs";
  }
  EXPECT_TRUE(a.beauty.pixels == b.beauty.pixels) << what << ": the float beauty differs";
  ASSERT_EQ(a.aovs.has_value(), b.aovs.has_value()) << what;
  if (a.aovs) {
    EXPECT_TRUE(a.aovs->pixels == b.aovs->pixels) << what << ": the AOVs differ";
  }
  ASSERT_EQ(a.objectIds.has_value(), b.objectIds.has_value()) << what;
  if (a.objectIds) {
    EXPECT_TRUE(a.objectIds->pixels == b.objectIds->pixels) << what << ": the object ids differ";
  }
}

}  // namespace omnishadow::test_support
