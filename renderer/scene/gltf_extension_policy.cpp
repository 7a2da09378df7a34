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
                                               {"EXT_texture_webp", "WebP"},
                                               {"EXT_texture_avif", "AVIF"},
                                               {"MSFT_texture_dds", "DDS"}};

// The image an image extension of `texture` names, or -1.
int extensionSource(const tinygltf::Texture& texture, const ImageExtension& extension) {
  const auto found = texture.extensions.find(extension.name);
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

std::vector<bool> imagesOnlyInExtensions(const Context& ctx) {
  std::vector<bool> viaExtension(ctx.model.images.size(), false);
  std::vector<bool> viaSource(ctx.model.images.size(), false);
  const auto mark = [](std::vector<bool>& marks, int image) {
    if (image >= 0 && static_cast<std::size_t>(image) < marks.size())
      marks[static_cast<std::size_t>(image)] = true;
  };
  for (const tinygltf::Texture& texture : ctx.model.textures) {
    mark(viaSource, texture.source);
    for (const ImageExtension& extension : kImageExtensions)
      mark(viaExtension, extensionSource(texture, extension));
  }
  for (std::size_t i = 0; i < viaExtension.size(); ++i)
    viaExtension[i] = viaExtension[i] && !viaSource[i];
  return viaExtension;
}

void requireFallbackSource(const Context& ctx, std::size_t index) {
  const tinygltf::Texture& texture = ctx.model.textures[index];
  if (texture.source >= 0) return;
  for (const ImageExtension& extension : kImageExtensions) {
    if (extensionSource(texture, extension) < 0) continue;
    ctx.fail(at("textures", index), std::string("its image is ") + extension.format + " (" +
                                        extension.name +
                                        "), which cannot be decoded, and it has no PNG or JPEG "
                                        "fallback source");
  }
}

}  // namespace omnishadow::gltf_detail
