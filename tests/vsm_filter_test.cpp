// The VSM blur (renderer/passes/vsm_filter.h) filters only the layers and texels that hold
// something besides the cleared moments, as the shadow pass's layer binding records them
// (renderer/passes/shadow_layer_binding.h, grown by the blur's spread). That is exact only if
// the blur leaves cleared moments exactly as they are and every texel it reads was filtered or
// cleared: so after two frames whose casters cover other texels, a light's layers must hold, bit
// for bit, what a blur of whole layers gives for the second frame's moments alone. That blur
// is in turn checked against the same Gaussian in doubles.
#include "renderer/passes/vsm_filter.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <ostream>
#include <random>
#include <vector>

#include "renderer/gl/gl_debug.h"
#include "renderer/gl/raster_state.h"
#include "renderer/passes/shadow_layer_binding.h"
#include "renderer/passes/shadow_textures.h"
#include "tests/support/shared_renderer.h"

namespace omnishadow::vsm_filter_test {
namespace {

constexpr int kSize = 48;
constexpr float kRadius = 2.5f;  // three taps each side

struct Layout {
  const char* name;
  ShadowLayout layout;
  int textureLayers;
  int firstLayer, layerCount;  // the light's layers
  int scratchLayers;           // the filter's scratch budget, in layers of kSize²
};

// What a shadow pass leaves: random moments (a mean and a second moment above its square) in
// `rect` of `layer`, the same for the same seed.
void drawMoments(const ShadowGroupTextures& group, int layer, const TexelRect& rect,
                 unsigned seed) {
  if (rect.empty()) return;
  std::mt19937 random(seed);
  std::uniform_real_distribution<float> mean(0.1f, 0.9f), spread(0.0f, 0.01f);
  const int w = rect.x1 - rect.x0, h = rect.y1 - rect.y0;
  std::vector<float> texels;
  for (int i = 0; i < w * h; ++i) {
    const float m = mean(random);
    texels.push_back(m);
    texels.push_back(m * m + spread(random));
  }
  glTextureSubImage3D(group.moments.get(), 0, rect.x0, rect.y0, layer, w, h, 1, GL_RG, GL_FLOAT,
                      texels.data());
}

std::vector<float> readMoments(const ShadowGroupTextures& group) {
  std::vector<float> texels(static_cast<std::size_t>(kSize) * kSize * group.layers * 2);
  glGetTextureImage(group.moments.get(), 0, GL_RG, GL_FLOAT,
                    static_cast<GLsizei>(texels.size() * sizeof(float)), texels.data());
  gl::checkErrors("reading moments back");
  return texels;
}

// The texels of `layer` in readMoments()'s array.
std::vector<float> layerOf(const std::vector<float>& all, int layer) {
  const std::size_t size = static_cast<std::size_t>(kSize) * kSize * 2;
  const auto first = all.begin() + static_cast<std::ptrdiff_t>(size * layer);
  return {first, first + static_cast<std::ptrdiff_t>(size)};
}

void PrintTo(const Layout& layout, std::ostream* out) {
  *out << layout.name;
}

// The separable Gaussian of VsmFilter in doubles: sigma = radius / 2, taps out to the radius,
// texels beyond an edge read as the edge's.
std::vector<float> gaussian(const std::vector<float>& layer, float radius) {
  const int taps = VsmFilter::spread(radius);
  const double sigma = std::max(0.5, radius * 0.5);
  std::vector<double> weights;
  double total = 0.0;
  for (int i = -taps; i <= taps; ++i) {
    weights.push_back(std::exp(-0.5 * i * i / (sigma * sigma)));
    total += weights.back();
  }
  const auto at = [](int x, int y) {
    return (static_cast<std::size_t>(std::clamp(y, 0, kSize - 1)) * kSize +
            static_cast<std::size_t>(std::clamp(x, 0, kSize - 1))) *
           2;
  };
  std::vector<double> rows(layer.size());
  std::vector<float> out(layer.size());
  for (int pass = 0; pass < 2; ++pass)
    for (int y = 0; y < kSize; ++y)
      for (int x = 0; x < kSize; ++x)
        for (int c = 0; c < 2; ++c) {
          double sum = 0.0;
          for (int i = -taps; i <= taps; ++i) {
            const double w = weights[static_cast<std::size_t>(i + taps)];
            sum += pass == 0 ? w * layer[at(x + i, y) + c] : w * rows[at(x, y + i) + c];
          }
          if (pass == 0)
            rows[at(x, y) + c] = sum / total;
          else
            out[at(x, y) + c] = static_cast<float>(sum / total);
        }
  return out;
}

class VsmFilterTest : public ::testing::TestWithParam<Layout> {};

TEST_P(VsmFilterTest, FilteringWhatFramesWroteEqualsFilteringWholeLayers) {
  test_support::sharedRenderer();  // its GL context is current here
  const Layout& layout = GetParam();
  ShadowTexturePool pool;
  ShadowGroupTextures group =
      pool.take({{layout.layout, kSize, DepthFormat::Float32, true}, layout.textureLayers});
  LightShadowPlan plan;
  plan.firstLayer = layout.firstLayer;
  plan.layerCount = layout.layerCount;
  // Another light's layers hold moments everywhere and must keep them.
  for (int layer = 0; layer < group.layers; ++layer)
    drawMoments(group, layer, TexelRect::whole(kSize), 100u + static_cast<unsigned>(layer));
  const std::vector<float> before = readMoments(group);

  // Casters per frame and layer of the light: at edges and corners, a layer left empty, a whole
  // one, and the second frame's away from the first's.
  const std::vector<TexelRect> first = {{5, 5, 20, 18},          {0, 30, 12, 48}, {},
                                        TexelRect::whole(kSize), {40, 0, 48, 9},  {22, 22, 25, 25}};
  const std::vector<TexelRect> second = {
      {28, 28, 44, 40}, {30, 2, 46, 14}, {10, 10, 20, 20}, {}, {2, 30, 14, 44}, {}};
  VsmFilter filter(8.0 * kSize * kSize * layout.scratchLayers);
  const gl::Framebuffer framebuffer = gl::createFramebuffer();
  const GLuint fb = framebuffer.get();
  const auto frame = [&](const std::vector<TexelRect>& casters, unsigned seed) {
    const std::vector<TexelRect> mine(casters.begin(), casters.begin() + plan.layerCount);
    glBindFramebuffer(GL_FRAMEBUFFER, fb);
    glNamedFramebufferDrawBuffer(fb, GL_COLOR_ATTACHMENT0);
    gl::RasterState state;  // what the shadow pass clears with: moments' RG writes on
    state.color.rgba = {true, true, false, false};
    state.viewport = {0, 0, kSize, kSize};
    state.apply();
    ShadowLayerBinding layers(fb, group, plan.firstLayer, plan.layerCount, mine,
                              VsmFilter::spread(kRadius));
    for (int layer = 0; layer < plan.layerCount; ++layer) layers.bind(layer);
    layers.detach();
    gl::RasterState::restoreDefaults();
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    for (int layer = 0; layer < plan.layerCount; ++layer)
      drawMoments(group, plan.firstLayer + layer, mine[static_cast<std::size_t>(layer)],
                  seed + static_cast<unsigned>(layer));
    filter.blur(group, plan, kRadius);
  };
  frame(first, 1);
  frame(second, 2);
  const std::vector<float> filtered = readMoments(group);
  for (int layer = 0; layer < group.layers; ++layer) {
    if (layer >= plan.firstLayer && layer < plan.firstLayer + plan.layerCount) continue;
    EXPECT_EQ(layerOf(filtered, layer), layerOf(before, layer))
        << "another light's layer " << layer;
  }

  // The reference: the second frame's moments on cleared layers, every texel filtered.
  clearShadowTextures(group);
  for (int layer = 0; layer < plan.layerCount; ++layer) {
    drawMoments(group, plan.firstLayer + layer, second[static_cast<std::size_t>(layer)],
                2u + static_cast<unsigned>(layer));
    group.written[static_cast<std::size_t>(plan.firstLayer + layer)] = TexelRect::whole(kSize);
  }
  const std::vector<float> unfiltered = readMoments(group);
  filter.blur(group, plan, kRadius);
  const std::vector<float> reference = readMoments(group);
  for (int layer = plan.firstLayer; layer < plan.firstLayer + plan.layerCount; ++layer) {
    const auto got = layerOf(filtered, layer), want = layerOf(reference, layer);
    const auto drawn = layerOf(unfiltered, layer);
    // The filter itself, against doubles: weights, edges and both directions.
    const std::vector<float> exact = gaussian(drawn, kRadius);
    float worst = 0.0f;
    for (std::size_t i = 0; i < want.size(); ++i)
      worst = std::max(worst, std::abs(want[i] - exact[i]));
    EXPECT_LT(worst, 1e-5f) << layout.name << " layer " << layer;
    ASSERT_EQ(got.size(), want.size());
    int differ = 0;
    for (std::size_t i = 0; i < got.size(); ++i) differ += got[i] != want[i] ? 1 : 0;
    EXPECT_EQ(differ, 0) << layout.name << " layer " << layer;
    const TexelRect reach = second[static_cast<std::size_t>(layer - plan.firstLayer)].grown(
        VsmFilter::spread(kRadius), VsmFilter::spread(kRadius), kSize);
    int moved = 0, outside = 0;
    for (int y = 0; y < kSize; ++y)
      for (int x = 0; x < kSize; ++x)
        for (int c = 0; c < 2; ++c) {
          const std::size_t i = (static_cast<std::size_t>(y) * kSize + x) * 2 + c;
          const bool inReach = x >= reach.x0 && x < reach.x1 && y >= reach.y0 && y < reach.y1;
          // Beyond the casters' reach the blur gives the cleared moments back exactly.
          if (!inReach && want[i] != kClearedMoments[c]) ++outside;
          if (want[i] != drawn[i]) ++moved;
        }
    EXPECT_EQ(outside, 0) << layout.name << " layer " << layer;
    if (!reach.empty()) {
      EXPECT_GT(moved, 100) << layout.name << " layer " << layer;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(
    Layouts, VsmFilterTest,
    ::testing::Values(Layout{"cube", ShadowLayout::Cube, 12, 6, 6, 6},
                      Layout{"cubeTwoLayersADraw", ShadowLayout::Cube, 12, 6, 6, 2},
                      Layout{"spot", ShadowLayout::Planar, 3, 1, 1, 6},
                      Layout{"cascades", ShadowLayout::Planar, 5, 1, 3, 6}),
    [](const ::testing::TestParamInfo<Layout>& test) { return test.param.name; });

}  // namespace
}  // namespace omnishadow::vsm_filter_test
