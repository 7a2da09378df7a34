// Transmittance pass (renderer/passes/transmittance_pass.h): each translucent caster in front
// of the opaque shadow map multiplies the layer's RGB by what it lets through, and the layer's
// A keeps the nearest one's reversed depth (GL_MAX blending). BLEND lets through 1 - alpha,
// KHR_materials_transmission transmission (factor x texture R) x base color, both (1 - alpha) + alpha x
// transmission x base color (renderer/scene/translucency.h); MASK texels below the cutoff are
// holes.
layout(binding = BASE_COLOR_UNIT) uniform sampler2D uBaseColorTexture;
uniform vec4 uBaseColorFactor;
uniform int uHasBaseColorTexture;
uniform int uBaseColorTexCoord;
uniform mat3 uBaseColorUvTransform;  // KHR_texture_transform
uniform int uAlphaMode;              // 0 opaque, 1 mask, 2 blend
uniform float uAlphaCutoff;
uniform float uTransmission;
layout(binding = TRANSMISSION_UNIT) uniform sampler2D uTransmissionTexture;  // R, linear
uniform int uHasTransmissionTexture;
uniform int uTransmissionTexCoord;
uniform mat3 uTransmissionUvTransform;

in ShadowVertex {
  vec3 world;
  vec2 uv0;
  vec2 uv1;
  float alpha;
  vec3 color;
} fIn;

layout(location = 0) out vec4 outTransmittance;

void main() {
  vec4 base = uBaseColorFactor * vec4(fIn.color, fIn.alpha);
  if (uHasBaseColorTexture != 0)
    base *= texture(uBaseColorTexture,
                    (uBaseColorUvTransform * vec3(uBaseColorTexCoord == 0 ? fIn.uv0 : fIn.uv1,
                                                  1.0)).xy);
  if (uAlphaMode == 1 && base.a < uAlphaCutoff) discard;
  float alpha = uAlphaMode == 2 ? clamp(base.a, 0.0, 1.0) : 1.0;
  float transmission = uTransmission;
  if (uHasTransmissionTexture != 0)
    transmission *= texture(uTransmissionTexture,
                            (uTransmissionUvTransform *
                             vec3(uTransmissionTexCoord == 0 ? fIn.uv0 : fIn.uv1, 1.0)).xy).r;
  vec3 t = vec3(1.0 - alpha) + alpha * transmission * clamp(base.rgb, 0.0, 1.0);
  outTransmittance = vec4(t, gl_FragCoord.z);
}
