#include "renderer/renderer.h"

#include <GL/glcorearb.h>

#include <algorithm>
#include <cmath>

#include "renderer/errors.h"
#include "renderer/gl_debug.h"
#include "renderer/gpu_scene.h"
#include "renderer/shadow_pass.h"

namespace omnishadow {
namespace {

// Reads attachment `index` of the frame as RGBA floats, rows flipped so row 0 = top.
std::vector<float> readAttachment(const FrameTargets& targets, int index) {
  const int w = targets.width(), h = targets.height();
  std::vector<float> pixels(static_cast<std::size_t>(w) * h * 4);
  glGetTextureImage(targets.color(index), 0, GL_RGBA, GL_FLOAT,
                    static_cast<GLsizei>(pixels.size() * sizeof(float)), pixels.data());
  const std::size_t row = static_cast<std::size_t>(w) * 4;
  for (int y = 0; y < h / 2; ++y)
    std::swap_ranges(pixels.begin() + y * row, pixels.begin() + (y + 1) * row,
                     pixels.begin() + (h - 1 - y) * row);
  return pixels;
}

// Copies channel `from` of an RGBA buffer into channel `to` of the image.
void copyChannel(const std::vector<float>& rgba, int from, FloatImage& image, int to) {
  const std::size_t count = static_cast<std::size_t>(image.width) * image.height;
  const std::size_t stride = image.channels.size();
  for (std::size_t i = 0; i < count; ++i) image.pixels[i * stride + to] = rgba[i * 4 + from];
}

bool castsPointShadow(const Light& light) {
  return light.type == LightType::Point && light.shadow.enabled;
}

}  // namespace

float effectiveShadowFar(const Light& light, const Bounds& sceneBounds) {
  if (light.shadow.far > 0.0f) return light.shadow.far;
  if (light.range > 0.0f) return light.range;
  // Far enough for every point of the scene, with a margin so the farthest corner is inside.
  float farthest = 0.0f;
  if (!sceneBounds.empty()) {
    for (int corner = 0; corner < 8; ++corner) {
      const glm::vec3 p{(corner & 1) ? sceneBounds.max.x : sceneBounds.min.x,
                        (corner & 2) ? sceneBounds.max.y : sceneBounds.min.y,
                        (corner & 4) ? sceneBounds.max.z : sceneBounds.min.z};
      farthest = std::max(farthest, glm::length(p - light.position));
    }
  }
  return std::max(farthest * 1.01f, light.shadow.near * 2.0f);
}

Renderer::Renderer(const ContextOptions& options)
    : context_(std::make_unique<EglContext>(options)) {
  if (options.debug) gl::enableDebugOutput();
  // Reversed depth with a [0,1] clip range keeps float depth precise from near to far.
  glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
  glEnable(GL_TEXTURE_CUBE_MAP_SEAMLESS);
  glEnable(GL_FRAMEBUFFER_SRGB);  // no effect on float targets; sRGB textures decode anyway
  shadowPass_ = std::make_unique<ShadowPass>();
  gl::checkErrors("context setup");
}

Renderer::~Renderer() = default;

LightingPass& Renderer::lightingPass(const RenderSettings& settings) {
  const auto key = std::make_pair(settings.shading, settings.aovs);
  for (auto& [k, pass] : lightingPasses_)
    if (k == key) return *pass;
  lightingPasses_.emplace_back(key,
                               std::make_unique<LightingPass>(settings.shading, settings.aovs));
  return *lightingPasses_.back().second;
}

Frame Renderer::render(const Scene& scene, const std::vector<Light>& lights,
                       const glm::vec3& ambient, const ViewCamera& camera,
                       const RenderSettings& settings, StageTimes& times) {
  Frame frame;
  const int shadowed =
      static_cast<int>(std::count_if(lights.begin(), lights.end(), castsPointShadow));
  if (shadowed > kMaxPointShadows)
    throw InputError(std::to_string(shadowed) + " point lights cast shadows, but one frame can " +
                     "sample at most " + std::to_string(kMaxPointShadows) +
                     ": set \"shadow\": false on some of them");
  for (const Light& light : lights) {
    if (light.type != LightType::Point && light.shadow.enabled)
      frame.warnings.push_back("light \"" + light.name + "\": " + toString(light.type) +
                               " lights are not shadowed yet; it lights the scene unshadowed");
  }

  ScopedStage shaders(times, "shaders");
  LightingPass& lighting = lightingPass(settings);  // compiled once per variant and renderer
  shaders.stop();

  ScopedStage upload(times, "upload");
  GpuScene gpuScene(scene);
  FrameTargets targets(camera.width, camera.height, settings.aovs);
  glFinish();
  upload.stop();

  ScopedStage shadowStage(times, "shadow maps");
  std::vector<PointShadowMap> maps;
  maps.reserve(lights.size());
  std::vector<ShadedLight> shaded;
  for (const Light& light : lights) {
    ShadedLight s{&light, nullptr};
    if (castsPointShadow(light)) {
      maps.push_back(shadowPass_->renderPointLight(gpuScene, light, light.shadow.near,
                                                   effectiveShadowFar(light, scene.bounds),
                                                   light.shadow.resolution));
      s.shadow = &maps.back();
    }
    shaded.push_back(s);
  }
  glFinish();
  shadowStage.stop();

  // One pass gives the beauty and the visibility of 20 lights; more lights take more passes.
  const int lightCount = static_cast<int>(lights.size());
  const int passes =
      settings.aovs ? std::max(1, (lightCount + kVisibilityPerPass - 1) / kVisibilityPerPass) : 1;
  std::vector<std::string> channels = {"R", "G", "B", "A"};
  if (settings.aovs) {
    for (const char* name : {"P.X", "P.Y", "P.Z", "N.X", "N.Y", "N.Z", "Z"})
      channels.push_back(name);
    for (const Light& light : lights) channels.push_back("visibility." + light.name);
  }
  FloatImage beauty{camera.width, camera.height, {"R", "G", "B", "A"}, {}};
  beauty.pixels.resize(static_cast<std::size_t>(camera.width) * camera.height * 4);
  FloatImage aovs{camera.width, camera.height, channels, {}};
  if (settings.aovs)
    aovs.pixels.resize(static_cast<std::size_t>(camera.width) * camera.height * channels.size());

  for (int pass = 0; pass < passes; ++pass) {
    const int base = pass * kVisibilityPerPass;
    {
      ScopedStage stage(times, "lighting");
      lighting.render(gpuScene, camera, shaded, ambient, targets, base);
      glFinish();
    }
    ScopedStage readback(times, "readback");
    if (pass == 0) {
      beauty.pixels = readAttachment(targets, 0);
      if (settings.aovs) {
        for (int c = 0; c < 4; ++c) copyChannel(beauty.pixels, c, aovs, c);
        const std::vector<float> position = readAttachment(targets, 1);
        const std::vector<float> normal = readAttachment(targets, 2);
        for (int c = 0; c < 3; ++c) copyChannel(position, c, aovs, 4 + c);
        for (int c = 0; c < 3; ++c) copyChannel(normal, c, aovs, 7 + c);
        copyChannel(position, 3, aovs, 10);
      }
    }
    if (!settings.aovs) continue;
    for (int target = 0; target < kVisibilityPerPass / 4; ++target) {
      const int first = base + target * 4;
      if (first >= lightCount) break;
      const std::vector<float> visibility = readAttachment(targets, 3 + target);
      for (int c = 0; c < 4 && first + c < lightCount; ++c)
        copyChannel(visibility, c, aovs, 11 + first + c);
    }
  }
  gl::checkErrors("reading back the frame");
  frame.beauty = std::move(beauty);
  if (settings.aovs) frame.aovs = std::move(aovs);
  return frame;
}

std::vector<CubeDistances> Renderer::renderShadowDistances(const Scene& scene,
                                                           const std::vector<Light>& lights) {
  GpuScene gpuScene(scene);
  std::vector<CubeDistances> out;
  for (const Light& light : lights) {
    if (!castsPointShadow(light)) continue;
    const PointShadowMap map = shadowPass_->renderPointLight(
        gpuScene, light, light.shadow.near, effectiveShadowFar(light, scene.bounds),
        light.shadow.resolution);
    out.push_back(ShadowPass::readDistances(map));
  }
  return out;
}

}  // namespace omnishadow
