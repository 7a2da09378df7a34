#include <cstddef>
#include <optional>
#include <string>

#include "renderer/core/errors.h"
#include "renderer/core/input_file.h"
#include "renderer/output/exr_reader.h"
#include "renderer/output/image_limits.h"
#include "renderer/output/image_writer.h"
#include "renderer/output/oiio_plugin.h"
#include "renderer/output/png_decoder.h"
#include "renderer/output/radiance_hdr_decoder.h"

namespace omnishadow {

// By content, not by name: PNG, OpenEXR and Radiance HDR are read here, anything else by
// OpenImageIO through its plugin (oiio_plugin.h), loaded only then (700 ms for an HDR panorama,
// most of it loading OpenImageIO's libraries).
FloatImage readImage(const std::filesystem::path& path) {
  const std::string name = path.string();
  // Read through the checks every input gets: a FIFO or /dev/zero must neither block nor fill
  // memory (renderer/core/input_file.h).
  std::string bytes;
  if (const std::string why = readRegularFile(path, kMaxImageFileBytes, bytes); !why.empty())
    throw InputError(name + ": cannot read image: " + why);
  if (bytes.size() >= 8 && bytes.compare(0, 8, std::string("\x89PNG\r\n\x1a\n", 8)) == 0)
    return decodePng(bytes, name);
  if (isRadianceHdr(bytes)) return decodeRadianceHdr(bytes, name);
  if (bytes.size() >= 4 && bytes.compare(0, 4, std::string("\x76\x2f\x31\x01", 4)) == 0) {
    if (std::optional<FloatImage> image = readExr(name)) return *std::move(image);
  }
  return readImageWithOiioPlugin(path);
}

}  // namespace omnishadow
