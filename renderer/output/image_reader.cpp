#include <cstddef>
#include <fstream>
#include <iterator>
#include <optional>
#include <string>

#include "renderer/core/errors.h"
#include "renderer/output/exr_reader.h"
#include "renderer/output/image_writer.h"
#include "renderer/output/oiio_plugin.h"
#include "renderer/output/png_decoder.h"

namespace omnishadow {

// By content, not by name: PNG and OpenEXR are read here, anything else by OpenImageIO through
// its plugin (oiio_plugin.h), loaded only then.
FloatImage readImage(const std::filesystem::path& path) {
  const std::string name = path.string();
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(name + ": cannot read image: cannot open the file");
  char magic[8] = {};
  in.read(magic, sizeof magic);
  const auto got = static_cast<std::size_t>(in.gcount());
  if (got == 8 && std::string(magic, 8) == std::string("\x89PNG\r\n\x1a\n", 8)) {
    in.seekg(0);
    const std::string bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    if (in.bad()) throw InputError(name + ": cannot read image: read error");
    return decodePng(bytes, name);
  }
  if (got >= 4 && std::string(magic, 4) == std::string("\x76\x2f\x31\x01", 4)) {
    if (std::optional<FloatImage> image = readExr(name)) return *std::move(image);
  }
  return readImageWithOiioPlugin(path);
}

}  // namespace omnishadow
