#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "renderer/gl_resources.h"
#include "renderer/gpu_scene.h"
#include "renderer/light.h"
#include "renderer/shader_program.h"
#include "renderer/shadow_atlas.h"

namespace omnishadow {

// How a point light's six cube faces are rendered (--shadow-pass). All of them write the same
// texels; they differ in speed, which depends on the driver (docs/performance.md).
enum class ShadowPassStrategy {
  Auto,       // the fastest measured on this driver (resolveShadowPassStrategy)
  Six,        // one pass per face, objects culled per face on the CPU
  Geometry,   // one pass, a geometry shader copies each triangle to six layers (the classic)
  Instanced,  // one pass, instances pick the face and write gl_Layer from the vertex shader;
              // objects are culled per face too (runs of faces per object)
};

const char* toString(ShadowPassStrategy strategy);
// "auto", "six", "geometry" or "instanced"; anything else is Auto (the CLI checks the spelling).
ShadowPassStrategy parseShadowPassStrategy(const std::string& name);

// What `auto` means on a GL renderer (its GL_RENDERER string).
ShadowPassStrategy resolveShadowPassStrategy(ShadowPassStrategy requested,
                                             const std::string& glRenderer);

// Renders depth (and vsm moments) of one light's layers. Spot lights and directional cascades
// are always drawn one layer per pass; the strategy applies to point lights. Opaque casters
// are drawn with glMultiDrawElementsIndirect; alpha-tested ones one by one with their texture.
class ShadowPass {
 public:
  ShadowPass();
  ~ShadowPass();

  void render(const GpuScene& scene, const Light& light, const LightShadowPlan& plan,
              const ShadowGroupTextures& target, ShadowPassStrategy strategy);

  // Object draws issued since construction (a draw covering k faces counts k), for --stats.
  long long drawCount() const { return drawCount_; }

 private:
  struct Variant;
  const ShaderProgram& program(ShadowPassStrategy strategy, bool masked, bool moments,
                               bool worldPositions);

  std::map<int, std::unique_ptr<ShaderProgram>> programs_;
  gl::Framebuffer framebuffer_;
  gl::StreamBuffer commands_, drawObjects_;
  long long drawCount_ = 0;
};

}  // namespace omnishadow
