// glTF extensions end to end: what `omnishadow info` says about them, the refusal of required
// ones that cannot be drawn (exit status 2, one line, no output), and the Khronos UnlitTest's
// colors in the PNG a render writes.
#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "renderer/output/image_writer.h"
#include "scenes/builder/gltf_builder.h"
#include "tests/support/cli_fixture.h"

namespace omnishadow::extensions_cli_test {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;
using test_support::contains;

const fs::path kScenes = fs::path(OMNISHADOW_SOURCE_DIR) / "scenes/khronos";

class ExtensionsCliTest : public test_support::CliFixture {
 protected:
  ExtensionsCliTest() : CliFixture("omnishadow-extensions-cli") {}

  // The box scene with `used` (and `required`) added to its extension lists.
  fs::path sceneUsing(const std::string& used, bool required) {
    const fs::path path = input("scene.gltf");
    test_support::writeBoxScene(path);
    tinygltf::Model model;
    tinygltf::TinyGLTF io;
    std::string error, warning;
    EXPECT_TRUE(io.LoadASCIIFromFile(&model, &error, &warning, path.string())) << error;
    model.extensionsUsed.push_back(used);
    if (required) model.extensionsRequired.push_back(used);
    EXPECT_TRUE(io.WriteGltfSceneToFile(&model, path.string(), true, true, true, false));
    return path;
  }

  void expectRefused(const Run& r, const std::string& message) {
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_TRUE(r.err.starts_with("omnishadow: ")) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_TRUE(contains(r.err, message));
    EXPECT_EQ(r.out, "");
  }
};

TEST_F(ExtensionsCliTest, InfoListsTheExtensionsAFileUsesAndWhetherEachIsSupported) {
  const fs::path transform = kScenes / "TextureTransformTest/TextureTransformTest.gltf";
  Run r = run({"info", transform.string()});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "\nextensions  1\n  KHR_texture_transform  used  supported\n"));
  r = run({"info", transform.string(), "--json"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(Json::parse(r.out)["extensions"],
            Json::parse(R"([{"name": "KHR_texture_transform", "required": false,
                             "supported": true, "drawnInstead": null}])"));

  const fs::path scene = sceneUsing("KHR_xmp_json_ld", false);
  r = run({"info", scene.string()});
  ASSERT_EQ(r.status, 0) << r.err;
  // The box scene has a KHR_lights_punctual light.
  EXPECT_TRUE(contains(r.out,
                       "\nextensions  2\n  KHR_lights_punctual  used  supported\n"
                       "  KHR_xmp_json_ld      used  not supported: drawn instead: "
                       "the scene; its metadata is not read\n"));
  EXPECT_TRUE(contains(r.out, scene.string() +
                                  ": extensionsUsed: KHR_xmp_json_ld is not supported; "
                                  "drawn instead: the scene; its metadata is not read\n"));
  r = run({"info", scene.string(), "--json"});
  ASSERT_EQ(r.status, 0) << r.err;
  const Json doc = Json::parse(r.out);
  EXPECT_EQ(doc["extensions"][1]["name"], "KHR_xmp_json_ld");
  EXPECT_EQ(doc["extensions"][1]["supported"], false);
  EXPECT_EQ(doc["extensions"][1]["drawnInstead"], "the scene; its metadata is not read");
  // The render warns once, naming it and what it draws instead.
  r = run({"render", scene.string(), "--width", "32", "--height", "32", "-o", "a.png"});
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string warning = "extensionsUsed: KHR_xmp_json_ld is not supported";
  const std::size_t first = r.err.find(warning);
  EXPECT_NE(first, std::string::npos) << r.err;
  EXPECT_EQ(r.err.find(warning, first + 1), std::string::npos) << r.err;
}

TEST_F(ExtensionsCliTest, RequiredExtensionsThatCannotBeDrawnAreRefusedWithoutOutput) {
  const fs::path scene = sceneUsing("KHR_xmp_json_ld", true);
  const std::string message =
      scene.string() + ": extensionsRequired: KHR_xmp_json_ld is not supported\n";
  Run r = run({"render", scene.string(), "--width", "32", "--height", "32", "-o", "a.png"});
  expectRefused(r, message);
  EXPECT_FALSE(fs::exists(output("a.png")));
  expectRefused(run({"info", scene.string()}), message);
  expectRefused(run({"info", scene.string(), "--json"}), message);
}

TEST_F(ExtensionsCliTest, InfoSaysHowEachMaterialIsShaded) {
  const fs::path unlit = kScenes / "UnlitTest/UnlitTest.glb";
  Run r = run({"info", unlit.string()});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "  0  \"Orange\"  OPAQUE  single-sided  no textures  unlit\n"));
  EXPECT_TRUE(contains(r.out, "\n  KHR_materials_unlit  required  supported\n"));
  r = run({"info", unlit.string(), "--json"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(Json::parse(r.out)["materials"][1]["model"], "unlit");
  r = run(
      {"info", (kScenes / "TextureTransformTest/TextureTransformTest.gltf").string(), "--json"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(Json::parse(r.out)["materials"][0]["model"], "metallicRoughness");
}

// UnlitTest's two materials are KHR_materials_unlit with base colors (1, 0.2176376, 0) and
// (0, 0.2176376, 1), linear. Unlit, a pixel is its base color whatever the light, so after the
// display transform (exposure 0, clamp, the sRGB curve, rounding to 8 bits) every covered pixel
// is (255, 128, 0) or (0, 128, 255): 255 * (1.055 * 0.2176376^(1 / 2.4) - 0.055) = 128.486.
TEST_F(ExtensionsCliTest, UnlitTestShowsExactlyItsBaseColors) {
  const fs::path scene = kScenes / "UnlitTest/UnlitTest.glb";
  const Run r = run({"render", scene.string(), "--width", "96", "--height", "64", "-o", "unlit.png",
                     "--aov", "unlit.exr"});
  ASSERT_EQ(r.status, 0) << r.err;
  const float g = 1.055f * std::pow(0.217637640824031f, 1.0f / 2.4f) - 0.055f;
  const int green = static_cast<int>(std::lround(g * 255.0f));
  ASSERT_EQ(green, 128);
  const FloatImage png = readImage(output("unlit.png"));
  const FloatImage aov = readImage(output("unlit.exr"));
  const int coverage = aov.channelIndex("A");
  ASSERT_GE(coverage, 0);
  int orange = 0, blue = 0;
  for (int y = 0; y < png.height; ++y) {
    for (int x = 0; x < png.width; ++x) {
      if (aov.at(x, y, coverage) < 1.0f) continue;  // background, or an edge pixel
      const glm::ivec3 rgb(std::lround(png.at(x, y, 0) * 255.0f),
                           std::lround(png.at(x, y, 1) * 255.0f),
                           std::lround(png.at(x, y, 2) * 255.0f));
      if (rgb == glm::ivec3(255, green, 0)) {
        ++orange;
      } else if (rgb == glm::ivec3(0, green, 255)) {
        ++blue;
      } else {
        ADD_FAILURE() << "pixel " << x << "," << y << " is (" << rgb.r << ", " << rgb.g << ", "
                      << rgb.b << ")";
      }
    }
  }
  EXPECT_GT(orange, 200);
  EXPECT_GT(blue, 200);
}

// KHR_materials_variants end to end: a quad of three unlit materials (its own white, the
// variants' red and green), so that each pixel shows exactly which material was drawn.
class MaterialVariantsCliTest : public ExtensionsCliTest {
 protected:
  fs::path writeVariantsScene() {
    using tinygltf::Value;
    builder::GltfBuilder b;
    const auto unlit = [&](const std::string& name, glm::vec4 color) {
      const int m = b.addMaterial({.name = name, .baseColor = color});
      b.model().materials[m].extensions["KHR_materials_unlit"] = Value(Value::Object{});
      return m;
    };
    const int own = unlit("own", {1, 1, 1, 1});
    const int red = unlit("red", {1, 0, 0, 1});
    const int green = unlit("green", {0, 1, 0, 1});
    b.addNode("floor", {}, b.addMesh(builder::makePlane(2.0f), {.material = own}));
    const auto mapping = [](int material, int variant) {
      return Value(Value::Object{{"material", Value(material)},
                                 {"variants", Value(Value::Array{Value(variant)})}});
    };
    b.model().meshes[0].primitives[0].extensions["KHR_materials_variants"] =
        Value(Value::Object{{"mappings", Value(Value::Array{mapping(red, 0), mapping(green, 1)})}});
    b.model().extensions["KHR_materials_variants"] = Value(Value::Object{
        {"variants",
         Value(Value::Array{Value(Value::Object{{"name", Value(std::string("Red paint"))}}),
                            Value(Value::Object{{"name", Value(std::string("Green paint"))}})})}});
    b.model().extensionsUsed = {"KHR_materials_unlit", "KHR_materials_variants"};
    const fs::path path = input("variants.gltf");
    b.write(path, builder::FileFormat::GltfEmbedded);
    return path;
  }
  // The one color every pixel of the floor seen from above has, as 8-bit sRGB.
  glm::ivec3 floorColor(const std::string& png) {
    const FloatImage image = readImage(output(png));
    const glm::ivec3 center(std::lround(image.at(8, 8, 0) * 255.0f),
                            std::lround(image.at(8, 8, 1) * 255.0f),
                            std::lround(image.at(8, 8, 2) * 255.0f));
    for (int y = 0; y < image.height; ++y)
      for (int x = 0; x < image.width; ++x)
        for (int c = 0; c < 3; ++c)
          EXPECT_EQ(std::lround(image.at(x, y, c) * 255.0f), center[c])
              << png << " pixel " << x << "," << y;
    return center;
  }
};

TEST_F(MaterialVariantsCliTest, RenderDrawsTheChosenVariantAndInfoListsThem) {
  const fs::path scene = writeVariantsScene();
  const std::vector<std::string> view = {"--width", "16",     "--height", "16",
                                         "--eye",   "0,3,0",  "--target", "0,0,0",
                                         "--up",    "0,0,-1", "--fov",    "20"};
  const auto render = [&](std::vector<std::string> args) {
    args.insert(args.begin(), {"render", scene.string()});
    args.insert(args.end(), view.begin(), view.end());
    const Run r = run(args);
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_FALSE(contains(r.err, "KHR_materials_variants")) << r.err;
  };
  render({"-o", "own.png"});
  render({"-o", "green.png", "--variant", "Green paint"});
  render({"-o", "red.png", "--variant", "0"});
  EXPECT_EQ(floorColor("own.png"), glm::ivec3(255, 255, 255));
  EXPECT_EQ(floorColor("green.png"), glm::ivec3(0, 255, 0));
  EXPECT_EQ(floorColor("red.png"), glm::ivec3(255, 0, 0));

  Run r = run({"info", scene.string(), "--variant", "Green paint"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(contains(r.out,
                       "\nvariants    2 (\"Red paint\", \"Green paint\"); drawn: "
                       "\"Green paint\"\n"))
      << r.out;
  r = run({"info", scene.string(), "--json"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(Json::parse(r.out)["materialVariants"],
            Json::parse(R"({"names": ["Red paint", "Green paint"], "drawn": null})"));

  // A batch manifest job names its variant.
  const fs::path manifest = input("variants.json");
  std::ofstream(manifest) << R"({"jobs": [
      {"scene": "variants.gltf", "variant": "Red paint", "outputs": ["a.png"],
       "width": 16, "height": 16, "eye": [0, 3, 0], "target": [0, 0, 0], "up": [0, 0, -1], "fov": 20},
      {"scene": "variants.gltf", "variant": "1", "outputs": ["b.png"],
       "width": 16, "height": 16, "eye": [0, 3, 0], "target": [0, 0, 0], "up": [0, 0, -1], "fov": 20}]})";
  r = run({"batch", manifest.string(), "--out", output("").string()});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(floorColor("a.png"), glm::ivec3(255, 0, 0));
  EXPECT_EQ(floorColor("b.png"), glm::ivec3(0, 255, 0));
}

TEST_F(MaterialVariantsCliTest, AnUnknownVariantIsRefusedWithoutOutput) {
  const fs::path scene = writeVariantsScene();
  const std::string message = scene.string() +
                              ": --variant Blue: the file has no such material variant (its "
                              "variants: \"Red paint\", \"Green paint\")\n";
  expectRefused(run({"render", scene.string(), "--variant", "Blue", "--width", "16", "--height",
                     "16", "-o", "blue.png"}),
                message);
  EXPECT_FALSE(fs::exists(output("blue.png")));
  expectRefused(run({"info", scene.string(), "--variant", "Blue"}), message);
  const fs::path plain = sceneUsing("KHR_texture_transform", false);
  expectRefused(run({"info", plain.string(), "--variant", "Red"}),
                plain.string() + ": --variant Red: the file has no material variants\n");
}

}  // namespace
}  // namespace omnishadow::extensions_cli_test
