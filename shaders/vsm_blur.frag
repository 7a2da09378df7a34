// One direction of a separable Gaussian over a layer of vsm moments. Filtering the moments
// (not depth) is what makes variance shadow maps soft without per-pixel taps when sampling.
layout(binding = VSM_SOURCE_UNIT) uniform sampler2DArray uSource;
uniform int uLayer;
uniform ivec2 uStep;     // (1, 0) or (0, 1)
uniform int uRadius;     // taps on each side
uniform float uSigma;    // in texels

layout(location = 0) out vec2 outMoments;

void main() {
  ivec2 size = textureSize(uSource, 0).xy;
  ivec2 center = ivec2(gl_FragCoord.xy);
  vec2 sum = vec2(0.0);
  float weights = 0.0;
  for (int i = -uRadius; i <= uRadius; ++i) {
    ivec2 at = clamp(center + uStep * i, ivec2(0), size - 1);
    float w = exp(-0.5 * float(i * i) / (uSigma * uSigma));
    sum += w * texelFetch(uSource, ivec3(at, uLayer), 0).rg;
    weights += w;
  }
  outMoments = sum / weights;
}
