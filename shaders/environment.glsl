// An environment light (renderer/passes/environment_textures.h): the light arriving from every
// direction, as equirectangular textures prefiltered on the CPU (renderer/view/environment_map.h).
// The split-sum approximation (Karis 2013): a surface reflects the radiance prefiltered at its
// roughness around R, times F0 A + F90 B from the BRDF table; it diffuses E(N) / pi.
layout(binding = ENVIRONMENT_SPECULAR_UNIT) uniform sampler2D uEnvironmentSpecular;
layout(binding = ENVIRONMENT_IRRADIANCE_UNIT) uniform sampler2D uEnvironmentIrradiance;
layout(binding = ENVIRONMENT_BRDF_UNIT) uniform sampler2D uEnvironmentBrdf;
uniform mat3 uEnvironmentRotation;  // a world direction into the image's frame
uniform vec3 uEnvironmentScale;     // color x intensity
uniform float uEnvironmentMaxLevel;  // the specular texture's last level: roughness 1

// environment_map.h's equirectCoordinates(), in the image's frame: the middle column looks
// along -Z, row 0 along +Y.
vec2 environmentCoordinates(vec3 direction) {
  vec3 d = uEnvironmentRotation * direction;
  // At the poles every column is the same direction; atan(0, 0) is undefined in GLSL.
  float u = (d.x == 0.0 && d.z == 0.0) ? 0.5 : 0.5 + atan(d.x, -d.z) * (0.5 / PI);
  return vec2(u, acos(clamp(d.y / length(d), -1.0, 1.0)) * (1.0 / PI));
}

// The radiance a white Lambertian surface of normal N reflects: E(N) / pi.
vec3 environmentDiffuse(vec3 N) {
  return uEnvironmentScale * textureLod(uEnvironmentIrradiance, environmentCoordinates(N), 0.0).rgb;
}

// The radiance around R prefiltered with the GGX lobe of `roughness` (perceptual).
vec3 environmentSpecular(vec3 R, float roughness) {
  return uEnvironmentScale *
         textureLod(uEnvironmentSpecular, environmentCoordinates(R), roughness * uEnvironmentMaxLevel).rgb;
}

// (A, B): the GGX lobe's directional albedo is F0 A + F90 B. The table's texel centres lie at
// (i + 0.5) / size in both n.v and roughness, as a texture's do.
vec2 environmentBrdf(float NdotV, float roughness) {
  return textureLod(uEnvironmentBrdf, vec2(NdotV, roughness), 0.0).rg;
}
