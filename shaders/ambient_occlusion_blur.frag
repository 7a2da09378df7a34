// The mean of ambient_occlusion.frag's estimates over the 4 x 4 block around each pixel, which
// holds each of its slice turns once, taken only from pixels of the same surface: those whose
// depth lies on the pixel's depth plane (reversed depth is affine across a plane in screen
// space, for both projections) to 1% of their distance. Writes the depth it is for beside it:
// a surface drawn later in front of the opaque ones (masked, see-through, blended) does not
// take their occlusion.
layout(binding = 1) uniform sampler2D uEstimate;  // the visible share, the depth (0: none)
layout(location = 0) out vec2 outOcclusion;  // visibility, the depth it is for

ivec2 gSize;

vec2 estimateAt(ivec2 pixel) {
  if (any(lessThan(pixel, ivec2(0))) || any(greaterThanEqual(pixel, gSize))) return vec2(1.0, 0.0);
  return texelFetch(uEstimate, pixel, 0).rg;
}

float depthAt(ivec2 pixel) {
  return estimateAt(pixel).y;
}

// The depth's slope along `step`: the side of the smaller change, 0 where neither neighbour
// has a surface.
float slope(ivec2 pixel, float center, ivec2 step) {
  float a = depthAt(pixel + step), b = depthAt(pixel - step);
  if (a > 0.0 && (b <= 0.0 || abs(a - center) <= abs(center - b))) return a - center;
  return b > 0.0 ? center - b : 0.0;
}

void main() {
  gSize = textureSize(uEstimate, 0);
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  float depth = depthAt(pixel);
  if (depth <= 0.0) {
    outOcclusion = vec2(1.0, 0.0);
    return;
  }
  vec2 gradient = vec2(slope(pixel, depth, ivec2(1, 0)), slope(pixel, depth, ivec2(0, 1)));
  float sum = 0.0, count = 0.0;
  for (int y = -2; y < 2; ++y)
    for (int x = -2; x < 2; ++x) {
      vec2 estimate = estimateAt(pixel + ivec2(x, y));
      float d = estimate.y;
      if (d <= 0.0 || abs(d - (depth + dot(gradient, vec2(x, y)))) > 0.01 * depth) continue;
      sum += estimate.x;
      count += 1.0;
    }
  outOcclusion = vec2(sum / count, depth);  // the pixel itself always counts
}
