#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "renderer/gl/gl_resources.h"
#include "renderer/scene/scene.h"

namespace omnishadow {

// Textures made from scenes' images, kept from one render to the next: a scene rendered again
// (frame sets, --repeat, batch jobs of one scene, the Python module's renders) takes its
// textures, mipmaps and all, from here instead of making them again (Sundial's 2048^2 texture
// was 13 of its 17 ms of upload a frame). A texture is taken for an image of its size and color
// space whose bytes have the 128-bit XXH3 digest of the bytes it was made from. Only candidates
// whose sample of 1024 words matches the image's are compared, so that the first render of an
// image hashes nothing, and images of one size (a model's textures, a batch of scenes) are not
// hashed against each other. An entry's own digest is taken once, from its first level read
// back, when an image first asks for it: a process that renders once never pays for it.
class TextureCache {
 public:
  struct Digest {
    std::uint64_t low = 0, high = 0;
    bool operator==(const Digest&) const = default;
  };

  // The texture of `image` as `srgb` says, made by `make` when none is here. Needs the GL
  // context the textures belong to. `known`, where given: the digest of the image's bytes if
  // known (taken as it is, not checked), and where the digest goes once this call has taken it.
  std::shared_ptr<const gl::Texture> find(const Image& image, bool srgb,
                                          const std::function<gl::Texture()>& make,
                                          std::optional<Digest>* known = nullptr);
  // Drops the textures not found since the last call: called once a scene is uploaded, it
  // leaves the cache holding that scene's textures (which the scene holds too while it draws).
  void dropUnused();
  std::size_t size() const { return entries_.size(); }

 private:
  struct Entry {
    int width = 0, height = 0;
    bool srgb = false;
    std::uint64_t sample = 0;     // sampleOf() the image
    std::optional<Digest> bytes;  // of the first level, taken when first compared
    std::shared_ptr<const gl::Texture> texture;
    bool used = true;
  };
  static std::uint64_t sampleOf(const Image& image);
  static Digest digestOf(const std::uint8_t* bytes, std::size_t size);
  Digest entryDigest(Entry& entry, std::size_t size);
  std::vector<Entry> entries_;
  std::vector<std::uint8_t> readback_;  // entryDigest()'s, kept for the next one
};

// The digests of a scene's images by image index, as TextureCache::find() took them: kept by a
// renderer for the next render of the same scene revision (Scene::revision).
using ImageDigests = std::vector<std::optional<TextureCache::Digest>>;

}  // namespace omnishadow
