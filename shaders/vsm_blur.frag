// One direction of a separable Gaussian over VSM_LAYERS layers of vsm moments at once, one
// color output per layer (renderer/passes/vsm_filter.h: llvmpipe's fixed cost per fragment is
// about that of five taps, paid once for all layers). Filtering the moments (not depth) is what
// makes variance shadow maps soft without per-pixel taps when sampling.
layout(binding = VSM_SOURCE_UNIT) uniform sampler2DArray uSource;
uniform int uSourceLayers[VSM_LAYERS];  // output i filters uSource's layer uSourceLayers[i]
uniform ivec2 uStep;     // (1, 0) or (0, 1)
uniform int uRadius;     // taps on each side
uniform float uSigma;    // in texels

layout(location = 0) out vec2 outMoments[VSM_LAYERS];

void main() {
  ivec2 size = textureSize(uSource, 0).xy;
  ivec2 center = ivec2(gl_FragCoord.xy);
  vec2 sum[VSM_LAYERS];
  for (int layer = 0; layer < VSM_LAYERS; ++layer) sum[layer] = vec2(0.0);
  float weights = 0.0;
  for (int i = -uRadius; i <= uRadius; ++i) {
    ivec2 at = clamp(center + uStep * i, ivec2(0), size - 1);
    float w = exp(-0.5 * float(i * i) / (uSigma * uSigma));
    for (int layer = 0; layer < VSM_LAYERS; ++layer)
      sum[layer] += w * texelFetch(uSource, ivec3(at, uSourceLayers[layer]), 0).rg;
    weights += w;
  }
  for (int layer = 0; layer < VSM_LAYERS; ++layer) outMoments[layer] = sum[layer] / weights;
}
