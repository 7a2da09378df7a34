#include "renderer/scene/gltf_extension_policy.h"

#include <algorithm>
#include <string>

#include "renderer/scene/gltf_extensions.h"

namespace omnishadow::gltf_detail {

namespace {

// Texture extensions that name an image in a format the loader cannot decode, with the format.
struct ImageExtension {
  const char* name;
  const char* format;
};
constexpr ImageExtension kImageExtensions[] = {{"KHR_texture_basisu", "KTX2"},
                                               {"MSFT_texture_dds", "DDS"}};
// Texture extensions whose images are decoded (avif_decoder, webp_decoder): a texture draws the
// first of them it has, before its core source.
constexpr const char* kDrawnImageExtensions[] = {"EXT_texture_avif", "EXT_texture_webp"};

// The image a texture extension names (its `source`), or -1.
int extensionSource(const tinygltf::Texture& texture, const char* extension) {
  const auto found = texture.extensions.find(extension);
  if (found == texture.extensions.end() || !found->second.IsObject()) return -1;
  const tinygltf::Value& source = found->second.Get("source");
  return source.IsInt() ? source.GetNumberAsInt() : -1;
}

}  // namespace

std::vector<ExtensionUse> checkExtensions(const Context& ctx) {
  std::vector<ExtensionUse> uses;
  const auto add = [&](const std::string& name) {
    if (std::none_of(uses.begin(), uses.end(),
                     [&](const ExtensionUse& u) { return u.name == name; }))
      uses.push_back({name, false, false, ""});
  };
  for (const std::string& name : ctx.model.extensionsUsed) add(name);
  for (const std::string& name : ctx.model.extensionsRequired) add(name);
  for (ExtensionUse& use : uses) {
    const KnownExtension* known = findKnownExtension(use.name);
    use.required =
        std::find(ctx.model.extensionsRequired.begin(), ctx.model.extensionsRequired.end(),
                  use.name) != ctx.model.extensionsRequired.end();
    use.supported = known && known->status == ExtensionStatus::Supported;
    if (use.supported) continue;
    use.drawnInstead = known ? std::string(known->drawnInstead) : "nothing of it (ignored)";
    if (use.required) {
      // A file may only require an extension with fallbacks when it has none to offer.
      ctx.fail("extensionsRequired",
               use.name + " is not supported" +
                   (known && known->status == ExtensionStatus::FallbackOnly
                        ? " (its images cannot be decoded, and a file that requires it has no "
                          "PNG or JPEG fallback)"
                        : ""));
    }
    ctx.warn("extensionsUsed: " + use.name + " is not supported; " +
             (known ? "drawn instead: " + use.drawnInstead : std::string("ignored")));
  }
  return uses;
}

std::string firstUnsupportedRequired(const std::vector<std::string>& required) {
  for (const std::string& name : required) {
    const KnownExtension* known = findKnownExtension(name);
    if (!known || known->status != ExtensionStatus::Supported) return name;
  }
  return {};
}

int drawnImage(const Context& ctx, std::size_t index) {
  const tinygltf::Texture& texture = ctx.model.textures[index];
  for (const char* name : kDrawnImageExtensions) {
    const auto extension = texture.extensions.find(name);
    if (extension == texture.extensions.end()) continue;
    const std::string object = at("textures", index) + ".extensions." + name;
    if (!extension->second.IsObject()) ctx.fail(object, "expected an object");
    const tinygltf::Value& source = extension->second.Get("source");
    if (!source.IsInt()) {
      // The validator's "empty object". Without a core source either, convertTextures says so.
      if (texture.source >= 0) ctx.warn(object + ": no source; the core source is drawn");
      continue;
    }
    ctx.checkIndex(object + ".source", "image", source.GetNumberAsInt(), ctx.model.images.size());
    return source.GetNumberAsInt();
  }
  return texture.source;
}

std::vector<bool> imagesNotDecoded(const Context& ctx) {
  std::vector<bool> setAside(ctx.model.images.size(), false);
  std::vector<bool> drawn(ctx.model.images.size(), false);
  const auto mark = [](std::vector<bool>& marks, int image) {
    if (image >= 0 && static_cast<std::size_t>(image) < marks.size())
      marks[static_cast<std::size_t>(image)] = true;
  };
  for (const tinygltf::Texture& texture : ctx.model.textures) {
    // As drawnImage chooses, without its checks (made when the textures are converted).
    int chosen = -1;
    for (const char* name : kDrawnImageExtensions) {
      const int image = extensionSource(texture, name);
      if (chosen < 0)
        chosen = image;
      else
        mark(setAside, image);
    }
    if (chosen >= 0) mark(setAside, texture.source);
    mark(drawn, chosen >= 0 ? chosen : texture.source);
    for (const ImageExtension& extension : kImageExtensions)
      mark(setAside, extensionSource(texture, extension.name));
  }
  for (std::size_t i = 0; i < setAside.size(); ++i) setAside[i] = setAside[i] && !drawn[i];
  return setAside;
}

void requireFallbackSource(const Context& ctx, std::size_t index) {
  const tinygltf::Texture& texture = ctx.model.textures[index];
  if (texture.source >= 0) return;
  for (const char* name : kDrawnImageExtensions)
    if (extensionSource(texture, name) >= 0) return;
  for (const ImageExtension& extension : kImageExtensions) {
    if (extensionSource(texture, extension.name) < 0) continue;
    ctx.fail(at("textures", index), std::string("its image is ") + extension.format + " (" +
                                        extension.name +
                                        "), which cannot be decoded, and it has no PNG or JPEG "
                                        "fallback source");
  }
}

}  // namespace omnishadow::gltf_detail
