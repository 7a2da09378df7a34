#include "renderer/scene/gltf_material_variants.h"

#include <cstddef>
#include <set>
#include <vector>

namespace omnishadow::gltf_detail {

namespace {

constexpr const char* kExtension = "KHR_materials_variants";

std::string quotedList(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& name : names) out += (out.empty() ? "\"" : ", \"") + name + "\"";
  return out;
}

}  // namespace

void chooseMaterialVariant(Context& ctx, const std::string& requested) {
  std::vector<std::string>& names = ctx.scene.source.materialVariants;
  const auto found = ctx.model.extensions.find(kExtension);
  if (found != ctx.model.extensions.end()) {
    const std::string where = std::string("extensions.") + kExtension;
    const tinygltf::Value& root = found->second;
    if (!root.IsObject()) ctx.fail(where, "must be an object");
    const tinygltf::Value& variants = root.Get("variants");
    if (!variants.IsArray() || variants.ArrayLen() == 0)
      ctx.fail(where, "variants must be an array of at least one variant");
    for (std::size_t i = 0; i < variants.ArrayLen(); ++i) {
      const tinygltf::Value& variant = variants.Get(static_cast<int>(i));
      const tinygltf::Value& name = variant.Get("name");
      if (!variant.IsObject() || !name.IsString())
        ctx.fail(where + "." + at("variants", i), "must be an object with a string name");
      names.push_back(name.Get<std::string>());
    }
  }
  if (requested.empty()) return;
  const std::string option = "--variant " + requested;
  if (names.empty()) ctx.fail(option, "the file has no material variants");
  for (std::size_t i = 0; i < names.size(); ++i)
    if (names[i] == requested) {
      ctx.materialVariant = static_cast<int>(i);
      ctx.scene.source.materialVariant = ctx.materialVariant;
      return;
    }
  // An index, when no variant has the name.
  std::size_t digits = 0;
  while (digits < requested.size() && requested[digits] >= '0' && requested[digits] <= '9')
    ++digits;
  if (digits == requested.size() && digits <= 9) {
    const std::size_t index = std::stoul(requested);
    if (index < names.size()) {
      ctx.materialVariant = static_cast<int>(index);
      ctx.scene.source.materialVariant = ctx.materialVariant;
      return;
    }
  }
  ctx.fail(option,
           "the file has no such material variant (its variants: " + quotedList(names) + ")");
}

int primitiveMaterial(const Context& ctx, const tinygltf::Primitive& primitive,
                      const std::string& object, int defaultMaterial) {
  const auto found = primitive.extensions.find(kExtension);
  if (found == primitive.extensions.end()) return defaultMaterial;
  const std::string where = object + ".extensions." + kExtension;
  const tinygltf::Value& extension = found->second;
  if (!extension.IsObject()) ctx.fail(where, "must be an object");
  const tinygltf::Value& mappings = extension.Get("mappings");
  if (!mappings.IsArray()) ctx.fail(where, "mappings must be an array");
  const std::size_t variantCount = ctx.scene.source.materialVariants.size();
  std::set<int> mapped;  // a variant may appear in one mapping of a primitive only
  int chosen = defaultMaterial;
  for (std::size_t m = 0; m < mappings.ArrayLen(); ++m) {
    const std::string mappingObject = where + "." + at("mappings", m);
    const tinygltf::Value& mapping = mappings.Get(static_cast<int>(m));
    if (!mapping.IsObject()) ctx.fail(mappingObject, "must be an object");
    const tinygltf::Value& material = mapping.Get("material");
    if (!material.IsInt()) ctx.fail(mappingObject, "material must be an integer");
    ctx.checkIndex(mappingObject, "material", material.GetNumberAsInt(),
                   ctx.model.materials.size());
    const tinygltf::Value& variants = mapping.Get("variants");
    if (!variants.IsArray() || variants.ArrayLen() == 0)
      ctx.fail(mappingObject, "variants must be an array of at least one variant index");
    for (std::size_t v = 0; v < variants.ArrayLen(); ++v) {
      const std::string variantObject = mappingObject + "." + at("variants", v);
      const tinygltf::Value& index = variants.Get(static_cast<int>(v));
      if (!index.IsInt()) ctx.fail(variantObject, "must be an integer");
      const int variant = index.GetNumberAsInt();
      if (variantCount == 0)
        ctx.fail(variantObject,
                 std::string("the file declares no variants (extensions.") + kExtension + ")");
      ctx.checkIndex(variantObject, "variant", variant, variantCount);
      if (!mapped.insert(variant).second)
        ctx.fail(variantObject, "variant " + std::to_string(variant) +
                                    " is mapped more than once in this primitive");
      if (variant == ctx.materialVariant) chosen = material.GetNumberAsInt();
    }
  }
  return chosen;
}

}  // namespace omnishadow::gltf_detail
