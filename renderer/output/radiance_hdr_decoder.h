#pragma once

#include <string>

#include "renderer/output/image_writer.h"

namespace omnishadow {

// Whether `bytes` begin as a Radiance HDR (RGBE) file does: "#?" then a program name
// ("#?RADIANCE", "#?RGBE").
bool isRadianceHdr(const std::string& bytes);

// Decodes a Radiance HDR file held in memory (the format of most HDR panoramas): RGBE pixels,
// flat or run-length encoded scanlines, rows top first ("-Y H +X W"; "+Y H +X W" is turned
// over). A value is (mantissa + 0.5) 2^(exponent - 136), as Radiance reads it; header lines
// other than FORMAT (EXPOSURE, PRIMARIES, ...) are not applied. Channels R, G, B. The size is
// checked (imageSizeProblem) before pixels are allocated. Throws InputError "NAME: cannot read
// image: ..." for a malformed, truncated or XYZE file, or another orientation.
FloatImage decodeRadianceHdr(const std::string& bytes, const std::string& name);

}  // namespace omnishadow
