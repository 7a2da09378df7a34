#include "renderer/shadow_pass.h"

#include <cmath>
#include <limits>

#include "renderer/gl_debug.h"

namespace omnishadow {
namespace {

// True when a sphere (view space of a cube face) may touch the face's 90 degree frustum
// between near and far.
bool sphereTouchesFace(const glm::vec3& c, float radius, float near, float far) {
  const float depth = -c.z;
  const float k = 0.70710678f;  // side planes x = +-depth, y = +-depth, normals normalized
  if (depth + radius < near || depth - radius > far) return false;
  if ((c.x - depth) * k > radius || (-c.x - depth) * k > radius) return false;
  if ((c.y - depth) * k > radius || (-c.y - depth) * k > radius) return false;
  return true;
}

}  // namespace

ShadowPass::ShadowPass()
    : opaque_("shadow_depth.vert", "shadow_depth.frag"),
      masked_("shadow_depth.vert", "shadow_depth.frag", {"ALPHA_MASK"}),
      framebuffer_(gl::createFramebuffer()) {
  glNamedFramebufferDrawBuffer(framebuffer_.get(), GL_NONE);
  glNamedFramebufferReadBuffer(framebuffer_.get(), GL_NONE);
}

PointShadowMap ShadowPass::renderPointLight(const GpuScene& scene, const Light& light, float near,
                                            float far, int resolution) {
  PointShadowMap map;
  map.resolution = resolution;
  map.near = near;
  map.far = far;
  map.position = light.position;
  map.cube = takeCube(resolution);
  glObjectLabel(GL_TEXTURE, map.cube.get(), -1, ("shadow cube " + light.name).c_str());

  const glm::mat4 projection = cubeFaceProjection(near, far);
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.get());
  glViewport(0, 0, resolution, resolution);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_GREATER);  // reversed depth: nearer is larger
  glDepthMask(GL_TRUE);
  glDisable(GL_CULL_FACE);
  glDisable(GL_BLEND);
  glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
  glBindVertexArray(scene.vertexArray());

  for (int face = 0; face < kCubeFaceCount; ++face) {
    glNamedFramebufferTextureLayer(framebuffer_.get(), GL_DEPTH_ATTACHMENT, map.cube.get(), 0,
                                   face);
    const float clearDepth = 0.0f;
    glClearNamedFramebufferfv(framebuffer_.get(), GL_DEPTH, 0, &clearDepth);
    const glm::mat4 view = cubeFaceView(static_cast<CubeFace>(face), light.position);
    const glm::mat4 viewProjection = projection * view;
    opaque_.set("uViewProjection", viewProjection);
    masked_.set("uViewProjection", viewProjection);

    for (const GpuDraw& draw : scene.draws()) {
      const glm::vec3 center = glm::vec3(view * glm::vec4(draw.boundsCenter, 1.0f));
      if (!sphereTouchesFace(center, draw.boundsRadius, near, far)) continue;
      const GpuMaterial& material = scene.materials()[draw.material];
      // Blended surfaces cast shadows where they are at least half opaque.
      const bool cutout = material.desc.alphaMode != AlphaMode::Opaque;
      const ShaderProgram& program = cutout ? masked_ : opaque_;
      program.use();
      program.set("uModel", draw.world);
      if (cutout) {
        program.set("uBaseColorFactor", material.desc.baseColorFactor);
        program.set("uHasBaseColorTexture", material.baseColor != 0 ? 1 : 0);
        program.set("uBaseColorTexCoord", material.desc.baseColorTexture.texCoord);
        program.set("uAlphaCutoff",
                    material.desc.alphaMode == AlphaMode::Mask ? material.desc.alphaCutoff : 0.5f);
        glBindTextureUnit(0, material.baseColor);
        glBindSampler(0, material.baseColorSampler);
      }
      const GpuMeshRange& range = scene.meshes()[draw.mesh];
      glDrawElementsBaseVertex(
          GL_TRIANGLES, range.indexCount, GL_UNSIGNED_INT,
          reinterpret_cast<const void*>(static_cast<std::uintptr_t>(range.firstIndex) * 4),
          range.baseVertex);
      ++map.drawsRendered;
    }
  }
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  gl::checkErrors("the shadow pass of light \"" + light.name + "\"");
  return map;
}

gl::Texture ShadowPass::takeCube(int resolution) {
  for (auto it = pool_.begin(); it != pool_.end(); ++it) {
    if (it->first != resolution) continue;
    gl::Texture cube = std::move(it->second);
    pool_.erase(it);
    return cube;
  }
  gl::Texture cube = gl::createTexture(GL_TEXTURE_CUBE_MAP);
  glTextureStorage2D(cube.get(), 1, GL_DEPTH_COMPONENT32F, resolution, resolution);
  return cube;
}

void ShadowPass::recycle(PointShadowMap&& map) {
  // Enough for the shadowed lights of one frame; older textures are deleted.
  constexpr std::size_t kPoolSize = 16;
  if (!map.cube) return;
  pool_.emplace_back(map.resolution, std::move(map.cube));
  if (pool_.size() > kPoolSize) pool_.erase(pool_.begin());
}

CubeDistances ShadowPass::readDistances(const PointShadowMap& map) {
  CubeDistances out;
  out.resolution = map.resolution;
  const int n = map.resolution;
  const std::size_t texels = static_cast<std::size_t>(n) * n;
  for (int face = 0; face < kCubeFaceCount; ++face) {
    std::vector<float> depth(texels);
    glGetTextureSubImage(map.cube.get(), 0, 0, 0, face, n, n, 1, GL_DEPTH_COMPONENT, GL_FLOAT,
                         static_cast<GLsizei>(texels * sizeof(float)), depth.data());
    std::vector<float>& distances = out.faces[face];
    distances.resize(texels);
    const glm::mat4 toWorldDirection = glm::inverse(cubeFaceView(static_cast<CubeFace>(face), {}));
    for (int row = 0; row < n; ++row) {
      for (int column = 0; column < n; ++column) {
        const std::size_t i = static_cast<std::size_t>(row) * n + column;
        if (depth[i] <= 0.0f) {
          distances[i] = std::numeric_limits<float>::infinity();
          continue;
        }
        // Texel center on the face plane at axis distance 1, back to a world direction.
        const float x = (2.0f * (static_cast<float>(column) + 0.5f) / static_cast<float>(n)) - 1.0f;
        const float y = (2.0f * (static_cast<float>(row) + 0.5f) / static_cast<float>(n)) - 1.0f;
        const glm::vec3 direction = glm::vec3(toWorldDirection * glm::vec4(x, y, -1.0f, 0.0f));
        const float axis = cubeDepthToAxisDistance(depth[i], map.near, map.far);
        distances[i] = axis * glm::length(direction);
      }
    }
  }
  gl::checkErrors("reading back a shadow map");
  return out;
}

}  // namespace omnishadow
