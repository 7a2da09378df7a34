#pragma once

#include <cstddef>
#include <future>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "renderer/scene/pixel_bytes.h"

namespace omnishadow {

// Decoded pictures by the exact bytes they were decoded from, for loads that may meet the same
// image again while a scene that holds it is still loaded or being loaded: a `batch` over a
// folder holding one model as glTF, glTF-Binary and glTF-Draco (the Khronos samples' layout),
// whose loads run ahead of its renders and beside each other, decodes each picture once. The
// cache holds no pixels itself (a PixelBytes::Watch each): a picture no scene holds any more is
// decoded again, so a folder of distinct models costs no memory. Safe to use from several
// threads.
class DecodedImageCache {
 public:
  struct Picture {
    int width = 0, height = 0;
    std::string mimeType;               // "image/jpeg", ...
    std::vector<std::string> warnings;  // what decoding said (damaged JPEG data)
    PixelBytes rgba;                    // RGBA8, first row = top
  };

  // A decode this caller was asked to make (Lookup::claim), which others may be waiting for.
  struct Pending;
  struct Lookup {
    std::optional<Picture> picture;  // decoded before, or by another load meanwhile
    // Without a picture: the caller decodes the bytes and hands the result to fulfil(), or
    // calls abandon() when it cannot (a damaged file), so that those waiting decode them too.
    std::shared_ptr<Pending> claim;
  };

  // The picture decoded from exactly these bytes while some scene holds it, waiting for another
  // load that is decoding them now; else a claim to decode them.
  Lookup find(const unsigned char* bytes, std::size_t size);
  // Remembers `picture` as what the claimed bytes decode to, watching its pixels (changing them
  // from now on copies them first), and gives it to those waiting.
  void fulfil(const std::shared_ptr<Pending>& claim, const Picture& picture);
  void abandon(const std::shared_ptr<Pending>& claim);
  // How many pictures some scene still holds.
  std::size_t size() const;

 private:
  struct Entry {
    std::vector<unsigned char> encoded;  // compared byte for byte: a digest alone could collide
    std::shared_ptr<Pending> pending;    // while the claim is open
    Picture picture;                     // without its pixels
    PixelBytes::Watch rgba;
  };

  void settle(const std::shared_ptr<Pending>& claim, const Picture* picture);

  mutable std::mutex mutex_;
  std::unordered_multimap<std::size_t, Entry> entries_;  // by a digest of the encoded bytes
};

}  // namespace omnishadow
