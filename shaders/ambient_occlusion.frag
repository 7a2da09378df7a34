// Ambient occlusion of the opaque and masked surfaces a camera sees, from their depth alone:
// ground-truth ambient occlusion (Jimenez et al. 2016, "Practical Realtime Strategies for
// Accurate Indirect Occlusion"). In each slice through the view vector the surface is lit by the arc between the
// two horizons that the depth buffer raises within uRadius; the cosine-weighted integral of
// that arc, summed over slices, is the visible share of the hemisphere above the surface.
// Drawn at half the frame's size, each texel for the lower left pixel of its 2 x 2 block: three
// slices, turned by a 2 x 2 pattern that the lighting pass averages away (lighting.frag,
// screenSpaceOcclusion()): 12 slices per 2 x 2 texels, the same every run.
const float PI = 3.14159265358979;
const float HALF_PI = 1.57079632679490;
const int SLICES = 3;
const int STEPS = 8;  // per side of a slice
const float kTangentTolerance = 0.05;  // sine of the elevation above the tangent plane

layout(binding = 0) uniform sampler2D uDepth;  // the opaque surfaces' reversed depth (0: none)
uniform mat4 uInverseProjection;
uniform float uRadius;         // view-space (world) units
uniform float uPixelsPerUnit;  // at a view distance of 1 (perspective) or anywhere (orthographic)
uniform int uOrthographic;
layout(location = 0) out vec2 outOcclusion;  // the visible share, the depth (to average by)

ivec2 gSize;

vec3 viewPosition(ivec2 pixel, float depth) {
  vec2 ndc = (vec2(pixel) + 0.5) / vec2(gSize) * 2.0 - 1.0;
  vec4 p = uInverseProjection * vec4(ndc, depth, 1.0);
  return p.xyz / p.w;
}

// The difference towards the neighbour on the same surface: the nearer in depth of the two
// sides, so that a silhouette does not bend the normal; none where neither side has a surface.
vec3 tangentTowards(vec3 center, ivec2 pixel, ivec2 step, bool horizontal) {
  ivec2 a = pixel + step, b = pixel - step;
  float da = (a.x < gSize.x && a.y < gSize.y) ? texelFetch(uDepth, a, 0).r : 0.0;
  float db = (b.x >= 0 && b.y >= 0) ? texelFetch(uDepth, b, 0).r : 0.0;
  vec3 pa = da > 0.0 ? viewPosition(a, da) : center;
  vec3 pb = db > 0.0 ? viewPosition(b, db) : center;
  bool useA = da > 0.0 && (db <= 0.0 || abs(pa.z - center.z) <= abs(center.z - pb.z));
  if (useA) return pa - center;
  if (db > 0.0) return center - pb;
  return horizontal ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0);
}

// (1/4) the cosine-weighted integral of the arc from the view vector to horizon angle h, in a
// slice where the normal projects at angle n (GTAO's inner integral); at the tangent plane's
// horizons, n -+ pi/2, it is (cos n + (n -+ pi/2) sin n) / 2, with no cosine to take.
float arc(float h, float n, float cosN, float sinN) {
  return 0.25 * (cosN + 2.0 * h * sinN - cos(2.0 * h - n));
}
float openArc(float h, float cosN, float sinN) {
  return 0.5 * (cosN + h * sinN);
}

void main() {
  gSize = textureSize(uDepth, 0);
  ivec2 texel = ivec2(gl_FragCoord.xy);
  ivec2 pixel = texel * 2;
  float depth = texelFetch(uDepth, pixel, 0).r;
  outOcclusion = vec2(1.0, depth);
  if (depth <= 0.0) return;
  vec3 P = viewPosition(pixel, depth);
  vec3 V = uOrthographic != 0 ? vec3(0.0, 0.0, 1.0) : normalize(-P);
  vec3 N = normalize(cross(tangentTowards(P, pixel, ivec2(1, 0), true),
                           tangentTowards(P, pixel, ivec2(0, 1), false)));
  if (dot(N, V) < 0.0) N = -N;
  float radiusPixels = uRadius * uPixelsPerUnit / (uOrthographic != 0 ? 1.0 : max(-P.z, 1e-20));
  radiusPixels = min(radiusPixels, float(max(gSize.x, gSize.y)));
  if (radiusPixels < 1.0) return;

  // A 2 x 2 ordered pattern: every 2 x 2 block holds each turn and step offset once.
  int cell = (texel.y & 1) * 2 + (texel.x & 1);
  const float turns[4] = float[4](0.125, 0.625, 0.875, 0.375);
  const float stepOffsets[4] = float[4](0.625, 0.125, 0.375, 0.875);
  float turn = turns[cell];
  float stepOffset = stepOffsets[cell];
  float falloffStart = 0.8 * uRadius;

  float visible = 0.0, unoccluded = 0.0;
  bool raised = false;
  for (int s = 0; s < SLICES; ++s) {
    float angle = (float(s) + turn) * (PI / float(SLICES));
    vec2 direction = vec2(cos(angle), sin(angle));
    // The slice's plane holds V and the screen direction (view space: x right, y up).
    vec3 along = vec3(direction, 0.0);
    vec3 ortho = along - dot(along, V) * V;
    vec3 axis = normalize(cross(ortho, V));
    vec3 projected = N - axis * dot(N, axis);
    float projectedLength = length(projected);
    if (projectedLength < 1e-6) continue;
    float cosN = clamp(dot(projected, V) / projectedLength, -1.0, 1.0);
    float n = (dot(ortho, projected) < 0.0 ? -1.0 : 1.0) * acos(cosN);
    float sinN = sin(n);
    // The lowest horizon on each side: the tangent plane's, cos(n + pi/2) and cos(n - pi/2).
    float lowPositive = -sinN, lowNegative = sinN;
    float horizonPositive = lowPositive, horizonNegative = lowNegative;
    for (int j = 0; j < STEPS; ++j) {
      float t = (float(j) + stepOffset) / float(STEPS);
      vec2 offset = direction * (t * t * radiusPixels);
      for (int side = 0; side < 2; ++side) {
        ivec2 at = pixel + ivec2(round(side == 0 ? offset : -offset));
        if (at == pixel || any(lessThan(at, ivec2(0))) || any(greaterThanEqual(at, gSize)))
          continue;
        float sampleDepth = texelFetch(uDepth, at, 0).r;
        if (sampleDepth <= 0.0) continue;
        vec3 delta = viewPosition(at, sampleDepth) - P;
        float reach = length(delta);
        // Surfaces within a few degrees of the tangent plane count as the plane itself: the
        // normal from depth differences is that uncertain, and the highest of many samples
        // would find its error everywhere (an open floor came out 1% occluded).
        if (reach >= uRadius || dot(delta, N) <= kTangentTolerance * reach) continue;
        // Nearer than 0.8 radius counts fully, then less and less: no hard edge at the radius.
        float weight = clamp((uRadius - reach) / (uRadius - falloffStart), 0.0, 1.0);
        float cosH = dot(delta / reach, V);
        if (side == 0)
          horizonPositive = max(horizonPositive, mix(lowPositive, cosH, weight));
        else
          horizonNegative = max(horizonNegative, mix(lowNegative, cosH, weight));
      }
    }
    // A horizon no sample raised is the tangent plane's.
    float open = openArc(n - HALF_PI, cosN, sinN) + openArc(n + HALF_PI, cosN, sinN);
    float seen = open;
    if (horizonPositive > lowPositive || horizonNegative > lowNegative) {
      raised = true;
      float hPositive = n + min(acos(horizonPositive) - n, HALF_PI);
      float hNegative = n + max(-acos(horizonNegative) - n, -HALF_PI);
      seen = (horizonNegative > lowNegative ? arc(hNegative, n, cosN, sinN)
                                            : openArc(n - HALF_PI, cosN, sinN)) +
             (horizonPositive > lowPositive ? arc(hPositive, n, cosN, sinN)
                                            : openArc(n + HALF_PI, cosN, sinN));
    }
    visible += projectedLength * seen;
    unoccluded += projectedLength * open;
  }
  // An open surface comes out exactly unoccluded.
  if (raised && unoccluded > 0.0) outOcclusion.x = clamp(visible / unoccluded, 0.0, 1.0);
}
