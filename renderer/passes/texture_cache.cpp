#include "renderer/passes/texture_cache.h"

#include <algorithm>
#include <cstring>

namespace omnishadow {

bool TextureCache::holds(const Entry& entry, const Image& image) {
  if (entry.width != image.width || entry.height != image.height || image.rgba.empty())
    return false;
  readback_.resize(image.rgba.size());
  // GL reads sRGB texels back as stored, without decoding them.
  glGetTextureImage(entry.texture->get(), 0, GL_RGBA, GL_UNSIGNED_BYTE,
                    static_cast<GLsizei>(readback_.size()), readback_.data());
  return std::memcmp(readback_.data(), image.rgba.data(), readback_.size()) == 0;
}

std::shared_ptr<const gl::Texture> TextureCache::find(const Image& image, bool srgb,
                                                      const std::function<gl::Texture()>& make) {
  for (Entry& entry : entries_)
    if (entry.srgb == srgb && holds(entry, image)) {
      entry.used = true;
      return entry.texture;
    }
  entries_.push_back(
      {image.width, image.height, srgb, std::make_shared<const gl::Texture>(make()), true});
  return entries_.back().texture;
}

void TextureCache::dropUnused() {
  std::erase_if(entries_, [](const Entry& entry) { return !entry.used; });
  for (Entry& entry : entries_) entry.used = false;
}

}  // namespace omnishadow
