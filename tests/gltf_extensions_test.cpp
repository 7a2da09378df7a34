// The loader's answer to every glTF extension: KHR_texture_transform on each texture slot,
// KHR_materials_unlit, KHR_materials_pbrSpecularGlossiness, KHR_materials_transmission,
// KHR_materials_sheen, image extensions with and without a
// fallback, and the refuse-or-warn policy for the rest, kept in one table that the README
// mirrors. No GL: these check the Scene the loader fills.
#include "renderer/scene/gltf_extensions.h"

#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "renderer/core/errors.h"
#include "renderer/scene/gltf_loader.h"
#include "scenes/builder/gltf_builder.h"
#include "tests/support/cli_fixture.h"
#include "tests/support/input_error.h"
#include "tests/support/temp_folder.h"

namespace omnishadow::gltf_extensions_test {
namespace {

namespace fs = std::filesystem;
using namespace builder;
using test_support::inputError;
using Json = nlohmann::json;
using Value = tinygltf::Value;
using test_support::contains;

std::vector<std::string> warningsAbout(const Scene& scene, const std::string& part) {
  std::vector<std::string> found;
  for (const std::string& w : scene.warnings)
    if (w.find(part) != std::string::npos) found.push_back(w);
  return found;
}

Value numbers(std::initializer_list<double> values) {
  Value::Array array;
  for (double v : values) array.emplace_back(v);
  return Value(std::move(array));
}

Value object(std::initializer_list<std::pair<const std::string, Value>> members) {
  return Value(Value::Object(members));
}

builder::MeshData quad() {
  builder::MeshData data;
  data.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  data.normals.assign(4, glm::vec3(0, 0, 1));
  data.uvs = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
  data.indices = {0, 1, 2, 0, 2, 3};
  return data;
}

class GltfExtensionsTest : public ::testing::Test {
 protected:
  test_support::TempFolder folder{"omnishadow-gltf-extensions"};

  // One quad with one material whose five slots use one 2x2 texture; the caller edits the
  // model before it is written.
  struct Quad {
    GltfBuilder builder;
    int material = -1;
    tinygltf::Material& gltfMaterial() { return builder.model().materials[material]; }
  };
  void makeQuad(Quad& q) {
    MaterialDesc material;
    const int texture = q.builder.addTexture(2, 2, std::vector<std::uint8_t>(16, 200), "tex");
    material.baseColorTexture = material.metallicRoughnessTexture = material.normalTexture =
        material.emissiveTexture = texture;
    PrimitiveOptions options;
    options.material = q.material = q.builder.addMaterial(material);
    q.gltfMaterial().occlusionTexture.index = texture;
    q.builder.addNode("quad", {}, q.builder.addMesh(quad(), options));
  }
  Scene load(GltfBuilder& builder, FileFormat format = FileFormat::GltfEmbedded) {
    const fs::path file = folder / "scene.gltf";
    builder.write(file, format);
    return loadGltf(file);
  }
  std::string file() const { return (folder / "scene.gltf").string(); }

  // What loading `q` says once the material extension's `slot` names texture `index`.
  std::string errorForTextureIndex(Quad& q, const std::string& extension, const std::string& slot,
                                   int index) {
    q.gltfMaterial().extensions[extension] = object({{slot, object({{"index", Value(index)}})}});
    return inputError([&] { load(q.builder); });
  }
};

// KHR_texture_transform written out (scale, then rotation, then offset), with the rotation's
// direction as the extension's example needs it: offset (0, 1), rotation pi/2 and scale 0.5 must
// map the unit square onto "the lower left quadrant" (checked below).
glm::vec2 specTransform(glm::vec2 uv, glm::vec2 offset, float r, glm::vec2 scale) {
  return {scale.x * std::cos(r) * uv.x + scale.y * std::sin(r) * uv.y + offset.x,
          -scale.x * std::sin(r) * uv.x + scale.y * std::cos(r) * uv.y + offset.y};
}

TEST_F(GltfExtensionsTest, TextureTransformAppliesToEveryTextureSlotAsTheSpecificationWrites) {
  Quad q;
  makeQuad(q);
  tinygltf::Material& m = q.gltfMaterial();
  const auto transform = [](double ox, double oy, double r, double sx, double sy) {
    return object(
        {{"offset", numbers({ox, oy})}, {"rotation", Value(r)}, {"scale", numbers({sx, sy})}});
  };
  m.pbrMetallicRoughness.baseColorTexture.extensions["KHR_texture_transform"] =
      transform(0.5, -0.25, 0.3, 2.0, 3.0);
  m.pbrMetallicRoughness.metallicRoughnessTexture.extensions["KHR_texture_transform"] =
      transform(0.1, 0.2, 0.0, 1.0, 1.0);
  m.normalTexture.extensions["KHR_texture_transform"] = transform(0.0, 0.0, -1.2, 1.0, 1.0);
  m.occlusionTexture.extensions["KHR_texture_transform"] = transform(0.0, 0.0, 0.0, 0.5, 4.0);
  // Only some properties: the others keep their defaults.
  m.emissiveTexture.extensions["KHR_texture_transform"] = object({{"rotation", Value(0.7)}});
  q.builder.model().extensionsUsed.push_back("KHR_texture_transform");
  const Scene scene = load(q.builder);
  EXPECT_TRUE(warningsAbout(scene, "KHR_texture_transform").empty());
  ASSERT_EQ(scene.materials.size(), 1u);
  const Material& material = scene.materials[0];
  const struct {
    const TextureSlot& slot;
    glm::vec2 offset;
    float rotation;
    glm::vec2 scale;
  } cases[] = {{material.baseColorTexture, {0.5f, -0.25f}, 0.3f, {2, 3}},
               {material.metallicRoughnessTexture, {0.1f, 0.2f}, 0.0f, {1, 1}},
               {material.normalTexture, {0, 0}, -1.2f, {1, 1}},
               {material.occlusionTexture, {0, 0}, 0.0f, {0.5f, 4}},
               {material.emissiveTexture, {0, 0}, 0.7f, {1, 1}}};
  for (const auto& c : cases) {
    EXPECT_EQ(c.slot.texture, 0);
    EXPECT_EQ(c.slot.texCoord, 0);
    for (const glm::vec2 uv : {glm::vec2(0, 0), glm::vec2(1, 0), glm::vec2(0, 1),
                               glm::vec2(0.3f, 0.8f), glm::vec2(-2, 5)}) {
      const glm::vec2 got = glm::vec2(c.slot.uvTransform * glm::vec3(uv, 1.0f));
      const glm::vec2 expected = specTransform(uv, c.offset, c.rotation, c.scale);
      EXPECT_NEAR(got.x, expected.x, 1e-5f) << uv.x << "," << uv.y;
      EXPECT_NEAR(got.y, expected.y, 1e-5f) << uv.x << "," << uv.y;
    }
  }
}

TEST_F(GltfExtensionsTest, TextureTransformMatchesTheSpecificationsExample) {
  // "This example utilizes only the lower left quadrant of the source image, rotated clockwise
  // 90 degrees": u in [0, 0.5], v in [0.5, 1] (v grows downwards in the image).
  Quad q;
  makeQuad(q);
  q.gltfMaterial().emissiveTexture.extensions["KHR_texture_transform"] =
      object({{"offset", numbers({0.0, 1.0})},
              {"rotation", Value(1.57079632679)},
              {"scale", numbers({0.5, 0.5})}});
  const glm::mat3 m = load(q.builder).materials[0].emissiveTexture.uvTransform;
  const auto at = [&](float u, float v) { return glm::vec2(m * glm::vec3(u, v, 1.0f)); };
  for (const auto& [uv, expected] :
       {std::pair{glm::vec2(0, 0), glm::vec2(0, 1)}, std::pair{glm::vec2(1, 0), glm::vec2(0, 0.5f)},
        std::pair{glm::vec2(1, 1), glm::vec2(0.5f, 0.5f)},
        std::pair{glm::vec2(0, 1), glm::vec2(0.5f, 1)}}) {
    EXPECT_NEAR(at(uv.x, uv.y).x, expected.x, 1e-6f);
    EXPECT_NEAR(at(uv.x, uv.y).y, expected.y, 1e-6f);
  }
}

TEST_F(GltfExtensionsTest, TextureTransformTexCoordOverridesTheTextureInfos) {
  Quad q;
  makeQuad(q);
  tinygltf::Material& m = q.gltfMaterial();
  m.pbrMetallicRoughness.baseColorTexture.extensions["KHR_texture_transform"] =
      object({{"texCoord", Value(1)}});
  m.normalTexture.texCoord = 1;
  m.normalTexture.extensions["KHR_texture_transform"] = object({{"texCoord", Value(0)}});
  m.emissiveTexture.extensions["KHR_texture_transform"] = object({{"texCoord", Value(2)}});
  const Scene scene = load(q.builder);
  const Material& material = scene.materials[0];
  EXPECT_EQ(material.baseColorTexture.texCoord, 1);
  EXPECT_EQ(material.baseColorTexture.uvTransform, glm::mat3(1.0f));
  EXPECT_EQ(material.normalTexture.texCoord, 0);
  EXPECT_EQ(material.metallicRoughnessTexture.texCoord, 0);  // untouched
  // TEXCOORD_2 is not read: the slot is dropped with a warning, as for a textureInfo's own.
  EXPECT_EQ(material.emissiveTexture.texture, -1);
  const std::vector<std::string> warnings = warningsAbout(scene, "TEXCOORD_2");
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0], file() +
                             ": materials[0].emissiveTexture: TEXCOORD_2 is not supported; the "
                             "texture is ignored");
}

TEST_F(GltfExtensionsTest, MalformedTextureTransformsAreInputErrorsNamingTheProperty) {
  const std::string where = ": materials[0].baseColorTexture.extensions.KHR_texture_transform: ";
  const struct {
    Value transform;
    std::string problem;
  } cases[] = {
      {object({{"offset", numbers({1.0})}}), "offset must be an array of 2 numbers"},
      {object({{"scale", Value(std::string("big"))}}), "scale must be an array of 2 numbers"},
      {object({{"rotation", numbers({1.0})}}), "rotation must be a number"},
      {object({{"texCoord", Value(0.5)}}), "texCoord must be an integer"}};
  for (const auto& c : cases) {
    Quad q;
    makeQuad(q);
    q.gltfMaterial().pbrMetallicRoughness.baseColorTexture.extensions["KHR_texture_transform"] =
        c.transform;
    EXPECT_EQ(inputError([&] { load(q.builder); }), file() + where + c.problem);
  }
}

TEST_F(GltfExtensionsTest, UnlitMaterialsAreMarkedAndMayBeRequired) {
  GltfBuilder builder;
  MaterialDesc desc;
  desc.baseColor = {1.0f, 0.25f, 0.0f, 1.0f};
  PrimitiveOptions options;
  options.material = builder.addMaterial(desc);
  const int plain = builder.addMaterial(desc);
  builder.addNode("quad", {}, builder.addMesh(quad(), options));
  builder.model().materials[options.material].extensions["KHR_materials_unlit"] = object({});
  builder.model().extensionsUsed = {"KHR_materials_unlit"};
  builder.model().extensionsRequired = {"KHR_materials_unlit"};
  const Scene scene = load(builder);
  EXPECT_TRUE(scene.warnings.empty()) << scene.warnings.front();
  EXPECT_TRUE(scene.materials[0].unlit);
  EXPECT_FALSE(scene.materials[static_cast<std::size_t>(plain)].unlit);
  EXPECT_EQ(scene.materials[0].baseColorFactor, glm::vec4(1.0f, 0.25f, 0.0f, 1.0f));
}

TEST_F(GltfExtensionsTest, SpecularGlossinessReplacesTheMetallicRoughnessInputs) {
  Quad q;
  makeQuad(q);
  const int second = q.builder.addTexture(1, 1, {10, 20, 30, 40}, "specgloss");
  Value::Object diffuseTexture = {{"index", Value(0)}, {"texCoord", Value(1)}};
  Value::Object specularTexture = {
      {"index", Value(second)},
      {"extensions",
       object({{"KHR_texture_transform", object({{"offset", numbers({0.5, 0.25})}})}})}};
  q.gltfMaterial().extensions["KHR_materials_pbrSpecularGlossiness"] =
      object({{"diffuseFactor", numbers({0.5, 0.25, 0.125, 0.75})},
              {"diffuseTexture", Value(diffuseTexture)},
              {"specularFactor", numbers({0.25, 0.5, 1.0})},
              {"glossinessFactor", Value(0.375)},
              {"specularGlossinessTexture", Value(specularTexture)}});
  q.builder.model().extensionsUsed = {"KHR_materials_pbrSpecularGlossiness"};
  q.builder.model().extensionsRequired = {"KHR_materials_pbrSpecularGlossiness"};
  const Scene scene = load(q.builder);
  EXPECT_TRUE(scene.warnings.empty()) << scene.warnings.front();
  const Material& m = scene.materials[0];
  EXPECT_TRUE(m.specularGlossiness);
  EXPECT_EQ(m.baseColorFactor, glm::vec4(0.5f, 0.25f, 0.125f, 0.75f));
  EXPECT_EQ(m.baseColorTexture.texture, 0);
  EXPECT_EQ(m.baseColorTexture.texCoord, 1);
  EXPECT_EQ(m.specularFactor, glm::vec3(0.25f, 0.5f, 1.0f));
  EXPECT_EQ(m.glossinessFactor, 0.375f);
  EXPECT_EQ(m.specularGlossinessTexture.texture, second);
  EXPECT_EQ(glm::vec2(m.specularGlossinessTexture.uvTransform * glm::vec3(0, 0, 1)),
            glm::vec2(0.5f, 0.25f));

  // Defaults: diffuse white, specular white, glossiness 1, no textures.
  q.gltfMaterial().extensions["KHR_materials_pbrSpecularGlossiness"] = object({});
  const Scene defaults = load(q.builder);
  const Material& d = defaults.materials[0];
  EXPECT_TRUE(d.specularGlossiness);
  EXPECT_EQ(d.baseColorFactor, glm::vec4(1.0f));
  EXPECT_EQ(d.baseColorTexture.texture, -1);
  EXPECT_EQ(d.specularFactor, glm::vec3(1.0f));
  EXPECT_EQ(d.glossinessFactor, 1.0f);
  EXPECT_EQ(d.specularGlossinessTexture.texture, -1);

  EXPECT_EQ(errorForTextureIndex(q, "KHR_materials_pbrSpecularGlossiness",
                                 "specularGlossinessTexture", 9),
            file() +
                ": materials[0].extensions.KHR_materials_pbrSpecularGlossiness."
                "specularGlossinessTexture: texture 9 is out of range (the file has 2 textures)");
}

TEST_F(GltfExtensionsTest, TransmissionFactorIsReadAndMayBeRequired) {
  Quad q;
  makeQuad(q);
  q.gltfMaterial().extensions["KHR_materials_transmission"] =
      object({{"transmissionFactor", Value(0.75)}});
  q.builder.model().extensionsUsed = {"KHR_materials_transmission"};
  q.builder.model().extensionsRequired = {"KHR_materials_transmission"};
  const Scene scene = load(q.builder);
  EXPECT_TRUE(scene.warnings.empty()) << scene.warnings.front();
  EXPECT_EQ(scene.materials[0].transmissionFactor, 0.75f);

  // The factor defaults to 0 (the spec's default): the extension alone transmits nothing.
  q.gltfMaterial().extensions["KHR_materials_transmission"] = object({});
  EXPECT_EQ(load(q.builder).materials[0].transmissionFactor, 0.0f);

  // The texture, with its own texCoord and KHR_texture_transform, as any textureInfo.
  Value::Object textureInfo = {
      {"index", Value(0)},
      {"texCoord", Value(1)},
      {"extensions",
       object({{"KHR_texture_transform", object({{"offset", numbers({0.5, 0.25})}})}})}};
  q.gltfMaterial().extensions["KHR_materials_transmission"] =
      object({{"transmissionFactor", Value(0.5)}, {"transmissionTexture", Value(textureInfo)}});
  const Scene textured = load(q.builder);
  EXPECT_TRUE(textured.warnings.empty()) << textured.warnings.front();
  const Material& m = textured.materials[0];
  EXPECT_EQ(m.transmissionFactor, 0.5f);
  EXPECT_EQ(m.transmissionTexture.texture, 0);
  EXPECT_EQ(m.transmissionTexture.texCoord, 1);
  EXPECT_EQ(glm::vec2(m.transmissionTexture.uvTransform * glm::vec3(0, 0, 1)),
            glm::vec2(0.5f, 0.25f));
  EXPECT_EQ(errorForTextureIndex(q, "KHR_materials_transmission", "transmissionTexture", 7),
            file() +
                ": materials[0].extensions.KHR_materials_transmission.transmissionTexture: "
                "texture 7 is out of range (the file has 1 texture)");

  for (const double bad : {-0.25, 1.5}) {
    q.gltfMaterial().extensions["KHR_materials_transmission"] =
        object({{"transmissionFactor", Value(bad)}});
    EXPECT_EQ(inputError([&] { load(q.builder); }),
              file() +
                  ": materials[0].extensions.KHR_materials_transmission: "
                  "transmissionFactor must be a number in [0, 1]");
  }
  q.gltfMaterial().extensions["KHR_materials_transmission"] =
      object({{"transmissionFactor", Value("half")}});
  EXPECT_EQ(inputError([&] { load(q.builder); }),
            file() +
                ": materials[0].extensions.KHR_materials_transmission: "
                "transmissionFactor must be a number");
}

TEST_F(GltfExtensionsTest, IorIsReadAndMayBeRequired) {
  Quad q;
  makeQuad(q);
  EXPECT_EQ(load(q.builder).materials[0].ior, 1.5f);  // glTF's own, without the extension
  EXPECT_EQ(dielectricF0(load(q.builder).materials[0]), 0.04f);
  q.gltfMaterial().extensions["KHR_materials_ior"] = object({{"ior", Value(1.33)}});
  q.builder.model().extensionsUsed = {"KHR_materials_ior"};
  q.builder.model().extensionsRequired = {"KHR_materials_ior"};
  const Scene water = load(q.builder);
  EXPECT_TRUE(water.warnings.empty()) << water.warnings.front();
  EXPECT_EQ(water.materials[0].ior, 1.33f);
  EXPECT_NEAR(dielectricF0(water.materials[0]), (0.33 / 2.33) * (0.33 / 2.33), 1e-7);
  q.gltfMaterial().extensions["KHR_materials_ior"] = object({});
  EXPECT_EQ(load(q.builder).materials[0].ior, 1.5f);  // the extension's default
  // 0 is in the schema's range (a reflectance of 1); so is anything from 1 up.
  q.gltfMaterial().extensions["KHR_materials_ior"] = object({{"ior", Value(0.0)}});
  EXPECT_EQ(dielectricF0(load(q.builder).materials[0]), 1.0f);
  q.gltfMaterial().extensions["KHR_materials_ior"] = object({{"ior", Value(2.42)}});
  EXPECT_EQ(load(q.builder).materials[0].ior, 2.42f);

  const std::string where = file() + ": materials[0].extensions.KHR_materials_ior: ";
  for (const double bad : {0.5, -1.0}) {
    q.gltfMaterial().extensions["KHR_materials_ior"] = object({{"ior", Value(bad)}});
    EXPECT_EQ(inputError([&] { load(q.builder); }),
              where + "ior must be 0 or a number of at least 1");
  }
  q.gltfMaterial().extensions["KHR_materials_ior"] = object({{"ior", Value("glass")}});
  EXPECT_EQ(inputError([&] { load(q.builder); }), where + "ior must be a number");
}

TEST_F(GltfExtensionsTest, SpecularFactorsAndTexturesAreRead) {
  Quad q;
  makeQuad(q);
  EXPECT_FALSE(hasDielectricSpecular(load(q.builder).materials[0]));
  const std::string where = file() + ": materials[0].extensions.KHR_materials_specular";
  q.gltfMaterial().extensions["KHR_materials_specular"] =
      object({{"specularFactor", Value(0.5)}, {"specularColorFactor", numbers({2.0, 1.0, 0.25})}});
  q.builder.model().extensionsUsed = {"KHR_materials_specular"};
  q.builder.model().extensionsRequired = {"KHR_materials_specular"};
  const Scene scene = load(q.builder);
  EXPECT_TRUE(scene.warnings.empty()) << scene.warnings.front();
  EXPECT_EQ(scene.materials[0].specularWeight, 0.5f);
  EXPECT_EQ(scene.materials[0].specularColorFactor, glm::vec3(2.0f, 1.0f, 0.25f));
  EXPECT_TRUE(hasDielectricSpecular(scene.materials[0]));
  // The defaults (factor 1, color 1) shade as no extension does.
  q.gltfMaterial().extensions["KHR_materials_specular"] = object({});
  EXPECT_FALSE(hasDielectricSpecular(load(q.builder).materials[0]));

  // The textures, each with its own texCoord as any textureInfo; a texture alone (default
  // factors) shades with the extension too.
  q.gltfMaterial().extensions["KHR_materials_specular"] =
      object({{"specularTexture", object({{"index", Value(0)}, {"texCoord", Value(1)}})},
              {"specularColorTexture", object({{"index", Value(0)}})}});
  const Scene textured = load(q.builder);
  EXPECT_TRUE(textured.warnings.empty()) << textured.warnings.front();
  EXPECT_EQ(textured.materials[0].specularTexture.texture, 0);
  EXPECT_EQ(textured.materials[0].specularTexture.texCoord, 1);
  EXPECT_EQ(textured.materials[0].specularColorTexture.texture, 0);
  EXPECT_TRUE(hasDielectricSpecular(textured.materials[0]));
  EXPECT_EQ(errorForTextureIndex(q, "KHR_materials_specular", "specularColorTexture", 4),
            where + ".specularColorTexture: texture 4 is out of range (the file has 1 texture)");

  for (const double bad : {1.5, -0.5}) {
    q.gltfMaterial().extensions["KHR_materials_specular"] =
        object({{"specularFactor", Value(bad)}});
    EXPECT_EQ(inputError([&] { load(q.builder); }),
              where + ": specularFactor must be a number in [0, 1]");
  }
  q.gltfMaterial().extensions["KHR_materials_specular"] =
      object({{"specularColorFactor", numbers({1.0, -1.0, 1.0})}});
  EXPECT_EQ(inputError([&] { load(q.builder); }),
            where + ": specularColorFactor must be an array of 3 numbers of at least 0");
}

TEST_F(GltfExtensionsTest, SheenFactorsAndTexturesAreReadAndMayBeRequired) {
  Quad q;
  makeQuad(q);
  const std::string where = file() + ": materials[0].extensions.KHR_materials_sheen";
  q.gltfMaterial().extensions["KHR_materials_sheen"] = object(
      {{"sheenColorFactor", numbers({1.0, 0.5, 0.25})}, {"sheenRoughnessFactor", Value(0.4)}});
  q.builder.model().extensionsUsed = {"KHR_materials_sheen"};
  q.builder.model().extensionsRequired = {"KHR_materials_sheen"};
  const Scene scene = load(q.builder);
  EXPECT_TRUE(scene.warnings.empty()) << scene.warnings.front();
  EXPECT_EQ(scene.materials[0].sheenColorFactor, glm::vec3(1.0f, 0.5f, 0.25f));
  EXPECT_EQ(scene.materials[0].sheenRoughnessFactor, 0.4f);
  EXPECT_TRUE(hasSheen(scene.materials[0]));

  // The specification's defaults: color 0 (no sheen at all), roughness 0.
  q.gltfMaterial().extensions["KHR_materials_sheen"] = object({});
  const Scene plain = load(q.builder);
  EXPECT_EQ(plain.materials[0].sheenColorFactor, glm::vec3(0.0f));
  EXPECT_EQ(plain.materials[0].sheenRoughnessFactor, 0.0f);
  EXPECT_FALSE(hasSheen(plain.materials[0]));

  // Both textures on one image, each with its own texCoord and transform, as any textureInfo.
  const Value::Object color = {
      {"index", Value(0)},
      {"texCoord", Value(1)},
      {"extensions",
       object({{"KHR_texture_transform", object({{"offset", numbers({0.5, 0.25})}})}})}};
  q.gltfMaterial().extensions["KHR_materials_sheen"] =
      object({{"sheenColorFactor", numbers({1.0, 1.0, 1.0})},
              {"sheenColorTexture", Value(color)},
              {"sheenRoughnessTexture", object({{"index", Value(0)}})}});
  const Scene textured = load(q.builder);
  EXPECT_TRUE(textured.warnings.empty()) << textured.warnings.front();
  const Material& m = textured.materials[0];
  EXPECT_EQ(m.sheenColorTexture.texture, 0);
  EXPECT_EQ(m.sheenColorTexture.texCoord, 1);
  EXPECT_EQ(glm::vec2(m.sheenColorTexture.uvTransform * glm::vec3(0, 0, 1)),
            glm::vec2(0.5f, 0.25f));
  EXPECT_EQ(m.sheenRoughnessTexture.texture, 0);
  EXPECT_EQ(m.sheenRoughnessTexture.texCoord, 0);
  EXPECT_EQ(errorForTextureIndex(q, "KHR_materials_sheen", "sheenRoughnessTexture", 3),
            where + ".sheenRoughnessTexture: texture 3 is out of range (the file has 1 texture)");

  // A roughness texture on another image than the color's is read too (through a unit of its
  // own).
  const int other = q.builder.addTexture(1, 1, {9, 9, 9, 9}, "other");
  q.gltfMaterial().extensions["KHR_materials_sheen"] =
      object({{"sheenColorFactor", numbers({1.0, 1.0, 1.0})},
              {"sheenRoughnessFactor", Value(0.5)},
              {"sheenColorTexture", object({{"index", Value(0)}})},
              {"sheenRoughnessTexture", object({{"index", Value(other)}})}});
  const Scene twoImages = load(q.builder);
  EXPECT_TRUE(twoImages.warnings.empty()) << twoImages.warnings.front();
  EXPECT_EQ(twoImages.materials[0].sheenRoughnessTexture.texture, other);
  EXPECT_EQ(twoImages.materials[0].sheenColorTexture.texture, 0);
  EXPECT_EQ(twoImages.materials[0].sheenRoughnessFactor, 0.5f);
  // Alone, a roughness texture of any image is read.
  q.gltfMaterial().extensions["KHR_materials_sheen"] =
      object({{"sheenColorFactor", numbers({1.0, 1.0, 1.0})},
              {"sheenRoughnessTexture", object({{"index", Value(other)}})}});
  EXPECT_EQ(load(q.builder).materials[0].sheenRoughnessTexture.texture, other);

  // The extension excludes unlit and specular-glossiness materials: drawn without the sheen.
  q.gltfMaterial().extensions["KHR_materials_sheen"] =
      object({{"sheenColorFactor", numbers({1.0, 1.0, 1.0})}});
  q.gltfMaterial().extensions["KHR_materials_unlit"] = object({});
  const Scene unlit = load(q.builder);
  EXPECT_EQ(warningsAbout(unlit, "KHR_materials_sheen"),
            std::vector<std::string>{
                where + ": must not be used with KHR_materials_unlit; the sheen is not drawn"});
  EXPECT_FALSE(hasSheen(unlit.materials[0]));
  q.gltfMaterial().extensions.erase("KHR_materials_unlit");

  const std::pair<Value, std::string> bad[] = {
      {numbers({1.0, 1.0}), "sheenColorFactor must be an array of 3 numbers"},
      {numbers({1.0, 1.5, 0.0}), "sheenColorFactor must be an array of 3 numbers in [0, 1]"},
      {numbers({-0.5, 0.0, 0.0}), "sheenColorFactor must be an array of 3 numbers in [0, 1]"}};
  for (const auto& [value, message] : bad) {
    q.gltfMaterial().extensions["KHR_materials_sheen"] = object({{"sheenColorFactor", value}});
    EXPECT_EQ(inputError([&] { load(q.builder); }), where + ": " + message);
  }
  for (const Value& roughness : {Value(1.25), Value(-0.1)}) {
    q.gltfMaterial().extensions["KHR_materials_sheen"] =
        object({{"sheenRoughnessFactor", roughness}});
    EXPECT_EQ(inputError([&] { load(q.builder); }),
              where + ": sheenRoughnessFactor must be a number in [0, 1]");
  }
}

// KHR_materials_volume: the thickness (factor, texture), the attenuation, the specification's
// defaults (a thin wall, no attenuation), a volume drawn only with a transmission, the ranges.
TEST_F(GltfExtensionsTest, VolumeThicknessAndAttenuationAreRead) {
  Quad q;
  makeQuad(q);
  const std::string where = file() + ": materials[0].extensions.KHR_materials_volume";
  q.gltfMaterial().extensions["KHR_materials_volume"] =
      object({{"thicknessFactor", Value(0.25)},
              {"thicknessTexture", object({{"index", Value(0)}})},
              {"attenuationDistance", Value(2.0)},
              {"attenuationColor", numbers({0.5, 0.75, 1.0})}});
  q.builder.model().extensionsUsed = {"KHR_materials_volume"};
  q.builder.model().extensionsRequired = {"KHR_materials_volume"};
  const Scene scene = load(q.builder);
  EXPECT_TRUE(scene.warnings.empty()) << scene.warnings.front();
  const Material& m = scene.materials[0];
  EXPECT_EQ(m.thicknessFactor, 0.25f);
  EXPECT_EQ(m.thicknessTexture.texture, 0);
  EXPECT_EQ(m.attenuationDistance, 2.0f);
  EXPECT_EQ(m.attenuationColor, glm::vec3(0.5f, 0.75f, 1.0f));
  EXPECT_FALSE(hasVolume(m));  // no transmission: the volume has no effect
  q.gltfMaterial().extensions["KHR_materials_transmission"] =
      object({{"transmissionFactor", Value(1.0)}});
  EXPECT_TRUE(hasVolume(load(q.builder).materials[0]));

  q.gltfMaterial().extensions["KHR_materials_volume"] = object({});
  const Scene plain = load(q.builder);
  EXPECT_EQ(plain.materials[0].thicknessFactor, 0.0f);
  EXPECT_EQ(plain.materials[0].attenuationDistance, std::numeric_limits<float>::infinity());
  EXPECT_EQ(plain.materials[0].attenuationColor, glm::vec3(1.0f));
  EXPECT_FALSE(hasVolume(plain.materials[0]));  // a thin wall

  EXPECT_EQ(errorForTextureIndex(q, "KHR_materials_volume", "thicknessTexture", 5),
            where + ".thicknessTexture: texture 5 is out of range (the file has 1 texture)");
  const std::pair<Value::Object, std::string> bad[] = {
      {{{"thicknessFactor", Value(-0.5)}}, "thicknessFactor must be a number of at least 0"},
      {{{"thicknessFactor", Value("thick")}}, "thicknessFactor must be a number"},
      {{{"attenuationDistance", Value(0.0)}}, "attenuationDistance must be a number above 0"},
      {{{"attenuationDistance", Value(-1.0)}}, "attenuationDistance must be a number above 0"},
      {{{"attenuationColor", numbers({1.5, 0.0, 0.0})}},
       "attenuationColor must be an array of 3 numbers in [0, 1]"},
      {{{"attenuationColor", numbers({1.0, 1.0})}},
       "attenuationColor must be an array of 3 numbers"}};
  for (const auto& [properties, message] : bad) {
    q.gltfMaterial().extensions["KHR_materials_volume"] = Value(properties);
    EXPECT_EQ(inputError([&] { load(q.builder); }), where + ": " + message);
  }

  // The extension excludes unlit materials: drawn without the volume, saying so.
  q.gltfMaterial().extensions["KHR_materials_volume"] = object({{"thicknessFactor", Value(1.0)}});
  q.gltfMaterial().extensions["KHR_materials_unlit"] = object({});
  const Scene unlit = load(q.builder);
  EXPECT_EQ(
      warningsAbout(unlit, "KHR_materials_volume"),
      std::vector<std::string>{where + ": must not be used with KHR_materials_unlit; the volume is "
                                       "not drawn"});
  EXPECT_FALSE(hasVolume(unlit.materials[0]));
}

// KHR_materials_dispersion: one number of at least 0 (values above 1 exaggerate, and are
// valid), drawn on a volume alone.
TEST_F(GltfExtensionsTest, DispersionIsReadAndDrawnOnVolumesAlone) {
  Quad q;
  makeQuad(q);
  const std::string where = file() + ": materials[0].extensions.KHR_materials_dispersion";
  q.gltfMaterial().extensions["KHR_materials_dispersion"] = object({{"dispersion", Value(2.5)}});
  q.builder.model().extensionsUsed = {"KHR_materials_dispersion"};
  q.builder.model().extensionsRequired = {"KHR_materials_dispersion"};
  Scene scene = load(q.builder);
  EXPECT_TRUE(scene.warnings.empty()) << scene.warnings.front();
  EXPECT_EQ(scene.materials[0].dispersion, 2.5f);
  EXPECT_FALSE(hasDispersion(scene.materials[0]));  // no volume
  q.gltfMaterial().extensions["KHR_materials_transmission"] =
      object({{"transmissionFactor", Value(1.0)}});
  q.gltfMaterial().extensions["KHR_materials_volume"] = object({{"thicknessFactor", Value(0.5)}});
  EXPECT_TRUE(hasDispersion(load(q.builder).materials[0]));
  q.gltfMaterial().extensions["KHR_materials_dispersion"] = object({});
  EXPECT_FALSE(hasDispersion(load(q.builder).materials[0]));  // the default, 0: none
  for (const Value& bad : {Value(-0.5), Value("strong")}) {
    q.gltfMaterial().extensions["KHR_materials_dispersion"] = object({{"dispersion", bad}});
    EXPECT_EQ(inputError([&] { load(q.builder); }),
              where + (bad.IsNumber() ? ": dispersion must be a number of at least 0"
                                      : ": dispersion must be a number"));
  }
}

// KHR_materials_anisotropy: strength, rotation and texture, the defaults (no anisotropy), the
// ranges, the exclusions; a mesh without tangents gets them for an anisotropic material, from
// its first texture coordinates when there is no texture to follow.
TEST_F(GltfExtensionsTest, AnisotropyIsReadAndItsMeshesGetTangents) {
  Quad q;
  makeQuad(q);
  const std::string where = file() + ": materials[0].extensions.KHR_materials_anisotropy";
  q.gltfMaterial().normalTexture.index = -1;  // no normal map asking for tangents
  EXPECT_TRUE(load(q.builder).meshes[0].tangents.empty());
  q.gltfMaterial().extensions["KHR_materials_anisotropy"] =
      object({{"anisotropyStrength", Value(0.6)}, {"anisotropyRotation", Value(1.5)}});
  q.builder.model().extensionsUsed = {"KHR_materials_anisotropy"};
  q.builder.model().extensionsRequired = {"KHR_materials_anisotropy"};
  const Scene scene = load(q.builder);
  EXPECT_TRUE(scene.warnings.empty()) << scene.warnings.front();
  EXPECT_EQ(scene.materials[0].anisotropyStrength, 0.6f);
  EXPECT_EQ(scene.materials[0].anisotropyRotation, 1.5f);
  EXPECT_TRUE(hasAnisotropy(scene.materials[0]));
  ASSERT_EQ(scene.meshes[0].tangents.size(), scene.meshes[0].positions.size());

  q.gltfMaterial().extensions["KHR_materials_anisotropy"] =
      object({{"anisotropyTexture", object({{"index", Value(0)}, {"texCoord", Value(1)}})}});
  const Scene plain = load(q.builder);
  EXPECT_EQ(plain.materials[0].anisotropyStrength, 0.0f);  // the default: none
  EXPECT_EQ(plain.materials[0].anisotropyRotation, 0.0f);
  EXPECT_EQ(plain.materials[0].anisotropyTexture.texture, 0);
  EXPECT_EQ(plain.materials[0].anisotropyTexture.texCoord, 1);
  EXPECT_FALSE(hasAnisotropy(plain.materials[0]));
  EXPECT_TRUE(plain.meshes[0].tangents.empty());

  EXPECT_EQ(errorForTextureIndex(q, "KHR_materials_anisotropy", "anisotropyTexture", 5),
            where + ".anisotropyTexture: texture 5 is out of range (the file has 1 texture)");
  for (const Value& bad : {Value(1.5), Value(-0.25), Value("strong")}) {
    q.gltfMaterial().extensions["KHR_materials_anisotropy"] = object({{"anisotropyStrength", bad}});
    EXPECT_EQ(inputError([&] { load(q.builder); }),
              where + (bad.IsNumber() ? ": anisotropyStrength must be a number in [0, 1]"
                                      : ": anisotropyStrength must be a number"));
  }
  q.gltfMaterial().extensions["KHR_materials_anisotropy"] =
      object({{"anisotropyRotation", Value("left")}});
  EXPECT_EQ(inputError([&] { load(q.builder); }), where + ": anisotropyRotation must be a number");

  q.gltfMaterial().extensions["KHR_materials_anisotropy"] =
      object({{"anisotropyStrength", Value(1.0)}});
  q.gltfMaterial().extensions["KHR_materials_unlit"] = object({});
  const Scene unlit = load(q.builder);
  EXPECT_EQ(warningsAbout(unlit, "KHR_materials_anisotropy"),
            std::vector<std::string>{where + ": must not be used with KHR_materials_unlit; the "
                                             "anisotropy is not drawn"});
  EXPECT_FALSE(hasAnisotropy(unlit.materials[0]));
}

// KHR_materials_iridescence: factor, index, thickness range and textures, the defaults (no
// film; index 1.3, 100 to 400 nm), the ranges (a minimum above the maximum is allowed), the
// exclusions.
TEST_F(GltfExtensionsTest, IridescenceIsRead) {
  Quad q;
  makeQuad(q);
  const std::string where = file() + ": materials[0].extensions.KHR_materials_iridescence";
  q.gltfMaterial().extensions["KHR_materials_iridescence"] = object(
      {{"iridescenceFactor", Value(0.5)},
       {"iridescenceIor", Value(1.8)},
       {"iridescenceThicknessMinimum", Value(500.0)},
       {"iridescenceThicknessMaximum", Value(250.0)},
       {"iridescenceTexture", object({{"index", Value(0)}})},
       {"iridescenceThicknessTexture", object({{"index", Value(0)}, {"texCoord", Value(1)}})}});
  q.builder.model().extensionsUsed = {"KHR_materials_iridescence"};
  q.builder.model().extensionsRequired = {"KHR_materials_iridescence"};
  const Scene scene = load(q.builder);
  EXPECT_TRUE(scene.warnings.empty()) << scene.warnings.front();
  const Material& m = scene.materials[0];
  EXPECT_EQ(m.iridescenceFactor, 0.5f);
  EXPECT_EQ(m.iridescenceIor, 1.8f);
  EXPECT_EQ(m.iridescenceThicknessMinimum, 500.0f);
  EXPECT_EQ(m.iridescenceThicknessMaximum, 250.0f);
  EXPECT_EQ(m.iridescenceTexture.texture, 0);
  EXPECT_EQ(m.iridescenceThicknessTexture.texCoord, 1);
  EXPECT_TRUE(hasIridescence(m));

  q.gltfMaterial().extensions["KHR_materials_iridescence"] = object({});
  const Material plain = load(q.builder).materials[0];
  EXPECT_EQ(plain.iridescenceFactor, 0.0f);
  EXPECT_EQ(plain.iridescenceIor, 1.3f);
  EXPECT_EQ(plain.iridescenceThicknessMinimum, 100.0f);
  EXPECT_EQ(plain.iridescenceThicknessMaximum, 400.0f);
  EXPECT_FALSE(hasIridescence(plain));

  EXPECT_EQ(errorForTextureIndex(q, "KHR_materials_iridescence", "iridescenceTexture", 5),
            where + ".iridescenceTexture: texture 5 is out of range (the file has 1 texture)");
  const std::pair<Value::Object, std::string> bad[] = {
      {{{"iridescenceFactor", Value(1.5)}}, "iridescenceFactor must be a number in [0, 1]"},
      {{{"iridescenceIor", Value(0.5)}}, "iridescenceIor must be a number of at least 1"},
      {{{"iridescenceThicknessMinimum", Value(-1.0)}},
       "iridescenceThicknessMinimum must be a number of at least 0"},
      {{{"iridescenceThicknessMaximum", Value("thick")}},
       "iridescenceThicknessMaximum must be a number"}};
  for (const auto& [properties, message] : bad) {
    q.gltfMaterial().extensions["KHR_materials_iridescence"] = Value(properties);
    EXPECT_EQ(inputError([&] { load(q.builder); }), where + ": " + message);
  }

  q.gltfMaterial().extensions["KHR_materials_iridescence"] =
      object({{"iridescenceFactor", Value(1.0)}});
  q.gltfMaterial().extensions["KHR_materials_unlit"] = object({});
  const Scene unlit = load(q.builder);
  EXPECT_EQ(warningsAbout(unlit, "KHR_materials_iridescence"),
            std::vector<std::string>{where + ": must not be used with KHR_materials_unlit; the "
                                             "iridescence is not drawn"});
  EXPECT_FALSE(hasIridescence(unlit.materials[0]));
}

// KHR_materials_diffuse_transmission: factor, color and their textures, the defaults (none;
// white), the ranges, the exclusions.
TEST_F(GltfExtensionsTest, DiffuseTransmissionIsRead) {
  Quad q;
  makeQuad(q);
  const std::string where = file() + ": materials[0].extensions.KHR_materials_diffuse_transmission";
  q.gltfMaterial().extensions["KHR_materials_diffuse_transmission"] =
      object({{"diffuseTransmissionFactor", Value(0.5)},
              {"diffuseTransmissionColorFactor", numbers({1.0, 0.5, 0.25})},
              {"diffuseTransmissionTexture", object({{"index", Value(0)}})},
              {"diffuseTransmissionColorTexture", object({{"index", Value(0)}})}});
  q.builder.model().extensionsUsed = {"KHR_materials_diffuse_transmission"};
  q.builder.model().extensionsRequired = {"KHR_materials_diffuse_transmission"};
  const Scene scene = load(q.builder);
  EXPECT_TRUE(scene.warnings.empty()) << scene.warnings.front();
  const Material& m = scene.materials[0];
  EXPECT_EQ(m.diffuseTransmissionFactor, 0.5f);
  EXPECT_EQ(m.diffuseTransmissionColorFactor, glm::vec3(1.0f, 0.5f, 0.25f));
  EXPECT_EQ(m.diffuseTransmissionTexture.texture, 0);
  EXPECT_EQ(m.diffuseTransmissionColorTexture.texture, 0);
  EXPECT_TRUE(hasDiffuseTransmission(m));

  q.gltfMaterial().extensions["KHR_materials_diffuse_transmission"] = object({});
  const Material plain = load(q.builder).materials[0];
  EXPECT_EQ(plain.diffuseTransmissionFactor, 0.0f);
  EXPECT_EQ(plain.diffuseTransmissionColorFactor, glm::vec3(1.0f));
  EXPECT_FALSE(hasDiffuseTransmission(plain));

  EXPECT_EQ(errorForTextureIndex(q, "KHR_materials_diffuse_transmission",
                                 "diffuseTransmissionColorTexture", 5),
            where +
                ".diffuseTransmissionColorTexture: texture 5 is out of range (the file has 1 "
                "texture)");
  const std::pair<Value::Object, std::string> bad[] = {
      {{{"diffuseTransmissionFactor", Value(1.5)}},
       "diffuseTransmissionFactor must be a number in [0, 1]"},
      {{{"diffuseTransmissionColorFactor", numbers({1.0, 2.0, 0.0})}},
       "diffuseTransmissionColorFactor must be an array of 3 numbers in [0, 1]"}};
  for (const auto& [properties, message] : bad) {
    q.gltfMaterial().extensions["KHR_materials_diffuse_transmission"] = Value(properties);
    EXPECT_EQ(inputError([&] { load(q.builder); }), where + ": " + message);
  }

  q.gltfMaterial().extensions["KHR_materials_diffuse_transmission"] =
      object({{"diffuseTransmissionFactor", Value(1.0)}});
  q.gltfMaterial().extensions["KHR_materials_unlit"] = object({});
  const Scene unlit = load(q.builder);
  EXPECT_EQ(
      warningsAbout(unlit, "KHR_materials_diffuse_transmission"),
      std::vector<std::string>{where + ": must not be used with KHR_materials_unlit; the diffuse "
                                       "transmission is not drawn"});
  EXPECT_FALSE(hasDiffuseTransmission(unlit.materials[0]));
}

TEST_F(GltfExtensionsTest, ClearcoatFactorsTexturesAndNormalScaleAreRead) {
  Quad q;
  makeQuad(q);
  EXPECT_FALSE(hasClearcoat(load(q.builder).materials[0]));
  const std::string where = file() + ": materials[0].extensions.KHR_materials_clearcoat";
  q.gltfMaterial().extensions["KHR_materials_clearcoat"] =
      object({{"clearcoatFactor", Value(0.75)}, {"clearcoatRoughnessFactor", Value(0.25)}});
  q.builder.model().extensionsUsed = {"KHR_materials_clearcoat"};
  q.builder.model().extensionsRequired = {"KHR_materials_clearcoat"};
  const Scene scene = load(q.builder);
  EXPECT_TRUE(scene.warnings.empty()) << scene.warnings.front();
  EXPECT_EQ(scene.materials[0].clearcoatFactor, 0.75f);
  EXPECT_EQ(scene.materials[0].clearcoatRoughnessFactor, 0.25f);
  EXPECT_EQ(scene.materials[0].clearcoatNormalScale, 1.0f);
  EXPECT_TRUE(hasClearcoat(scene.materials[0]));

  // The specification's defaults: factor 0 (no layer at all), roughness 0.
  q.gltfMaterial().extensions["KHR_materials_clearcoat"] = object({});
  const Scene plain = load(q.builder);
  EXPECT_EQ(plain.materials[0].clearcoatFactor, 0.0f);
  EXPECT_EQ(plain.materials[0].clearcoatRoughnessFactor, 0.0f);
  EXPECT_FALSE(hasClearcoat(plain.materials[0]));

  // Three textures, each with its own texCoord and transform as any textureInfo; the normal
  // texture's scale.
  const int other = q.builder.addTexture(1, 1, {9, 9, 9, 9}, "other");
  const Value::Object intensity = {
      {"index", Value(0)},
      {"texCoord", Value(1)},
      {"extensions",
       object({{"KHR_texture_transform", object({{"offset", numbers({0.5, 0.25})}})}})}};
  q.gltfMaterial().extensions["KHR_materials_clearcoat"] =
      object({{"clearcoatFactor", Value(1.0)},
              {"clearcoatTexture", Value(intensity)},
              {"clearcoatRoughnessTexture", object({{"index", Value(other)}})},
              {"clearcoatNormalTexture", object({{"index", Value(0)}, {"scale", Value(0.5)}})}});
  const Scene textured = load(q.builder);
  EXPECT_TRUE(textured.warnings.empty()) << textured.warnings.front();
  const Material& m = textured.materials[0];
  EXPECT_EQ(m.clearcoatTexture.texture, 0);
  EXPECT_EQ(m.clearcoatTexture.texCoord, 1);
  EXPECT_EQ(glm::vec2(m.clearcoatTexture.uvTransform * glm::vec3(0, 0, 1)), glm::vec2(0.5f, 0.25f));
  EXPECT_EQ(m.clearcoatRoughnessTexture.texture, other);
  EXPECT_EQ(m.clearcoatNormalTexture.texture, 0);
  EXPECT_EQ(m.clearcoatNormalScale, 0.5f);
  EXPECT_EQ(errorForTextureIndex(q, "KHR_materials_clearcoat", "clearcoatNormalTexture", 5),
            where + ".clearcoatNormalTexture: texture 5 is out of range (the file has 2 textures)");

  // The extension excludes unlit and specular-glossiness materials: drawn without the layer.
  q.gltfMaterial().extensions["KHR_materials_clearcoat"] =
      object({{"clearcoatFactor", Value(1.0)}});
  q.gltfMaterial().extensions["KHR_materials_unlit"] = object({});
  const Scene unlit = load(q.builder);
  EXPECT_EQ(
      warningsAbout(unlit, "KHR_materials_clearcoat"),
      std::vector<std::string>{where + ": must not be used with KHR_materials_unlit; the clearcoat "
                                       "is not drawn"});
  EXPECT_FALSE(hasClearcoat(unlit.materials[0]));
  q.gltfMaterial().extensions.erase("KHR_materials_unlit");

  for (const char* factor : {"clearcoatFactor", "clearcoatRoughnessFactor"})
    for (const Value& bad : {Value(1.5), Value(-0.25), Value("glossy")}) {
      q.gltfMaterial().extensions["KHR_materials_clearcoat"] = object({{factor, bad}});
      EXPECT_EQ(inputError([&] { load(q.builder); }),
                where + ": " + factor +
                    (bad.IsNumber() ? " must be a number in [0, 1]" : " must be a number"));
    }
  q.gltfMaterial().extensions["KHR_materials_clearcoat"] =
      object({{"clearcoatNormalTexture", object({{"index", Value(0)}, {"scale", Value("flat")}})}});
  EXPECT_EQ(inputError([&] { load(q.builder); }),
            where + ".clearcoatNormalTexture: scale must be a number");
}

// KHR_materials_variants: a quad whose material 0 is its own, with variants "red" and "green"
// (materials 1 and 2) mapped on its primitive.
class MaterialVariantsTest : public GltfExtensionsTest {
 protected:
  GltfBuilder builder;
  void SetUp() override {
    PrimitiveOptions options;
    options.material = builder.addMaterial({.name = "own"});
    builder.addMaterial({.name = "red", .baseColor = {1, 0, 0, 1}});
    builder.addMaterial({.name = "green", .baseColor = {0, 1, 0, 1}});
    builder.addNode("quad", {}, builder.addMesh(quad(), options));
    builder.model().extensionsUsed = {"KHR_materials_variants"};
    builder.model().extensions["KHR_materials_variants"] = object(
        {{"variants", Value(Value::Array{object({{"name", Value(std::string("red"))}}),
                                         object({{"name", Value(std::string("green"))}})})}});
    mappings() = Value(Value::Array{mapping(1, {0}), mapping(2, {1})});
  }
  static Value mapping(int material, const std::vector<int>& variants) {
    Value::Array indices;
    for (const int v : variants) indices.emplace_back(v);
    return object({{"material", Value(material)}, {"variants", Value(indices)}});
  }
  Value& mappings() {
    Value& extension = builder.model().meshes[0].primitives[0].extensions["KHR_materials_variants"];
    if (!extension.IsObject()) extension = object({{"mappings", Value(Value::Array{})}});
    return extension.Get<Value::Object>()["mappings"];
  }
  Scene loadVariant(const std::string& variant) {
    const fs::path path = folder / "scene.gltf";
    builder.write(path, FileFormat::GltfEmbedded);
    GltfLoadOptions options;
    options.materialVariant = variant;
    return loadGltf(path, options);
  }
};

TEST_F(MaterialVariantsTest, AVariantByNameOrIndexGivesItsMappedMaterials) {
  const Scene own = loadVariant("");
  EXPECT_TRUE(own.warnings.empty()) << own.warnings.front();
  EXPECT_EQ(own.meshes[0].material, 0);
  EXPECT_EQ(own.source.materialVariants, (std::vector<std::string>{"red", "green"}));
  EXPECT_EQ(own.source.materialVariant, -1);
  EXPECT_EQ(loadVariant("red").meshes[0].material, 1);
  const Scene green = loadVariant("green");
  EXPECT_EQ(green.meshes[0].material, 2);
  EXPECT_EQ(green.source.materialVariant, 1);
  EXPECT_EQ(loadVariant("1").meshes[0].material, 2);
  // A variant the primitive does not map keeps its own material.
  mappings() = Value(Value::Array{mapping(1, {0})});
  EXPECT_EQ(loadVariant("green").meshes[0].material, 0);
  // One mapping may serve several variants.
  mappings() = Value(Value::Array{mapping(2, {0, 1})});
  EXPECT_EQ(loadVariant("red").meshes[0].material, 2);
  EXPECT_EQ(loadVariant("green").meshes[0].material, 2);
}

TEST_F(MaterialVariantsTest, UnknownVariantsAndMalformedMappingsAreInputErrors) {
  const std::string file = (folder / "scene.gltf").string() + ": ";
  EXPECT_EQ(inputError([&] { loadVariant("blue"); }),
            file +
                "--variant blue: the file has no such material variant (its variants: "
                "\"red\", \"green\")");
  EXPECT_EQ(inputError([&] { loadVariant("2"); }),
            file +
                "--variant 2: the file has no such material variant (its variants: "
                "\"red\", \"green\")");
  const std::string primitive = file + "meshes[0].primitives[0].extensions.KHR_materials_variants.";
  mappings() = Value(Value::Array{mapping(7, {0})});
  EXPECT_EQ(inputError([&] { loadVariant(""); }),
            primitive + "mappings[0]: material 7 is out of range (the file has 3 materials)");
  mappings() = Value(Value::Array{mapping(1, {2})});
  EXPECT_EQ(inputError([&] { loadVariant(""); }),
            primitive +
                "mappings[0].variants[0]: variant 2 is out of range (the file has 2 "
                "variants)");
  mappings() = Value(Value::Array{mapping(1, {0}), mapping(2, {0})});
  EXPECT_EQ(inputError([&] { loadVariant(""); }),
            primitive +
                "mappings[1].variants[0]: variant 0 is mapped more than once in this "
                "primitive");
  mappings() = Value(Value::Array{mapping(1, {})});
  EXPECT_EQ(inputError([&] { loadVariant(""); }),
            primitive + "mappings[0]: variants must be an array of at least one variant index");
  mappings() = Value(Value::Array{object({{"variants", Value(Value::Array{Value(0)})}})});
  EXPECT_EQ(inputError([&] { loadVariant(""); }),
            primitive + "mappings[0]: material must be an integer");
  mappings() = Value(Value::Array{mapping(1, {0})});
  builder.model().extensions["KHR_materials_variants"] =
      object({{"variants", Value(Value::Array{Value(3.0)})}});
  EXPECT_EQ(inputError([&] { loadVariant(""); }),
            file +
                "extensions.KHR_materials_variants.variants[0]: must be an object with a "
                "string name");
  builder.model().extensions.erase("KHR_materials_variants");
  EXPECT_EQ(inputError([&] { loadVariant("red"); }),
            file + "--variant red: the file has no material variants");
}

// A scene whose texture 0 has a PNG `source` (image 0) and a KTX2 image (image 1, a file with
// the KTX2 signature and nothing a decoder could use) through KHR_texture_basisu.
class ImageExtensionsTest : public GltfExtensionsTest {
 protected:
  Json writeBasisScene() {
    GltfBuilder builder;
    const int texture = builder.addTexture(1, 1, {255, 0, 0, 255}, "png");
    builder.addNode("quad", {}, builder.addTexturedMesh(quad(), texture));
    builder.write(folder / "scene.gltf", FileFormat::GltfExternal);
    std::ifstream in(folder / "scene.gltf");
    Json gltf = Json::parse(in);
    gltf["images"].push_back({{"uri", "texture.ktx2"}});
    gltf["textures"][0]["extensions"]["KHR_texture_basisu"] = {{"source", 1}};
    gltf["extensionsUsed"] = {"KHR_texture_basisu"};
    const unsigned char ktx2[] = {0xAB, 'K',  'T', 'X', ' ', '2', '0', 0xBB, 0x0D, 0x0A,
                                  0x1A, 0x0A, 0,   0,   0,   0,   0,   0,    0,    0};
    std::ofstream(folder / "texture.ktx2", std::ios::binary)
        .write(reinterpret_cast<const char*>(ktx2), sizeof ktx2);
    return gltf;
  }
  void write(const Json& gltf) { std::ofstream(folder / "scene.gltf") << gltf.dump(); }
};

TEST_F(ImageExtensionsTest, BasisuTexturesDrawTheirFallbackSource) {
  write(writeBasisScene());
  const Scene scene = loadGltf(folder / "scene.gltf");
  ASSERT_EQ(scene.textures.size(), 1u);
  EXPECT_EQ(scene.textures[0].image, 0);
  EXPECT_EQ(scene.materials[0].baseColorTexture.texture, 0);
  ASSERT_EQ(scene.images.size(), 2u);
  EXPECT_EQ(scene.images[0].rgba, (std::vector<std::uint8_t>{255, 0, 0, 255}));
  EXPECT_TRUE(scene.images[1].rgba.empty());  // never decoded
  const std::vector<std::string> warnings = warningsAbout(scene, "KHR_texture_basisu");
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0], file() +
                             ": extensionsUsed: KHR_texture_basisu is not supported; drawn "
                             "instead: the textures' PNG/JPEG fallback images");
  ASSERT_EQ(scene.source.extensions.size(), 1u);
  EXPECT_EQ(scene.source.extensions[0].name, "KHR_texture_basisu");
  EXPECT_FALSE(scene.source.extensions[0].supported);
  EXPECT_FALSE(scene.source.extensions[0].required);
}

// The same in a .glb, the KTX2 image in a bufferView of the binary chunk.
TEST_F(GltfExtensionsTest, BasisuImagesInABinaryFileAreNotDecodedEither) {
  GltfBuilder builder;
  const int texture = builder.addTexture(1, 1, {0, 255, 0, 255}, "png");
  builder.addNode("quad", {}, builder.addTexturedMesh(quad(), texture));
  tinygltf::Model& model = builder.model();
  const std::vector<unsigned char> ktx2 = {0xAB, 'K',  'T',  'X',  ' ', '2', '0', 0xBB,
                                           0x0D, 0x0A, 0x1A, 0x0A, 1,   2,   3,   4};
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = model.buffers[0].data.size();
  view.byteLength = ktx2.size();
  model.buffers[0].data.insert(model.buffers[0].data.end(), ktx2.begin(), ktx2.end());
  model.bufferViews.push_back(view);
  tinygltf::Image image;
  image.bufferView = static_cast<int>(model.bufferViews.size()) - 1;
  image.mimeType = "image/ktx2";
  model.images.push_back(image);
  model.textures[0].extensions["KHR_texture_basisu"] =
      object({{"source", Value(static_cast<int>(model.images.size()) - 1)}});
  model.extensionsUsed = {"KHR_texture_basisu"};
  const fs::path path = folder / "scene.glb";
  builder.write(path, FileFormat::Glb);
  const Scene scene = loadGltf(path);
  EXPECT_EQ(scene.textures[0].image, 0);
  EXPECT_EQ(scene.images[0].rgba, (std::vector<std::uint8_t>{0, 255, 0, 255}));
  EXPECT_EQ(warningsAbout(scene, "KHR_texture_basisu").size(), 1u);

  model.textures[0].source = -1;
  builder.write(path, FileFormat::Glb);
  EXPECT_EQ(inputError([&] { loadGltf(path); }),
            path.string() +
                ": textures[0]: its image is KTX2 (KHR_texture_basisu), which cannot be decoded, "
                "and it has no PNG or JPEG fallback source");
}

TEST_F(ImageExtensionsTest, BasisuTexturesWithoutFallbackAreRefusedNamingTheExtension) {
  Json gltf = writeBasisScene();
  gltf["textures"][0].erase("source");
  write(gltf);
  EXPECT_EQ(inputError([&] { loadGltf(folder / "scene.gltf"); }),
            file() +
                ": textures[0]: its image is KTX2 (KHR_texture_basisu), which cannot be decoded, "
                "and it has no PNG or JPEG fallback source");

  gltf["extensionsRequired"] = {"KHR_texture_basisu"};
  write(gltf);
  EXPECT_EQ(inputError([&] { loadGltf(folder / "scene.gltf"); }),
            file() +
                ": extensionsRequired: KHR_texture_basisu is not supported (its images cannot be "
                "decoded, and a file that requires it has no PNG or JPEG fallback)");
}

TEST_F(GltfExtensionsTest, UnsupportedExtensionsAreRefusedWhenRequiredAndNamedWhenUsed) {
  GltfBuilder builder;
  builder.addNode("quad", {}, builder.addMesh(quad()));
  tinygltf::Model& model = builder.model();
  model.extensionsUsed = {"MSFT_lod", "VENDOR_made_up", "KHR_texture_transform"};
  const Scene scene = load(builder);
  ASSERT_EQ(scene.warnings.size(), 2u);
  EXPECT_EQ(scene.warnings[0], file() +
                                   ": extensionsUsed: MSFT_lod is not supported; "
                                   "drawn instead: the full-detail meshes");
  EXPECT_EQ(scene.warnings[1],
            file() + ": extensionsUsed: VENDOR_made_up is not supported; ignored");
  ASSERT_EQ(scene.source.extensions.size(), 3u);
  EXPECT_EQ(scene.source.extensions[0].drawnInstead, "the full-detail meshes");
  EXPECT_FALSE(scene.source.extensions[1].supported);
  EXPECT_TRUE(scene.source.extensions[2].supported);
  EXPECT_EQ(scene.source.extensions[2].drawnInstead, "");

  for (const std::string name : {"MSFT_lod", "VENDOR_made_up", "KHR_xmp_json_ld"}) {
    model.extensionsRequired = {name};
    EXPECT_EQ(inputError([&] { load(builder); }),
              file() + ": extensionsRequired: " + name + " is not supported");
  }
  // Required but not listed as used (invalid, but seen): still refused.
  model.extensionsUsed.clear();
  model.extensionsRequired = {"MSFT_lod"};
  EXPECT_EQ(inputError([&] { load(builder); }),
            file() + ": extensionsRequired: MSFT_lod is not supported");
}

// Compressed geometry leaves accessors without a bufferView. Such an accessor is zeros by the
// spec (the plain file loads), but under an unsupported required extension the message names
// the extension, not the accessor.
TEST_F(GltfExtensionsTest, RequiredExtensionsAreNamedWhereAccessorsLackABufferView) {
  GltfBuilder builder;
  builder.addNode("quad", {}, builder.addMesh(quad()));
  tinygltf::Model& model = builder.model();
  model.accessors[static_cast<std::size_t>(model.meshes[0].primitives[0].indices)].bufferView = -1;
  const fs::path path = folder / "scene.gltf";
  builder.write(path, FileFormat::GltfEmbedded);
  EXPECT_NO_THROW(loadGltf(path));
  model.extensionsUsed = {"VENDOR_geometry_compression"};
  model.extensionsRequired = {"VENDOR_geometry_compression"};
  builder.write(path, FileFormat::GltfEmbedded);
  EXPECT_EQ(inputError([&] { loadGltf(path); }),
            file() + ": extensionsRequired: VENDOR_geometry_compression is not supported");
}

// The README's "Scene support" table lists every extension of the loader's table, with the
// same status, so that neither can drift from the other.
TEST(ExtensionTable, ReadmeListsEveryKnownExtensionWithItsStatus) {
  std::ifstream in(fs::path(OMNISHADOW_SOURCE_DIR) / "README.md");
  ASSERT_TRUE(in);
  std::string line;
  std::vector<std::pair<std::string, std::string>> rows;  // name, status cell
  while (std::getline(in, line)) {
    if (!line.starts_with("| `")) continue;
    const std::size_t end = line.find('`', 3);
    const std::size_t cell = line.find('|', end);
    const std::size_t cellEnd = line.find('|', cell + 1);
    if (end == std::string::npos || cellEnd == std::string::npos) continue;
    std::string status = line.substr(cell + 1, cellEnd - cell - 1);
    status.erase(0, status.find_first_not_of(' '));
    status.erase(status.find_last_not_of(' ') + 1);
    rows.emplace_back(line.substr(3, end - 3), status);
  }
  for (const KnownExtension& known : knownExtensions()) {
    const auto row = std::find_if(rows.begin(), rows.end(),
                                  [&](const auto& r) { return r.first == known.name; });
    ASSERT_NE(row, rows.end()) << known.name << " is not in the README's table";
    const char* status = known.status == ExtensionStatus::Supported      ? "supported"
                         : known.status == ExtensionStatus::FallbackOnly ? "fallback only"
                                                                         : "not supported";
    EXPECT_EQ(row->second, status) << known.name;
  }
}

}  // namespace
}  // namespace omnishadow::gltf_extensions_test
