// Punctual lights as KHR_lights_punctual defines them. Layout mirrors contract::GpuLight;
// LIGHT_*, FILTER_* and the bindings come from renderer/passes/shader_contract.h.
struct Light {
  vec4 positionRange;     // world position, range (0 = unlimited)
  vec4 directionType;     // direction the light travels, type
  vec4 radianceShadow;    // color * intensity, shadow group (-1 = unshadowed)
  vec4 spotFilter;        // cone scale, cone offset, filter, shadow resolution
  vec4 shadowDepth;       // near, far, constant bias (world), slope bias (texels)
  vec4 shadowBias;        // min bias (texels), normal bias (texels), filter radius, samples
  vec4 shadowSoft;        // source radius, vsm bleed reduction, first layer, layer count
  vec4 shadowProjection;  // spot: tan(half fov); first entry in uShadowViewProjections;
                          // 1 when translucent casters tint the shadow
  vec4 cascadeEnd;        // directional: camera view depth where each cascade ends
  vec4 cascadeTexel;      // directional: world size of a texel in each cascade
};

// LIGHTS_IN_STORAGE: more lights or view-projections than the uniform blocks hold
// (renderer/passes/shader_contract.h); the blocks are the faster read on llvmpipe.
#ifdef LIGHTS_IN_STORAGE
layout(std430, binding = LIGHTS_BINDING) readonly buffer LightBuffer {
  Light uLights[];
};
#else
layout(std140, binding = LIGHTS_UNIFORM_BINDING) uniform LightBlock {
  Light uLights[MAX_UNIFORM_LIGHTS];
};
#endif
uniform int uLightCount;

// Spot lights: one view-projection; directional: one per cascade. Kept out of `Light` so the
// shading loop's copy of a light stays small.
#ifdef LIGHTS_IN_STORAGE
layout(std430, binding = SHADOW_VIEW_PROJECTIONS_BINDING) readonly buffer ShadowViewProjections {
  mat4 uShadowViewProjections[];
};
#else
layout(std140, binding = SHADOW_VIEW_PROJECTIONS_UNIFORM_BINDING) uniform ShadowViewProjectionBlock {
  mat4 uShadowViewProjections[MAX_UNIFORM_VIEW_PROJECTIONS];
};
#endif

// KHR_lights_punctual's recommended range window: smooth to zero at the range.
float rangeWindow(float distance, float range) {
  if (range <= 0.0) return 1.0;
  float ratio = distance / range;
  float ratio4 = ratio * ratio * ratio * ratio;
  float window = clamp(1.0 - ratio4, 0.0, 1.0);
  return window * window;
}

// From P towards the light, not normalized: to its position, or against a directional light's
// direction.
vec3 towardsLight(Light light, vec3 P) {
#ifdef DIRECTIONAL_LIGHTS
  if (int(light.directionType.w) == LIGHT_DIRECTIONAL) return -light.directionType.xyz;
#endif
  return light.positionRange.xyz - P;
}

// Direction towards the light (L) and the radiance arriving at P, unshadowed. The pass is
// compiled for the light types the frame has (DIRECTIONAL_LIGHTS, SPOT_LIGHTS) and, without
// CLUSTERED_LIGHTS, for lights without a range (renderer/passes/lighting_pass.cpp): llvmpipe
// runs every branch in every fragment, so code for what the frame lacks would cost each one.
void incidentLight(Light light, vec3 P, out vec3 L, out vec3 radiance, out float distance) {
  int type = int(light.directionType.w);
#ifdef DIRECTIONAL_LIGHTS
  if (type == LIGHT_DIRECTIONAL) {
    L = -light.directionType.xyz;
    radiance = light.radianceShadow.rgb;
    distance = 1e30;
    return;
  }
#endif
  vec3 toLight = light.positionRange.xyz - P;  // towardsLight(), the directional case handled
  distance = length(toLight);
  L = toLight / max(distance, 1e-8);
#ifdef CLUSTERED_LIGHTS
  float attenuation = rangeWindow(distance, light.positionRange.w) / max(distance * distance, 1e-8);
#else
  float attenuation = 1.0 / max(distance * distance, 1e-8);  // rangeWindow() would be 1
#endif
#ifdef SPOT_LIGHTS
  if (type == LIGHT_SPOT) {
    float cd = dot(light.directionType.xyz, -L);
    float t = clamp(cd * light.spotFilter.x + light.spotFilter.y, 0.0, 1.0);
    attenuation *= t * t;
  }
#endif
  radiance = light.radianceShadow.rgb * attenuation;
}
