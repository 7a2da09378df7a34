// Shadow terms of every light type from the frame's shadow atlas (renderer/view/shadow_plan.h):
// point lights in cube map arrays, spot lights and directional cascades in 2D arrays, each
// group of lights sharing a texture. All maps store reversed depth (nearer = larger), so a
// receiver is lit when its own depth is at least the stored one (GL_GEQUAL samplers).
//
// Bias (README, "Shadow settings"): the receiver moves along its geometric normal by
// normalBias texels (default 0) and towards the light by bias + texel * max(slopeBias * tan,
// minBias), tan being the tangent of the angle between the geometric normal and the light (N.L
// floored at 0.05), a texel the world size of one shadow-map texel at the receiver: a plane's
// depth changes by tan texels per texel across the map, so this follows what the lookup needs
// without the sideways step of a normal offset, which carried the lookup past casters in
// creases (issue 18). Filter taps lie in the receiver's tangent plane, so each compares against
// its own exact depth.
//
// The pass is compiled for the light types and filters the frame uses (SHADOW_CUBE,
// SHADOW_PLANAR, SHADOW_<FILTER>, renderer/passes/lighting_pass.cpp): llvmpipe runs both sides of
// every branch with lane masks, so code for absent features would cost every pixel.
//
// Each sampler array's size, SHADOW_SLOTS (at most MAX_SHADOW_GROUPS), is the frame's number of
// groups of the layout that has more (renderer/passes/lighting_pass.cpp): llvmpipe compiles an
// array's texture code once per slot when the index is not a constant, which a cold shader
// cache pays for. Only the arrays the frame's filters read are declared, each at the unit
// shadowSamplerUnits() gives it (<FAMILY>_UNIT): hardware comparisons (pcf, pcf-disk, poisson,
// pcss), raw depth (hard, pcss's blocker search, the depth debug view) and VSM moments.
#if (defined(SHADOW_PCF) || defined(SHADOW_PCF_DISK) || defined(SHADOW_POISSON) || \
     defined(SHADOW_PCSS))
#define SHADOW_COMPARE_READS
#endif
#if defined(SHADOW_HARD) || defined(SHADOW_PCSS) || defined(DEBUG_DEPTH)
#define SHADOW_DEPTH_READS
#endif
#if defined(SHADOW_CUBE) && ((defined(SHADOW_COMPARE_READS) && !defined(CUBE_COMPARE_UNIT)) || \
                             (defined(SHADOW_DEPTH_READS) && !defined(CUBE_DEPTH_UNIT)) ||     \
                             (defined(SHADOW_VSM) && !defined(CUBE_MOMENTS_UNIT)))
#error "a cube map sampler array the frame's filters read has no texture unit"
#endif
#if defined(SHADOW_PLANAR) &&                                                           \
    ((defined(SHADOW_COMPARE_READS) && !defined(PLANAR_COMPARE_UNIT)) ||                \
     (defined(SHADOW_DEPTH_READS) && !defined(PLANAR_DEPTH_UNIT)) ||                    \
     (defined(SHADOW_VSM) && !defined(PLANAR_MOMENTS_UNIT)))
#error "a planar sampler array the frame's filters read has no texture unit"
#endif
#ifdef CUBE_COMPARE_UNIT
layout(binding = CUBE_COMPARE_UNIT) uniform samplerCubeArrayShadow uCubeCompare[SHADOW_SLOTS];
#endif
#ifdef CUBE_DEPTH_UNIT
layout(binding = CUBE_DEPTH_UNIT) uniform samplerCubeArray uCubeDepth[SHADOW_SLOTS];
#endif
#ifdef PLANAR_COMPARE_UNIT
layout(binding = PLANAR_COMPARE_UNIT) uniform sampler2DArrayShadow uPlanarCompare[SHADOW_SLOTS];
#endif
#ifdef PLANAR_DEPTH_UNIT
layout(binding = PLANAR_DEPTH_UNIT) uniform sampler2DArray uPlanarDepth[SHADOW_SLOTS];
#endif
#ifdef CUBE_MOMENTS_UNIT
layout(binding = CUBE_MOMENTS_UNIT) uniform samplerCubeArray uCubeMoments[SHADOW_SLOTS];
#endif
#ifdef PLANAR_MOMENTS_UNIT
layout(binding = PLANAR_MOMENTS_UNIT) uniform sampler2DArray uPlanarMoments[SHADOW_SLOTS];
#endif

uniform mat4 uCameraView;  // directional lights pick their cascade by camera view depth

// A world point as a light's shadow map sees it.
struct MapPoint {
  vec4 coord;       // cube: (direction, cube index); planar: (u, v, layer, -)
  float reference;  // the point's own depth in the map's depth space, in [0, 1]
  float axis;       // distance along the map's view axis (directional: along the light)
  bool inside;      // false: outside the map, where everything is lit
};

int lightType(Light light) { return int(light.directionType.w); }
// The light's slot in its layout's sampler arrays; negative for a light without a shadow.
int shadowGroup(Light light) { return int(light.radianceShadow.w); }
// shadowGroup() of a shadowed light as the index of its sampler: a constant where the arrays
// have one slot, so that only one copy of the texture code is compiled.
#if SHADOW_SLOTS == 1
int shadowSlot(Light light) { return 0; }
#else
int shadowSlot(Light light) { return shadowGroup(light); }
#endif

MapPoint mapPoint(Light light, int cascade, vec3 Q) {
  MapPoint m;
  float near = light.shadowDepth.x, far = light.shadowDepth.y;
#ifdef SHADOW_CUBE
  if (lightType(light) == LIGHT_POINT) {
    vec3 d = Q - light.positionRange.xyz;
    m.axis = max(max(abs(d.x), abs(d.y)), max(abs(d.z), 1e-6));
    // Receivers beyond `far` compare against the cleared depth 0 and so stay lit unless a
    // caster within `far` hides them; receivers nearer than `near` are lit.
    m.reference = clamp(near * (far - m.axis) / (m.axis * (far - near)), 0.0, 1.0);
    m.coord = vec4(d, floor(light.shadowSoft.z / 6.0 + 0.5));
    m.inside = true;
    return m;
  }
#endif
#ifdef SHADOW_PLANAR
  vec4 clip = uShadowViewProjections[int(light.shadowProjection.y) + cascade] * vec4(Q, 1.0);
  m.inside = clip.w > 0.0;
  vec3 ndc = clip.xyz / max(clip.w, 1e-20);
  vec2 uv = ndc.xy * 0.5 + 0.5;
  m.inside = m.inside && all(greaterThanEqual(uv, vec2(0.0))) && all(lessThanEqual(uv, vec2(1.0)));
  m.reference = clamp(ndc.z, 0.0, 1.0);
  m.coord = vec4(uv, light.shadowSoft.z + float(cascade), 0.0);
  m.axis = lightType(light) == LIGHT_SPOT ? clip.w : near + (1.0 - ndc.z) * (far - near);
#endif
  return m;
}

// Distance along the view axis of a stored depth (the inverse of the projections).
float storedAxis(Light light, float depth) {
  float near = light.shadowDepth.x, far = light.shadowDepth.y;
  if (lightType(light) == LIGHT_DIRECTIONAL) return near + (1.0 - depth) * (far - near);
  return near * far / (depth * (far - near) + near);
}

// Hardware comparison, bilinear where the light's filter asks for it (sampler state).
float compareMap(Light light, MapPoint m) {
  if (!m.inside) return 1.0;
  int g = shadowSlot(light);
#ifdef CUBE_COMPARE_UNIT
  if (lightType(light) == LIGHT_POINT) return texture(uCubeCompare[g], m.coord, m.reference);
#endif
#ifdef PLANAR_COMPARE_UNIT
  return texture(uPlanarCompare[g], vec4(m.coord.xyz, m.reference));
#endif
  return 1.0;
}

// The stored depth nearest to the point's texel (0 = nothing rendered there).
float storedDepth(Light light, MapPoint m) {
  if (!m.inside) return 0.0;
  int g = shadowSlot(light);
#ifdef CUBE_DEPTH_UNIT
  if (lightType(light) == LIGHT_POINT) return texture(uCubeDepth[g], m.coord).r;
#endif
#ifdef PLANAR_DEPTH_UNIT
  return texture(uPlanarDepth[g], m.coord.xyz).r;
#endif
  return 0.0;
}

float compareNearest(Light light, MapPoint m) {
  return m.reference >= storedDepth(light, m) ? 1.0 : 0.0;
}

// World size of one shadow-map texel at P.
float shadowTexel(Light light, int cascade, vec3 P) {
  float resolution = light.spotFilter.w;
#ifdef SHADOW_PLANAR
  int type = lightType(light);
  if (type == LIGHT_DIRECTIONAL) return light.cascadeTexel[cascade];
  if (type == LIGHT_SPOT) {
    float depth = dot(P - light.positionRange.xyz, normalize(light.directionType.xyz));
    return 2.0 * max(depth, 1e-6) * light.shadowProjection.x / resolution;
  }
#endif
  vec3 d = P - light.positionRange.xyz;
  return 2.0 * max(max(abs(d.x), abs(d.y)), abs(d.z)) / resolution;
}

const vec3 PCF_DISK_DIRECTIONS[20] = vec3[](
    vec3(1, 1, 1), vec3(1, -1, 1), vec3(-1, -1, 1), vec3(-1, 1, 1),
    vec3(1, 1, -1), vec3(1, -1, -1), vec3(-1, -1, -1), vec3(-1, 1, -1),
    vec3(1, 1, 0), vec3(1, -1, 0), vec3(-1, -1, 0), vec3(-1, 1, 0),
    vec3(1, 0, 1), vec3(-1, 0, 1), vec3(1, 0, -1), vec3(-1, 0, -1),
    vec3(0, 1, 1), vec3(0, -1, 1), vec3(0, -1, -1), vec3(0, 1, -1));

// Per-pixel rotation for sample disks (Jimenez's interleaved gradient noise): neighbouring
// pixels get well-spread angles, and the result is the same on every run.
float interleavedGradientNoise(vec2 pixel) {
  return fract(52.9829189 * fract(dot(pixel, vec2(0.06711056, 0.00583715))));
}

// Point i of n on a Vogel (golden angle) disk of radius 1, rotated by `angle`.
vec2 vogelDisk(int i, int n, float angle) {
  float r = sqrt((float(i) + 0.5) / float(n));
  float theta = float(i) * 2.39996323 + angle;
  return r * vec2(cos(theta), sin(theta));
}

void tangentFrame(vec3 N, out vec3 T, out vec3 B) {
  T = normalize(cross(abs(N.x) < 0.9 ? vec3(1, 0, 0) : vec3(0, 1, 0), N));
  B = cross(N, T);
}

// Percentage of `samples` rotated disk taps of `radius` (world) around Q that are lit.
float diskCompare(Light light, int cascade, vec3 Q, vec3 N, float radius, int samples) {
  vec3 T, B;
  tangentFrame(N, T, B);
  float angle = 6.28318531 * interleavedGradientNoise(gl_FragCoord.xy);
  float sum = 0.0;
  for (int i = 0; i < samples; ++i) {
    vec2 o = vogelDisk(i, samples, angle) * radius;
    sum += compareMap(light, mapPoint(light, cascade, Q + T * o.x + B * o.y));
  }
  return sum / float(samples);
}

// Percentage-closer soft shadows: the average blocker in a search region sized by the light's
// radius gives the penumbra width (similar triangles), which sets the filter radius.
float pcss(Light light, int cascade, vec3 Q, vec3 N, float texel, float receiverAxis) {
  int samples = int(light.shadowBias.w);
  float radius = light.shadowSoft.x;
  bool directional = lightType(light) == LIGHT_DIRECTIONAL;
  float near = light.shadowDepth.x;
  // Blockers nearer than a fifth of the receiver distance are taken as that near.
  float nearest = directional ? near : max(near, 0.2 * receiverAxis);
  float spread = directional ? tan(radius) : radius / nearest;
  float search = clamp(spread * (receiverAxis - nearest), texel, 32.0 * texel);

  vec3 T, B;
  tangentFrame(N, T, B);
  float angle = 6.28318531 * interleavedGradientNoise(gl_FragCoord.xy);
  float blockers = 0.0, blockerAxis = 0.0;
  for (int i = 0; i < samples; ++i) {
    vec2 o = vogelDisk(i, samples, angle) * search;
    MapPoint m = mapPoint(light, cascade, Q + T * o.x + B * o.y);
    float stored = storedDepth(light, m);
    if (stored > m.reference) {
      blockers += 1.0;
      blockerAxis += storedAxis(light, stored);
    }
  }
  if (blockers == 0.0) return 1.0;
  blockerAxis /= blockers;
  float penumbra = directional ? tan(radius) * (receiverAxis - blockerAxis)
                               : radius * (receiverAxis - blockerAxis) / max(blockerAxis, 1e-6);
  return diskCompare(light, cascade, Q, N, clamp(penumbra, texel, 32.0 * texel), samples);
}

// Chebyshev's upper bound on the lit fraction from filtered moments, with light-bleeding
// reduction: bounds below `bleed` count as shadow and the rest is rescaled.
float varianceShadow(Light light, MapPoint m, vec3 Q, float texel) {
  if (!m.inside) return 1.0;
  int g = shadowSlot(light);
  float far = light.shadowDepth.y;
  vec2 moments = vec2(1.0);
  float t = 0.0;
#ifdef CUBE_MOMENTS_UNIT
  if (lightType(light) == LIGHT_POINT) {
    moments = texture(uCubeMoments[g], m.coord).rg;
    t = length(Q - light.positionRange.xyz) / far;
  }
#endif
#ifdef PLANAR_MOMENTS_UNIT
  if (lightType(light) != LIGHT_POINT) {
    moments = texture(uPlanarMoments[g], m.coord.xyz).rg;
    t = lightType(light) == LIGHT_SPOT ? length(Q - light.positionRange.xyz) / far
                                       : 1.0 - m.reference;
  }
#endif
  if (t <= moments.x) return 1.0;
  float scale = lightType(light) == LIGHT_DIRECTIONAL ? far - light.shadowDepth.x : far;
  float minVariance = 0.25 * (texel / scale) * (texel / scale);
  float variance = max(moments.y - moments.x * moments.x, minVariance);
  float d = t - moments.x;
  float p = variance / (variance + d * d);
  float bleed = light.shadowSoft.y;
  return clamp((p - bleed) / (1.0 - bleed), 0.0, 1.0);
}

// The cascade of a directional light holding P, or -1 beyond the last one.
int shadowCascade(Light light, vec3 P) {
#ifndef SHADOW_PLANAR
  return 0;
#endif
  if (lightType(light) != LIGHT_DIRECTIONAL) return 0;
  float viewDepth = -(uCameraView * vec4(P, 1.0)).z;
  int count = int(light.shadowSoft.w);
  for (int c = 0; c < count; ++c)
    if (viewDepth <= light.cascadeEnd[c]) return c;
  return -1;
}

#ifdef TRANSLUCENT_SHADOWS
// The frame's transmittance atlas (renderer/passes/transmittance_pass.h): per light, one layer
// for each of its shadow layers that translucent casters reach, RGB the product of what they
// let through, A the nearest one's reversed depth (0 = none). Each atlas layer holds, from its
// corner, the rectangle (x0, y0, x1, y1) of the shadow layer's texels that uTransmittanceRects
// gives; outside it nothing is tinted.
layout(binding = TRANSMITTANCE_UNIT) uniform sampler2DArray uTransmittance;
layout(binding = TRANSMITTANCE_RECTS_UNIT) uniform isamplerBuffer uTransmittanceRects;

// The cube face a direction selects and the (s, t) in it, as GL's cube map lookup defines them
// (OpenGL 4.6, section 8.13, table 8.19).
int cubeFace(vec3 d, out vec2 st) {
  vec3 a = abs(d);
  float sc, tc, ma;
  int face;
  if (a.x >= a.y && a.x >= a.z) {
    face = d.x >= 0.0 ? 0 : 1;
    ma = a.x;
    sc = d.x >= 0.0 ? -d.z : d.z;
    tc = -d.y;
  } else if (a.y >= a.z) {
    face = d.y >= 0.0 ? 2 : 3;
    ma = a.y;
    sc = d.x;
    tc = d.y >= 0.0 ? d.z : -d.z;
  } else {
    face = d.z >= 0.0 ? 4 : 5;
    ma = a.z;
    sc = d.z >= 0.0 ? d.x : -d.x;
    tc = -d.y;
  }
  st = 0.5 * vec2(sc, tc) / max(ma, 1e-30) + 0.5;
  return face;
}

// What the translucent casters between the light and Q let through (1 = all): the product (RGB)
// in Q's texel of the light's transmittance layer, where Q is behind the nearest translucent
// caster of that texel; receivers in front of it (and the glass itself) are not tinted. The
// nearest texel: tinted shadows have hard edges.
vec3 shadowTransmittance(Light light, int cascade, vec3 Q) {
  if (light.shadowProjection.z == 0.0) return vec3(1.0);
  MapPoint m = mapPoint(light, cascade, Q);
  if (!m.inside) return vec3(1.0);
  // shadowProjection.z is 1 + a bit per shadow layer with an atlas layer, w the first of them.
  uint tinted = uint(light.shadowProjection.z) - 1u;
  int layer = cascade;
  vec2 st = m.coord.xy;
#ifdef SHADOW_CUBE
  if (lightType(light) == LIGHT_POINT) layer = cubeFace(m.coord.xyz, st);
#endif
  if ((tinted & (1u << uint(layer))) == 0u) return vec3(1.0);
  int atlasLayer = int(light.shadowProjection.w) + bitCount(tinted & ((1u << uint(layer)) - 1u));
  int n = int(light.spotFilter.w);
  ivec2 texel = clamp(ivec2(floor(st * float(n))), ivec2(0), ivec2(n - 1));
  ivec4 rect = texelFetch(uTransmittanceRects, atlasLayer);
  if (any(lessThan(texel, rect.xy)) || any(greaterThanEqual(texel, rect.zw))) return vec3(1.0);
  vec4 t = texelFetch(uTransmittance, ivec3(texel - rect.xy, atlasLayer), 0);
  return m.reference < t.a ? t.rgb : vec3(1.0);
}
#endif

// Shadow term (1 = lit) of a light at P. Ngeom: geometric normal on the light's side; L: unit
// direction towards the light. `transmittance`: the translucent casters' color (1 without).
float shadowVisibility(Light light, vec3 P, vec3 Ngeom, vec3 L, float cameraDistance,
                       out vec3 transmittance) {
  transmittance = vec3(1.0);
  if (shadowGroup(light) < 0) return 1.0;
  int cascade = shadowCascade(light, P);
  if (cascade < 0) return 1.0;  // beyond the directional light's shadow distance

  float texel = shadowTexel(light, cascade, P);
  float NdotL = clamp(dot(Ngeom, L), 0.0, 1.0);
  float tanNL = sqrt(max(1.0 - NdotL * NdotL, 0.0)) / max(NdotL, 0.05);
  float depthBias =
      light.shadowDepth.z + texel * max(light.shadowDepth.w * tanNL, light.shadowBias.x);
  vec3 Q = P + Ngeom * (light.shadowBias.y * texel) + L * depthBias;

  int filterMode = int(light.spotFilter.z);
  float filterRadius = light.shadowBias.z * texel;
  int samples = int(light.shadowBias.w);
  MapPoint m = mapPoint(light, cascade, Q);
  float visibility = 1.0;
#ifdef TRANSLUCENT_SHADOWS
  transmittance = shadowTransmittance(light, cascade, Q);
#endif
#ifdef SHADOW_HARD
  if (filterMode == FILTER_HARD) visibility = m.inside ? compareNearest(light, m) : 1.0;
#endif
#ifdef SHADOW_PCF
  if (filterMode == FILTER_PCF) visibility = compareMap(light, m);
#endif
#ifdef SHADOW_VSM
  if (filterMode == FILTER_VSM) visibility = varianceShadow(light, m, Q, texel);
#endif
#ifdef SHADOW_POISSON
  if (filterMode == FILTER_POISSON)
    visibility = diskCompare(light, cascade, Q, Ngeom, filterRadius, samples);
#endif
#ifdef SHADOW_PCSS
  if (filterMode == FILTER_PCSS) visibility = pcss(light, cascade, Q, Ngeom, texel, m.axis);
#endif
#ifdef SHADOW_PCF_DISK
  if (filterMode == FILTER_PCF_DISK) {
    // The classic 20 directions, radius growing with the distance to the camera.
    float far = lightType(light) == LIGHT_DIRECTIONAL
                    ? light.cascadeEnd[int(light.shadowSoft.w) - 1]
                    : light.shadowDepth.y;
    float radius = (1.0 + cameraDistance / far) * filterRadius;
    float sum = 0.0;
    for (int i = 0; i < 20; ++i) {
      vec3 offset = PCF_DISK_DIRECTIONS[i];
      offset -= Ngeom * dot(offset, Ngeom);
      sum += compareMap(light, mapPoint(light, cascade, Q + offset * radius));
    }
    visibility = sum / 20.0;
  }
#endif
  return visibility;
}

// Distance (over the map's far) of what the light's map holds in P's direction, 1 if nothing.
float shadowDepthView(Light light, vec3 P) {
  if (shadowGroup(light) < 0) return 1.0;
  int cascade = max(shadowCascade(light, P), 0);
  MapPoint m = mapPoint(light, cascade, P);
  float stored = storedDepth(light, m);
  if (stored <= 0.0) return 1.0;
  float axis = storedAxis(light, stored);
  float far = light.shadowDepth.y;
  if (lightType(light) == LIGHT_POINT) {
    vec3 d = P - light.positionRange.xyz;
    return clamp(axis * length(d) / max(max(abs(d.x), abs(d.y)), abs(d.z)) / far, 0.0, 1.0);
  }
  return clamp(axis / far, 0.0, 1.0);
}

// --debug-view cascade: the debug light's cascade as a hue (0 red, 1 green, 2 blue, 3 yellow),
// the shaded picture kept as brightness so the scene stays readable; grey beyond the last one.
vec3 cascadeDebugColor(int cascade, vec3 shaded) {
  const vec3 hues[4] = vec3[](vec3(1.0, 0.2, 0.2), vec3(0.2, 1.0, 0.2), vec3(0.2, 0.35, 1.0),
                              vec3(1.0, 0.9, 0.2));
  float brightness = 0.35 + 0.65 * clamp(dot(shaded, vec3(0.2126, 0.7152, 0.0722)), 0.0, 1.0);
  return (cascade < 0 ? vec3(0.5) : hues[clamp(cascade, 0, 3)]) * brightness;
}
