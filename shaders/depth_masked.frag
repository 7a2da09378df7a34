// Depth of masked (alpha-cutoff) surfaces alone, for the ambient occlusion estimate: the texels
// the lighting pass discards (lighting.frag, the same base color alpha and cutoff) write none,
// so the depths are the ones it shades at.
in VertexData {
  vec3 worldPosition;
  vec3 worldNormal;
  vec4 worldTangent;
  vec2 uv0;
  vec2 uv1;
  vec4 color;
} vIn;

layout(binding = BASE_COLOR_UNIT) uniform sampler2D uBaseColorTexture;
uniform vec4 uBaseColorFactor;
uniform int uBaseColorTexCoord;      // -1: no texture
uniform mat3 uBaseColorUvTransform;  // KHR_texture_transform
uniform float uAlphaCutoff;

void main() {
  float alpha = uBaseColorFactor.a * vIn.color.a;
  if (uBaseColorTexCoord >= 0)
    alpha *= texture(uBaseColorTexture, (uBaseColorUvTransform *
                                         vec3(uBaseColorTexCoord == 0 ? vIn.uv0 : vIn.uv1, 1.0)).xy).a;
  if (alpha < uAlphaCutoff) discard;
}
