// The lighting pass's 8-bit output (PassOutputs::Srgb8): the byte the CPU's toSrgb8() gives a
// linear value (renderer/scene/srgb_transfer.h), exactly. The transfer function's float
// approximations here differ from the CPU's pow() in the last bits, so they only pick a
// candidate byte at most one below the right one (the bias of 0.2 of a step covers their
// error many times over); the comparison with the first float of the next byte, which the CPU
// found, decides. Values below 0 and NaN give 0, values above 1 give 255, as on the CPU.
uniform float uSrgb8Next[256];  // [k]: the least float whose byte is k + 1 ([255]: above 1)

uint srgb8(float linear) {
  float c = linear > 0.0 ? (linear < 1.0 ? linear : 1.0) : 0.0;
  float encoded = c <= 0.0031308 ? 12.92 * c : 1.055 * pow(c, 1.0 / 2.4) - 0.055;
  int candidate = clamp(int(encoded * 255.0 + 0.3), 0, 255);
  return uint(candidate + (c >= uSrgb8Next[candidate] ? 1 : 0));
}

uvec4 srgb8(vec3 linear) {
  return uvec4(srgb8(linear.r), srgb8(linear.g), srgb8(linear.b), 255u);
}
