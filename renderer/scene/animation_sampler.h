#pragma once

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <vector>

namespace omnishadow {

// glTF animation.sampler.interpolation.
enum class Interpolation { Step, Linear, CubicSpline };

// One glTF animation sampler, read from its accessors: keyframe times (strictly increasing) and
// `components` floats per output element. CUBICSPLINE samplers hold three elements per keyframe
// (in-tangent, value, out-tangent), as in the file.
struct AnimationSampler {
  std::vector<float> times;
  std::vector<float> values;
  int components = 1;
  Interpolation interpolation = Interpolation::Linear;
};

// The sampler's value at `time`, as the glTF 2.0 specification defines it (Appendix C): times
// before the first keyframe or after the last clamp to it; STEP holds the previous keyframe;
// LINEAR interpolates linearly, or for `quaternion` (rotations, x y z w) by spherical linear
// interpolation along the shorter arc; CUBICSPLINE evaluates the Hermite spline whose tangents
// are scaled by the keyframe interval. Quaternion results are normalized. Returns `components`
// floats; the sampler must have at least one keyframe.
std::vector<float> sampleAnimation(const AnimationSampler& sampler, double time,
                                   bool quaternion = false);

// Spherical linear interpolation of unit quaternions along the shorter arc, s in [0, 1].
glm::quat shortestSlerp(const glm::quat& a, const glm::quat& b, float s);

}  // namespace omnishadow
