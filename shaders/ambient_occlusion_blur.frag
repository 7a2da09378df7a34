// The frame's ambient occlusion from ambient_occlusion.frag's half-size estimates: the mean of
// the 2 x 2 estimates nearest each pixel, which hold each of their slice turns once, taken only
// from estimates of the pixel's surface: those made at a depth on the pixel's depth plane
// (reversed depth is affine across a plane in screen space, for both projections) to 1% of
// their distance; where none is, the one nearest that plane. Writes the depth it is for beside
// it: a surface drawn later in front of the opaque ones (masked, see-through, blended) does not
// take their occlusion.
layout(binding = 0) uniform sampler2D uDepth;     // the opaque surfaces' reversed depth (0: none)
layout(binding = 1) uniform sampler2D uEstimate;  // half size: the visible share, the depth
layout(location = 0) out vec2 outOcclusion;       // visibility, the depth it is for

float depthAt(ivec2 pixel) {
  if (any(lessThan(pixel, ivec2(0))) || any(greaterThanEqual(pixel, textureSize(uDepth, 0))))
    return 0.0;
  return texelFetch(uDepth, pixel, 0).r;
}

// The depth's slope along `step`: the side of the smaller change, 0 where neither neighbour
// has a surface.
float slope(ivec2 pixel, float center, ivec2 step) {
  float a = depthAt(pixel + step), b = depthAt(pixel - step);
  if (a > 0.0 && (b <= 0.0 || abs(a - center) <= abs(center - b))) return a - center;
  return b > 0.0 ? center - b : 0.0;
}

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  float depth = depthAt(pixel);
  if (depth <= 0.0) {
    outOcclusion = vec2(1.0, 0.0);
    return;
  }
  vec2 gradient = vec2(slope(pixel, depth, ivec2(1, 0)), slope(pixel, depth, ivec2(0, 1)));
  ivec2 size = textureSize(uEstimate, 0);
  // The estimates made at the pixels 2q nearest this one: q from (pixel - 1) / 2 on.
  ivec2 first = (pixel - 1) >> 1;
  float sum = 0.0, count = 0.0, nearest = 1.0, nearestError = 1e30;
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 2; ++x) {
      ivec2 q = clamp(first + ivec2(x, y), ivec2(0), size - 1);
      vec2 estimate = texelFetch(uEstimate, q, 0).rg;
      if (estimate.y <= 0.0) continue;
      float error = abs(estimate.y - (depth + dot(gradient, vec2(q * 2 - pixel))));
      if (error <= 0.01 * depth) {
        sum += estimate.x;
        count += 1.0;
      }
      if (error < nearestError) {
        nearestError = error;
        nearest = estimate.x;
      }
    }
  outOcclusion = vec2(count > 0.0 ? sum / count : nearest, depth);
}
