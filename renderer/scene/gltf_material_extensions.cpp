#include "renderer/scene/gltf_material_extensions.h"

#include <cmath>
#include <glm/glm.hpp>
#include <limits>

namespace omnishadow::gltf_detail {

namespace {

// The number, or `fallback` when the property is absent; fails when it is not a number.
double number(const Context& ctx, const std::string& object, const tinygltf::Value& parent,
              const char* property, double fallback) {
  if (!parent.Has(property)) return fallback;
  const tinygltf::Value& value = parent.Get(property);
  if (!value.IsNumber()) ctx.fail(object, std::string(property) + " must be a number");
  return value.GetNumberAsDouble();
}

// An array of N numbers, or `fallback` when the property is absent.
template <glm::length_t N>
glm::vec<N, float> numbers(const Context& ctx, const std::string& object,
                           const tinygltf::Value& parent, const char* property,
                           glm::vec<N, float> fallback) {
  if (!parent.Has(property)) return fallback;
  const tinygltf::Value& value = parent.Get(property);
  const auto fail = [&] {
    ctx.fail(object,
             std::string(property) + " must be an array of " + std::to_string(N) + " numbers");
  };
  if (!value.IsArray() || value.ArrayLen() != static_cast<std::size_t>(N)) fail();
  glm::vec<N, float> out;
  for (glm::length_t i = 0; i < N; ++i) {
    const tinygltf::Value& element = value.Get(static_cast<int>(i));
    if (!element.IsNumber()) fail();
    out[i] = static_cast<float>(element.GetNumberAsDouble());
  }
  return out;
}

// KHR_texture_transform's matrix, translation * rotation * scale, mapping a surface's UV to the
// UV sampled: u' = sx cos(r) u + sy sin(r) v + ox, v' = -sx sin(r) u + sy cos(r) v + oy. The
// specification's GLSL listing writes the rotation transposed; its own example ("the lower left
// quadrant, rotated clockwise 90 degrees") and the markers of the Khronos TextureTransformTest
// model (tests/material_render_test.cpp) both need this direction, as three.js and the Khronos
// sample viewer implement it.
glm::mat3 uvTransform(glm::vec2 offset, float rotation, glm::vec2 scale) {
  const float c = std::cos(rotation), s = std::sin(rotation);
  const glm::mat3 translation(1, 0, 0, 0, 1, 0, offset.x, offset.y, 1);
  const glm::mat3 rotate(c, -s, 0, s, c, 0, 0, 0, 1);  // columns
  const glm::mat3 scaling(scale.x, 0, 0, 0, scale.y, 0, 0, 0, 1);
  return translation * rotate * scaling;
}

// A textureInfo given as a JSON object (inside another extension), or the empty slot.
TextureSlot slotFromValue(const Context& ctx, const std::string& object,
                          const tinygltf::Value& info) {
  if (!info.IsObject()) return {};
  const tinygltf::Value& index = info.Get("index");
  if (!index.IsInt()) ctx.fail(object, "index must be an integer");
  const tinygltf::Value& texCoord = info.Get("texCoord");
  if (info.Has("texCoord") && !texCoord.IsInt()) ctx.fail(object, "texCoord must be an integer");
  const tinygltf::Value& extensions = info.Get("extensions");
  const tinygltf::Value* transform = nullptr;
  if (extensions.IsObject() && extensions.Has("KHR_texture_transform"))
    transform = &extensions.Get("KHR_texture_transform");
  return makeTextureSlot(ctx, object, index.GetNumberAsInt(),
                         info.Has("texCoord") ? texCoord.GetNumberAsInt() : 0, transform);
}

const tinygltf::Value* extensionOf(const tinygltf::Material& material, const char* name) {
  const auto found = material.extensions.find(name);
  return found == material.extensions.end() ? nullptr : &found->second;
}

// A number that `valid` accepts, or `fallback` when the property is absent; any other value
// fails "<property> must be <what>".
template <class Valid>
float checkedNumber(const Context& ctx, const std::string& object, const tinygltf::Value& parent,
                    const char* property, double fallback, Valid valid, const char* what) {
  if (!parent.Has(property)) return static_cast<float>(fallback);
  const double value = number(ctx, object, parent, property, fallback);
  if (!valid(value)) ctx.fail(object, std::string(property) + " must be " + what);
  return static_cast<float>(value);
}

// A number in [0, 1], or `fallback` when the property is absent.
float unitNumber(const Context& ctx, const std::string& object, const tinygltf::Value& parent,
                 const char* property, float fallback) {
  return checkedNumber(
      ctx, object, parent, property, fallback, [](double v) { return v >= 0.0 && v <= 1.0; },
      "a number in [0, 1]");
}

// A number of at least 0 (finite), or `fallback` when the property is absent.
float nonNegativeNumber(const Context& ctx, const std::string& object,
                        const tinygltf::Value& parent, const char* property, float fallback) {
  return checkedNumber(
      ctx, object, parent, property, fallback,
      [](double v) { return v >= 0.0 && std::isfinite(v); }, "a number of at least 0");
}

// A color of 3 numbers in [0, 1], or `fallback` when the property is absent.
glm::vec3 unitColor(const Context& ctx, const std::string& object, const tinygltf::Value& parent,
                    const char* property, glm::vec3 fallback) {
  const glm::vec3 color = numbers<3>(ctx, object, parent, property, fallback);
  for (int c = 0; c < 3; ++c)
    if (!(color[c] >= 0.0f && color[c] <= 1.0f))
      ctx.fail(object, std::string(property) + " must be an array of 3 numbers in [0, 1]");
  return color;
}

// Material `index`'s extension `name`, which must be an object, and the object that names it in
// messages; a null value without one.
struct MaterialExtension {
  const tinygltf::Value* value = nullptr;
  std::string where;
};
MaterialExtension materialExtension(const Context& ctx, std::size_t index, const char* name) {
  MaterialExtension extension;
  extension.value = extensionOf(ctx.model.materials[index], name);
  if (!extension.value) return extension;
  extension.where = at("materials", index) + ".extensions." + name;
  if (!extension.value->IsObject()) ctx.fail(extension.where, "must be an object");
  return extension;
}

// The layers (sheen, clearcoat) whose specifications exclude unlit and specular-glossiness
// materials: such a material is drawn without `layer`, saying so. `where` names the extension.
void warnIfExcluded(const Context& ctx, std::size_t index, const Material& material,
                    const std::string& where, const char* layer) {
  if (!material.unlit &&
      !extensionOf(ctx.model.materials[index], "KHR_materials_pbrSpecularGlossiness"))
    return;
  ctx.warn(where + ": must not be used with " +
           (material.unlit ? "KHR_materials_unlit" : "KHR_materials_pbrSpecularGlossiness") + "; " +
           layer + " is not drawn");
}

// KHR_materials_specular: two factors and their textures.
void applySpecular(const Context& ctx, std::size_t index, Material& material) {
  const auto [specular, where] = materialExtension(ctx, index, "KHR_materials_specular");
  if (!specular) return;
  material.specularWeight = unitNumber(ctx, where, *specular, "specularFactor", 1.0f);
  const glm::vec3 color = numbers<3>(ctx, where, *specular, "specularColorFactor", glm::vec3(1.0f));
  for (int c = 0; c < 3; ++c)
    if (!(color[c] >= 0.0f && std::isfinite(color[c])))
      ctx.fail(where, "specularColorFactor must be an array of 3 numbers of at least 0");
  material.specularColorFactor = color;
  material.specularTexture =
      slotFromValue(ctx, where + ".specularTexture", specular->Get("specularTexture"));
  material.specularColorTexture =
      slotFromValue(ctx, where + ".specularColorTexture", specular->Get("specularColorTexture"));
}

// KHR_materials_sheen: a color and a roughness, each a factor and a texture.
void applySheen(const Context& ctx, std::size_t index, Material& material) {
  const auto [sheen, where] = materialExtension(ctx, index, "KHR_materials_sheen");
  if (!sheen) return;
  material.sheenColorFactor = unitColor(ctx, where, *sheen, "sheenColorFactor", glm::vec3(0.0f));
  material.sheenRoughnessFactor = unitNumber(ctx, where, *sheen, "sheenRoughnessFactor", 0.0f);
  material.sheenColorTexture =
      slotFromValue(ctx, where + ".sheenColorTexture", sheen->Get("sheenColorTexture"));
  material.sheenRoughnessTexture =
      slotFromValue(ctx, where + ".sheenRoughnessTexture", sheen->Get("sheenRoughnessTexture"));
  warnIfExcluded(ctx, index, material, where, "the sheen");
}

// KHR_materials_clearcoat: two factors and three textures, each on a texture unit of its own.
void applyClearcoat(const Context& ctx, std::size_t index, Material& material) {
  const auto [clearcoat, where] = materialExtension(ctx, index, "KHR_materials_clearcoat");
  if (!clearcoat) return;
  material.clearcoatFactor = unitNumber(ctx, where, *clearcoat, "clearcoatFactor", 0.0f);
  material.clearcoatRoughnessFactor =
      unitNumber(ctx, where, *clearcoat, "clearcoatRoughnessFactor", 0.0f);
  material.clearcoatTexture =
      slotFromValue(ctx, where + ".clearcoatTexture", clearcoat->Get("clearcoatTexture"));
  material.clearcoatRoughnessTexture = slotFromValue(ctx, where + ".clearcoatRoughnessTexture",
                                                     clearcoat->Get("clearcoatRoughnessTexture"));
  const tinygltf::Value& normal = clearcoat->Get("clearcoatNormalTexture");
  material.clearcoatNormalTexture = slotFromValue(ctx, where + ".clearcoatNormalTexture", normal);
  if (normal.IsObject())
    material.clearcoatNormalScale =
        static_cast<float>(number(ctx, where + ".clearcoatNormalTexture", normal, "scale", 1.0));
  warnIfExcluded(ctx, index, material, where, "the clearcoat");
}

// KHR_materials_volume: a thickness (factor and texture) and the medium's attenuation.
void applyVolume(const Context& ctx, std::size_t index, Material& material) {
  const auto [volume, where] = materialExtension(ctx, index, "KHR_materials_volume");
  if (!volume) return;
  material.thicknessFactor = nonNegativeNumber(ctx, where, *volume, "thicknessFactor", 0.0f);
  material.thicknessTexture =
      slotFromValue(ctx, where + ".thicknessTexture", volume->Get("thicknessTexture"));
  material.attenuationDistance = checkedNumber(
      ctx, where, *volume, "attenuationDistance", std::numeric_limits<double>::infinity(),
      [](double v) { return v > 0.0 && std::isfinite(v); }, "a number above 0");
  material.attenuationColor = unitColor(ctx, where, *volume, "attenuationColor", glm::vec3(1.0f));
  warnIfExcluded(ctx, index, material, where, "the volume");
}

// KHR_materials_anisotropy: a strength, a rotation and a texture.
void applyAnisotropy(const Context& ctx, std::size_t index, Material& material) {
  const auto [anisotropy, where] = materialExtension(ctx, index, "KHR_materials_anisotropy");
  if (!anisotropy) return;
  material.anisotropyStrength = unitNumber(ctx, where, *anisotropy, "anisotropyStrength", 0.0f);
  material.anisotropyRotation = checkedNumber(
      ctx, where, *anisotropy, "anisotropyRotation", 0.0, [](double v) { return std::isfinite(v); },
      "a finite number");
  material.anisotropyTexture =
      slotFromValue(ctx, where + ".anisotropyTexture", anisotropy->Get("anisotropyTexture"));
  warnIfExcluded(ctx, index, material, where, "the anisotropy");
}

// KHR_materials_iridescence: a factor, the film's index, a thickness range, two textures.
void applyIridescence(const Context& ctx, std::size_t index, Material& material) {
  const auto [film, where] = materialExtension(ctx, index, "KHR_materials_iridescence");
  if (!film) return;
  material.iridescenceFactor = unitNumber(ctx, where, *film, "iridescenceFactor", 0.0f);
  material.iridescenceTexture =
      slotFromValue(ctx, where + ".iridescenceTexture", film->Get("iridescenceTexture"));
  material.iridescenceIor = checkedNumber(
      ctx, where, *film, "iridescenceIor", 1.3,
      [](double v) { return v >= 1.0 && std::isfinite(v); }, "a number of at least 1");
  // The minimum may exceed the maximum (the specification allows it).
  material.iridescenceThicknessMinimum =
      nonNegativeNumber(ctx, where, *film, "iridescenceThicknessMinimum", 100.0f);
  material.iridescenceThicknessMaximum =
      nonNegativeNumber(ctx, where, *film, "iridescenceThicknessMaximum", 400.0f);
  material.iridescenceThicknessTexture = slotFromValue(ctx, where + ".iridescenceThicknessTexture",
                                                       film->Get("iridescenceThicknessTexture"));
  warnIfExcluded(ctx, index, material, where, "the iridescence");
}

// KHR_materials_diffuse_transmission: a factor and a color, each with a texture.
void applyDiffuseTransmission(const Context& ctx, std::size_t index, Material& material) {
  const auto [diffuse, where] = materialExtension(ctx, index, "KHR_materials_diffuse_transmission");
  if (!diffuse) return;
  material.diffuseTransmissionFactor =
      unitNumber(ctx, where, *diffuse, "diffuseTransmissionFactor", 0.0f);
  material.diffuseTransmissionTexture = slotFromValue(ctx, where + ".diffuseTransmissionTexture",
                                                      diffuse->Get("diffuseTransmissionTexture"));
  material.diffuseTransmissionColorFactor =
      unitColor(ctx, where, *diffuse, "diffuseTransmissionColorFactor", glm::vec3(1.0f));
  material.diffuseTransmissionColorTexture =
      slotFromValue(ctx, where + ".diffuseTransmissionColorTexture",
                    diffuse->Get("diffuseTransmissionColorTexture"));
  warnIfExcluded(ctx, index, material, where, "the diffuse transmission");
}

// KHR_materials_dispersion: one number, 20 / the Abbe number.
void applyDispersion(const Context& ctx, std::size_t index, Material& material) {
  const auto [dispersion, where] = materialExtension(ctx, index, "KHR_materials_dispersion");
  if (!dispersion) return;
  material.dispersion = nonNegativeNumber(ctx, where, *dispersion, "dispersion", 0.0f);
  warnIfExcluded(ctx, index, material, where, "the dispersion");
}

}  // namespace

const tinygltf::Value* textureTransformOf(const tinygltf::ExtensionMap& extensions) {
  const auto found = extensions.find("KHR_texture_transform");
  return found == extensions.end() ? nullptr : &found->second;
}

TextureSlot makeTextureSlot(const Context& ctx, const std::string& object, int index, int texCoord,
                            const tinygltf::Value* transform) {
  if (index < 0) return {};
  ctx.checkIndex(object, "texture", index, ctx.model.textures.size());
  TextureSlot slot{index, texCoord, glm::mat3(1.0f)};
  if (transform) {
    const std::string where = object + ".extensions.KHR_texture_transform";
    if (!transform->IsObject()) ctx.fail(where, "must be an object");
    slot.uvTransform =
        uvTransform(numbers<2>(ctx, where, *transform, "offset", glm::vec2(0.0f)),
                    static_cast<float>(number(ctx, where, *transform, "rotation", 0.0)),
                    numbers<2>(ctx, where, *transform, "scale", glm::vec2(1.0f)));
    if (transform->Has("texCoord")) {
      const tinygltf::Value& override = transform->Get("texCoord");
      if (!override.IsInt()) ctx.fail(where, "texCoord must be an integer");
      slot.texCoord = override.GetNumberAsInt();
    }
  }
  if (slot.texCoord < 0 || slot.texCoord > 1) {
    ctx.warn(object + ": TEXCOORD_" + std::to_string(slot.texCoord) +
             " is not supported; the texture is ignored");
    return {};
  }
  if (ctx.scene.textures[static_cast<std::size_t>(index)].image < 0) return {};
  return slot;
}

void applyMaterialExtensions(const Context& ctx, std::size_t index, Material& material) {
  const tinygltf::Material& source = ctx.model.materials[index];
  if (extensionOf(source, "KHR_materials_unlit")) material.unlit = true;
  if (const auto [transmission, where] =
          materialExtension(ctx, index, "KHR_materials_transmission");
      transmission) {
    material.transmissionFactor = unitNumber(ctx, where, *transmission, "transmissionFactor", 0.0f);
    material.transmissionTexture = slotFromValue(ctx, where + ".transmissionTexture",
                                                 transmission->Get("transmissionTexture"));
  }
  if (const auto [ior, where] = materialExtension(ctx, index, "KHR_materials_ior"); ior) {
    // The schema's range: 1 and above, or exactly 0 (a reflectance of 1, for materials
    // converted from specular-glossiness).
    material.ior = checkedNumber(
        ctx, where, *ior, "ior", 1.5,
        [](double v) { return v == 0.0 || (v >= 1.0 && std::isfinite(v)); },
        "0 or a number of at least 1");
  }
  applySpecular(ctx, index, material);
  applySheen(ctx, index, material);
  applyClearcoat(ctx, index, material);
  applyVolume(ctx, index, material);
  applyDispersion(ctx, index, material);
  applyAnisotropy(ctx, index, material);
  applyIridescence(ctx, index, material);
  applyDiffuseTransmission(ctx, index, material);
  const auto [specGloss, where] =
      materialExtension(ctx, index, "KHR_materials_pbrSpecularGlossiness");
  if (!specGloss) return;
  material.specularGlossiness = true;
  // The diffuse color takes the base color's place: the same sRGB texture and alpha roles.
  material.baseColorFactor = numbers<4>(ctx, where, *specGloss, "diffuseFactor", glm::vec4(1.0f));
  material.baseColorTexture =
      slotFromValue(ctx, where + ".diffuseTexture", specGloss->Get("diffuseTexture"));
  material.specularFactor = numbers<3>(ctx, where, *specGloss, "specularFactor", glm::vec3(1.0f));
  material.glossinessFactor =
      static_cast<float>(number(ctx, where, *specGloss, "glossinessFactor", 1.0));
  material.specularGlossinessTexture = slotFromValue(ctx, where + ".specularGlossinessTexture",
                                                     specGloss->Get("specularGlossinessTexture"));
}

}  // namespace omnishadow::gltf_detail
