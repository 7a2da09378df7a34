// The lighting pass's 8-bit output (PassOutputs::Srgb8): the byte the CPU's toSrgb8() gives a
// linear value (renderer/scene/srgb_transfer.h), exactly. An approximation of the transfer
// function only picks a candidate byte, the right one or the one below (the bias of 0.3 of a
// step allows an error of 0.2 steps either way); the comparison with the first float of the
// next byte, which the CPU found, decides. Values below 0 and NaN give 0, values above 1 give
// 255, as on the CPU.
uniform float uSrgb8Next[256];  // [k]: the least float whose byte is k + 1 ([255]: above 1)

uint srgb8(float linear) {
  float c = linear > 0.0 ? (linear < 1.0 ? linear : 1.0) : 0.0;
  // 1.055 c^(1/2.4) - 0.055 as a polynomial in c^(1/4) (least squares, off by at most 0.011
  // of a step over (0.0031308, 1]): two square roots cost llvmpipe less than pow().
  float q = sqrt(sqrt(c));
  float curve = (((0.0788558 * q - 0.329372) * q + 1.117347) * q + 0.198041) * q - 0.0648438;
  float encoded = c <= 0.0031308 ? 12.92 * c : curve;
  int candidate = clamp(int(encoded * 255.0 + 0.3), 0, 255);
  return uint(candidate + (c >= uSrgb8Next[candidate] ? 1 : 0));
}

uvec4 srgb8(vec3 linear) {
  return uvec4(srgb8(linear.r), srgb8(linear.g), srgb8(linear.b), 255u);
}
