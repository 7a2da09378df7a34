#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "renderer/gl/gl_resources.h"
#include "renderer/scene/scene.h"

namespace omnishadow {

// Textures made from scenes' images, kept from one render to the next: a scene rendered again
// (frame sets, --repeat, batch jobs of one scene, the Python module's renders) takes its
// textures, mipmaps and all, from here instead of making them again (Sundial's 2048^2 texture
// was 13 of its 17 ms of upload a frame). A texture is taken for an image of its size and color
// space whose bytes equal its first level, read back and compared: exact. Only candidates whose
// sample of 1024 words matches the image's are read back, so that images of one size (a
// model's textures, a batch of scenes) are not compared with each other whole.
class TextureCache {
 public:
  // The texture of `image` as `srgb` says, made by `make` when none is here. Needs the GL
  // context the textures belong to.
  std::shared_ptr<const gl::Texture> find(const Image& image, bool srgb,
                                          const std::function<gl::Texture()>& make);
  // Drops the textures not found since the last call: called once a scene is uploaded, it
  // leaves the cache holding that scene's textures (which the scene holds too while it draws).
  void dropUnused();
  std::size_t size() const { return entries_.size(); }

 private:
  struct Entry {
    int width = 0, height = 0;
    bool srgb = false;
    std::uint64_t sample = 0;  // sampleOf() the image
    std::shared_ptr<const gl::Texture> texture;
    bool used = true;
  };
  static std::uint64_t sampleOf(const Image& image);
  bool holds(const Entry& entry, const Image& image, std::uint64_t sample);
  std::vector<Entry> entries_;
  std::vector<std::uint8_t> readback_;  // holds()'s, kept for the next comparison
};

}  // namespace omnishadow
