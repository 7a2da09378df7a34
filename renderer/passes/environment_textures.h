#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>

#include "renderer/gl/gl_resources.h"
#include "renderer/scene/light.h"
#include "renderer/view/environment_map.h"

namespace omnishadow {

// The radiance of `light`: its image as linear RGB, or a uniform 1 without one (the shader
// scales either by color x intensity). Throws InputError naming the file and the lights file's
// field when the image cannot be read or holds a value that is not finite.
EquirectImage environmentRadiance(const EnvironmentLight& light);

// The background keeps this much of a panorama's width: 4096 texels over 360 degrees are about
// a pixel of a 1920-wide frame at a 90-degree field of view. The lighting reads at most 1024.
inline constexpr int kMaxBackgroundWidth = 4096;

// What the lighting pass reads of an environment light: its prefiltered specular levels as one
// mipmapped equirectangular texture (level k = roughness k / maxLevel), the irradiance over pi,
// and the split-sum BRDF table. Float textures: an HDR sky's sun is far above a half's range.
class EnvironmentTextures {
 public:
  EnvironmentTextures(const PrefilteredEnvironment& environment, const SpecularBrdfTable& brdf);
  GLuint specular() const { return specular_.get(); }
  GLuint irradiance() const { return irradiance_.get(); }
  GLuint brdf() const { return brdf_.get(); }
  GLuint sampler() const { return sampler_.get(); }            // equirect: u wraps, v clamps
  GLuint tableSampler() const { return tableSampler_.get(); }  // the BRDF table: clamps
  float maxLevel() const { return maxLevel_; }
  // The picture itself for the background (EnvironmentLight::background), up to
  // kMaxBackgroundWidth wide (area-averaged down), with area-averaged mipmaps; 0 until
  // makeBackground().
  GLuint background() const { return background_.get(); }
  void makeBackground(const EquirectImage& radiance, int threads);

 private:
  gl::Texture specular_, irradiance_, brdf_, background_;
  gl::Sampler sampler_, tableSampler_;
  float maxLevel_ = 0.0f;
};

// An environment light, the scene-independent part of it (rotation, color, intensity, whether it
// is the background), and its textures.
struct EnvironmentBinding {
  const EnvironmentTextures* textures = nullptr;  // null: no environment
  glm::mat3 toEnvironment{1.0f};                  // world direction -> the image's frame
  glm::vec3 scale{1.0f};                          // color x intensity
  bool background = false;
  // EnvironmentLight::sun: the image's sun as a directional light (none found: nullopt).
  std::optional<Light> sun;
};

// Keeps the textures of the last environment a renderer drew with, so that a batch over one
// environment reads and prefilters its image once. An image is the same while its path, size
// and modification time are.
class EnvironmentCache {
 public:
  // Throws InputError as environmentRadiance() does.
  EnvironmentBinding bind(const EnvironmentLight& light);

 private:
  struct Key {
    std::filesystem::path image;
    std::uintmax_t size = 0;
    std::filesystem::file_time_type modified{};
    bool sunTakenOut = false;
    bool operator==(const Key&) const = default;
  };
  std::optional<Key> key_;
  std::unique_ptr<EnvironmentTextures> textures_;
  std::optional<EnvironmentSun> sun_;  // what extractSun() took out of the kept textures' image
};

}  // namespace omnishadow
