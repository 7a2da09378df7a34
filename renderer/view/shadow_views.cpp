#include "renderer/view/shadow_views.h"

#include <algorithm>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>

namespace omnishadow {
namespace {

// A stable "up" for looking along `direction`.
glm::vec3 upFor(const glm::vec3& direction) {
  return std::abs(direction.y) < 0.99f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
}

std::array<glm::vec3, 8> corners(const Bounds& b) {
  std::array<glm::vec3, 8> out;
  for (int i = 0; i < 8; ++i)
    out[i] = {(i & 1) ? b.max.x : b.min.x, (i & 2) ? b.max.y : b.min.y,
              (i & 4) ? b.max.z : b.min.z};
  return out;
}

// View-space corners of the camera's view between view depths d0 and d1.
std::array<glm::vec3, 8> sliceCorners(const ViewCamera& camera, float d0, float d1) {
  std::array<glm::vec3, 8> out;
  const float sx = 1.0f / camera.projection[0][0];
  const float sy = 1.0f / camera.projection[1][1];
  for (int i = 0; i < 8; ++i) {
    const float d = (i & 4) ? d1 : d0;
    const float x = (i & 1) ? sx : -sx;
    const float y = (i & 2) ? sy : -sy;
    out[i] = camera.orthographic ? glm::vec3(x, y, -d) : glm::vec3(x * d, y * d, -d);
  }
  return out;
}

}  // namespace

SpotShadowFrame spotShadowFrame(const Light& light, float near, float far, int resolution) {
  SpotShadowFrame frame;
  const glm::vec3 direction = glm::normalize(light.direction);
  const glm::mat4 view = glm::lookAt(light.position, light.position + direction, upFor(direction));
  // Two texels of margin so filter taps at the cone's edge stay on the map.
  float half = light.outerConeAngle * (1.0f + 4.0f / static_cast<float>(resolution));
  frame.coneClipped = half > kMaxSpotShadowHalfAngle;
  half = std::min(half, kMaxSpotShadowHalfAngle);
  frame.tanHalfFov = std::tan(half);
  frame.viewProjection = reversedPerspective(2.0f * half, 1.0f, near, far) * view;
  return frame;
}

ViewCamera planarLightCamera(const Light& light, const glm::mat4& viewProjection, float near,
                             float far, int size) {
  ViewCamera camera;
  camera.width = camera.height = size;
  camera.glRowOrder = true;
  camera.orthographic = light.type == LightType::Directional;
  const glm::vec3 direction = glm::normalize(light.direction);
  if (camera.orthographic) {
    // The centre of the map's near plane (reversed depth: NDC z = 1).
    const glm::vec4 eye = glm::inverse(viewProjection) * glm::vec4(0.0f, 0.0f, 1.0f, 1.0f);
    camera.eye = glm::vec3(eye) / eye.w;
    camera.znear = 1e-3f * (far - near);
  } else {
    camera.eye = light.position;
    camera.znear = near;
  }
  camera.zfar = camera.orthographic ? far - near : far;
  camera.view = glm::lookAt(camera.eye, camera.eye + direction, upFor(direction));
  camera.projection = viewProjection * glm::inverse(camera.view);
  camera.description = "light view of \"" + light.name + "\"";
  return camera;
}

std::vector<float> cascadeSplits(float near, float far, int count, float lambda) {
  std::vector<float> splits;
  for (int i = 1; i <= count; ++i) {
    const float t = static_cast<float>(i) / static_cast<float>(count);
    const float logarithmic = near * std::pow(far / near, t);
    const float linear = near + (far - near) * t;
    splits.push_back(lambda * logarithmic + (1.0f - lambda) * linear);
  }
  splits.back() = far;
  return splits;
}

glm::mat4 reversedOrthographicBox(float left, float right, float bottom, float top, float near,
                                  float far) {
  glm::mat4 p(1.0f);
  p[0][0] = 2.0f / (right - left);
  p[1][1] = 2.0f / (top - bottom);
  p[3][0] = -(right + left) / (right - left);
  p[3][1] = -(top + bottom) / (top - bottom);
  // depth = (far + z) / (far - near) for view-space z: -near -> 1, -far -> 0.
  p[2][2] = 1.0f / (far - near);
  p[3][2] = far / (far - near);
  return p;
}

DirectionalShadowFrame directionalShadowFrame(const Light& light, const ViewCamera& camera,
                                              const Bounds& sceneBounds) {
  DirectionalShadowFrame frame;
  const glm::vec3 direction = glm::normalize(light.direction);
  const glm::vec3 center = sceneBounds.empty() ? glm::vec3(0.0f) : sceneBounds.center();
  const glm::mat4 lightView = glm::lookAt(center - direction, center, upFor(direction));

  // The scene in light space: its depth range is what every cascade covers.
  glm::vec3 sceneMin(1e30f), sceneMax(-1e30f);
  float farthestViewDepth = 0.0f;
  for (const glm::vec3& corner : corners(sceneBounds)) {
    const glm::vec3 p = glm::vec3(lightView * glm::vec4(corner, 1.0f));
    sceneMin = glm::min(sceneMin, p);
    sceneMax = glm::max(sceneMax, p);
    farthestViewDepth = std::max(farthestViewDepth, -(camera.view * glm::vec4(corner, 1.0f)).z);
  }
  if (sceneBounds.empty()) sceneMin = sceneMax = glm::vec3(0.0f);
  // A margin keeps surfaces exactly on the bounds off the clip planes.
  const float margin = 1e-3f * std::max(glm::length(sceneMax - sceneMin), 1e-30f);
  const float nearZ = -sceneMax.z - margin;  // view-space z is negative in front
  const float farZ = -sceneMin.z + margin;
  frame.nearToLight = nearZ;
  frame.farFromLight = farZ;

  // The floor only guards a zero camera near; relative to the scene, so any scale gets the same
  // splits.
  const float cameraNear = std::max(camera.znear, 1e-6f * std::max(farthestViewDepth, 1e-30f));
  float end = light.shadow.distance > 0.0f ? light.shadow.distance : farthestViewDepth * 1.001f;
  end = std::max(end, cameraNear * 2.0f);
  const int count = std::clamp(light.shadow.cascades, 1, 4);
  const std::vector<float> splits =
      cascadeSplits(cameraNear, end, count, light.shadow.cascadeSplit);
  const glm::mat4 cameraToLight = lightView * glm::inverse(camera.view);
  float begin = cameraNear;
  for (const float split : splits) {
    glm::vec2 lo(1e30f), hi(-1e30f);
    for (const glm::vec3& corner : sliceCorners(camera, begin, split)) {
      const glm::vec3 p = glm::vec3(cameraToLight * glm::vec4(corner, 1.0f));
      lo = glm::min(lo, glm::vec2(p));
      hi = glm::max(hi, glm::vec2(p));
    }
    // Nothing outside the scene casts or receives: clip the slice to it.
    lo = glm::max(lo, glm::vec2(sceneMin) - margin);
    hi = glm::min(hi, glm::vec2(sceneMax) + margin);
    hi = glm::max(hi, lo + glm::vec2(margin));
    Cascade cascade;
    cascade.viewProjection =
        reversedOrthographicBox(lo.x, hi.x, lo.y, hi.y, nearZ, farZ) * lightView;
    cascade.viewDepthEnd = split;
    cascade.texelSize =
        std::max(hi.x - lo.x, hi.y - lo.y) / static_cast<float>(light.shadow.resolution);
    frame.cascades.push_back(cascade);
    begin = split;
  }
  return frame;
}

}  // namespace omnishadow
