#include "renderer/shadow_atlas.h"

#include <GL/glcorearb.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "renderer/cube_faces.h"
#include "renderer/errors.h"
#include "renderer/gl_debug.h"
#include "renderer/shadow_views.h"

namespace omnishadow {

GLenum depthInternalFormat(DepthFormat format) {
  return format == DepthFormat::Fixed24 ? GL_DEPTH_COMPONENT24 : GL_DEPTH_COMPONENT32F;
}

namespace {

double bytesPerTexel(const ShadowGroupKey& key) {
  return 4.0 + (key.moments ? 8.0 : 0.0);  // 24-bit depth is stored in 32 bits
}

const char* layoutName(ShadowLayout layout) {
  return layout == ShadowLayout::Cube ? "point" : "spot/directional";
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

ShadowAtlasPlan planShadowAtlas(const std::vector<Light>& lights, const ViewCamera& camera,
                                const Bounds& sceneBounds, const ShadowLimits& limits) {
  ShadowAtlasPlan plan;
  // A group is found by key and by room: past the layer limit a key opens another group.
  auto place = [&](const ShadowGroupKey& key, int layers) {
    for (std::size_t g = 0; g < plan.groups.size(); ++g) {
      ShadowGroupPlan& group = plan.groups[g];
      if (group.key == key && group.layers + layers <= limits.maxArrayLayers) {
        group.layers += layers;
        return std::make_pair(static_cast<int>(g), group.layers - layers);
      }
    }
    const auto sameLayout =
        std::count_if(plan.groups.begin(), plan.groups.end(),
                      [&](const auto& g) { return g.key.layout == key.layout; });
    if (sameLayout >= kMaxShadowGroups)
      throw InputError(std::string("the ") + layoutName(key.layout) +
                       " lights' shadow maps need more than " + std::to_string(kMaxShadowGroups) +
                       " textures (one per resolution, depth format and vsm or not, " +
                       std::to_string(limits.maxArrayLayers) +
                       " layers each): use fewer distinct shadow resolutions");
    plan.groups.push_back({key, layers});
    return std::make_pair(static_cast<int>(plan.groups.size() - 1), 0);
  };

  for (std::size_t i = 0; i < lights.size(); ++i) {
    const Light& light = lights[i];
    if (!light.shadow.enabled) continue;
    LightShadowPlan shadow;
    shadow.light = static_cast<int>(i);
    ShadowGroupKey key;
    key.resolution = light.shadow.resolution;
    key.format = light.shadow.depthFormat;
    key.moments = light.shadow.filter == ShadowFilter::Vsm;
    switch (light.type) {
      case LightType::Point: {
        key.layout = ShadowLayout::Cube;
        shadow.layerCount = kCubeFaceCount;
        shadow.near = light.shadow.near;
        shadow.far = effectiveShadowFar(light, sceneBounds);
        shadow.position = light.position;
        const glm::mat4 projection = cubeFaceProjection(shadow.near, shadow.far);
        for (int face = 0; face < kCubeFaceCount; ++face)
          shadow.viewProjection[face] =
              projection * cubeFaceView(static_cast<CubeFace>(face), light.position);
        break;
      }
      case LightType::Spot: {
        key.layout = ShadowLayout::Planar;
        shadow.layerCount = 1;
        shadow.near = light.shadow.near;
        shadow.far = effectiveShadowFar(light, sceneBounds);
        shadow.position = light.position;
        const SpotShadowFrame frame =
            spotShadowFrame(light, shadow.near, shadow.far, light.shadow.resolution);
        shadow.viewProjection[0] = frame.viewProjection;
        shadow.tanHalfFov = frame.tanHalfFov;
        if (frame.coneClipped)
          plan.warnings.push_back("light \"" + light.name +
                                  "\": the spot cone is wider than the 170 degrees one shadow map "
                                  "covers; the part outside is lit unshadowed");
        break;
      }
      case LightType::Directional: {
        key.layout = ShadowLayout::Planar;
        const DirectionalShadowFrame frame = directionalShadowFrame(light, camera, sceneBounds);
        shadow.layerCount = static_cast<int>(frame.cascades.size());
        shadow.near = frame.nearToLight;
        shadow.far = frame.farFromLight;
        for (std::size_t c = 0; c < frame.cascades.size(); ++c) {
          shadow.viewProjection[c] = frame.cascades[c].viewProjection;
          shadow.cascadeEnd[c] = frame.cascades[c].viewDepthEnd;
          shadow.cascadeTexel[c] = frame.cascades[c].texelSize;
        }
        break;
      }
    }
    const auto [group, first] = place(key, shadow.layerCount);
    shadow.group = group;
    shadow.firstLayer = first;
    plan.lights.push_back(shadow);
  }
  for (const ShadowGroupPlan& group : plan.groups)
    plan.bytes += bytesPerTexel(group.key) * group.layers *
                  static_cast<double>(group.key.resolution) * group.key.resolution;
  return plan;
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
  return textures;
}

void ShadowTexturePool::give(ShadowGroupTextures&& textures) {
  // Enough for the groups of one frame; older textures are deleted.
  constexpr std::size_t kPoolSize = 8;
  if (!textures.depth) return;
  free_.push_back(std::move(textures));
  if (free_.size() > kPoolSize) free_.erase(free_.begin());
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
