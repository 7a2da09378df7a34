// Transmittance pass (renderer/passes/transmittance_pass.h): each translucent caster in front
// of the opaque shadow map multiplies the layer's RGB by what it lets through, and the layer's
// A keeps the nearest one's reversed depth (GL_MAX blending), as renderer/scene/translucency.h
// writes it (surfaceTransmittance): BLEND lets through 1 - alpha; KHR_materials_transmission
// transmission (factor x texture R) x base color, on a volume times Beer's law over half the
// thickness (factor x texture G); KHR_materials_diffuse_transmission also (1 - transmission) x
// its fraction (factor x texture A) x its color (factor x texture RGB); (1 - alpha) + alpha x
// those. MASK texels below the cutoff are holes. The volume and diffuse transmission terms are
// compiled in (VOLUME, DIFFUSE_TRANSMISSION) only for scenes whose casters need them: llvmpipe
// reads the textures of a skipped branch anyway.
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
#ifdef VOLUME
// ln(attenuationColor) x thicknessFactor x scale / (2 x attenuationDistance): 0 without a volume.
uniform vec3 uVolumeAttenuationExponent;
layout(binding = SHADOW_THICKNESS_UNIT) uniform sampler2D uThicknessTexture;  // G, linear
uniform int uHasThicknessTexture;
uniform int uThicknessTexCoord;
uniform mat3 uThicknessUvTransform;
#endif
#ifdef DIFFUSE_TRANSMISSION
uniform float uDiffuseTransmission;  // 0: none
uniform vec3 uDiffuseTransmissionColor;
layout(binding = SHADOW_DIFFUSE_TRANSMISSION_UNIT) uniform sampler2D uDiffuseTransmissionTexture;  // A
uniform int uHasDiffuseTransmissionTexture;
uniform int uDiffuseTransmissionTexCoord;
uniform mat3 uDiffuseTransmissionUvTransform;
layout(binding = SHADOW_DIFFUSE_TRANSMISSION_COLOR_UNIT) uniform sampler2D
    uDiffuseTransmissionColorTexture;  // RGB, sRGB (decoded by the sampler)
uniform int uHasDiffuseTransmissionColorTexture;
uniform int uDiffuseTransmissionColorTexCoord;
uniform mat3 uDiffuseTransmissionColorUvTransform;
#endif

in ShadowVertex {
  vec3 world;
  vec2 uv0;
  vec2 uv1;
  float alpha;
  vec3 color;
} fIn;

layout(location = 0) out vec4 outTransmittance;

#if defined(VOLUME) || defined(DIFFUSE_TRANSMISSION)
vec2 textureUv(mat3 uvTransform, int texCoord) {
  return (uvTransform * vec3(texCoord == 0 ? fIn.uv0 : fIn.uv1, 1.0)).xy;
}
#endif

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
  vec3 color = clamp(base.rgb, 0.0, 1.0);
#ifdef VOLUME
  if (uVolumeAttenuationExponent != vec3(0.0)) {
    float thickness = 1.0;
    if (uHasThicknessTexture != 0)
      thickness = clamp(texture(uThicknessTexture, textureUv(uThicknessUvTransform,
                                                             uThicknessTexCoord)).g, 0.0, 1.0);
    color *= exp(uVolumeAttenuationExponent * thickness);
  }
#endif
  vec3 t = vec3(1.0 - alpha) + alpha * transmission * color;
#ifdef DIFFUSE_TRANSMISSION
  if (uDiffuseTransmission > 0.0) {
    float fraction = uDiffuseTransmission;
    if (uHasDiffuseTransmissionTexture != 0)
      fraction *= clamp(texture(uDiffuseTransmissionTexture,
                                textureUv(uDiffuseTransmissionUvTransform,
                                          uDiffuseTransmissionTexCoord)).a, 0.0, 1.0);
    vec3 diffuseColor = uDiffuseTransmissionColor;
    if (uHasDiffuseTransmissionColorTexture != 0)
      diffuseColor *= clamp(texture(uDiffuseTransmissionColorTexture,
                                    textureUv(uDiffuseTransmissionColorUvTransform,
                                              uDiffuseTransmissionColorTexCoord)).rgb, 0.0, 1.0);
    t += alpha * (1.0 - transmission) * fraction * diffuseColor;
  }
#endif
  outTransmittance = vec4(t, gl_FragCoord.z);
}
