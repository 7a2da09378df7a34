// Shadow pass. Opaque casters write hardware depth only (no gl_FragDepth: early depth tests
// stay on). With ALPHA_MASK, texels below the cutoff cast no shadow, so cut-out leaves cast
// cut-out shadows. With MOMENTS (vsm lights) the first two moments of the receiver metric go to
// a color layer: distance / far for point and spot lights, linear depth for directional ones.
#ifdef ALPHA_MASK
layout(binding = BASE_COLOR_UNIT) uniform sampler2D uBaseColorTexture;
uniform vec4 uBaseColorFactor;
uniform int uHasBaseColorTexture;
uniform int uBaseColorTexCoord;
uniform mat3 uBaseColorUvTransform;  // KHR_texture_transform
uniform float uAlphaCutoff;
#endif
#ifdef MOMENTS
uniform vec3 uLightPosition;
uniform float uMomentScale;  // 1 / far
uniform int uMomentFromDepth;  // directional: the orthographic depth itself
layout(location = 0) out vec2 outMoments;
#endif

#if defined(ALPHA_MASK) || defined(MOMENTS)
in ShadowVertex {
  vec3 world;
  vec2 uv0;
  vec2 uv1;
  float alpha;
} fIn;
#endif

void main() {
#ifdef ALPHA_MASK
  float alpha = uBaseColorFactor.a * fIn.alpha;
  if (uHasBaseColorTexture != 0)
    alpha *= texture(uBaseColorTexture,
                     (uBaseColorUvTransform * vec3(uBaseColorTexCoord == 0 ? fIn.uv0 : fIn.uv1,
                                                   1.0)).xy).a;
  if (alpha < uAlphaCutoff) discard;
#endif
#ifdef MOMENTS
  float m = uMomentFromDepth != 0 ? 1.0 - gl_FragCoord.z
                                  : length(fIn.world - uLightPosition) * uMomentScale;
  outMoments = vec2(m, m * m);
#endif
}
