#include "renderer/scene/animation_sampler.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace omnishadow {
namespace {

glm::quat quatAt(const float* v) {
  return glm::quat(v[3], v[0], v[1], v[2]);
}

std::vector<float> normalizedQuat(std::vector<float> v) {
  const float length = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2] + v[3] * v[3]);
  if (length > 0.0f && std::isfinite(length))
    for (float& c : v) c /= length;
  return v;
}

}  // namespace

glm::quat shortestSlerp(const glm::quat& a, const glm::quat& b, float s) {
  float d = glm::dot(a, b);
  glm::quat end = b;
  // q and -q are the same rotation; the shorter arc goes to the one in a's hemisphere.
  if (d < 0.0f) {
    d = -d;
    end = -b;
  }
  if (d > 0.9995f) {
    // sin(angle) is too small to divide by; the arc is a straight line at this precision.
    return glm::normalize(a * (1.0f - s) + end * s);
  }
  const float angle = std::acos(d);
  const float sinAngle = std::sin(angle);
  return a * (std::sin((1.0f - s) * angle) / sinAngle) + end * (std::sin(s * angle) / sinAngle);
}

std::vector<float> sampleAnimation(const AnimationSampler& sampler, double time, bool quaternion) {
  const std::size_t n = static_cast<std::size_t>(sampler.components);
  const std::vector<float>& times = sampler.times;
  const bool cubic = sampler.interpolation == Interpolation::CubicSpline;
  // Element k's value: for CUBICSPLINE the middle of (in-tangent, value, out-tangent).
  const auto value = [&](std::size_t k) { return &sampler.values[(cubic ? 3 * k + 1 : k) * n]; };
  const auto copy = [&](const float* v) {
    std::vector<float> out(v, v + n);
    return quaternion ? normalizedQuat(std::move(out)) : out;
  };
  if (times.size() == 1 || !(time > times.front())) return copy(value(0));
  if (time >= times.back()) return copy(value(times.size() - 1));
  // times[k] <= time < times[k + 1]
  const std::size_t k = static_cast<std::size_t>(
      std::upper_bound(times.begin(), times.end(), static_cast<float>(time)) - times.begin() - 1);
  const double t0 = times[k], t1 = times[k + 1];
  const double interval = t1 - t0;
  const float s = static_cast<float>(std::clamp((time - t0) / interval, 0.0, 1.0));
  switch (sampler.interpolation) {
    case Interpolation::Step:
      return copy(value(k));
    case Interpolation::Linear: {
      if (quaternion) {
        const glm::quat q = shortestSlerp(quatAt(value(k)), quatAt(value(k + 1)), s);
        return normalizedQuat({q.x, q.y, q.z, q.w});
      }
      std::vector<float> out(n);
      for (std::size_t c = 0; c < n; ++c) out[c] = (1.0f - s) * value(k)[c] + s * value(k + 1)[c];
      return out;
    }
    case Interpolation::CubicSpline: {
      const float td = static_cast<float>(interval);
      const float s2 = s * s, s3 = s2 * s;
      const float* v0 = value(k);
      const float* b0 = &sampler.values[(3 * k + 2) * n];    // out-tangent of keyframe k
      const float* a1 = &sampler.values[(3 * (k + 1)) * n];  // in-tangent of keyframe k + 1
      const float* v1 = value(k + 1);
      std::vector<float> out(n);
      for (std::size_t c = 0; c < n; ++c) {
        out[c] = (2 * s3 - 3 * s2 + 1) * v0[c] + td * (s3 - 2 * s2 + s) * b0[c] +
                 (-2 * s3 + 3 * s2) * v1[c] + td * (s3 - s2) * a1[c];
      }
      return quaternion ? normalizedQuat(std::move(out)) : out;
    }
  }
  return copy(value(k));
}

}  // namespace omnishadow
