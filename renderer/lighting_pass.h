#pragma once

#include <vector>

#include "renderer/camera.h"
#include "renderer/gl_resources.h"
#include "renderer/gpu_scene.h"
#include "renderer/light.h"
#include "renderer/shader_program.h"
#include "renderer/shadow_pass.h"

namespace omnishadow {

enum class Shading { Pbr, Phong };

// How many lights one lighting pass reports visibility for (5 RGBA32F targets).
inline constexpr int kVisibilityPerPass = 20;
// Shadowed point lights one frame can sample (texture units 8..23).
inline constexpr int kMaxPointShadows = 16;

// A light as the lighting pass sees it: its description plus the shadow map it samples.
struct ShadedLight {
  const Light* light = nullptr;
  const PointShadowMap* shadow = nullptr;  // null = unshadowed
};

// Render targets of one frame. Attachment 0: linear premultiplied RGBA; with AOVs also
// 1: world position + camera distance, 2: camera-facing normal, 3..7: visibility of 20 lights.
class FrameTargets {
 public:
  FrameTargets(int width, int height, bool aovs);
  GLuint framebuffer() const { return framebuffer_.get(); }
  GLuint color(int attachment) const { return colors_[attachment].get(); }
  int attachmentCount() const { return static_cast<int>(colors_.size()); }
  int width() const { return width_; }
  int height() const { return height_; }

 private:
  int width_, height_;
  gl::Framebuffer framebuffer_;
  std::vector<gl::Texture> colors_;
  gl::Texture depth_;
};

class LightingPass {
 public:
  LightingPass(Shading shading, bool aovs);

  // Draws opaque and masked surfaces, then blended ones (unsorted, depth writes off, AOV
  // targets untouched). `visibilityBase` is the first light whose shadow term goes to the
  // visibility targets.
  void render(const GpuScene& scene, const ViewCamera& camera,
              const std::vector<ShadedLight>& lights, const glm::vec3& ambient,
              FrameTargets& targets, int visibilityBase);

 private:
  void uploadLights(const std::vector<ShadedLight>& lights);
  void drawScene(const GpuScene& scene, bool blended);

  bool aovs_;
  ShaderProgram program_;
  gl::Sampler hardCompare_, linearCompare_;
  gl::Buffer lightBuffer_;
  GLsizeiptr lightBufferSize_ = 0;
};

}  // namespace omnishadow
