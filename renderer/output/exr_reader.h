#pragma once

#include <optional>
#include <string>

#include "renderer/output/image_writer.h"

namespace omnishadow {

// Reads the first part of an OpenEXR file with OpenEXR itself, every channel as float, in the
// order OpenImageIO has always presented them to `omnishadow diff` (ExrChannelOrder below), the
// data window's pixels only. nullopt for a luminance/chroma file (Y, RY, BY), which only
// OpenImageIO turns into RGB. Throws InputError "NAME: cannot read image: ..." when OpenEXR
// cannot read it or a channel is subsampled.
std::optional<FloatImage> readExr(const std::string& path);

// OpenImageIO's order of EXR channels: by layer (the name before the last dot; channels without
// one first), then within a layer R, G, B, (Y), A ... Z, then the rest by name, where a layer with
// X and Y or Z puts X, Y, Z right after R, G, B. The indices into `names`, in that order.
std::vector<std::size_t> exrChannelOrder(const std::vector<std::string>& names);

}  // namespace omnishadow
