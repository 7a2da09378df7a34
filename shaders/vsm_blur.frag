// One direction of a separable Gaussian over VSM_LAYERS layers of vsm moments at once, one
// color output per layer (renderer/passes/vsm_filter.h: llvmpipe's fixed cost per fragment is
// about that of five taps, paid once for all layers). Filtering the moments (not depth) is what
// makes variance shadow maps soft without per-pixel taps when sampling. Texels are read at
// their centres through a nearest sampler that clamps at the edges (VsmFilter binds it): on
// llvmpipe a quarter faster than texelFetch of clamped texel coordinates, the same texels.
layout(binding = VSM_SOURCE_UNIT) uniform sampler2DArray uSource;
uniform int uSourceLayers[VSM_LAYERS];  // output i filters uSource's layer uSourceLayers[i]
uniform ivec2 uStep;     // (1, 0) or (0, 1)
uniform int uRadius;     // taps on each side
uniform float uSigma;    // in texels

layout(location = 0) out vec2 outMoments[VSM_LAYERS];

void main() {
  vec2 texel = 1.0 / vec2(textureSize(uSource, 0).xy);
  vec2 sum[VSM_LAYERS];
  for (int layer = 0; layer < VSM_LAYERS; ++layer) sum[layer] = vec2(0.0);
  float weights = 0.0;
  for (int i = -uRadius; i <= uRadius; ++i) {
    vec2 at = (gl_FragCoord.xy + vec2(uStep * i)) * texel;
    float w = exp(-0.5 * float(i * i) / (uSigma * uSigma));
    for (int layer = 0; layer < VSM_LAYERS; ++layer)
      sum[layer] += w * textureLod(uSource, vec3(at, float(uSourceLayers[layer])), 0.0).rg;
    weights += w;
  }
  for (int layer = 0; layer < VSM_LAYERS; ++layer) outMoments[layer] = sum[layer] / weights;
}
