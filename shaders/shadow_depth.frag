// Shadow pass. Opaque casters write hardware depth only (no gl_FragDepth: early depth tests
// stay on). With ALPHA_MASK, texels below the cutoff cast no shadow, so cut-out leaves cast
// cut-out shadows.
#ifdef ALPHA_MASK
layout(binding = 0) uniform sampler2D uBaseColorTexture;
uniform vec4 uBaseColorFactor;
uniform int uHasBaseColorTexture;
uniform int uBaseColorTexCoord;
uniform float uAlphaCutoff;

in vec2 vUv0;
in vec2 vUv1;
in float vAlpha;
#endif

void main() {
#ifdef ALPHA_MASK
  float alpha = uBaseColorFactor.a * vAlpha;
  if (uHasBaseColorTexture != 0)
    alpha *= texture(uBaseColorTexture, uBaseColorTexCoord == 0 ? vUv0 : vUv1).a;
  if (alpha < uAlphaCutoff) discard;
#endif
}
