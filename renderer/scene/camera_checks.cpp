#include "renderer/scene/camera_checks.h"

#include <cmath>
#include <sstream>

#include "renderer/core/errors.h"

namespace omnishadow {

namespace {

std::string number(float value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

// Empty when `value` is finite and, unless zero is allowed, its reciprocal too.
std::string badValue(const std::string& name, float value, bool zeroAllowed) {
  if (!std::isfinite(value)) return name + " must be a finite number";
  if (zeroAllowed) return {};
  if (value == 0.0f) return name + " must be non-zero";
  if (!std::isfinite(1.0f / value)) return name + " " + number(value) + " is too close to zero";
  return {};
}

// The projection's depth terms are 1 / (zfar - znear) and zfar / (zfar - znear).
std::string badDepthRange(const std::string& type, float znear, float zfar) {
  if (!(zfar > znear) || !std::isfinite(1.0f / (zfar - znear)) ||
      !std::isfinite(zfar / (zfar - znear))) {
    return type + " zfar " + number(zfar) + " must be greater than znear " + number(znear);
  }
  return {};
}

}  // namespace

std::string cameraProblem(const Camera& camera) {
  std::string problem;
  const auto check = [&problem](std::string found) {
    if (problem.empty()) problem = std::move(found);
  };
  if (camera.orthographic) {
    check(badValue("orthographic xmag", camera.xmag, false));
    check(badValue("orthographic ymag", camera.ymag, false));
    check(badValue("orthographic znear", camera.znear, true));
    check(badValue("orthographic zfar", camera.zfar, true));
    if (problem.empty()) check(badDepthRange("orthographic", camera.znear, camera.zfar));
    return problem;
  }
  check(badValue("perspective yfov", camera.yfov, false));
  if (problem.empty() && !(camera.yfov > 0.0f)) check("perspective yfov must be positive");
  constexpr float kDegreesPerRadian = 57.29577951f;
  if (problem.empty() && !(camera.yfov * kDegreesPerRadian >= kMinFovDegrees &&
                           camera.yfov * kDegreesPerRadian < kMaxFovDegrees)) {
    check("perspective yfov " + number(camera.yfov) +
          " must be from 1.745e-05 (0.001 degrees) to below pi");
  }
  check(badValue("perspective znear", camera.znear, false));
  if (problem.empty() && !(camera.znear > 0.0f)) check("perspective znear must be positive");
  check(badValue("perspective zfar", camera.zfar, true));
  // zfar 0 is an infinite far plane.
  if (problem.empty() && camera.zfar > 0.0f) {
    check(badDepthRange("perspective", camera.znear, camera.zfar));
  }
  return problem;
}

void checkCameraUsable(const Scene& scene, const Camera& camera) {
  if (const std::string problem = cameraProblem(camera); !problem.empty()) {
    throw InputError(scene.path + ": cameras[" + std::to_string(camera.index) + "]: " + problem);
  }
}

}  // namespace omnishadow
