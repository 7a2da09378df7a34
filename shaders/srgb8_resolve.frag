// The 8-bit beauty of a frame drawn into the float target (blended or see-through surfaces,
// which the 8-bit target cannot take): each pixel's premultiplied RGB times 2^exposure, as
// toSrgb8() encodes it on the CPU (srgb8_encode.glsl); A unused.
#include "srgb8_encode.glsl"

layout(binding = 0) uniform sampler2D uBeauty;
uniform float uExposureScale;

layout(location = 0) out uvec4 outBeauty;

void main() {
  outBeauty = srgb8(texelFetch(uBeauty, ivec2(gl_FragCoord.xy), 0).rgb * uExposureScale);
}
