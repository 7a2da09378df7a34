#include "renderer/view/camera.h"

#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <sstream>

#include "renderer/core/errors.h"
#include "renderer/scene/camera_checks.h"

namespace omnishadow {
namespace {

// The largest side --width and --height accept.
constexpr int kMaxDerivedSide = 16384;

// Automatic framing looks at the scene from the front (+Z), somewhat above, like a person
// standing in front of a table: the habitual view of glTF's +Y up, +Z forward models.
constexpr glm::vec3 kAutoViewDirection{0.0f, 0.45f, 1.0f};
constexpr float kAutoFovDegrees = 45.0f;

std::optional<int> parseIndex(const std::string& text) {
  if (text.empty() || text.size() > 9) return std::nullopt;
  for (char c : text)
    if (c < '0' || c > '9') return std::nullopt;
  return std::stoi(text);
}

const Camera* findCamera(const Scene& scene, const std::string& select) {
  if (scene.cameras.empty() && select.empty()) return nullptr;
  if (select.empty()) return &scene.cameras.front();
  const auto index = parseIndex(select);
  for (const Camera& camera : scene.cameras) {
    if (index ? camera.index == *index : (camera.name == select || camera.nodeName == select))
      return &camera;
  }
  std::string known;
  for (const Camera& camera : scene.cameras) {
    known += known.empty() ? "" : ", ";
    known += std::to_string(camera.index) + " \"" + camera.name + "\"";
  }
  throw InputError("--camera " + select + ": " + scene.path + " has no such camera" +
                   (known.empty() ? " (it has none)" : " (cameras: " + known + ")"));
}

bool isFinite(const glm::mat4& m) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(m[c][r])) return false;
  return true;
}

// Which of --eye and --target placed the view, for messages; "the camera" when neither did.
std::string placedBy(const CameraRequest& request) {
  if (request.eye && request.target) return "--eye/--target";
  if (request.eye) return "--eye";
  if (request.target) return "--target";
  return "the camera";
}

// glm::lookAt(eye, target, up), checked. The checks run in double: the float length of a
// vector longer than about 1.8e19 is infinite, which made an --eye at 3e38 read as an --up
// parallel to the view. Ordinary views keep glm's float operations (their pictures do not
// change by a bit); the others (`direction` is target - eye, or the file camera's forward when
// the eye is so far out that a unit step is lost) get their axes in double.
glm::mat4 lookAtChecked(const glm::vec3& eye, const glm::vec3& target, const glm::dvec3& direction,
                        const glm::vec3& up, const CameraRequest& request) {
  if (glm::length(direction) < 1e-6)
    throw InputError(placedBy(request) + ": the eye and the target are the same point");
  const glm::dvec3 f = glm::normalize(direction);
  if (glm::length(glm::cross(f, glm::normalize(glm::dvec3(up)))) < 1e-4)
    throw InputError("--up: the up vector is parallel to the view direction");
  const float floatLength = glm::length(target - eye);
  glm::mat4 view;
  if (floatLength > 0.0f && std::isfinite(floatLength) && std::isfinite(glm::length(up))) {
    view = glm::lookAt(eye, target, up);
  } else {
    const glm::dvec3 s = glm::normalize(glm::cross(f, glm::normalize(glm::dvec3(up))));
    const glm::dvec3 u = glm::cross(s, f);
    glm::dmat4 m(1.0);
    for (int i = 0; i < 3; ++i) {
      m[i][0] = s[i];
      m[i][1] = u[i];
      m[i][2] = -f[i];
    }
    m[3][0] = -glm::dot(s, glm::dvec3(eye));
    m[3][1] = -glm::dot(u, glm::dvec3(eye));
    m[3][2] = glm::dot(f, glm::dvec3(eye));
    view = glm::mat4(m);
  }
  if (!isFinite(view))
    throw InputError(placedBy(request) +
                     ": the eye is too far from the origin: the view matrix overflows float");
  return view;
}

}  // namespace

glm::mat4 reversedPerspective(float yfov, float aspect, float znear, float zfar) {
  const float f = 1.0f / std::tan(yfov * 0.5f);
  glm::mat4 p(0.0f);
  p[0][0] = f / aspect;
  p[1][1] = f;
  p[2][3] = -1.0f;
  if (zfar > 0.0f) {
    p[2][2] = znear / (zfar - znear);
    p[3][2] = zfar * znear / (zfar - znear);
  } else {
    p[3][2] = znear;  // depth = znear / distance
  }
  return p;
}

glm::mat4 reversedOrthographic(float xmag, float ymag, float znear, float zfar) {
  glm::mat4 p(1.0f);
  p[0][0] = 1.0f / xmag;
  p[1][1] = 1.0f / ymag;
  p[2][2] = 1.0f / (zfar - znear);  // depth = (zfar - distance) / (zfar - znear)
  p[3][2] = zfar / (zfar - znear);
  return p;
}

glm::vec4 viewDepthRow(const glm::mat4& view) {
  return {-view[0][2], -view[1][2], -view[2][2], -view[3][2]};
}

namespace {

// Image size: the camera's aspect ratio fills in the side the user did not give.
void imageSize(const Scene& scene, const Camera* camera, const CameraRequest& request,
               ViewCamera& out) {
  const float aspectHint = camera ? camera->aspectRatio : 0.0f;
  out.width = request.width.value_or(kDefaultWidth);
  out.height = request.height.value_or(kDefaultHeight);
  // The side the aspect ratio fills in stays within what --width and --height accept (and
  // within int: lround of 720 x 1e30 is undefined).
  if (aspectHint > 0.0f && (!request.height || !request.width)) {
    const double derived =
        request.height ? double(*request.height) * aspectHint : double(out.width) / aspectHint;
    if (!(derived <= kMaxDerivedSide)) {
      throw InputError(scene.path + ": cameras[" + std::to_string(camera->index) +
                       "]: aspectRatio " + std::to_string(aspectHint) + " gives an image " +
                       std::to_string(std::llround(std::min(derived, 1e18))) + " pixels " +
                       (request.height ? "wide" : "high") + ", more than " +
                       std::to_string(kMaxDerivedSide) + "; give both --width and --height");
    }
  }
  if (aspectHint > 0.0f && !request.height)
    out.height =
        std::max(1, static_cast<int>(std::lround(static_cast<float>(out.width) / aspectHint)));
  else if (aspectHint > 0.0f && request.height && !request.width)
    out.width = std::max(
        1, static_cast<int>(std::lround(static_cast<float>(*request.height) * aspectHint)));
}

}  // namespace

ViewCamera resolveCamera(const Scene& scene, const CameraRequest& request) {
  ViewCamera out;
  const Camera* camera = findCamera(scene, request.select);
  // A broken glTF camera (orthographic ymag 0, zfar <= znear, ...) is refused here, when it is
  // rendered from, and not when the file is loaded: like other viewers, the loader accepts the
  // file (with a warning), so that its other cameras and automatic framing still work.
  if (camera) checkCameraUsable(scene, *camera);

  imageSize(scene, camera, request, out);
  const float aspect = static_cast<float>(out.width) / static_cast<float>(out.height);

  // Checked before automatic framing uses it: a field of view of 1e-30 degrees put the eye
  // 1e32 scene radii away, where the scene is lost to float precision.
  if (request.fovDegrees &&
      !(*request.fovDegrees >= kMinFovDegrees && *request.fovDegrees < kMaxFovDegrees)) {
    std::ostringstream given;
    given << *request.fovDegrees;
    throw InputError("--fov " + given.str() + ": expected degrees from 0.001 to below 180");
  }
  glm::vec3 eye, forward, up;
  float yfov;
  std::optional<glm::vec3> lookAtPoint;  // what an --eye alone keeps looking at
  // Any positive size frames the same picture at its own scale; only a point-like scene needs one.
  const float sceneRadius = scene.bounds.radius() > 0.0f ? scene.bounds.radius() : 1.0f;
  if (camera) {
    eye = glm::vec3(camera->world[3]);
    forward = -glm::normalize(glm::vec3(camera->world[2]));
    up = glm::normalize(glm::vec3(camera->world[1]));
    yfov = camera->yfov;
    out.orthographic = camera->orthographic;
    out.znear = camera->znear;
    out.zfar = camera->zfar;
    out.description = "glTF camera " + std::to_string(camera->index) + " \"" + camera->name + "\"";
    out.gltfCamera = static_cast<int>(camera - scene.cameras.data());
  } else {
    yfov = glm::radians(request.fovDegrees.value_or(kAutoFovDegrees));
    const glm::vec3 center = scene.bounds.empty() ? glm::vec3(0.0f) : scene.bounds.center();
    // Distance at which the bounding sphere fits the narrower field of view.
    const float halfFov = 0.5f * std::min(yfov, 2.0f * std::atan(std::tan(yfov * 0.5f) * aspect));
    const float distance = sceneRadius / std::sin(halfFov) * 1.02f;
    forward = -glm::normalize(kAutoViewDirection);
    eye = center - forward * distance;
    lookAtPoint = center;
    up = glm::vec3(0.0f, 1.0f, 0.0f);
    out.znear = std::max(distance - sceneRadius, distance * 1e-3f) * 0.5f;
    out.zfar = 0.0f;
    out.description = "automatic framing of the scene bounds";
  }

  if (request.fovDegrees) yfov = glm::radians(*request.fovDegrees);
  glm::vec3 target = eye + forward;
  if (request.eye) {
    eye = *request.eye;
    if (!request.target) target = lookAtPoint.value_or(eye + forward);
  }
  if (request.target) target = *request.target;
  glm::dvec3 direction = glm::dvec3(target) - glm::dvec3(eye);
  if (request.eye && !request.target && !lookAtPoint && direction == glm::dvec3(0.0))
    direction = glm::dvec3(forward);
  if (request.up) {
    up = *request.up;
  } else if (request.eye || request.target) {
    // A chosen view is level (+Y up, glTF's up), not rolled like the file's camera; looking
    // straight up or down, +Y cannot be up and the top of the image faces -Z.
    up = glm::vec3(0.0f, 1.0f, 0.0f);
    if (glm::length(direction) > 0.0 &&
        glm::length(glm::cross(glm::normalize(direction), glm::dvec3(up))) < 1e-4)
      up = glm::vec3(0.0f, 0.0f, -1.0f);
  }
  if (request.eye || request.target || request.up) {
    if (request.eye || request.target) out.description += " with --eye/--target";
    // An explicit view always gets a near plane proportional to the scene, as the glTF one
    // was chosen for the original position.
    if (!camera) out.znear = std::min(out.znear, sceneRadius * 1e-3f);
  }
  if (glm::length(up) < 1e-6f) throw InputError("--up: expected a non-zero vector");

  out.eye = eye;
  out.view = lookAtChecked(eye, target, direction, up, request);
  if (out.orthographic) {
    const float ymag = camera->ymag;
    out.projection = reversedOrthographic(ymag * aspect, ymag, out.znear, out.zfar);
  } else {
    out.projection = reversedPerspective(yfov, aspect, out.znear, out.zfar);
  }
  // checkCameraUsable() rules out what makes the projection divide by zero; this catches what
  // is left, e.g. a ymag so small that ymag * aspect underflows.
  if (camera && !isFinite(out.projection)) {
    throw InputError(scene.path + ": cameras[" + std::to_string(camera->index) +
                     "]: the projection for a " + std::to_string(out.width) + "x" +
                     std::to_string(out.height) + " image is not finite");
  }
  return out;
}

}  // namespace omnishadow
