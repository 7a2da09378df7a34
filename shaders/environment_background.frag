// An environment light drawn where no surface covers a pixel (EnvironmentLight::background):
// the radiance seen along each pixel's view ray, from the picture at up to 4096 texels wide.
// Drawn over the cleared beauty with the depth test passing only where nothing was drawn.
// Variants: WRITE_SRGB8 (the 8-bit beauty, encoded as the lighting pass encodes it).
const float PI = 3.14159265358979;
#include "environment.glsl"
#ifdef WRITE_SRGB8
#include "srgb8_encode.glsl"
layout(location = 0) out uvec4 outBeauty;
uniform float uExposureScale;
#else
layout(location = 0) out vec4 outBeauty;  // premultiplied: the environment covers the pixel
#endif

// The picture at up to 4096 wide with mipmaps (EnvironmentTextures::background()), on the
// specular texture's unit, which this program does not read.
layout(binding = ENVIRONMENT_SPECULAR_UNIT) uniform sampler2D uEnvironmentBackground;
uniform mat4 uInverseViewProjection;
uniform vec2 uViewportSize;

void main() {
  // Two points of the pixel's ray (reversed depth: 1 is the near plane): a perspective camera's
  // rays spread from its eye, an orthographic camera's are parallel.
  vec2 ndc = gl_FragCoord.xy / uViewportSize * 2.0 - 1.0;
  vec4 near = uInverseViewProjection * vec4(ndc, 1.0, 1.0);
  vec4 farther = uInverseViewProjection * vec4(ndc, 0.5, 1.0);
  vec3 direction = farther.xyz / farther.w - near.xyz / near.w;
  // The level whose texels are as wide as a pixel, from the angle between neighbouring rays
  // (the texture coordinates jump at the panorama's seam; the directions do not).
  vec3 ray = normalize(direction);
  float radiansPerPixel = max(length(dFdx(ray)), length(dFdy(ray)));
  float texelsPerRadian = float(textureSize(uEnvironmentBackground, 0).x) * (0.5 / PI);
  float level = log2(max(radiansPerPixel * texelsPerRadian, 1e-8));
  vec3 radiance =
      uEnvironmentScale * textureLod(uEnvironmentBackground, environmentCoordinates(ray), level).rgb;
#ifdef WRITE_SRGB8
  outBeauty = srgb8(radiance * uExposureScale);
#else
  outBeauty = vec4(radiance, 1.0);
#endif
}
