#include "renderer/scene/gltf_materials.h"

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <cstring>
#include <exception>
#include <limits>
#include <optional>
#include <string>
#include <system_error>
#include <thread>
#include <utility>
#include <vector>

#include "renderer/scene/gltf_accessors.h"
#include "renderer/scene/gltf_extension_policy.h"
#include "renderer/scene/gltf_file_safety.h"
#include "renderer/scene/gltf_material_extensions.h"

namespace omnishadow::gltf_detail {

namespace {

// The bytes of an image stored in a bufferView (see decodeUriImage). On the loading thread: a
// meshopt-compressed view is decoded into the context's cache on first use.
std::pair<const unsigned char*, std::size_t> bufferViewImageBytes(const Context& ctx,
                                                                  std::size_t index,
                                                                  const std::string& object) {
  const tinygltf::Image& source = ctx.model.images[index];
  std::size_t length = 0;
  const unsigned char* bytes = bufferViewData(ctx, object, source.bufferView, &length);
  if (length == 0 || length > static_cast<std::size_t>(std::numeric_limits<int>::max())) {
    ctx.fail(object, "bufferView " + std::to_string(source.bufferView) + " has " +
                         std::to_string(length) + " bytes");
  }
  return {bytes, length};
}

// Decodes an image's bytes (from a bufferView or its file), after the checks of
// gltf_file_safety; what libjpeg says of damaged data goes to `warnings`. Reads the context
// only, so images are decoded on several threads.
tinygltf::Image decodeImageBytes(const Context& ctx, std::size_t index, const std::string& object,
                                 const unsigned char* bytes, std::size_t length,
                                 std::vector<std::string>& warnings) {
  if (!isDecodableImage(bytes, length)) {
    ctx.fail(object,
             "unknown image format: glTF images are PNG or JPEG (or WebP and AVIF through "
             "their extensions)");
  }
  if (const std::string why = imageTooLarge(bytes, length); !why.empty()) ctx.fail(object, why);
  tinygltf::Image decoded;
  decoded.name = ctx.model.images[index].name;  // for stb_image's messages
  std::string error, warning;
  if (!decodeImage(&decoded, static_cast<int>(index), &error, &warning, bytes,
                   static_cast<int>(length))) {
    const std::vector<std::string> lines = nonEmptyLines(error);
    ctx.fail(object, lines.empty() ? "cannot decode the image data" : lines.front());
  }
  warnings = nonEmptyLines(warning);
  return decoded;
}

// Whether the loader decodes the image itself (decodeImages): stored in a bufferView, or in a
// file of its own whose bytes decodeUriImage kept (Image::as_is); tinygltf decoded the others.
bool decodedByLoader(const tinygltf::Image& source) {
  return source.bufferView >= 0 || source.as_is;
}

// One image the loader decodes, decoded, or why not. With a DecodedImageCache the RGBA8 pixels
// are in `rgba` (taken from the cache or put there), and `image` keeps the rest.
struct Decoded {
  tinygltf::Image image;
  PixelBytes rgba;
  std::vector<std::string> warnings;
  std::exception_ptr error;
};

bool isRgba8(const tinygltf::Image& image) {
  return image.component == 4 && image.bits == 8 &&
         image.image.size() ==
             static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height) * 4;
}

// Decodes an image's bytes, or takes the picture another load decoded from the same bytes
// (Context::decodedImages), which that load's checks and decoding passed and said the same of.
Decoded decodeOrFind(const Context& ctx, std::size_t index, const std::string& object,
                     const unsigned char* bytes, std::size_t length) {
  Decoded out;
  DecodedImageCache* cache = ctx.decodedImages;
  DecodedImageCache::Lookup lookup;
  if (cache) lookup = cache->find(bytes, length);
  if (lookup.picture) {
    out.image.width = lookup.picture->width;
    out.image.height = lookup.picture->height;
    out.image.component = 4;
    out.image.bits = 8;
    out.image.mimeType = lookup.picture->mimeType;
    out.rgba = std::move(lookup.picture->rgba);
    out.warnings = std::move(lookup.picture->warnings);
    return out;
  }
  try {
    out.image = decodeImageBytes(ctx, index, object, bytes, length, out.warnings);
  } catch (...) {
    if (lookup.claim) cache->abandon(lookup.claim);
    throw;
  }
  if (!lookup.claim) return out;
  if (!isRgba8(out.image)) {
    cache->abandon(lookup.claim);  // converted by convertImages(), not shared
    return out;
  }
  DecodedImageCache::Picture picture{out.image.width, out.image.height, out.image.mimeType,
                                     out.warnings, std::move(out.image.image)};
  out.image.image = {};
  out.rgba = picture.rgba;
  cache->fulfil(lookup.claim, picture);
  return out;
}

// At most this many threads decode a file's images: a .glb's five 2048^2 JPEGs (DamagedHelmet)
// were decoded one after the other, on the thread the load keeps busy while the GL context opens.
constexpr unsigned kMaxDecodeThreads = 4;

// Decodes the images stored in bufferViews or in files of their own (whose bytes decodeUriImage
// kept: Image::as_is), by image index (the others stay empty), several at a time. Errors are
// kept, not thrown: convertImages() throws each where a loader decoding one image after the
// other would have.
std::vector<Decoded> decodeImages(const Context& ctx, const std::vector<bool>& undecoded,
                                  const std::vector<std::string>& objects) {
  std::vector<Decoded> out(ctx.model.images.size());
  std::vector<std::pair<std::size_t, std::pair<const unsigned char*, std::size_t>>> work;
  for (std::size_t i = 0; i < out.size(); ++i) {
    const tinygltf::Image& source = ctx.model.images[i];
    if (undecoded[i] || !decodedByLoader(source)) continue;
    if (source.bufferView < 0) {
      if (!source.image.empty())
        work.emplace_back(i, std::make_pair(source.image.data(), source.image.size()));
      continue;
    }
    try {
      work.emplace_back(i, bufferViewImageBytes(ctx, i, objects[i]));
    } catch (...) {
      out[i].error = std::current_exception();
    }
  }
  std::atomic<std::size_t> next{0};
  const auto decodeAll = [&] {
    for (std::size_t k; (k = next.fetch_add(1)) < work.size();) {
      const auto& [i, bytes] = work[k];
      try {
        out[i] = decodeOrFind(ctx, i, objects[i], bytes.first, bytes.second);
      } catch (...) {
        out[i].error = std::current_exception();
      }
    }
  };
  const std::size_t threads = std::min<std::size_t>(
      {std::max(1u, std::thread::hardware_concurrency()), kMaxDecodeThreads, work.size()});
  std::vector<std::thread> helpers;
  for (std::size_t t = 1; t < threads; ++t) {
    try {
      helpers.emplace_back(decodeAll);
    } catch (const std::system_error&) {
      break;  // no thread to be had: this one decodes the rest
    }
  }
  decodeAll();
  for (std::thread& helper : helpers) helper.join();
  return out;
}

// "PNG", "JPEG", "WebP" or "AVIF" for the mime type decodeImage() set.
std::string formatName(const std::string& mimeType) {
  return mimeType == "image/png"    ? "PNG"
         : mimeType == "image/jpeg" ? "JPEG"
         : mimeType == "image/webp" ? "WebP"
         : mimeType == "image/avif" ? "AVIF"
                                    : "";
}

// Any channel count (1 = gray, 2 = gray + alpha) and 8 or 16 bits to RGBA8.
std::vector<std::uint8_t> toRgba8(const Context& ctx, const tinygltf::Image& decoded,
                                  const std::string& object) {
  const auto pixels =
      static_cast<std::size_t>(decoded.width) * static_cast<std::size_t>(decoded.height);
  const int channels = decoded.component;
  const int bytes = decoded.bits / 8;
  if (channels < 1 || channels > 4 || (decoded.bits != 8 && decoded.bits != 16) ||
      decoded.image.size() < pixels * static_cast<std::size_t>(channels * bytes)) {
    ctx.fail(object, "unsupported pixel format (" + std::to_string(channels) + " channels, " +
                         std::to_string(decoded.bits) + " bits)");
  }
  const unsigned char* data = decoded.image.data();
  if (channels == 4 && bytes == 1) return std::vector<std::uint8_t>(data, data + pixels * 4);
  const auto sample = [&](std::size_t index) -> std::uint8_t {
    if (bytes == 1) return data[index];
    std::uint16_t value;
    std::memcpy(&value, data + 2 * index, 2);
    return static_cast<std::uint8_t>((value * 255u + 32767u) / 65535u);
  };
  std::vector<std::uint8_t> rgba(pixels * 4);
  for (std::size_t p = 0; p < pixels; ++p) {
    const std::size_t in = p * static_cast<std::size_t>(channels);
    std::uint8_t* out = &rgba[p * 4];
    const bool gray = channels <= 2;
    out[0] = sample(in);
    out[1] = gray ? out[0] : sample(in + 1);
    out[2] = gray ? out[0] : sample(in + 2);
    out[3] = channels == 2 ? sample(in + 1) : channels == 4 ? sample(in + 3) : 255;
  }
  return rgba;
}

}  // namespace

void convertImages(Context& ctx) {
  const std::vector<bool> undecoded = imagesNotDecoded(ctx);
  std::vector<std::string> names, objects;
  for (std::size_t i = 0; i < ctx.model.images.size(); ++i) {
    const tinygltf::Image& source = ctx.model.images[i];
    const bool externalFile = !source.uri.empty() && !tinygltf::IsDataURI(source.uri);
    names.push_back(!source.name.empty() ? source.name
                    : externalFile       ? source.uri
                                         : "image" + std::to_string(i));
    objects.push_back(at("images", i) + " \"" + names.back() + "\"");
  }
  std::vector<Decoded> decodedHere = decodeImages(ctx, undecoded, objects);
  for (std::size_t i = 0; i < ctx.model.images.size(); ++i) {
    const tinygltf::Image& source = ctx.model.images[i];
    const bool externalFile = !source.uri.empty() && !tinygltf::IsDataURI(source.uri);
    Image image;
    image.name = names[i];
    if (undecoded[i]) {
      // KTX2 and the like (textures draw their fallback source), or the fallback of a WebP:
      // an empty image keeps the indices.
      ctx.scene.images.push_back(std::move(image));
      continue;
    }
    const std::string& object = objects[i];
    Decoded& ours = decodedHere[i];
    if (ours.error) std::rethrow_exception(ours.error);
    for (const std::string& line : ours.warnings) ctx.warn(object + ": " + line);
    const bool byLoader = decodedByLoader(source);
    const tinygltf::Image& decoded = byLoader ? ours.image : source;
    const bool shared = byLoader && !ours.rgba.empty();  // RGBA8 kept by the cache
    if ((decoded.image.empty() && !shared) || decoded.width <= 0 || decoded.height <= 0) {
      // tinygltf only warns when an external image is missing or undecodable.
      ctx.fail(object, externalFile ? "cannot read or decode " + source.uri
                                    : "cannot decode the image data");
    }
    image.width = decoded.width;
    image.height = decoded.height;
    // A decoded JPEG is RGBA8 already; the copy of 16 MB (Sundial) is not free.
    if (shared)
      image.rgba = std::move(ours.rgba);
    else
      image.rgba = isRgba8(decoded) && byLoader ? std::move(ours.image.image)
                                                : toRgba8(ctx, decoded, object);
    image.format = formatName(decoded.mimeType);
    ours.image = {};  // the decoded bytes, when they were converted
    ctx.scene.images.push_back(std::move(image));
  }
}

void convertTextures(Context& ctx) {
  const SamplerDesc defaults;
  for (std::size_t i = 0; i < ctx.model.textures.size(); ++i) {
    const tinygltf::Texture& source = ctx.model.textures[i];
    const std::string object = at("textures", i);
    Texture texture;
    requireFallbackSource(ctx, i);
    if (const int image = drawnImage(ctx, i); image >= 0) {
      ctx.checkIndex(object, "image", image, ctx.model.images.size());
      texture.image = image;
    } else {
      // No core image, and no image extension we know of (those fail above).
      ctx.warn(object + ": no image in a supported format; the texture is ignored");
    }
    if (source.sampler >= 0) {
      ctx.checkIndex(object, "sampler", source.sampler, ctx.model.samplers.size());
      const tinygltf::Sampler& sampler =
          ctx.model.samplers[static_cast<std::size_t>(source.sampler)];
      texture.sampler.magFilter = sampler.magFilter >= 0 ? sampler.magFilter : defaults.magFilter;
      texture.sampler.minFilter = sampler.minFilter >= 0 ? sampler.minFilter : defaults.minFilter;
      texture.sampler.wrapS = sampler.wrapS;
      texture.sampler.wrapT = sampler.wrapT;
    }
    ctx.scene.textures.push_back(texture);
  }
}

namespace {

// NormalTextureInfo, OcclusionTextureInfo and TextureInfo share these fields but no base class.
template <typename Info>
TextureSlot textureSlot(const Context& ctx, const std::string& object, const Info& info) {
  return makeTextureSlot(ctx, object, info.index, info.texCoord,
                         textureTransformOf(info.extensions));
}

}  // namespace

void convertMaterials(Context& ctx) {
  for (std::size_t i = 0; i < ctx.model.materials.size(); ++i) {
    const tinygltf::Material& source = ctx.model.materials[i];
    const std::string object = at("materials", i);
    const tinygltf::PbrMetallicRoughness& pbr = source.pbrMetallicRoughness;
    Material material;
    material.name = source.name;
    material.baseColorFactor = factor<4>(pbr.baseColorFactor, material.baseColorFactor);
    material.baseColorTexture =
        textureSlot(ctx, object + ".baseColorTexture", pbr.baseColorTexture);
    material.metallicFactor = static_cast<float>(pbr.metallicFactor);
    material.roughnessFactor = static_cast<float>(pbr.roughnessFactor);
    material.metallicRoughnessTexture =
        textureSlot(ctx, object + ".metallicRoughnessTexture", pbr.metallicRoughnessTexture);
    material.normalTexture = textureSlot(ctx, object + ".normalTexture", source.normalTexture);
    material.normalScale = static_cast<float>(source.normalTexture.scale);
    material.occlusionTexture =
        textureSlot(ctx, object + ".occlusionTexture", source.occlusionTexture);
    material.occlusionStrength = static_cast<float>(source.occlusionTexture.strength);
    material.emissiveFactor = factor<3>(source.emissiveFactor, material.emissiveFactor);
    material.emissiveTexture =
        textureSlot(ctx, object + ".emissiveTexture", source.emissiveTexture);
    const auto strength = source.extensions.find("KHR_materials_emissive_strength");
    if (strength != source.extensions.end() && strength->second.IsObject() &&
        strength->second.Get("emissiveStrength").IsNumber()) {
      material.emissiveStrength =
          static_cast<float>(strength->second.Get("emissiveStrength").GetNumberAsDouble());
    }
    if (source.alphaMode == "MASK") {
      material.alphaMode = AlphaMode::Mask;
    } else if (source.alphaMode == "BLEND") {
      material.alphaMode = AlphaMode::Blend;
    } else if (source.alphaMode != "OPAQUE" && !source.alphaMode.empty()) {
      ctx.warn(object + ": unknown alphaMode \"" + source.alphaMode + "\"; using OPAQUE");
    }
    material.alphaCutoff = static_cast<float>(source.alphaCutoff);
    material.doubleSided = source.doubleSided;
    applyMaterialExtensions(ctx, i, material);
    ctx.scene.materials.push_back(std::move(material));
  }
}

}  // namespace omnishadow::gltf_detail
