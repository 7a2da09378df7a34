// Point-light shadows from depth cube maps. The maps store hardware depth of a 90 degree
// reversed-Z projection per face (renderer/cube_faces.cpp), i.e. a function of the distance
// along the face's major axis; comparisons happen in that depth space with the reference built
// from the fragment's own axis distance, so hardware comparison and filtering work.
const int MAX_POINT_SHADOWS = 16;
layout(binding = 8) uniform samplerCubeShadow uPointShadows[MAX_POINT_SHADOWS];

float axisDistanceToDepth(float z, float near, float far) {
  return near * (far - z) / (z * (far - near));
}

// Visibility (1 = lit) of the point P from the light, for one comparison in direction d
// (light to receiver) against a receiver at distance `distance` minus `bias` along d.
float compareCube(int index, vec3 d, float bias, float near, float far) {
  float distance = length(d);
  float axis = max(abs(d.x), max(abs(d.y), abs(d.z)));
  float z = (distance - bias) * axis / distance;
  // Receivers beyond `far` compare against the cleared depth 0 and so are lit unless a caster
  // within `far` hides them; receivers nearer than `near` are lit.
  float reference = clamp(axisDistanceToDepth(max(z, 1e-6), near, far), 0.0, 1.0);
  return texture(uPointShadows[index], vec4(d, reference));
}

const vec3 PCF_DISK_DIRECTIONS[20] = vec3[](
    vec3(1, 1, 1), vec3(1, -1, 1), vec3(-1, -1, 1), vec3(-1, 1, 1),
    vec3(1, 1, -1), vec3(1, -1, -1), vec3(-1, -1, -1), vec3(-1, 1, -1),
    vec3(1, 1, 0), vec3(1, -1, 0), vec3(-1, -1, 0), vec3(-1, 1, 0),
    vec3(1, 0, 1), vec3(-1, 0, 1), vec3(1, 0, -1), vec3(-1, 0, -1),
    vec3(0, 1, 1), vec3(0, -1, 1), vec3(0, -1, -1), vec3(0, 1, -1));

// Shadow term for a point light; Ngeom is the geometric normal facing the light's side.
float pointShadowVisibility(Light light, vec3 P, vec3 Ngeom, float cameraDistance) {
  int index = int(light.radianceShadow.w);
  if (index < 0) return 1.0;
  float near = light.shadowParameters.x;
  float far = light.shadowParameters.y;
  float resolution = light.spotFilter.w;
  int filterMode = int(light.spotFilter.z);

  vec3 d = P - light.positionRange.xyz;
  float distance = length(d);
  float axis = max(abs(d.x), max(abs(d.y), abs(d.z)));
  // Bias in world units along the ray: constant + slope-scaled in texels of this depth
  // (renderer/shadow_bias.h documents the formula).
  float texel = 2.0 * axis / resolution;
  float cosTheta = clamp(abs(dot(Ngeom, -d / distance)), 1e-4, 1.0);
  float tanTheta = min(sqrt(1.0 - cosTheta * cosTheta) / cosTheta, 10.0);
  float bias = light.shadowParameters.z + light.shadowParameters.w * texel * (1.0 + tanTheta);

  if (filterMode != FILTER_PCF_DISK) return compareCube(index, d, bias, near, far);

  // Classic 20-direction disk, radius growing with the distance to the camera; taps are moved
  // within the receiver's tangent plane so each compares against its own exact distance.
  float radius = (1.0 + cameraDistance / far) * 1.5 * texel;
  float sum = 0.0;
  for (int i = 0; i < 20; ++i) {
    vec3 offset = PCF_DISK_DIRECTIONS[i];
    offset -= Ngeom * dot(offset, Ngeom);
    sum += compareCube(index, d + offset * radius, bias, near, far);
  }
  return sum / 20.0;
}
