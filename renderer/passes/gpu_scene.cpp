#include "renderer/passes/gpu_scene.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <future>
#include <memory>
#include <set>
#include <stdexcept>
#include <utility>
#include <vector>

#include "renderer/core/errors.h"
#include "renderer/scene/image_mipmaps.h"
#include "renderer/scene/mipmap_queue.h"

namespace omnishadow {
namespace {

// Box-filtered half-size copy (a side of 1 stays 1).
Image halved(const Image& in) {
  Image out;
  out.name = in.name;
  out.width = std::max(1, in.width / 2);
  out.height = std::max(1, in.height / 2);
  out.rgba.resize(static_cast<std::size_t>(out.width) * out.height * 4);
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x)
      for (int c = 0; c < 4; ++c) {
        int sum = 0, count = 0;
        for (int dy = 0; dy < 2; ++dy)
          for (int dx = 0; dx < 2; ++dx) {
            const int sx = std::min(2 * x + dx, in.width - 1),
                      sy = std::min(2 * y + dy, in.height - 1);
            sum += in.rgba[(static_cast<std::size_t>(sy) * in.width + sx) * 4 + c];
            ++count;
          }
        out.rgba[(static_cast<std::size_t>(y) * out.width + x) * 4 + c] =
            static_cast<std::uint8_t>((sum + count / 2) / count);
      }
  return out;
}

// A texture slot of a material, the color space its texels are in, and where its GL texture
// and sampler go.
struct TextureUse {
  const TextureSlot* slot;
  bool srgb;
  GLuint GpuMaterial::*texture;
  GLuint GpuMaterial::*sampler;
};

// The slot whose image holds a material's sheen: the color texture's, else the roughness
// texture's (whose A it then also holds when it is the same image); none when the material
// draws no sheen.
const TextureSlot& sheenSlot(const Material& desc) {
  static const TextureSlot kNone;
  if (!hasSheen(desc)) return kNone;
  return desc.sheenColorTexture.texture >= 0 ? desc.sheenColorTexture : desc.sheenRoughnessTexture;
}

// The sheen roughness texture's slot when it needs a unit of its own: both sheen textures given,
// on different images; none otherwise (sheenSlot() then holds it, or there is none).
const TextureSlot& ownSheenRoughnessSlot(const Scene& scene, const Material& desc) {
  static const TextureSlot kNone;
  const TextureSlot &color = desc.sheenColorTexture, &roughness = desc.sheenRoughnessTexture;
  if (!hasSheen(desc) || color.texture < 0 || roughness.texture < 0) return kNone;
  const auto image = [&](const TextureSlot& slot) {
    return scene.textures[static_cast<std::size_t>(slot.texture)].image;
  };
  return image(color) == image(roughness) ? kNone : roughness;
}

// An extension's texture slot, or none when the material is not drawn with that extension
// (hasClearcoat(), hasDielectricSpecular()).
const TextureSlot& slotIf(bool drawn, const TextureSlot& slot) {
  static const TextureSlot kNone;
  return drawn ? slot : kNone;
}

std::array<TextureUse, 19> textureUses(const Scene& scene, const Material& desc) {
  // Specular-glossiness materials have no metallic-roughness texture; their specular color
  // (sRGB) and glossiness (alpha, linear either way) take its unit. The sheen's texture holds
  // its color in RGB (sRGB) and its roughness in A, unless the roughness is another image.
  const TextureSlot& specularOrMetallic =
      desc.specularGlossiness ? desc.specularGlossinessTexture : desc.metallicRoughnessTexture;
  const bool clearcoat = hasClearcoat(desc), specular = hasDielectricSpecular(desc);
  return {
      {{&desc.baseColorTexture, true, &GpuMaterial::baseColor, &GpuMaterial::baseColorSampler},
       {&specularOrMetallic, desc.specularGlossiness, &GpuMaterial::metallicRoughness,
        &GpuMaterial::metallicRoughnessSampler},
       {&desc.normalTexture, false, &GpuMaterial::normal, &GpuMaterial::normalSampler},
       {&desc.occlusionTexture, false, &GpuMaterial::occlusion, &GpuMaterial::occlusionSampler},
       {&desc.emissiveTexture, true, &GpuMaterial::emissive, &GpuMaterial::emissiveSampler},
       {&desc.transmissionTexture, false, &GpuMaterial::transmission,
        &GpuMaterial::transmissionSampler},
       {&sheenSlot(desc), true, &GpuMaterial::sheen, &GpuMaterial::sheenSampler},
       {&slotIf(clearcoat, desc.clearcoatTexture), false, &GpuMaterial::clearcoat,
        &GpuMaterial::clearcoatSampler},
       {&slotIf(clearcoat, desc.clearcoatRoughnessTexture), false, &GpuMaterial::clearcoatRoughness,
        &GpuMaterial::clearcoatRoughnessSampler},
       {&slotIf(clearcoat, desc.clearcoatNormalTexture), false, &GpuMaterial::clearcoatNormal,
        &GpuMaterial::clearcoatNormalSampler},
       {&slotIf(specular, desc.specularTexture), false, &GpuMaterial::specular,
        &GpuMaterial::specularSampler},
       {&slotIf(specular, desc.specularColorTexture), true, &GpuMaterial::specularColor,
        &GpuMaterial::specularColorSampler},
       // Its A is linear either way; as sRGB it shares the texture with a sheen color of
       // another material that uses the image.
       {&ownSheenRoughnessSlot(scene, desc), true, &GpuMaterial::sheenRoughness,
        &GpuMaterial::sheenRoughnessSampler},
       {&slotIf(hasVolume(desc), desc.thicknessTexture), false, &GpuMaterial::thickness,
        &GpuMaterial::thicknessSampler},
       {&slotIf(hasAnisotropy(desc), desc.anisotropyTexture), false, &GpuMaterial::anisotropy,
        &GpuMaterial::anisotropySampler},
       {&slotIf(hasIridescence(desc), desc.iridescenceTexture), false, &GpuMaterial::iridescence,
        &GpuMaterial::iridescenceSampler},
       {&slotIf(hasIridescence(desc), desc.iridescenceThicknessTexture), false,
        &GpuMaterial::iridescenceThickness, &GpuMaterial::iridescenceThicknessSampler},
       {&slotIf(hasDiffuseTransmission(desc), desc.diffuseTransmissionTexture), false,
        &GpuMaterial::diffuseTransmission, &GpuMaterial::diffuseTransmissionSampler},
       {&slotIf(hasDiffuseTransmission(desc), desc.diffuseTransmissionColorTexture), true,
        &GpuMaterial::diffuseTransmissionColor, &GpuMaterial::diffuseTransmissionColorSampler}}};
}

// At most this many textures wait for their mipmap levels: the GL thread goes on making the
// next textures' storage while the queue makes their chains, and no more chains' levels than
// this are held in memory at once (a scene of hundreds of large textures held them all).
constexpr std::size_t kMaxPendingChains = 4;

// A texture made but for its mipmap levels, whose chain the queue is making.
struct PendingLevels {
  GLuint texture = 0;
  std::future<std::vector<Image>> chain;
  std::unique_ptr<Image> image;  // the image halved to fit the GL, when it had to be
};

}  // namespace

struct GpuScene::TextureUploads {
  explicit TextureUploads(bool chainsOnTheirOwnThread) : chains(chainsOnTheirOwnThread) {}
  std::deque<PendingLevels> pending;  // declared before the queue, so destroyed after it
  MipmapQueue chains;
};

GpuScene::GpuScene(const Scene& scene, TextureCache* textures, GeometryCache* geometry,
                   const std::vector<MeshDigests>* meshes, ImageDigests* images)
    : geometry_(!geometry ? std::make_shared<const GpuGeometry>(scene)
                : meshes  ? geometry->find(scene, *meshes)
                          : geometry->find(scene, meshDigests(scene))),
      textureCache_(textures) {
  if (images && images->size() != scene.images.size())
    throw std::logic_error("image digests of another scene");
  uploadMaterials(scene, images);
}

GLuint GpuScene::textureFor(const Scene& scene, const TextureSlot& slot, bool srgb,
                            TextureUploads& uploads, ImageDigests* images) {
  if (slot.texture < 0) return 0;
  const int imageIndex = scene.textures[slot.texture].image;
  if (imageIndex < 0) return 0;
  std::shared_ptr<const gl::Texture>& texture = textures_[2 * imageIndex + (srgb ? 1 : 0)];
  if (!texture) {
    GLint maxSize = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxSize);
    std::unique_ptr<Image> fitted;
    const Image* source = &scene.images[imageIndex];
    if (source->width > maxSize || source->height > maxSize) {
      fitted = std::make_unique<Image>(*source);
      while (fitted->width > maxSize || fitted->height > maxSize) *fitted = halved(*fitted);
      warnings_.push_back("images[" + std::to_string(imageIndex) + "] \"" + source->name + "\": " +
                          std::to_string(source->width) + "x" + std::to_string(source->height) +
                          " exceeds this GL's maximum texture size " + std::to_string(maxSize) +
                          "; downscaled to " + std::to_string(fitted->width) + "x" +
                          std::to_string(fitted->height));
      source = fitted.get();
    }
    const Image& image = *source;
    const auto make = [&] {
      // The chain is made on the queue's thread while this one makes the storage and the first
      // level; finishOldest() puts it in, kMaxPendingChains textures later or at the end.
      PendingLevels pending;
      pending.chain = uploads.chains.add(image, srgb);
      pending.image = std::move(fitted);
      gl::Texture made = gl::createTexture(GL_TEXTURE_2D);
      const int levels =
          1 + static_cast<int>(std::floor(std::log2(std::max(image.width, image.height))));
      glTextureStorage2D(made.get(), levels, srgb ? GL_SRGB8_ALPHA8 : GL_RGBA8, image.width,
                         image.height);
      glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
      // glTF's UV (0,0) is the top-left of the image and GL's texel row 0 is t = 0, so the
      // image's first (top) row goes into row 0 unflipped.
      glTextureSubImage2D(made.get(), 0, 0, 0, image.width, image.height, GL_RGBA, GL_UNSIGNED_BYTE,
                          image.rgba.data());
      pending.texture = made.get();
      uploads.pending.push_back(std::move(pending));
      while (uploads.pending.size() > kMaxPendingChains) finishOldest(uploads);
      return made;
    };
    // A downscaled image's digest is not its source's.
    std::optional<TextureCache::Digest>* known =
        images && !fitted ? &(*images)[static_cast<std::size_t>(imageIndex)] : nullptr;
    texture = textureCache_ ? textureCache_->find(image, srgb, make, known)
                            : std::make_shared<const gl::Texture>(make());
  }
  return texture->get();
}

void GpuScene::finishOldest(TextureUploads& uploads) {
  PendingLevels& oldest = uploads.pending.front();
  int level = 1;
  for (const Image& smaller : oldest.chain.get())
    glTextureSubImage2D(oldest.texture, level++, 0, 0, smaller.width, smaller.height, GL_RGBA,
                        GL_UNSIGNED_BYTE, smaller.rgba.data());
  uploads.pending.pop_front();
}

void GpuScene::finishLevels(TextureUploads& uploads) {
  while (!uploads.pending.empty()) finishOldest(uploads);
}

GLuint GpuScene::samplerFor(const Scene& scene, const TextureSlot& slot) {
  if (slot.texture < 0) return 0;
  gl::Sampler& sampler = samplers_[slot.texture];
  if (!sampler) {
    const SamplerDesc& desc = scene.textures[slot.texture].sampler;
    sampler = gl::createSampler();
    glSamplerParameteri(sampler.get(), GL_TEXTURE_MAG_FILTER, desc.magFilter);
    glSamplerParameteri(sampler.get(), GL_TEXTURE_MIN_FILTER, desc.minFilter);
    glSamplerParameteri(sampler.get(), GL_TEXTURE_WRAP_S, desc.wrapS);
    glSamplerParameteri(sampler.get(), GL_TEXTURE_WRAP_T, desc.wrapT);
  }
  return sampler.get();
}

void GpuScene::uploadMaterials(const Scene& scene, ImageDigests* images) {
  textures_.resize(2 * scene.images.size());
  samplers_.resize(scene.textures.size());
  std::vector<Material> descs = scene.materials;
  descs.emplace_back();  // glTF's default material: white, metallic 1, roughness 1
  descs.back().name = "(default)";
  std::set<std::pair<int, bool>> toMake;  // (image, sRGB) of every texture the materials use
  for (const Material& desc : descs)
    for (const TextureUse& use : textureUses(scene, desc)) {
      const int texture = use.slot->texture;
      if (texture >= 0 && scene.textures[texture].image >= 0)
        toMake.emplace(scene.textures[texture].image, use.srgb);
    }
  TextureUploads uploads(toMake.size() > 1);
  for (const Material& desc : descs) {
    GpuMaterial m;
    m.desc = desc;
    for (const TextureUse& use : textureUses(scene, desc)) {
      m.*use.texture = textureFor(scene, *use.slot, use.srgb, uploads, images);
      m.*use.sampler = samplerFor(scene, *use.slot);
    }
    materials_.push_back(std::move(m));
  }
  finishLevels(uploads);
}

}  // namespace omnishadow
