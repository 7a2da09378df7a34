// Lighting pass: material, all lights in one loop, shadows, and the AOVs.
// Variants: SHADING_PHONG (Blinn-Phong instead of metallic-roughness), WRITE_AOVS (position,
// normal, distance, visibility), WRITE_LAYERS (material layers or one light's diffuse and
// specular, chosen by uLayerMode), WRITE_SRGB8 (the beauty as 8-bit sRGB codes), WITH_IDS (beside
// the beauty, what WRITE_IDS writes), WRITE_IDS
// (the surface's objectId and coverage alone: no material beyond the alpha, no light), DEBUG_VIEWS
// (the --debug-view pictures, chosen by uDebugView: frames without one leave their sums out),
// FACING_LIGHT_LOOP (the beauty alone: each lane group loops over the lights it may face),
// SHEEN, SHEEN_TEXTURE and SHEEN_ROUGHNESS_TEXTURE (KHR_materials_sheen, its texture, and a
// roughness texture of another image), DIELECTRIC_SPECULAR and SPECULAR_<TEXTURE>
// (KHR_materials_specular and each of its textures), CLEARCOAT and CLEARCOAT_<TEXTURE>
// (KHR_materials_clearcoat and each of its textures), TRANSMISSION and TRANSMISSION_TEXTURE
// (KHR_materials_transmission, and its texture), VOLUME and THICKNESS_TEXTURE (with it,
// KHR_materials_volume, and its texture), DISPERSION (with VOLUME, KHR_materials_dispersion),
// ANISOTROPY and ANISOTROPY_TEXTURE (KHR_materials_anisotropy, and its texture), IRIDESCENCE,
// IRIDESCENCE_TEXTURE and IRIDESCENCE_THICKNESS_TEXTURE (KHR_materials_iridescence, and each of
// its textures; IRIDESCENCE_DIELECTRIC_ONLY or IRIDESCENCE_METAL_ONLY where metallic is 0 or 1
// throughout), DIFFUSE_TRANSMISSION, DIFFUSE_TRANSMISSION_TEXTURE and
// DIFFUSE_TRANSMISSION_COLOR_TEXTURE (KHR_materials_diffuse_transmission, and each texture),
// ENVIRONMENT (an environment light: image-based diffuse and specular reflection),
// AMBIENT_OCCLUSION (the ambient and environment light screen-space occluded, from
// ambient_occlusion.frag's estimate for the opaque surfaces).
#ifdef FACING_LIGHT_LOOP
#extension GL_ARB_shader_ballot : require
#endif
#include "lights.glsl"
#include "brdf.glsl"
#include "shadows.glsl"
#ifdef ENVIRONMENT
#include "environment.glsl"
#endif
#ifdef WRITE_SRGB8
#include "srgb8_encode.glsl"
#endif
#ifdef AMBIENT_OCCLUSION
// Half the frame's size: at texel q, the visible share ambient_occlusion.frag estimated at
// pixel 2q of the opaque surfaces, and that pixel's depth (0: none).
layout(binding = AMBIENT_OCCLUSION_UNIT) uniform sampler2D uAmbientOcclusion;
uniform float uAmbientOcclusionStrength;

// The mean of the four estimates nearest the pixel, which hold each of the estimate's slice
// turns once, taken only from those of this surface: made at a depth on its depth plane
// (reversed depth is affine across a triangle in screen space, for both projections) to 1% of
// the distance; where none is, the one nearest that plane if within 5%, else none: a surface
// in front of those estimated (see-through, blended) does not take their occlusion.
// `gradient`: the depth's derivatives, taken before any lane of the quad may be discarded.
float screenSpaceOcclusion(vec2 gradient) {
  float depth = gl_FragCoord.z;
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  ivec2 last = textureSize(uAmbientOcclusion, 0) - 1;
  ivec2 first = (pixel - 1) >> 1;  // the estimates at pixels 2q nearest this one
  float sum = 0.0, count = 0.0, nearest = 1.0, nearestError = 0.05 * depth;
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 2; ++x) {
      ivec2 q = clamp(first + ivec2(x, y), ivec2(0), last);
      vec2 estimate = texelFetch(uAmbientOcclusion, q, 0).rg;
      float error = abs(estimate.y - (depth + dot(gradient, vec2(q * 2 - pixel))));
      if (estimate.y <= 0.0) continue;
      if (error <= 0.01 * depth) {
        sum += estimate.x;
        count += 1.0;
      }
      if (error < nearestError) {
        nearestError = error;
        nearest = estimate.x;
      }
    }
  float visible = count > 0.0 ? sum / count : nearest;
  return 1.0 + uAmbientOcclusionStrength * (visible - 1.0);
}
#endif

in VertexData {
  vec3 worldPosition;
  vec3 worldNormal;
  vec4 worldTangent;
  vec2 uv0;
  vec2 uv1;
  vec4 color;
} vIn;

layout(binding = BASE_COLOR_UNIT) uniform sampler2D uBaseColorTexture;
layout(binding = METALLIC_ROUGHNESS_UNIT) uniform sampler2D uMetallicRoughnessTexture;
layout(binding = NORMAL_UNIT) uniform sampler2D uNormalTexture;
layout(binding = OCCLUSION_UNIT) uniform sampler2D uOcclusionTexture;
layout(binding = EMISSIVE_UNIT) uniform sampler2D uEmissiveTexture;

uniform vec4 uBaseColorFactor;
uniform float uMetallicFactor;
uniform float uRoughnessFactor;
uniform vec3 uEmissive;  // factor * strength
uniform float uNormalScale;
uniform float uOcclusionStrength;
uniform int uAlphaMode;  // 0 opaque, 1 mask, 2 blend
uniform float uAlphaCutoff;
uniform int uHasTangents;
// Per texture slot: -1 = none, else the TEXCOORD set.
uniform int uBaseColorTexCoord;
uniform int uMetallicRoughnessTexCoord;
uniform int uNormalTexCoord;
uniform int uOcclusionTexCoord;
uniform int uEmissiveTexCoord;
// Per texture slot: KHR_texture_transform (identity when the file has none).
uniform mat3 uBaseColorUvTransform;
uniform mat3 uMetallicRoughnessUvTransform;
uniform mat3 uNormalUvTransform;
uniform mat3 uOcclusionUvTransform;
uniform mat3 uEmissiveUvTransform;
// The normal texture's X and Y axes in the mesh's tangent frame (upper 2x2; identity without a
// transform): a rotated or mirrored texture turns the normals it stores with it.
uniform mat3 uNormalTextureAxes;
uniform int uUnlit;  // KHR_materials_unlit, points and lines: the base color as is, no lights
// KHR_materials_pbrSpecularGlossiness: the base color is the diffuse color, and the
// metallic-roughness unit holds the specular-glossiness texture.
uniform int uSpecularGlossiness;
uniform vec3 uSpecularFactor;
uniform float uGlossinessFactor;
uniform float uDielectricF0;  // KHR_materials_ior: ((ior - 1) / (ior + 1))^2, 0.04 by default
#ifdef DIELECTRIC_SPECULAR
uniform float uSpecularWeight;      // KHR_materials_specular: specularFactor
uniform vec3 uSpecularColorFactor;  // and specularColorFactor
#ifdef SPECULAR_TEXTURE
layout(binding = SPECULAR_UNIT) uniform sampler2D uSpecularTexture;  // A
uniform int uSpecularTexCoord;
uniform mat3 uSpecularUvTransform;
#endif
#ifdef SPECULAR_COLOR_TEXTURE
layout(binding = SPECULAR_COLOR_UNIT) uniform sampler2D uSpecularColorTexture;  // RGB, sRGB
uniform int uSpecularColorTexCoord;
uniform mat3 uSpecularColorUvTransform;
#endif
#endif
#ifdef SHEEN
// KHR_materials_sheen: one texture, its RGB the color and its A the roughness, each read at its
// own slot's coordinates (texCoord -1: that slot has no texture).
uniform vec3 uSheenColorFactor;
uniform float uSheenRoughnessFactor;
#ifdef SHEEN_TEXTURE
layout(binding = SHEEN_UNIT) uniform sampler2D uSheenTexture;
#ifdef SHEEN_ROUGHNESS_TEXTURE
// A roughness texture of another image than the color's, on a unit of its own.
layout(binding = SHEEN_ROUGHNESS_UNIT) uniform sampler2D uSheenRoughnessTexture;
#else
#define uSheenRoughnessTexture uSheenTexture
#endif
uniform int uSheenColorTexCoord;
uniform int uSheenRoughnessTexCoord;
uniform mat3 uSheenColorUvTransform;
uniform mat3 uSheenRoughnessUvTransform;
#endif
#endif
#ifdef CLEARCOAT
// KHR_materials_clearcoat: its factors, and each texture on a unit of its own (texCoord -1: that
// slot has no texture).
uniform float uClearcoatFactor;
uniform float uClearcoatRoughnessFactor;
#ifdef CLEARCOAT_TEXTURE
layout(binding = CLEARCOAT_UNIT) uniform sampler2D uClearcoatTexture;  // R
uniform int uClearcoatTexCoord;
uniform mat3 uClearcoatUvTransform;
#endif
#ifdef CLEARCOAT_ROUGHNESS_TEXTURE
layout(binding = CLEARCOAT_ROUGHNESS_UNIT) uniform sampler2D uClearcoatRoughnessTexture;  // G
uniform int uClearcoatRoughnessTexCoord;
uniform mat3 uClearcoatRoughnessUvTransform;
#endif
#ifdef CLEARCOAT_NORMAL_TEXTURE
layout(binding = CLEARCOAT_NORMAL_UNIT) uniform sampler2D uClearcoatNormalTexture;
uniform int uClearcoatNormalTexCoord;
uniform mat3 uClearcoatNormalUvTransform;
uniform mat3 uClearcoatNormalTextureAxes;  // as uNormalTextureAxes
uniform float uClearcoatNormalScale;
#endif
#endif
#ifdef TRANSMISSION
// KHR_materials_transmission: the surface lets through transmission x base color of what lies
// behind it, as the frame's opaque surfaces drew it (uSceneBehind, premultiplied, at this pixel
// for a thin wall, else where VOLUME's ray leaves; a rough surface reads a coarser level, as the
// Khronos sample viewer does), and of the lights behind it (a GGX lobe around the view ray).
uniform float uTransmissionFactor;
uniform float uIor;
layout(binding = SCENE_BEHIND_UNIT) uniform sampler2D uSceneBehind;
#ifdef TRANSMISSION_TEXTURE
layout(binding = SURFACE_TRANSMISSION_UNIT) uniform sampler2D uTransmissionTexture;  // R
uniform int uTransmissionTexCoord;
uniform mat3 uTransmissionUvTransform;
#endif
#if defined(WRITE_SRGB8)
#error "see-through surfaces read the float beauty: the 8-bit one cannot draw them"
#endif
#ifdef VOLUME
// KHR_materials_volume, as the Khronos sample viewer approximates it: the view ray refracts
// into the volume and leaves it `thickness` (in the mesh's units) further on, where the scene
// behind is read (projected to the screen); light loses exp(-uAttenuationCoefficient x the
// distance) on the way, and a light behind the surface is seen from the exit point.
uniform float uThicknessFactor;
uniform vec3 uAttenuationCoefficient;  // -ln(attenuationColor) / attenuationDistance
uniform mat4 uModel;
uniform mat4 uViewProjection;
#ifdef THICKNESS_TEXTURE
layout(binding = THICKNESS_UNIT) uniform sampler2D uThicknessTexture;  // G
uniform int uThicknessTexCoord;
uniform mat3 uThicknessUvTransform;
#endif
#ifdef DISPERSION
// KHR_materials_dispersion (20 / the Abbe number): red and blue refract with iors half the
// spread (ior - 1) / Abbe number below and above the ior, green with the ior (the
// specification's implementation notes), each read where its own ray leaves.
uniform float uDispersion;
#endif

// The ray through the volume from a point of normal N seen from V, for one ior: refracted, as
// long as the thickness, stretched by the mesh's scale along each axis.
vec3 volumeRayFor(float ior, vec3 N, vec3 V, float thickness, vec3 modelScale) {
  vec3 refracted = refract(-V, N, ior >= 1.0 ? 1.0 / ior : 1.0);
  return (dot(refracted, refracted) > 0.0 ? normalize(refracted) : -N) * thickness * modelScale;
}

// Where the scene behind is read for a point: its projection, in [0, 1] texture coordinates.
vec2 behindCoordOf(vec3 P) {
  vec4 clip = uViewProjection * vec4(P, 1.0);
  return clip.xy / clip.w * 0.5 + 0.5;
}
#endif
#endif
#ifdef ANISOTROPY
// KHR_materials_anisotropy: the strength, and the rotation as (cos, sin); the texture's RG is a
// direction in [-1, 1] turned by the rotation, its B multiplies the strength.
uniform float uAnisotropyStrength;
uniform vec2 uAnisotropyRotation;
#ifdef ANISOTROPY_TEXTURE
layout(binding = ANISOTROPY_UNIT) uniform sampler2D uAnisotropyTexture;
uniform int uAnisotropyTexCoord;
uniform mat3 uAnisotropyUvTransform;
#endif
#endif
#ifdef DIFFUSE_TRANSMISSION
// KHR_materials_diffuse_transmission: the fraction of the light that enters the surface and
// leaves it on the other side (factor x texture's A), as Lambert of the color (factor x
// texture's RGB, sRGB); lights behind the surface shine through it.
uniform float uDiffuseTransmissionFactor;
uniform vec3 uDiffuseTransmissionColorFactor;
#ifdef DIFFUSE_TRANSMISSION_TEXTURE
layout(binding = DIFFUSE_TRANSMISSION_UNIT) uniform sampler2D uDiffuseTransmissionTexture;
uniform int uDiffuseTransmissionTexCoord;
uniform mat3 uDiffuseTransmissionUvTransform;
#endif
#ifdef DIFFUSE_TRANSMISSION_COLOR_TEXTURE
layout(binding = DIFFUSE_TRANSMISSION_COLOR_UNIT) uniform sampler2D uDiffuseTransmissionColorTexture;
uniform int uDiffuseTransmissionColorTexCoord;
uniform mat3 uDiffuseTransmissionColorUvTransform;
#endif
#endif
#ifdef IRIDESCENCE
// KHR_materials_iridescence: the film's strength (factor x texture's R), index and thickness in
// nanometres (mix(minimum, maximum, thickness texture's G), the maximum without a texture).
uniform float uIridescenceFactor;
uniform float uIridescenceIor;
uniform float uIridescenceThicknessMinimum;
uniform float uIridescenceThicknessMaximum;
#ifdef IRIDESCENCE_TEXTURE
layout(binding = IRIDESCENCE_UNIT) uniform sampler2D uIridescenceTexture;
uniform int uIridescenceTexCoord;
uniform mat3 uIridescenceUvTransform;
#endif
#ifdef IRIDESCENCE_THICKNESS_TEXTURE
layout(binding = IRIDESCENCE_THICKNESS_UNIT) uniform sampler2D uIridescenceThicknessTexture;
uniform int uIridescenceThicknessTexCoord;
uniform mat3 uIridescenceThicknessUvTransform;
#endif
#endif
// Material variants (renderer/passes/lighting_pass.cpp): the texture slots and the BRDF a
// material lacks are constants here, so their reads compile out (llvmpipe would run them).
#ifndef BASE_COLOR_TEXTURE
#define uBaseColorTexCoord (-1)
#endif
#ifndef METALLIC_ROUGHNESS_TEXTURE
#define uMetallicRoughnessTexCoord (-1)
#endif
#ifndef NORMAL_TEXTURE
#define uNormalTexCoord (-1)
#endif
#ifndef OCCLUSION_TEXTURE
#define uOcclusionTexCoord (-1)
#endif
#ifndef EMISSIVE_TEXTURE
#define uEmissiveTexCoord (-1)
#endif
#ifndef SPECULAR_GLOSSINESS
#define uSpecularGlossiness 0
#endif

uniform vec3 uCameraPosition;

#ifdef CLUSTERED_LIGHTS
// Light clusters (renderer/view/light_clusters.h), for frames where some light has a range.
layout(std430, binding = CLUSTER_RANGES_BINDING) readonly buffer ClusterRanges { uint uClusterRanges[]; };
layout(std430, binding = CLUSTER_LIGHTS_BINDING) readonly buffer ClusterLights { uint uClusterLights[]; };
uniform int uTileSize;
uniform int uTileColumns;
uniform int uTileRows;
uniform int uSlices;
uniform float uSliceNear;
uniform float uSliceScale;
uniform vec4 uViewDepth;  // view depth of P: dot(uViewDepth.xyz, P) + uViewDepth.w
uniform int uGlobalLights;
#endif
uniform vec3 uAmbient;

uniform int uDebugView;  // DEBUG_VIEW_*: DebugView in renderer/render/render_settings.h
uniform int uDebugLight;  // the light --debug-view depth shows

#if defined(WRITE_IDS)
// R: objectId; G: coverage, which the blended surfaces blend over (A, their alpha, is the
// blend's factor) as they blend the beauty's A.
layout(location = 0) out vec4 outIds;
uniform float uObjectId;
#elif defined(WRITE_SRGB8)
// 2^exposure times the beauty, encoded as toSrgb8() encodes the float beauty; A unused.
layout(location = 0) out uvec4 outBeauty;
uniform float uExposureScale;
#else
layout(location = 0) out vec4 outBeauty;
#endif
#ifdef WITH_IDS
// What WRITE_IDS writes, beside the beauty: the id, and the coverage blended surfaces blend
// over (the float beauty; the 8-bit one has none to blend and keeps the id alone).
layout(location = 1) out vec4 outIds;
uniform float uObjectId;
#endif
#ifdef WRITE_AOVS
layout(location = 1) out vec4 outPositionDistance;  // P.xyz, camera distance
layout(location = 2) out vec4 outNormal;            // shading normal facing the camera
layout(location = 3) out vec4 outVisibility[VISIBILITY_OUTPUTS];
uniform int uVisibilityBase;  // first light whose shadow terms go to outVisibility
// Channels 0 to uScalarTerms - 1 of outVisibility hold the lights' scalar shadow terms; from
// channel uRgbFirst on (-1: none), their RGB terms (the shadow times the translucent casters'
// transmittance), three channels each, as many as fit.
uniform int uScalarTerms;
uniform int uRgbFirst;
#endif
#ifdef WRITE_LAYERS
layout(location = 1) out vec4 outLayerA;  // mode 0: albedo, roughness; mode 1: diffuse
layout(location = 2) out vec4 outLayerB;  // mode 0: metallic, objectId, materialId; 1: specular
uniform int uLayerMode;
uniform int uLayerLight;
uniform float uObjectId;
uniform float uMaterialId;
#endif

vec2 uvFor(int texCoord, mat3 transform) {
  return (transform * vec3(texCoord == 0 ? vIn.uv0 : vIn.uv1, 1.0)).xy;
}

// The mesh's tangent frame at a point of normal N (facing the camera's side of the surface):
// the tangent made orthogonal to N, and the bitangent its handedness and the face give.
void meshTangentFrame(vec3 N, out vec3 T, out vec3 B) {
  T = normalize(vIn.worldTangent.xyz - N * dot(N, vIn.worldTangent.xyz));
  B = cross(N, T) * vIn.worldTangent.w * (gl_FrontFacing ? 1.0 : -1.0);
}

// The normal a tangent-space normal map's `texel` gives at a point of interpolated normal N,
// in the mesh's tangent frame; `axes` and `scale` as uNormalTextureAxes and uNormalScale. The
// base material's and the clearcoat's maps alike.
vec3 mappedNormal(vec3 N, vec3 texel, mat3 axes, float scale) {
  vec3 T, B;
  meshTangentFrame(N, T, B);
  vec3 tangentNormal = texel * 2.0 - 1.0;
  tangentNormal.xy = mat2(axes) * tangentNormal.xy * scale;
  return normalize(mat3(T, B, N) * tangentNormal);
}

void main() {
  vec4 baseColor = uBaseColorFactor * vIn.color;
  if (uBaseColorTexCoord >= 0) baseColor *= texture(uBaseColorTexture, uvFor(uBaseColorTexCoord, uBaseColorUvTransform));
#ifdef AMBIENT_OCCLUSION
  vec2 depthGradient = vec2(dFdx(gl_FragCoord.z), dFdy(gl_FragCoord.z));  // the triangle's plane
#endif
  if (uAlphaMode == 1 && baseColor.a < uAlphaCutoff) discard;
  float alpha = uAlphaMode == 2 ? baseColor.a : 1.0;
#if defined(WRITE_IDS) || defined(WITH_IDS)
  outIds = vec4(uObjectId, alpha, 0.0, alpha);
#endif
#ifdef WRITE_IDS
  return;
#endif

  float metallic = uMetallicFactor;
  float roughness = uRoughnessFactor;
  vec3 specularColor = vec3(0.0);
  if (uSpecularGlossiness != 0) {
    vec4 specularGlossiness = vec4(uSpecularFactor, uGlossinessFactor);
    if (uMetallicRoughnessTexCoord >= 0)
      specularGlossiness *= texture(uMetallicRoughnessTexture,
                                    uvFor(uMetallicRoughnessTexCoord, uMetallicRoughnessUvTransform));
    specularColor = specularGlossiness.rgb;
    roughness = 1.0 - specularGlossiness.a;
    metallic = 0.0;
  } else if (uMetallicRoughnessTexCoord >= 0) {
    vec4 mr = texture(uMetallicRoughnessTexture, uvFor(uMetallicRoughnessTexCoord, uMetallicRoughnessUvTransform));
    roughness *= mr.g;
    metallic *= mr.b;
  }
  metallic = clamp(metallic, 0.0, 1.0);
  roughness = clamp(roughness, 0.0, 1.0);

  vec3 V = normalize(uCameraPosition - vIn.worldPosition);
  // Geometric normal from the triangle itself: robust for back faces and for the shadow bias.
  vec3 Ngeom = normalize(cross(dFdx(vIn.worldPosition), dFdy(vIn.worldPosition)));
  if (dot(Ngeom, V) < 0.0) Ngeom = -Ngeom;

  vec3 N = normalize(vIn.worldNormal);
  if (!gl_FrontFacing) N = -N;  // back faces are only drawn for double-sided materials
  if (uNormalTexCoord >= 0 && uHasTangents != 0) {
    N = mappedNormal(N, texture(uNormalTexture, uvFor(uNormalTexCoord, uNormalUvTransform)).xyz,
                     uNormalTextureAxes, uNormalScale);
  }
  vec3 facingNormal = dot(N, V) < 0.0 ? -N : N;
#ifdef ANISOTROPY
  {
    float strength = uAnisotropyStrength;
    vec2 direction = uAnisotropyRotation;
#ifdef ANISOTROPY_TEXTURE
    if (uAnisotropyTexCoord >= 0) {
      vec3 texel = texture(uAnisotropyTexture, uvFor(uAnisotropyTexCoord, uAnisotropyUvTransform)).rgb;
      vec2 stored = texel.rg * 2.0 - 1.0;
      // A texel of no direction keeps the tangent's, turned.
      if (dot(stored, stored) > 0.0)
        direction = mat2(uAnisotropyRotation.x, uAnisotropyRotation.y, -uAnisotropyRotation.y,
                         uAnisotropyRotation.x) * normalize(stored);
      strength *= texel.b;
    }
#endif
    // In the tangent frame of the shading normal; without tangents the highlights stay round.
    vec3 T, B;
    meshTangentFrame(N, T, B);
    pixelAnisotropy.T = normalize(T * direction.x + B * direction.y);
    pixelAnisotropy.B = normalize(cross(N, pixelAnisotropy.T));
    pixelAnisotropy.stretch = uHasTangents != 0 ? strength * strength : 0.0;
    // Without tangents any frame of the surface (shadows.glsl's): with no stretch the lobe is
    // round whatever its axes.
    if (uHasTangents == 0) tangentFrame(N, pixelAnisotropy.T, pixelAnisotropy.B);
  }
#endif

  float occlusion = 1.0;
  if (uOcclusionTexCoord >= 0)
    occlusion = 1.0 + uOcclusionStrength *
                          (texture(uOcclusionTexture, uvFor(uOcclusionTexCoord, uOcclusionUvTransform)).r - 1.0);
#ifdef AMBIENT_OCCLUSION
  occlusion *= screenSpaceOcclusion(depthGradient);
#endif
  vec3 emissive = uEmissive;
  if (uEmissiveTexCoord >= 0) emissive *= texture(uEmissiveTexture, uvFor(uEmissiveTexCoord, uEmissiveUvTransform)).rgb;

#ifdef SHEEN
  vec3 sheenColor = uSheenColorFactor;
  float sheenRoughness = uSheenRoughnessFactor;
#ifdef SHEEN_TEXTURE
  if (uSheenColorTexCoord >= 0)
    sheenColor *= texture(uSheenTexture, uvFor(uSheenColorTexCoord, uSheenColorUvTransform)).rgb;
  if (uSheenRoughnessTexCoord >= 0)
    sheenRoughness *= texture(uSheenRoughnessTexture, uvFor(uSheenRoughnessTexCoord, uSheenRoughnessUvTransform)).a;
#endif
  Sheen sheen = sheenAt(sheenColor, sheenRoughness, max(dot(N, V), 1e-4));
#endif

#ifdef DIELECTRIC_SPECULAR
  float specularWeight = uSpecularWeight;
  vec3 specularColorFactor = uSpecularColorFactor;
#ifdef SPECULAR_TEXTURE
  if (uSpecularTexCoord >= 0)
    specularWeight *= texture(uSpecularTexture, uvFor(uSpecularTexCoord, uSpecularUvTransform)).a;
#endif
#ifdef SPECULAR_COLOR_TEXTURE
  if (uSpecularColorTexCoord >= 0)
    specularColorFactor *= texture(uSpecularColorTexture, uvFor(uSpecularColorTexCoord, uSpecularColorUvTransform)).rgb;
#endif
  // The dielectric's reflectance at normal incidence, as KHR_materials_specular writes it.
  vec3 specularF0 = min(uDielectricF0 * specularColorFactor, vec3(1.0)) * specularWeight;
#endif
#ifdef CLEARCOAT
  float clearcoatFactor = uClearcoatFactor;
  float clearcoatRoughness = uClearcoatRoughnessFactor;
#ifdef CLEARCOAT_TEXTURE
  if (uClearcoatTexCoord >= 0)
    clearcoatFactor *= texture(uClearcoatTexture, uvFor(uClearcoatTexCoord, uClearcoatUvTransform)).r;
#endif
#ifdef CLEARCOAT_ROUGHNESS_TEXTURE
  if (uClearcoatRoughnessTexCoord >= 0)
    clearcoatRoughness *= texture(uClearcoatRoughnessTexture,
                                  uvFor(uClearcoatRoughnessTexCoord, uClearcoatRoughnessUvTransform)).g;
#endif
  // Without a normal texture of its own the layer follows the interpolated normal, not the
  // base's normal map (the specification).
  vec3 Nc = normalize(vIn.worldNormal);
  if (!gl_FrontFacing) Nc = -Nc;
#ifdef CLEARCOAT_NORMAL_TEXTURE
  if (uClearcoatNormalTexCoord >= 0 && uHasTangents != 0) {
    Nc = mappedNormal(Nc,
                      texture(uClearcoatNormalTexture,
                              uvFor(uClearcoatNormalTexCoord, uClearcoatNormalUvTransform)).xyz,
                      uClearcoatNormalTextureAxes, uClearcoatNormalScale);
  }
#endif
  Clearcoat coat = clearcoatAt(clamp(clearcoatFactor, 0.0, 1.0), clamp(clearcoatRoughness, 0.0, 1.0), Nc, V);
#endif

#if defined(TRANSMISSION) || defined(DIFFUSE_TRANSMISSION)
  // What the dielectric's Fresnel towards the camera leaves of light that passes through.
#ifdef DIELECTRIC_SPECULAR
  vec3 throughF = specularF0 + (vec3(specularWeight) - specularF0) *
                                  fresnelSchlick(vec3(0.0), max(dot(N, V), 0.0)).r;
  float transmitted = 1.0 - max(throughF.r, max(throughF.g, throughF.b));
#else
  float transmitted = 1.0 - fresnelSchlick(vec3(uDielectricF0), max(dot(N, V), 0.0)).r;
#endif
#endif
#ifdef TRANSMISSION
  float transmission = uTransmissionFactor;
#ifdef TRANSMISSION_TEXTURE
  if (uTransmissionTexCoord >= 0)
    transmission *= texture(uTransmissionTexture, uvFor(uTransmissionTexCoord, uTransmissionUvTransform)).r;
#endif
  transmission = uUnlit != 0 ? 0.0 : clamp(transmission, 0.0, 1.0);
  // The dielectric part alone lets light through, and only what its Fresnel towards the camera
  // does not reflect: each light's diffuse keeps 1 - transmission, and `through` x base color
  // of the light from behind comes in its place.
  float through = transmission * (1.0 - metallic) * transmitted;
  // The specification's roughness of the transmission lobe: none at an ior of 1.
  float throughRoughness = roughness * clamp(uIor * 2.0 - 2.0, 0.0, 1.0);
  float throughAlpha = max(throughRoughness * throughRoughness, 1e-3);
  vec3 ambientBase = baseColor.rgb * (1.0 - transmission * (1.0 - metallic));
#ifdef VOLUME
  float thickness = uThicknessFactor;
#ifdef THICKNESS_TEXTURE
  if (uThicknessTexCoord >= 0)
    thickness *= texture(uThicknessTexture, uvFor(uThicknessTexCoord, uThicknessUvTransform)).g;
#endif
  // The mesh's units along each of its axes, whatever its rotation.
  vec3 modelScale = vec3(length(uModel[0].xyz), length(uModel[1].xyz), length(uModel[2].xyz));
  vec3 volumeRay = volumeRayFor(uIor, N, V, thickness, modelScale);
#ifdef DISPERSION
  float halfSpread = (uIor - 1.0) * 0.025 * uDispersion;
  vec3 redRay = volumeRayFor(max(uIor - halfSpread, 1.0), N, V, thickness, modelScale);
  vec3 blueRay = volumeRayFor(uIor + halfSpread, N, V, thickness, modelScale);
  vec3 volumeTransmittance = exp(-uAttenuationCoefficient *
                                 vec3(length(redRay), length(volumeRay), length(blueRay)));
#else
  vec3 volumeTransmittance = exp(-uAttenuationCoefficient * length(volumeRay));
#endif
#endif
#else
  vec3 ambientBase = baseColor.rgb;
#endif
#ifdef DIFFUSE_TRANSMISSION
  float diffuseTransmission = uDiffuseTransmissionFactor;
#ifdef DIFFUSE_TRANSMISSION_TEXTURE
  if (uDiffuseTransmissionTexCoord >= 0)
    diffuseTransmission *= texture(uDiffuseTransmissionTexture,
                                   uvFor(uDiffuseTransmissionTexCoord, uDiffuseTransmissionUvTransform)).a;
#endif
  vec3 diffuseTransmissionColor = uDiffuseTransmissionColorFactor;
#ifdef DIFFUSE_TRANSMISSION_COLOR_TEXTURE
  if (uDiffuseTransmissionColorTexCoord >= 0)
    diffuseTransmissionColor *= texture(uDiffuseTransmissionColorTexture,
                                        uvFor(uDiffuseTransmissionColorTexCoord,
                                              uDiffuseTransmissionColorUvTransform)).rgb;
#endif
  diffuseTransmission = uUnlit != 0 ? 0.0 : clamp(diffuseTransmission, 0.0, 1.0);
  // The ambient arrives from both sides: the diffuse reflection keeps 1 - the fraction, and the
  // light through the surface brings the fraction of the color.
  ambientBase = mix(ambientBase, diffuseTransmissionColor, diffuseTransmission);
#endif
#ifdef IRIDESCENCE
  Iridescence film;
  {
    float strength = uIridescenceFactor;
#ifdef IRIDESCENCE_TEXTURE
    if (uIridescenceTexCoord >= 0)
      strength *= texture(uIridescenceTexture, uvFor(uIridescenceTexCoord, uIridescenceUvTransform)).r;
#endif
    float thickness = uIridescenceThicknessMaximum;
#ifdef IRIDESCENCE_THICKNESS_TEXTURE
    if (uIridescenceThicknessTexCoord >= 0)
      thickness = mix(uIridescenceThicknessMinimum, uIridescenceThicknessMaximum,
                      texture(uIridescenceThicknessTexture,
                              uvFor(uIridescenceThicknessTexCoord, uIridescenceThicknessUvTransform)).g);
#endif
#ifdef DIELECTRIC_SPECULAR
    vec3 filmBaseF0 = specularF0;
#else
    vec3 filmBaseF0 = vec3(uDielectricF0);
#endif
    float cosView = clamp(dot(N, V), 0.0, 1.0);
    film.strength = thickness > 0.0 ? clamp(strength, 0.0, 1.0) : 0.0;
    // A base that weighs 0 everywhere (metallic 0 or 1 throughout) takes no film: mix() with a
    // weight of 0 or 1 leaves the other's value exactly.
#ifdef IRIDESCENCE_METAL_ONLY
    film.dielectric = vec3(0.0);
#else
    film.dielectric = iridescentFresnel(uIridescenceIor, filmBaseF0, thickness, cosView);
#endif
#ifdef IRIDESCENCE_DIELECTRIC_ONLY
    film.metal = vec3(0.0);
#else
    film.metal = iridescentFresnel(uIridescenceIor, baseColor.rgb, thickness, cosView);
#endif
  }
#endif
  float cameraDistance = length(uCameraPosition - vIn.worldPosition);
#ifdef SHEEN
  // Towards the camera, the sheen reflects E(N.V) of light arriving evenly from everywhere (the
  // ambient), and leaves 1 - max(sheenColor) E(N.V) of it to the base material.
  vec3 color = uAmbient * (ambientBase * sheen.scalingV + sheenColor * sheen.albedoV) * occlusion + emissive;
#else
  vec3 color = uAmbient * ambientBase * occlusion + emissive;
#endif
#ifdef ENVIRONMENT
  // The environment as each light is reflected below (the same layers, weights and Fresnel),
  // with each lobe's response to light from everywhere taken from the split-sum table.
  {
    float envNdotV = clamp(dot(N, V), 1e-4, 1.0);
    vec2 envBrdf = environmentBrdf(envNdotV, roughness);
    vec3 envR = reflect(-V, N);
#ifdef ANISOTROPY
    // The lobe stretched along the anisotropy direction reflects what a normal bent towards
    // it does (the Khronos sample viewer's bent normal).
    {
      float strength = sqrt(pixelAnisotropy.stretch);
      vec3 bent = normalize(cross(cross(pixelAnisotropy.B, V), pixelAnisotropy.B));
      float keep = 1.0 - strength * (1.0 - roughness);
      keep *= keep;
      envR = reflect(-V, normalize(mix(bent, N, keep * keep)));
    }
#endif
    vec3 envPrefiltered = environmentSpecular(envR, roughness);
    vec3 envIrradiance = environmentDiffuse(N);
    vec3 envDiffuse, envSpecular;
#ifdef SHADING_PHONG
    envDiffuse = envIrradiance * baseColor.rgb;
#ifdef DIELECTRIC_SPECULAR
    envSpecular = envPrefiltered * specularF0;
#else
    envSpecular = envPrefiltered * uDielectricF0;
#endif
#else
    if (uSpecularGlossiness != 0) {
      envSpecular = envPrefiltered * (specularColor * envBrdf.x + envBrdf.y);
      envDiffuse = envIrradiance * baseColor.rgb *
                   (1.0 - max(specularColor.r, max(specularColor.g, specularColor.b)));
    } else {
#ifdef DIELECTRIC_SPECULAR
      vec3 envDielectric = specularF0 * envBrdf.x + specularWeight * envBrdf.y;
#else
      vec3 envDielectric = vec3(uDielectricF0 * envBrdf.x + envBrdf.y);
#endif
      vec3 envMetal = baseColor.rgb * envBrdf.x + envBrdf.y;
#ifdef IRIDESCENCE
      // The film's Fresnel towards the camera in place of Schlick's, over the lobe's albedo.
      envDielectric = mix(envDielectric, film.dielectric * (envBrdf.x + envBrdf.y), film.strength);
      envMetal = mix(envMetal, film.metal * (envBrdf.x + envBrdf.y), film.strength);
#endif
      envSpecular = envPrefiltered * mix(envDielectric, envMetal, metallic);
      // What the dielectric's lobe does not reflect, it diffuses.
      envDiffuse = envIrradiance * baseColor.rgb * (1.0 - metallic) *
                   (1.0 - max(envDielectric.r, max(envDielectric.g, envDielectric.b)));
    }
#endif
#ifdef TRANSMISSION
    // The transmitted part arrives from behind (below), as each light's does.
    envDiffuse *= 1.0 - transmission;
#endif
#ifdef DIFFUSE_TRANSMISSION
    envDiffuse = envDiffuse * (1.0 - diffuseTransmission) +
                 diffuseTransmission * (1.0 - metallic) * transmitted * diffuseTransmissionColor *
                     environmentDiffuse(-N);
#endif
    vec3 envColor = envDiffuse + envSpecular;
#ifdef SHEEN
    // The sheen's lobe is broad: it reflects about the cosine-weighted mean of the radiance.
    envColor = envColor * sheen.scalingV + sheenColor * sheen.albedoV * envIrradiance;
#endif
    color += envColor * occlusion;
  }
#endif
#ifdef CLEARCOAT
  // The layer reflects the ambient with its weight (its lobe's albedo taken as 1) and covers
  // the emission and the ambient the layers below reflect.
  color = color * (1.0 - coat.weight) + coat.weight * uAmbient * occlusion;
#ifdef ENVIRONMENT
  {
    float coatRoughness = clamp(clearcoatRoughness, 0.0, 1.0);
    vec2 coatBrdf = environmentBrdf(coat.NdotV, coatRoughness);
    color += clamp(clearcoatFactor, 0.0, 1.0) * (0.04 * coatBrdf.x + coatBrdf.y) *
             environmentSpecular(reflect(-V, coat.N), coatRoughness) * occlusion;
  }
#endif
#endif
#ifdef TRANSMISSION
  // What comes through from behind, under the sheen and the clearcoat; the fraction of the
  // background it lets through also sets the pixel's coverage (below).
  vec3 throughFactor = through * baseColor.rgb;
#ifdef VOLUME
  throughFactor *= volumeTransmittance;
  vec2 behindCoord = behindCoordOf(vIn.worldPosition + volumeRay);
#endif
#ifdef SHEEN
  throughFactor *= sheen.scalingV;
#endif
#ifdef CLEARCOAT
  throughFactor *= 1.0 - coat.weight;
#endif
  vec2 behindSize = vec2(textureSize(uSceneBehind, 0));
#ifndef VOLUME
  vec2 behindCoord = gl_FragCoord.xy / behindSize;
#endif
  float behindLevel = log2(max(behindSize.x, behindSize.y)) * throughRoughness;
  vec4 behind = textureLod(uSceneBehind, behindCoord, behindLevel);
#ifdef DISPERSION
  behind.r = textureLod(uSceneBehind, behindCoordOf(vIn.worldPosition + redRay), behindLevel).r;
  behind.b = textureLod(uSceneBehind, behindCoordOf(vIn.worldPosition + blueRay), behindLevel).b;
#endif
  color += throughFactor * behind.rgb;
#endif
#ifdef WRITE_AOVS
  float visibility[4 * VISIBILITY_OUTPUTS];
  for (int i = 0; i < 4 * VISIBILITY_OUTPUTS; ++i) visibility[i] = 1.0;
#endif
#ifdef WRITE_LAYERS
  vec3 layerDiffuse = vec3(0.0), layerSpecular = vec3(0.0);
#endif
#ifdef DEBUG_VIEWS
  float shadowSum = 0.0;
  int shadowedLights = 0;
  int contributing = 0;
  float depthView = 1.0;
  int debugCascade = -1;
#endif
  // The lights the loop visits. A layer pass writes no beauty that is read: material layers
  // (mode 0) need no light, one light's diffuse and specular (mode 1) only that light.
  bool noLights = uUnlit != 0;
  int firstLight = 0, endLight = uLightCount;
#ifdef WRITE_LAYERS
  noLights = noLights || uLayerMode == 0;
  if (uLayerMode == 1) {
    firstLight = uLayerLight;
    endLight = uLayerLight + 1;
  }
#endif
#ifdef CLUSTERED_LIGHTS
  // The lights reaching everywhere, then those of this point's cluster (the lights whose
  // range may reach it).
  ivec2 tile = ivec2(gl_FragCoord.xy) / uTileSize;
  float viewDepth = dot(uViewDepth.xyz, vIn.worldPosition) + uViewDepth.w;
  int slice = int(clamp(floor(log(max(viewDepth, 1e-30) / uSliceNear) * uSliceScale), 0.0,
                        float(uSlices - 1)));
  int cluster = (slice * uTileRows + tile.y) * uTileColumns + tile.x;
  uint firstClusterLight = uClusterRanges[2 * cluster];
  uint lightCount = noLights ? 0u : uint(uGlobalLights) + uClusterRanges[2 * cluster + 1];
  for (uint k = 0u; k < lightCount; ++k) {
    uint entry = k < uint(uGlobalLights) ? k : firstClusterLight + (k - uint(uGlobalLights));
    int i = int(uClusterLights[entry]);
#elif defined(FACING_LIGHT_LOOP)
  // At most 32 lights, none with a range. A light that the shading normal of every pixel of
  // this invocation's lane group faces away from adds exactly nothing there (shadeBrdf and
  // shadePhong return 0 for N.L <= 0), so the loop visits only the lights some pixel of the
  // group may face. llvmpipe runs both sides of every branch, but a loop only while some lane
  // is in it: with the group's mask the same in all lanes (a ballot), each light the group
  // skips saves its shadow lookup and BRDF (a clearcoat's lobe follows its own normal, so a
  // coated pixel keeps the lights either normal faces). The test keeps a margin of 1e-4 in
  // N.L, so that the lights it leaves out are those the BRDF would have found facing away,
  // whatever the rounding; a NaN normal keeps every light, as before.
  uint groupLights = 0u;
  for (int i = 0; i < (noLights ? 0 : uLightCount); ++i) {
    vec3 toLight = towardsLight(uLights[i], vIn.worldPosition);
    bool awayFromLight = dot(N, toLight) <= -1e-4 * length(toLight);
#ifdef CLEARCOAT
    awayFromLight = awayFromLight && dot(coat.N, toLight) <= -1e-4 * length(toLight);
#endif
#if defined(TRANSMISSION) || defined(DIFFUSE_TRANSMISSION)
    awayFromLight = false;  // a light behind the surface shines through it
#endif
    if (ballotARB(!awayFromLight) != 0ul) groupLights |= 1u << uint(i);
  }
  // do-while: a loop's exit test sits at its end, so a `while` would run its body once more,
  // with every lane masked, after the last light.
  uint pendingLights = groupLights;
  do {
    int i = findLSB(pendingLights);  // -1: none (the body then runs once, masked)
    pendingLights &= pendingLights - 1u;
    if (i < 0) break;
#else
  // No light has a range: every light reaches everywhere, and the clusters would list them all.
  for (int i = firstLight; i < (noLights ? 0 : endLight); ++i) {
#endif
    Light light = uLights[i];
    vec3 L, radiance;
    float distance;
    incidentLight(light, vIn.worldPosition, L, radiance, distance);
    float shadow = 1.0;
    vec3 transmittance = vec3(1.0);
    // Lights that do not reach P (range, cone) need no shadow lookup.
    bool reaches = any(greaterThan(radiance, vec3(0.0)));
    if (reaches && shadowGroup(light) >= 0) {
      // The bias uses the geometric normal on the light's side of the surface.
      vec3 Nlight = dot(Ngeom, L) >= 0.0 ? Ngeom : -Ngeom;
      shadow = shadowVisibility(light, vIn.worldPosition, Nlight, L, cameraDistance, transmittance);
    }
    vec3 shadowColor = vec3(shadow);
#ifdef TRANSLUCENT_SHADOWS
    // Lights with translucent casters: the scalar term is the mean of the RGB one.
    if (light.shadowProjection.z != 0.0) {
      shadowColor = shadow * transmittance;
      shadow = (shadowColor.r + shadowColor.g + shadowColor.b) / 3.0;
    }
#endif
#ifdef DEBUG_VIEWS
    if (reaches && shadowGroup(light) >= 0) {
      shadowSum += shadow;
      ++shadowedLights;
    }
#endif
#ifdef DEBUG_DEPTH
    if (i == uDebugLight) depthView = shadowDepthView(light, vIn.worldPosition);
    if (i == uDebugLight) debugCascade = shadowCascade(light, vIn.worldPosition);
#endif
#ifdef WRITE_AOVS
    int slot = i - uVisibilityBase;
    if (slot >= 0 && slot < uScalarTerms) visibility[slot] = shadow;
    if (uRgbFirst >= 0)
      for (int c = 0; c < 3; ++c) {
        int channel = uRgbFirst + 3 * slot + c;
        if (slot >= 0 && channel < 4 * VISIBILITY_OUTPUTS) visibility[channel] = shadowColor[c];
      }
#endif
    if (max(max(shadowColor.r, shadowColor.g), shadowColor.b) <= 0.0) continue;
    vec3 diffuse, specular;
#ifdef SHADING_PHONG
#ifdef DIELECTRIC_SPECULAR
    shadePhong(N, V, L, radiance, baseColor.rgb, roughness, specularF0, diffuse, specular);
#else
    shadePhong(N, V, L, radiance, baseColor.rgb, roughness, vec3(uDielectricF0), diffuse, specular);
#endif
#else
    if (uSpecularGlossiness != 0)
      shadeSpecularGlossiness(N, V, L, radiance, baseColor.rgb, specularColor, roughness, diffuse,
                              specular);
    else
#if defined(IRIDESCENCE) && defined(DIELECTRIC_SPECULAR)
      shadePbrSpecularIridescent(N, V, L, radiance, baseColor.rgb, metallic, roughness,
                                 uDielectricF0, specularWeight, specularColorFactor, film,
                                 diffuse, specular);
#elif defined(IRIDESCENCE)
      shadePbrIridescent(N, V, L, radiance, baseColor.rgb, metallic, roughness, uDielectricF0,
                         film, diffuse, specular);
#elif defined(DIELECTRIC_SPECULAR)
      shadePbrSpecular(N, V, L, radiance, baseColor.rgb, metallic, roughness, uDielectricF0,
                       specularWeight, specularColorFactor, diffuse, specular);
#else
      shadePbr(N, V, L, radiance, baseColor.rgb, metallic, roughness, uDielectricF0, diffuse,
               specular);
#endif
#ifdef TRANSMISSION
#ifdef VOLUME
    // Seen from where the view ray leaves the volume, and attenuated on the way.
    vec3 throughL = normalize(L * distance - volumeRay);
    diffuse = diffuse * (1.0 - transmission) +
              through * baseColor.rgb * volumeTransmittance *
                  transmittedRadiance(N, V, throughL, radiance, throughAlpha);
#else
    diffuse = diffuse * (1.0 - transmission) +
              through * baseColor.rgb * transmittedRadiance(N, V, L, radiance, throughAlpha);
#endif
#endif
#ifdef DIFFUSE_TRANSMISSION
    // The specification's mix of the diffuse BRDF and BTDF: Lambert of the color for a light
    // behind, under what the dielectric's Fresnel towards the camera leaves.
    diffuse = diffuse * (1.0 - diffuseTransmission) +
              diffuseTransmission * (1.0 - metallic) * transmitted * diffuseTransmissionColor /
                  PI * radiance * max(-dot(N, L), 0.0);
#endif
#ifdef SHEEN
    addSheen(sheen, N, V, L, radiance, diffuse, specular);
#endif
#ifdef CLEARCOAT
    addClearcoat(coat, V, L, radiance, diffuse, specular);
#endif
#endif
    color += shadowColor * (diffuse + specular);
#ifdef DEBUG_VIEWS
    if (any(greaterThan(diffuse + specular, vec3(0.0)))) ++contributing;
#endif
#ifdef WRITE_LAYERS
    if (i == uLayerLight) {
      layerDiffuse = shadowColor * diffuse;
      layerSpecular = shadowColor * specular;
    }
#endif
#ifdef FACING_LIGHT_LOOP
  } while (pendingLights != 0u);
#else
  }
#endif

  if (uUnlit != 0) color = baseColor.rgb;
#ifdef DEBUG_VIEWS
  if (uDebugView == DEBUG_VIEW_SHADOW) color = vec3(shadowedLights > 0 ? shadowSum / float(shadowedLights) : 1.0);
  if (uDebugView == DEBUG_VIEW_DEPTH) color = vec3(depthView);
  if (uDebugView == DEBUG_VIEW_NORMALS) color = facingNormal * 0.5 + 0.5;
  if (uDebugView == DEBUG_VIEW_ALBEDO) color = baseColor.rgb;
  if (uDebugView == DEBUG_VIEW_CASCADE) color = cascadeDebugColor(debugCascade, color);
  if (uDebugView == DEBUG_VIEW_LIGHT_COUNT) color = vec3(float(contributing) / float(max(uLightCount, 1)));
  if (uDebugView == DEBUG_VIEW_OCCLUSION) color = vec3(occlusion);
#endif
#if defined(WRITE_SRGB8)
  // The float the RGBA32F target would hold, scaled as the CPU scales it: the same products.
  outBeauty = srgb8((color * alpha) * uExposureScale);
#elif !defined(WRITE_IDS)
#if defined(TRANSMISSION) && !defined(DEBUG_VIEWS)
  // Premultiplied already (what shows from behind came with its coverage): the surface covers
  // all but what it lets through of the background where nothing lies behind it.
  outBeauty = vec4(color, 1.0 - (1.0 - behind.a) * (throughFactor.r + throughFactor.g + throughFactor.b) / 3.0);
#else
  outBeauty = vec4(color * alpha, alpha);  // premultiplied, A = coverage
#endif
#endif
#ifdef WRITE_AOVS
  outPositionDistance = vec4(vIn.worldPosition, cameraDistance);
  outNormal = vec4(facingNormal, occlusion);  // A: the occlusion AOV layer
  for (int o = 0; o < VISIBILITY_OUTPUTS; ++o)
    outVisibility[o] = vec4(visibility[4 * o], visibility[4 * o + 1], visibility[4 * o + 2],
                            visibility[4 * o + 3]);
#endif
#ifdef WRITE_LAYERS
  if (uLayerMode == 0) {
    outLayerA = vec4(baseColor.rgb, roughness);
    outLayerB = vec4(metallic, uObjectId, uMaterialId, 0.0);
  } else {
    outLayerA = vec4(layerDiffuse, 0.0);
    outLayerB = vec4(layerSpecular, 0.0);
  }
#endif
}
