#pragma once

#include <glm/glm.hpp>
#include <vector>

#include "renderer/cube_distances.h"
#include "renderer/cube_faces.h"
#include "renderer/gl_resources.h"
#include "renderer/gpu_scene.h"
#include "renderer/light.h"
#include "renderer/shader_program.h"

namespace omnishadow {

// A point light's depth cube map (GL_DEPTH_COMPONENT32F). Each face holds the reversed-Z depth
// of cubeFaceProjection(near, far); distance is rebuilt when sampling (shaders/point_shadow.glsl).
struct PointShadowMap {
  gl::Texture cube;
  int resolution = 0;
  float near = 0.0f;
  float far = 0.0f;
  glm::vec3 position{0.0f};
  int drawsRendered = 0;  // instance draws over all faces after culling, for --stats
};

class ShadowPass {
 public:
  ShadowPass();

  // Renders one face at a time; instances whose bounding sphere misses a face's frustum (or
  // lies beyond `far`) are skipped for that face. Casters are drawn double-sided.
  PointShadowMap renderPointLight(const GpuScene& scene, const Light& light, float near, float far,
                                  int resolution);

  // Reads the map back as distances along each texel center's ray.
  static CubeDistances readDistances(const PointShadowMap& map);

  // Gives the map's texture back for reuse by later renders (batch mode renders many scenes
  // with the same resolutions); the pool keeps a few and deletes the rest.
  void recycle(PointShadowMap&& map);

 private:
  gl::Texture takeCube(int resolution);

  std::vector<std::pair<int, gl::Texture>> pool_;  // (resolution, cube map)
  ShaderProgram opaque_;
  ShaderProgram masked_;
  gl::Framebuffer framebuffer_;
};

}  // namespace omnishadow
