#include "renderer/passes/texture_cache.h"

#include <algorithm>
#include <cstring>

namespace omnishadow {

// A hash of the size and of 1024 words spread evenly over the bytes: cheap, and different for
// nearly any two different textures.
std::uint64_t TextureCache::sampleOf(const Image& image) {
  const auto mix = [](std::uint64_t h, std::uint64_t v) {
    h = (h ^ v) * 0x9e3779b97f4a7c15ull;
    return h ^ (h >> 32);
  };
  const std::vector<std::uint8_t>& bytes = image.rgba;
  std::uint64_t h = mix(mix(0x243f6a8885a308d3ull, static_cast<std::uint64_t>(image.width)),
                        static_cast<std::uint64_t>(image.height));
  constexpr std::size_t kWords = 1024;
  if (bytes.size() < 8) return mix(h, bytes.empty() ? 0 : bytes[0]);
  for (std::size_t i = 0; i < kWords; ++i) {
    std::uint64_t word;
    std::memcpy(&word, bytes.data() + (bytes.size() - 8) * i / (kWords - 1), 8);
    h = mix(h, word);
  }
  return h;
}

bool TextureCache::holds(const Entry& entry, const Image& image, std::uint64_t sample) {
  if (entry.width != image.width || entry.height != image.height || entry.sample != sample ||
      image.rgba.empty())
    return false;
  readback_.resize(image.rgba.size());
  // GL reads sRGB texels back as stored, without decoding them.
  glGetTextureImage(entry.texture->get(), 0, GL_RGBA, GL_UNSIGNED_BYTE,
                    static_cast<GLsizei>(readback_.size()), readback_.data());
  return std::memcmp(readback_.data(), image.rgba.data(), readback_.size()) == 0;
}

std::shared_ptr<const gl::Texture> TextureCache::find(const Image& image, bool srgb,
                                                      const std::function<gl::Texture()>& make) {
  const std::uint64_t sample = sampleOf(image);
  for (Entry& entry : entries_)
    if (entry.srgb == srgb && holds(entry, image, sample)) {
      entry.used = true;
      return entry.texture;
    }
  entries_.push_back(
      {image.width, image.height, srgb, sample, std::make_shared<const gl::Texture>(make()), true});
  return entries_.back().texture;
}

void TextureCache::dropUnused() {
  std::erase_if(entries_, [](const Entry& entry) { return !entry.used; });
  for (Entry& entry : entries_) entry.used = false;
}

}  // namespace omnishadow
