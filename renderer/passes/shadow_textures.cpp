#include "renderer/passes/shadow_textures.h"

#include <algorithm>
#include <limits>

#include "renderer/gl/gl_debug.h"
#include "renderer/view/cube_faces.h"

namespace omnishadow {

GLenum depthInternalFormat(DepthFormat format) {
  return format == DepthFormat::Fixed24 ? GL_DEPTH_COMPONENT24 : GL_DEPTH_COMPONENT32F;
}

ShadowGroupTextures ShadowTexturePool::take(const ShadowGroupPlan& plan) {
  for (auto it = free_.begin(); it != free_.end(); ++it) {
    if (!(it->key == plan.key) || it->layers != plan.layers) continue;
    ShadowGroupTextures textures = std::move(*it);
    free_.erase(it);
    return textures;
  }
  ShadowGroupTextures textures;
  textures.key = plan.key;
  textures.layers = plan.layers;
  const GLenum target =
      plan.key.layout == ShadowLayout::Cube ? GL_TEXTURE_CUBE_MAP_ARRAY : GL_TEXTURE_2D_ARRAY;
  const int n = plan.key.resolution;
  textures.depth = gl::createTexture(target);
  glTextureStorage3D(textures.depth.get(), 1, depthInternalFormat(plan.key.format), n, n,
                     plan.layers);
  if (plan.key.moments) {
    textures.moments = gl::createTexture(target);
    glTextureStorage3D(textures.moments.get(), 1, GL_RG32F, n, n, plan.layers);
  }
  gl::checkErrors("allocating shadow maps");
  static_assert(kClearedDepth == 0.0f, "zero bytes must be the cleared depth");
  const bool cleared = madeZeroed_ && !plan.key.moments;  // moments clear to 1, not 0
  textures.written.assign(static_cast<std::size_t>(plan.layers),
                          cleared ? TexelRect{} : TexelRect::whole(n));
  return textures;
}

void clearShadowTextures(ShadowGroupTextures& textures) {
  if (std::all_of(textures.written.begin(), textures.written.end(),
                  [](const TexelRect& texels) { return texels.empty(); }))
    return;
  // Through a layered framebuffer, so that llvmpipe's rasterizer threads clear while the
  // calling thread goes on. Clears obey the write masks and the scissor, which are at their
  // defaults between passes.
  const gl::Framebuffer framebuffer = gl::createFramebuffer();
  const GLuint fb = framebuffer.get();
  glNamedFramebufferTexture(fb, GL_DEPTH_ATTACHMENT, textures.depth.get(), 0);
  glNamedFramebufferTexture(fb, GL_COLOR_ATTACHMENT0, textures.moments.get(), 0);
  glNamedFramebufferDrawBuffer(fb, textures.moments ? GL_COLOR_ATTACHMENT0 : GL_NONE);
  glNamedFramebufferReadBuffer(fb, GL_NONE);
  glClearNamedFramebufferfv(fb, GL_DEPTH, 0, &kClearedDepth);
  if (textures.moments) glClearNamedFramebufferfv(fb, GL_COLOR, 0, kClearedMoments);
  gl::checkErrors("clearing shadow maps");
  textures.written.assign(textures.written.size(), TexelRect{});
}

void ShadowTexturePool::give(ShadowGroupTextures&& textures) {
  // Enough for the groups of one frame; older textures are deleted.
  constexpr std::size_t kPoolSize = 8;
  if (!textures.depth) return;
  free_.push_back(std::move(textures));
  if (free_.size() > kPoolSize) free_.erase(free_.begin());
}

std::vector<float> readPlanarDistances(const ShadowGroupTextures& group,
                                       const LightShadowPlan& light, int layer, bool orthographic) {
  const int n = group.key.resolution;
  const std::size_t texels = static_cast<std::size_t>(n) * n;
  std::vector<float> depth(texels);
  glGetTextureSubImage(group.depth.get(), 0, 0, 0, light.firstLayer + layer, n, n, 1,
                       GL_DEPTH_COMPONENT, GL_FLOAT, static_cast<GLsizei>(texels * sizeof(float)),
                       depth.data());
  gl::checkErrors("reading back a shadow map");
  const float near = light.near, far = light.far;
  for (float& d : depth) {
    if (d <= 0.0f)
      d = std::numeric_limits<float>::infinity();
    else  // the inverses of reversedOrthographicBox and reversedPerspective
      d = orthographic ? (1.0f - d) * (far - near) : near * far / (d * (far - near) + near);
  }
  return depth;
}

CubeDistances readCubeDistances(const ShadowGroupTextures& group, const LightShadowPlan& light) {
  CubeDistances out;
  const int n = group.key.resolution;
  out.resolution = n;
  const std::size_t texels = static_cast<std::size_t>(n) * n;
  for (int face = 0; face < kCubeFaceCount; ++face) {
    std::vector<float> depth(texels);
    glGetTextureSubImage(group.depth.get(), 0, 0, 0, light.firstLayer + face, n, n, 1,
                         GL_DEPTH_COMPONENT, GL_FLOAT, static_cast<GLsizei>(texels * sizeof(float)),
                         depth.data());
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
        const float axis = cubeDepthToAxisDistance(depth[i], light.near, light.far);
        distances[i] = axis * glm::length(direction);
      }
    }
  }
  gl::checkErrors("reading back a shadow map");
  return out;
}

}  // namespace omnishadow
