#include "renderer/passes/environment_textures.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <system_error>
#include <thread>

#include "renderer/core/errors.h"
#include "renderer/output/image_writer.h"

namespace omnishadow {
namespace {

// The split-sum table's entries along n.v and roughness: smooth in both, read bilinearly.
constexpr int kBrdfTableSize = 32;
// Far above any measured sky (the sun is about 1e9 cd/m^2), far below a float's 3.4e38.
constexpr float kMaxRadiance = 1e20f;

// The channels of `image` that hold red, green and blue: R, G, B when named so, else the first
// channel for all three (grey images).
std::array<int, 3> rgbChannels(const FloatImage& image) {
  const int r = image.channelIndex("R"), g = image.channelIndex("G"), b = image.channelIndex("B");
  if (r >= 0 && g >= 0 && b >= 0) return {r, g, b};
  return {0, 0, 0};
}

// A texture of `levels`, level 0 first, each uploaded as RGB floats (the GL converts them to
// `format`).
gl::Texture mipmappedTexture(const std::vector<EquirectImage>& levels, GLenum format) {
  gl::Texture texture = gl::createTexture(GL_TEXTURE_2D);
  glTextureStorage2D(texture.get(), static_cast<GLsizei>(levels.size()), format,
                     levels.front().width, levels.front().height);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  for (std::size_t k = 0; k < levels.size(); ++k)
    glTextureSubImage2D(texture.get(), static_cast<GLint>(k), 0, 0, levels[k].width,
                        levels[k].height, GL_RGB, GL_FLOAT, levels[k].rgb.data());
  return texture;
}

}  // namespace

EquirectImage environmentRadiance(const EnvironmentLight& light) {
  EquirectImage radiance;
  if (light.image.empty()) {
    // A uniform environment: any image of one value prefilters to that value.
    radiance.width = 4;
    radiance.height = 2;
    radiance.rgb.assign(4 * 2 * 3, 1.0f);
    return radiance;
  }
  const std::string where = light.origin + ": environment.image: ";
  FloatImage image;
  try {
    image = readImage(light.image);
  } catch (const InputError& error) {
    throw InputError(where + error.what());
  }
  if (image.width <= 0 || image.height <= 0 || image.channels.empty())
    throw InputError(where + light.image.string() + ": the image is empty");
  // A latitude-longitude panorama is twice as wide as it is high; other shapes are some other
  // kind of picture, and a very tall one would exceed the GL's texture sizes.
  if (image.height > image.width || image.width > 4 * image.height)
    throw InputError(where + light.image.string() + ": " + std::to_string(image.width) + "x" +
                     std::to_string(image.height) +
                     " is not an equirectangular panorama (twice as wide as high)");
  const std::array<int, 3> channels = rgbChannels(image);
  radiance.width = image.width;
  radiance.height = image.height;
  radiance.rgb.resize(static_cast<std::size_t>(image.width) * image.height * 3);
  const std::size_t stride = image.channels.size();
  for (std::size_t i = 0, n = static_cast<std::size_t>(image.width) * image.height; i < n; ++i) {
    for (std::size_t c = 0; c < 3; ++c) {
      const float value = image.pixels[i * stride + static_cast<std::size_t>(channels[c])];
      // One infinite or NaN texel would spread over every blurred level and the irradiance,
      // and sums of texels near the float's limit overflow to infinity.
      if (!std::isfinite(value) || value > kMaxRadiance) {
        throw InputError(where + light.image.string() + ": pixel (" +
                         std::to_string(i % static_cast<std::size_t>(image.width)) + ", " +
                         std::to_string(i / static_cast<std::size_t>(image.width)) + ") is " +
                         (std::isfinite(value) ? "above 1e20" : "not finite"));
      }
      // Radiance cannot be negative; resampling in an editor leaves small negative lobes.
      radiance.rgb[i * 3 + c] = std::max(value, 0.0f);
    }
  }
  return radiance;
}

EnvironmentTextures::EnvironmentTextures(const PrefilteredEnvironment& environment,
                                         const SpecularBrdfTable& brdf) {
  specular_ = mipmappedTexture(environment.specular, GL_RGB32F);
  maxLevel_ = static_cast<float>(environment.specular.size() - 1);
  irradiance_ = mipmappedTexture({environment.irradiance}, GL_RGB32F);

  brdf_ = gl::createTexture(GL_TEXTURE_2D);
  glTextureStorage2D(brdf_.get(), 1, GL_RG32F, brdf.size, brdf.size);
  glTextureSubImage2D(brdf_.get(), 0, 0, 0, brdf.size, brdf.size, GL_RG, GL_FLOAT,
                      brdf.scaleBias.data());

  sampler_ = gl::createSampler();
  glSamplerParameteri(sampler_.get(), GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
  glSamplerParameteri(sampler_.get(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glSamplerParameteri(sampler_.get(), GL_TEXTURE_WRAP_S, GL_REPEAT);
  glSamplerParameteri(sampler_.get(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  tableSampler_ = gl::createSampler();
  glSamplerParameteri(tableSampler_.get(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glSamplerParameteri(tableSampler_.get(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glSamplerParameteri(tableSampler_.get(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glSamplerParameteri(tableSampler_.get(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}

void EnvironmentTextures::makeBackground(const EquirectImage& radiance, int threads) {
  // Shared-exponent texels: 4 bytes for RGB with 9 bits of mantissa, to 65408 (a brighter sun
  // shows white either way), a sixth of a float texture's memory at 4096 x 2048.
  std::vector<EquirectImage> levels;
  levels.push_back(
      radiance.width > kMaxBackgroundWidth
          ? resampleEquirect(radiance, kMaxBackgroundWidth,
                             std::max(1, radiance.height * kMaxBackgroundWidth / radiance.width),
                             threads)
          : radiance);
  for (EquirectImage& mip : equirectMips(levels.front(), threads)) levels.push_back(std::move(mip));
  background_ = mipmappedTexture(levels, GL_RGB9_E5);
}

EnvironmentBinding EnvironmentCache::bind(const EnvironmentLight& light) {
  Key key{light.image, 0, {}, light.sun};
  if (!light.image.empty()) {
    std::error_code error;
    key.size = std::filesystem::file_size(light.image, error);
    if (!error) key.modified = std::filesystem::last_write_time(light.image, error);
    if (error)
      key = Key{light.image, 0, {}, light.sun};  // unreadable: environmentRadiance() says why
  }
  const bool fresh = !textures_ || key_ != key || (key.size == 0 && !light.image.empty());
  if (fresh || (light.background && !textures_->background())) {
    // A kept environment first drawn as a background reads its image again: the full picture
    // is not kept in memory for a background that may never be asked for.
    const EquirectImage radiance = environmentRadiance(light);
    const unsigned threads = std::max(1u, std::min(std::thread::hardware_concurrency(), 8u));
    if (fresh) {
      textures_.reset();
      key_.reset();
      // The background shows the sun; the lighting leaves it to the directional light.
      std::optional<EquirectImage> sunless;
      sun_.reset();
      if (light.sun) {
        sunless = radiance;
        sun_ = extractSun(*sunless);
      }
      const EquirectImage& lighting = sunless ? *sunless : radiance;
      textures_ = std::make_unique<EnvironmentTextures>(
          prefilterEnvironment(lighting, static_cast<int>(threads)),
          specularBrdfTable(kBrdfTableSize));
      key_ = key;
    }
    if (light.background) textures_->makeBackground(radiance, static_cast<int>(threads));
  }
  EnvironmentBinding binding;
  binding.textures = textures_.get();
  // The image turns with `rotation` about +Y: a world direction is turned back into its frame.
  const float c = std::cos(light.rotation), s = std::sin(light.rotation);
  binding.toEnvironment = glm::transpose(glm::mat3(c, 0.0f, -s, 0.0f, 1.0f, 0.0f, s, 0.0f, c));
  binding.scale = light.color * light.intensity;
  binding.background = light.background;
  if (light.sun && sun_) {
    // A directional light's color x intensity is the irradiance it gives a surface facing it.
    const glm::vec3 irradiance = sun_->irradiance * binding.scale;
    const float brightest = std::max({irradiance.r, irradiance.g, irradiance.b});
    if (brightest > 0.0f) {
      Light sun;
      sun.name = kEnvironmentSunName;
      sun.type = LightType::Directional;
      sun.direction = -glm::normalize(glm::transpose(binding.toEnvironment) * sun_->direction);
      sun.color = irradiance / brightest;
      sun.intensity = brightest;
      sun.shadow.radius = sun_->angularRadius;  // the penumbrae of "pcss"
      sun.origin = light.origin;
      binding.sun = sun;
    }
  }
  return binding;
}

}  // namespace omnishadow
