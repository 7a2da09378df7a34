#include "renderer/passes/texture_cache.h"

#include <algorithm>
#include <cstring>
#include <future>
#include <system_error>

// Compiled into this file (the header alone; no library to load): XXH3 inlined here is about a
// fifth faster than Debian's shared libxxhash, which is built for the baseline x86-64.
#define XXH_INLINE_ALL
#include <xxhash.h>

namespace omnishadow {

// A hash of the size and of 1024 words spread evenly over the bytes: cheap, and different for
// nearly any two different textures.
std::uint64_t TextureCache::sampleOf(const Image& image) {
  const auto mix = [](std::uint64_t h, std::uint64_t v) {
    h = (h ^ v) * 0x9e3779b97f4a7c15ull;
    return h ^ (h >> 32);
  };
  const PixelBytes& bytes = image.rgba;
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

// Large images in two halves, the second on a thread of its own, then the digest of the two
// digests: a render's upload leaves the other core idle, and one core hashes at about half the
// speed the memory allows.
TextureCache::Digest TextureCache::digestOf(const std::uint8_t* bytes, std::size_t size) {
  constexpr std::size_t kSplitAbove = std::size_t{4} << 20;
  const auto whole = [](const std::uint8_t* from, std::size_t count) {
    const XXH128_hash_t h = XXH3_128bits(from, count);
    return Digest{h.low64, h.high64};
  };
  if (size <= kSplitAbove) return whole(bytes, size);
  const std::size_t half = size / 2;
  std::future<Digest> second;
  try {
    second = std::async(std::launch::async, whole, bytes + half, size - half);
  } catch (const std::system_error&) {  // no thread to be had: the same digest on this one
    second = std::async(std::launch::deferred, whole, bytes + half, size - half);
  }
  const Digest halves[2] = {whole(bytes, half), second.get()};
  return whole(reinterpret_cast<const std::uint8_t*>(halves), sizeof halves);
}

TextureCache::Digest TextureCache::entryDigest(Entry& entry, std::size_t size) {
  if (!entry.bytes) {
    readback_.resize(size);
    // GL reads sRGB texels back as stored, without decoding them.
    glGetTextureImage(entry.texture->get(), 0, GL_RGBA, GL_UNSIGNED_BYTE,
                      static_cast<GLsizei>(readback_.size()), readback_.data());
    entry.bytes = digestOf(readback_.data(), readback_.size());
  }
  return *entry.bytes;
}

std::shared_ptr<const gl::Texture> TextureCache::find(const Image& image, bool srgb,
                                                      const std::function<gl::Texture()>& make,
                                                      std::optional<Digest>* known) {
  const std::uint64_t sample = sampleOf(image);
  std::optional<Digest> digest;  // the image's, once a candidate needs it
  bool fromBytes = false;        // hashed here rather than known
  for (Entry& entry : entries_) {
    if (entry.srgb != srgb || entry.width != image.width || entry.height != image.height ||
        entry.sample != sample || image.rgba.empty())
      continue;
    if (!digest && known && *known) {
      digest = *known;
    } else if (!digest) {
      digest = digestOf(image.rgba.data(), image.rgba.size());
      fromBytes = true;
      if (known) *known = digest;
    }
    if (entryDigest(entry, image.rgba.size()) == *digest) {
      entry.used = true;
      return entry.texture;
    }
  }
  // Only bytes hashed here vouch for what a new entry is made of, not a known digest.
  entries_.push_back({image.width, image.height, srgb, sample, fromBytes ? digest : std::nullopt,
                      std::make_shared<const gl::Texture>(make()), true});
  return entries_.back().texture;
}

void TextureCache::dropUnused() {
  std::erase_if(entries_, [](const Entry& entry) { return !entry.used; });
  for (Entry& entry : entries_) entry.used = false;
}

}  // namespace omnishadow
