#pragma once

#include <string>

#include "renderer/output/image_writer.h"

namespace omnishadow {

// Decodes a PNG file held in memory with libpng, the way `omnishadow diff` has always read PNG
// (through OpenImageIO until version 0.2): every colour type and bit depth, interlaced or not;
// palettes become RGB, a tRNS chunk becomes an alpha channel, grey below 8 bits is scaled to
// 8; values are the stored ones times 1/255 (or 1/65535 for 16 bits), alpha straight, no gamma
// applied. Channels: Y; Y,A; R,G,B; R,G,B,A. Throws InputError "NAME: cannot read image: ...".
FloatImage decodePng(const std::string& bytes, const std::string& name);

}  // namespace omnishadow
