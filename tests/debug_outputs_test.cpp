// End-to-end tests of the debugging outputs of `omnishadow render`: shadow map dumps
// (--dump-depth), light views (--light-views), debug views (--debug-view, --debug-light) and AOV
// layers (--aov-layers) with their id sidecar. Every test runs the real executable in a fresh
// temporary folder:
//   <root>/in   inputs, written with GltfBuilder and as JSON text
//   <root>/out  the working directory of the run, where relative outputs go
// Renders are tiny (64x48, 32-texel shadow maps and light views): llvmpipe is slow.
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfEnvmapAttribute.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "renderer/output/image_writer.h"
#include "scenes/builder/gltf_builder.h"
#include "tests/support/cli_fixture.h"

namespace omnishadow::debug_outputs_test {
namespace {

namespace fs = std::filesystem;
using builder::FileFormat;
using builder::GltfBuilder;

const char* const kFaces[] = {"px", "nx", "py", "ny", "pz", "nz"};

// ---------------------------------------------------------------------------------------------
// Inputs

// Two shadowed point lights (one with a space in its name) and an unshadowed one.
constexpr const char* kTwoShadowedLights = R"({
  "lights": [
    {"name": "key light", "position": [-1.5, 3, 1.5], "intensity": 20,
     "shadow": {"resolution": 32}},
    {"name": "fill", "position": [2, 2, 2], "intensity": 10, "shadow": {"resolution": 32}},
    {"name": "off", "position": [0, 3, -2], "intensity": 5, "shadow": false}
  ]
})";

// Two shadowed lights and no ambient: the beauty is exactly the sum of the lights' layers.
constexpr const char* kNoAmbientLights = R"({
  "ambient": [0, 0, 0],
  "lights": [
    {"name": "key", "position": [-1.5, 3, 1.5], "intensity": 20, "shadow": {"resolution": 32}},
    {"name": "fill", "position": [2, 2, 2], "intensity": 10, "shadow": {"resolution": 32}}
  ]
})";

// A point light "lamp" at the origin, inside the six boxes of writeSixBoxes.
constexpr const char* kLampAtOrigin = R"({
  "ambient": [0, 0, 0],
  "lights": [
    {"name": "lamp", "position": [0, 0, 0], "intensity": 4, "shadow": {"resolution": 32}}
  ]
})";

// What writeScene put where, for checking ids.
struct SceneLayout {
  // Node index of each drawn node -> glTF material index (-1 = the default material).
  std::map<int, int> nodeMaterial;
  // glTF material index -> (base color, roughness, metallic).
  struct Material {
    std::string name;
    glm::vec3 color;
    float roughness, metallic;
  };
  std::vector<Material> materials;
};

// A floor, a box and a ball without material (the glTF default material), a camera "main"
// looking at all three and a camera "top" straight above the floor. No lights.
SceneLayout writeScene(const fs::path& path) {
  GltfBuilder b;
  SceneLayout layout;
  layout.materials = {{"floor", {0.3f, 0.6f, 0.3f}, 0.8f, 0.0f},
                      {"box", {0.8f, 0.2f, 0.1f}, 0.4f, 0.5f}};
  std::vector<int> materials;
  for (const SceneLayout::Material& m : layout.materials)
    materials.push_back(b.addMaterial({.name = m.name,
                                       .baseColor = glm::vec4(m.color, 1.0f),
                                       .metallic = m.metallic,
                                       .roughness = m.roughness}));
  const int floor = b.addNode(
      "floor", {}, b.addMesh(builder::makePlane(6.0f), {.material = materials[0]}, "floorMesh"));
  const int box = b.addNode(
      "box", {.translation = {0.8f, 0.5f, 0.0f}},
      b.addMesh(builder::makeBox(glm::vec3(0.5f)), {.material = materials[1]}, "boxMesh"));
  const int ball = b.addNode("ball", {.translation = {-1.2f, 0.4f, 0.8f}},
                             b.addMesh(builder::makeSphere(0.4f, 16, 8), {}, "ballMesh"));
  layout.nodeMaterial = {{floor, 0}, {box, 1}, {ball, -1}};
  b.addPerspectiveCamera("main", {0.0f, 2.5f, 4.5f}, {0.0f, 0.3f, 0.0f}, 0.8f);
  b.addPerspectiveCamera("top", {-1.5f, 5.0f, -1.5f}, {-1.5f, 0.0f, -1.6f}, 0.4f);
  b.write(path, FileFormat::GltfEmbedded);
  return layout;
}

// Six boxes around the origin, one on each axis, each with its face towards the origin at
// kBoxDistance[face] and its own color kBoxColor[face] (faces in GL order px nx py ny pz nz).
constexpr float kBoxDistance[] = {1.0f, 1.25f, 1.5f, 1.75f, 2.0f, 2.25f};
const glm::vec3 kBoxColor[] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 0}, {0, 1, 1}, {1, 0, 1}};

void writeSixBoxes(const fs::path& path) {
  GltfBuilder b;
  const glm::vec3 axes[] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  constexpr float depth = 0.25f, side = 0.6f;  // half extents along and across the axis
  for (int face = 0; face < 6; ++face) {
    const glm::vec3 axis = axes[face];
    const glm::vec3 half = glm::abs(axis) * depth + (glm::vec3(1.0f) - glm::abs(axis)) * side;
    // Rough and dielectric: almost no specular, so the light views show the base colors.
    const int material = b.addMaterial(
        {.name = kFaces[face], .baseColor = glm::vec4(kBoxColor[face], 1.0f), .roughness = 1.0f});
    b.addNode(kFaces[face], {.translation = axis * (kBoxDistance[face] + depth)},
              b.addMesh(builder::makeBox(half), {.material = material}));
  }
  b.addPerspectiveCamera("main", {4.0f, 3.0f, 5.0f}, {0.0f, 0.0f, 0.0f}, 0.8f);
  b.write(path, FileFormat::GltfEmbedded);
}

// ---------------------------------------------------------------------------------------------
// Reading results

using test_support::contains;
using test_support::filesIn;
using test_support::pngSize;
using test_support::readFile;

// An EXR as OpenEXR itself sees it: size, channel names and types, envmap, and the "Z" values.
struct ExrFile {
  int width = 0, height = 0;
  std::vector<std::pair<std::string, Imf::PixelType>> channels;
  bool hasEnvmap = false;
  Imf::Envmap envmap = Imf::ENVMAP_LATLONG;
  std::vector<float> z;  // row by row; empty without a "Z" channel
};

ExrFile readExr(const fs::path& path) {
  ExrFile exr;
  Imf::InputFile file(path.string().c_str());
  const Imf::Header& header = file.header();
  const Imath::Box2i window = header.dataWindow();
  exr.width = window.max.x - window.min.x + 1;
  exr.height = window.max.y - window.min.y + 1;
  for (auto c = header.channels().begin(); c != header.channels().end(); ++c)
    exr.channels.emplace_back(c.name(), c.channel().type);
  if (const auto* envmap = header.findTypedAttribute<Imf::EnvmapAttribute>("envmap")) {
    exr.hasEnvmap = true;
    exr.envmap = envmap->value();
  }
  if (header.channels().findChannel("Z")) {
    exr.z.resize(static_cast<std::size_t>(exr.width) * exr.height);
    Imf::FrameBuffer frameBuffer;
    char* origin = reinterpret_cast<char*>(exr.z.data() - window.min.x -
                                           static_cast<std::ptrdiff_t>(window.min.y) * exr.width);
    frameBuffer.insert("Z", Imf::Slice(Imf::FLOAT, origin, sizeof(float),
                                       sizeof(float) * static_cast<std::size_t>(exr.width)));
    file.setFrameBuffer(frameBuffer);
    file.readPixels(window.min.y, window.max.y);
  }
  return exr;
}

// The per-light files --dump-depth writes for a light of this (file-safe) name.
std::vector<std::string> dumpFiles(const std::string& light) {
  std::vector<std::string> files = {light + "_cube.exr", light + "_cross.png"};
  for (const char* face : kFaces)
    for (const char* ext : {".exr", ".png"}) files.push_back(light + "_" + face + ext);
  return files;
}

std::vector<std::string> sorted(std::vector<std::string> names) {
  std::sort(names.begin(), names.end());
  return names;
}

// ---------------------------------------------------------------------------------------------
// Running the binary

class DebugOutputsTest : public test_support::CliFixture {
 protected:
  DebugOutputsTest() : CliFixture("omnishadow-debug") {}

  // `omnishadow render args... --width 64 --height 48 --no-gltf-lights`, expected to succeed.
  Run render(std::vector<std::string> args) {
    return runSucceeding("render", std::move(args),
                         {"--width", "64", "--height", "48", "--no-gltf-lights"});
  }
};

// ---------------------------------------------------------------------------------------------
// --dump-depth

TEST_F(DebugOutputsTest, DumpDepthWritesTheDocumentedFilesForEachShadowedLight) {
  writeScene(input("scene.gltf"));
  const fs::path lights = writeText("lights.json", kTwoShadowedLights);
  const Run r = render(
      {input("scene.gltf").string(), "-l", lights.string(), "-o", "a.png", "--dump-depth", "d"});

  // "key light" becomes "key_light"; "off" casts no shadow and gets nothing.
  std::vector<std::string> expected = dumpFiles("key_light");
  for (const std::string& file : dumpFiles("fill")) expected.push_back(file);
  EXPECT_EQ(filesIn(output("d")), sorted(expected));
  EXPECT_EQ(filesIn(out_).size(), expected.size() + 2) << "a.png, d/ and the dumps";
  EXPECT_TRUE(std::regex_search(r.out, std::regex("(^|\n)[^\n]*shadow maps[^\n]* d\n"))) << r.out;

  for (const std::string light : {"key_light", "fill"}) {
    SCOPED_TRACE(light);
    std::vector<float> faceTexels;
    for (const char* face : kFaces) {
      const ExrFile exr = readExr(output("d") / (light + "_" + face + ".exr"));
      EXPECT_EQ(exr.width, 32);
      EXPECT_EQ(exr.height, 32);
      ASSERT_EQ(exr.channels.size(), 1u) << face;
      EXPECT_EQ(exr.channels[0].first, "Z");
      EXPECT_EQ(exr.channels[0].second, Imf::FLOAT);
      EXPECT_FALSE(exr.hasEnvmap);
      faceTexels.insert(faceTexels.end(), exr.z.begin(), exr.z.end());
      EXPECT_EQ(pngSize(output("d") / (light + "_" + face + ".png")), std::make_pair(32u, 32u));
    }
    // Distances are positive; the floor below the light is always in the -Y face.
    for (float distance : faceTexels) ASSERT_GT(distance, 0.0f);
    const ExrFile ny = readExr(output("d") / (light + "_ny.exr"));
    EXPECT_TRUE(std::isfinite(ny.z[16 * 32 + 16]));

    const ExrFile cube = readExr(output("d") / (light + "_cube.exr"));
    EXPECT_TRUE(cube.hasEnvmap);
    EXPECT_EQ(cube.envmap, Imf::ENVMAP_CUBE);
    EXPECT_EQ(cube.width, 32);
    EXPECT_EQ(cube.height, 192);
    ASSERT_EQ(cube.channels.size(), 1u);
    EXPECT_EQ(cube.channels[0].first, "Z");
    EXPECT_EQ(cube.channels[0].second, Imf::FLOAT);
    // Each texel of the faces is copied into the cube exactly once.
    std::vector<float> cubeTexels = cube.z;
    std::sort(cubeTexels.begin(), cubeTexels.end());
    std::sort(faceTexels.begin(), faceTexels.end());
    EXPECT_EQ(cubeTexels, faceTexels);

    EXPECT_EQ(pngSize(output("d") / (light + "_cross.png")), std::make_pair(128u, 96u));
  }
}

TEST_F(DebugOutputsTest, DumpFacesAreInGlFaceOrder) {
  writeSixBoxes(input("boxes.gltf"));
  const fs::path lights = writeText("lights.json", kLampAtOrigin);
  render({input("boxes.gltf").string(), "-l", lights.string(), "-o", "a.png", "--dump-depth", "d"});
  ASSERT_EQ(filesIn(output("d")), sorted(dumpFiles("lamp")));
  for (int face = 0; face < 6; ++face) {
    SCOPED_TRACE(kFaces[face]);
    const ExrFile exr = readExr(output("d") / ("lamp_" + std::string(kFaces[face]) + ".exr"));
    ASSERT_EQ(exr.z.size(), 32u * 32u);
    // The four texels around the face centre look almost straight along the axis.
    for (int row : {15, 16})
      for (int column : {15, 16})
        EXPECT_NEAR(exr.z[row * 32 + column], kBoxDistance[face], 0.01 * kBoxDistance[face])
            << "texel " << column << "," << row;
  }
}

// ---------------------------------------------------------------------------------------------
// --light-views

TEST_F(DebugOutputsTest, LightViewFacesAreInGlFaceOrder) {
  writeSixBoxes(input("boxes.gltf"));
  const fs::path lights = writeText("lights.json", kLampAtOrigin);
  const Run r = render({input("boxes.gltf").string(), "-l", lights.string(), "-o", "a.png",
                        "--light-views", "v", "--light-view-size", "32"});
  std::vector<std::string> expected;
  for (const char* face : kFaces) expected.push_back(std::string("lamp_") + face + ".png");
  ASSERT_EQ(filesIn(output("v")), sorted(expected));
  EXPECT_TRUE(contains(r.out, " v\n")) << r.out;

  for (int face = 0; face < 6; ++face) {
    SCOPED_TRACE(kFaces[face]);
    const fs::path path = output("v") / expected[face];
    EXPECT_EQ(pngSize(path), std::make_pair(32u, 32u));
    const FloatImage view = readImage(path);
    ASSERT_EQ(view.channels.size(), 3u);
    for (int y : {15, 16})
      for (int x : {15, 16})
        for (int c = 0; c < 3; ++c) {
          // sRGB-encoded: a lit color channel is well above half, an unlit one near black.
          if (kBoxColor[face][c] > 0.0f) {
            EXPECT_GT(view.at(x, y, c), 0.4f) << "pixel " << x << "," << y << " channel " << c;
          } else {
            EXPECT_LT(view.at(x, y, c), 0.25f) << "pixel " << x << "," << y << " channel " << c;
          }
        }
  }
}

TEST_F(DebugOutputsTest, DumpsAndLightViewsAreByteIdenticalAcrossRuns) {
  writeScene(input("scene.gltf"));
  const fs::path lights = writeText("lights.json", kTwoShadowedLights);
  for (const std::string folder : {"first", "second"})
    render({input("scene.gltf").string(), "-l", lights.string(), "-o", folder + "/a.png",
            "--dump-depth", folder + "/d", "--light-views", folder + "/v", "--light-view-size",
            "32"});
  const std::vector<std::string> files = filesIn(output("first"));
  // 2 x 14 dump files, 3 x 6 light views (the unshadowed point light has views too), a.png,
  // and the folders d and v.
  EXPECT_EQ(files.size(), 28u + 18u + 1u + 2u);
  EXPECT_EQ(filesIn(output("second")), files);
  for (const std::string& file : files) {
    if (fs::is_directory(output("first") / file)) continue;
    const std::string first = readFile(output("first") / file);
    EXPECT_FALSE(first.empty()) << file;
    EXPECT_TRUE(first == readFile(output("second") / file)) << file << " differs";
  }
}

// ---------------------------------------------------------------------------------------------
// --aov-layers

TEST_F(DebugOutputsTest, AllAovLayersWithIdSidecar) {
  const SceneLayout layout = writeScene(input("scene.gltf"));
  const fs::path lights = writeText("lights.json", kNoAmbientLights);
  const Run r = render({input("scene.gltf").string(), "-l", lights.string(), "--aov", "a.exr",
                        "--aov-layers", "all"});
  EXPECT_EQ(filesIn(out_), (std::vector<std::string>{"a.exr", "a.ids.json"}));

  const FloatImage aovs = readImage(output("a.exr"));
  std::vector<std::string> expected = {
      "R",         "G",        "B",        "A",          "P.X",      "P.Y",      "P.Z",
      "N.X",       "N.Y",      "N.Z",      "Z",          "albedo.R", "albedo.G", "albedo.B",
      "roughness", "metallic", "objectId", "materialId", "occlusion"};
  for (const std::string light : {"key", "fill"}) {
    expected.push_back("visibility." + light);
    for (const std::string layer : {"diffuse.", "specular."})
      for (const char* c : {"R", "G", "B"}) expected.push_back(layer + light + "." + c);
  }
  EXPECT_EQ(sorted(aovs.channels), sorted(expected));

  // The sidecar: every instance, every material and the default one, the background.
  std::ifstream sidecarFile(output("a.ids.json"));
  const nlohmann::json ids = nlohmann::json::parse(sidecarFile, nullptr, false);
  ASSERT_FALSE(ids.is_discarded()) << readFile(output("a.ids.json"));
  EXPECT_EQ(ids.value("background", 0), -1);
  ASSERT_TRUE(ids.contains("objectId") && ids["objectId"].is_array());
  ASSERT_EQ(ids["objectId"].size(), layout.nodeMaterial.size());
  std::map<int, int> objectNode;  // objectId -> glTF node
  std::set<int> nodes;
  for (std::size_t i = 0; i < ids["objectId"].size(); ++i) {
    const nlohmann::json& entry = ids["objectId"][i];
    ASSERT_TRUE(entry.contains("id") && entry.contains("node") && entry.contains("mesh")) << entry;
    EXPECT_EQ(entry["id"], i);
    ASSERT_TRUE(entry["node"].is_number_integer()) << entry;
    ASSERT_TRUE(entry["mesh"].is_string()) << entry;
    const int node = entry["node"];
    ASSERT_TRUE(layout.nodeMaterial.contains(node)) << entry;
    objectNode[static_cast<int>(i)] = node;
    nodes.insert(node);
    const std::string mesh = entry["mesh"];
    const std::map<int, std::string> meshOfMaterial = {
        {0, "floorMesh"}, {1, "boxMesh"}, {-1, "ballMesh"}};
    EXPECT_TRUE(mesh.starts_with(meshOfMaterial.at(layout.nodeMaterial.at(node)))) << entry;
  }
  EXPECT_EQ(nodes.size(), layout.nodeMaterial.size()) << "an instance is listed twice";
  ASSERT_TRUE(ids.contains("materialId") && ids["materialId"].is_array());
  std::vector<std::string> materialNames;
  for (std::size_t i = 0; i < ids["materialId"].size(); ++i) {
    EXPECT_EQ(ids["materialId"][i].value("id", -1), static_cast<int>(i));
    materialNames.push_back(ids["materialId"][i].value("name", ""));
  }
  EXPECT_EQ(materialNames, (std::vector<std::string>{"floor", "box", "(default)"}));
  const int defaultMaterial = 2;

  // Per pixel: ids and material layers agree with the scene; the lights' layers add up to the
  // beauty (no ambient, no emission).
  auto channel = [&](const std::string& name) {
    const int index = aovs.channelIndex(name);
    EXPECT_GE(index, 0) << name;
    return std::max(index, 0);
  };
  const int alpha = channel("A"), objectId = channel("objectId"),
            materialId = channel("materialId"), roughness = channel("roughness"),
            metallic = channel("metallic");
  std::map<int, int> pixelsOf;  // objectId -> pixels
  int lit = 0;
  for (int y = 0; y < aovs.height; ++y) {
    for (int x = 0; x < aovs.width; ++x) {
      const int object = static_cast<int>(aovs.at(x, y, objectId));
      const int material = static_cast<int>(aovs.at(x, y, materialId));
      ASSERT_EQ(aovs.at(x, y, objectId), object) << "not an integer at " << x << "," << y;
      ++pixelsOf[object];
      if (aovs.at(x, y, alpha) == 0.0f) {
        ASSERT_EQ(object, -1) << x << "," << y;
        ASSERT_EQ(material, -1) << x << "," << y;
      } else {
        ASSERT_TRUE(objectNode.contains(object)) << object << " at " << x << "," << y;
        const int gltfMaterial = layout.nodeMaterial.at(objectNode.at(object));
        ASSERT_EQ(material, gltfMaterial < 0 ? defaultMaterial : gltfMaterial) << x << "," << y;
        // The glTF default material: white, fully rough, fully metallic.
        const SceneLayout::Material m = gltfMaterial < 0
                                            ? SceneLayout::Material{"", glm::vec3(1), 1.0f, 1.0f}
                                            : layout.materials[gltfMaterial];
        for (int c = 0; c < 3; ++c)
          ASSERT_NEAR(aovs.at(x, y, channel(std::string("albedo.") + "RGB"[c])), m.color[c], 1e-5)
              << x << "," << y;
        ASSERT_NEAR(aovs.at(x, y, roughness), m.roughness, 1e-5) << x << "," << y;
        ASSERT_NEAR(aovs.at(x, y, metallic), m.metallic, 1e-5) << x << "," << y;
      }
      for (int c = 0; c < 3; ++c) {
        const std::string rgb(1, "RGB"[c]);
        double sum = 0.0;
        for (const std::string light : {"key", "fill"})
          sum += aovs.at(x, y, channel("diffuse." + light + "." + rgb)) +
                 aovs.at(x, y, channel("specular." + light + "." + rgb));
        const float beauty = aovs.at(x, y, channel(rgb));
        ASSERT_NEAR(sum, beauty, 1e-4 * std::max(1.0f, std::abs(beauty)))
            << rgb << " at " << x << "," << y;
        lit += beauty > 0.01f;
      }
    }
  }
  EXPECT_GT(pixelsOf[-1], 0) << "no background";
  for (const auto& [object, node] : objectNode)
    EXPECT_GT(pixelsOf[object], 10) << "object " << object << " (node " << node << ") not seen";
  EXPECT_GT(lit, 1000) << "too dark to tell";
  EXPECT_TRUE(contains(r.out, "a.exr"));
}

TEST_F(DebugOutputsTest, NoIdSidecarWithoutIdLayers) {
  writeScene(input("scene.gltf"));
  const fs::path lights = writeText("lights.json", kNoAmbientLights);
  render({input("scene.gltf").string(), "-l", lights.string(), "--aov", "a.exr", "--aov-layers",
          "albedo,roughness,metallic,diffuse,specular"});
  EXPECT_EQ(filesIn(out_), std::vector<std::string>{"a.exr"});
  const FloatImage aovs = readImage(output("a.exr"));
  EXPECT_GE(aovs.channelIndex("albedo.R"), 0);
  EXPECT_GE(aovs.channelIndex("specular.fill.B"), 0);
  EXPECT_EQ(aovs.channelIndex("objectId"), -1);
  EXPECT_EQ(aovs.channelIndex("materialId"), -1);
}

// ---------------------------------------------------------------------------------------------
// --debug-view

TEST_F(DebugOutputsTest, NormalsViewOfAFloorSeenFromAbove) {
  writeScene(input("scene.gltf"));
  const fs::path lights = writeText("lights.json", kTwoShadowedLights);
  render({input("scene.gltf").string(), "-l", lights.string(), "--camera", "top", "--debug-view",
          "normals", "-o", "n.png", "-o", "n.exr"});
  // The "top" camera sees nothing but the floor, whose normal is +Y: N * 0.5 + 0.5 = (0.5, 1, 0.5).
  const FloatImage exr = readImage(output("n.exr"));
  for (int y = 0; y < exr.height; ++y)
    for (int x = 0; x < exr.width; ++x) {
      ASSERT_EQ(exr.at(x, y, exr.channelIndex("A")), 1.0f) << x << "," << y;
      for (int c = 0; c < 3; ++c)
        ASSERT_NEAR(exr.at(x, y, c), c == 1 ? 1.0f : 0.5f, 2e-3) << x << "," << y;
    }
  // sRGB-encoded in the PNG: 0.5 -> 188.
  const FloatImage png = readImage(output("n.png"));
  ASSERT_EQ(png.channels.size(), 3u);
  for (int y = 0; y < png.height; ++y)
    for (int x = 0; x < png.width; ++x)
      for (int c = 0; c < 3; ++c)
        ASSERT_NEAR(png.at(x, y, c) * 255.0f, c == 1 ? 255.0f : 188.0f, 1.01f) << x << "," << y;
}

TEST_F(DebugOutputsTest, DepthViewOfANamedLight) {
  writeScene(input("scene.gltf"));
  const fs::path lights = writeText("lights.json", kTwoShadowedLights);
  render({input("scene.gltf").string(), "-l", lights.string(), "--debug-view", "depth",
          "--debug-light", "key light", "-o", "key.exr"});
  render({input("scene.gltf").string(), "-l", lights.string(), "--debug-view", "depth",
          "--debug-light", "fill", "-o", "fill.exr"});
  EXPECT_EQ(filesIn(out_), (std::vector<std::string>{"fill.exr", "key.exr"}));
  // Grey distance / far in [0, 1]; the two lights see the scene from different places.
  const FloatImage key = readImage(output("key.exr")), fill = readImage(output("fill.exr"));
  ASSERT_EQ(key.pixels.size(), fill.pixels.size());
  int differ = 0, covered = 0;
  for (int y = 0; y < key.height; ++y)
    for (int x = 0; x < key.width; ++x) {
      if (key.at(x, y, 3) < 1.0f) continue;
      ++covered;
      const float grey = key.at(x, y, 0);
      ASSERT_GE(grey, 0.0f);
      ASSERT_LE(grey, 1.0f);
      ASSERT_EQ(key.at(x, y, 1), grey);
      ASSERT_EQ(key.at(x, y, 2), grey);
      differ += std::abs(fill.at(x, y, 0) - grey) > 0.02f;
    }
  EXPECT_GT(covered, 1000);
  EXPECT_GT(differ, covered / 4) << "--debug-light made no difference";
}

// ---------------------------------------------------------------------------------------------
// Errors: status 2, one line naming the problem, and no file at all in the output folder

struct ErrorCase {
  std::string name;
  std::string lightsJson;         // written to in/lights.json
  std::vector<std::string> args;  // "$scene", "$lights" and "$in" are replaced by paths
  std::string message;            // "$..." replaced likewise
  bool oneLine = true;            // false: a CLI11 usage error
};

void PrintTo(const ErrorCase& c, std::ostream* os) {
  *os << c.name;
}

class DebugOutputsErrorTest : public DebugOutputsTest,
                              public ::testing::WithParamInterface<ErrorCase> {};

constexpr const char* kClashingLights = R"({"lights": [
  {"name": "a b", "position": [-1, 3, 1], "shadow": {"resolution": 32}},
  {"name": "a_b", "position": [1, 3, 1], "shadow": {"resolution": 32}}
]})";

const ErrorCase kErrorCases[] = {
    {"AovLayersWithoutAov",
     kTwoShadowedLights,
     {"render", "$scene", "-l", "$lights", "--aov-layers", "albedo", "-o", "a.png"},
     "--aov-layers: needs --aov"},
    {"UnknownAovLayer",
     kTwoShadowedLights,
     {"render", "$scene", "-l", "$lights", "--aov", "a.exr", "--aov-layers", "albedo,bogus"},
     "unknown layer \"bogus\""},
    {"DebugLightWithoutDepthView",
     kTwoShadowedLights,
     {"render", "$scene", "-l", "$lights", "--debug-light", "x", "-o", "a.png"},
     "--debug-light: only used with --debug-view depth"},
    {"DebugLightWithAnotherDebugView",
     kTwoShadowedLights,
     {"render", "$scene", "-l", "$lights", "--debug-view", "normals", "--debug-light", "fill", "-o",
      "a.png"},
     "--debug-light: only used with --debug-view depth"},
    {"UnknownDebugLight",
     kTwoShadowedLights,
     {"render", "$scene", "-l", "$lights", "--debug-view", "depth", "--debug-light", "nosuch", "-o",
      "a.png"},
     "--debug-light nosuch: no shadowed light has that name"},
    {"UnshadowedDebugLight",
     kTwoShadowedLights,
     {"render", "$scene", "-l", "$lights", "--debug-view", "depth", "--debug-light", "off", "-o",
      "a.png"},
     "--debug-light off: no shadowed light has that name"},
    {"DumpDepthIsAFile",
     kTwoShadowedLights,
     {"render", "$scene", "-l", "$lights", "-o", "a.png", "--dump-depth", "$in/lights.json"},
     "--dump-depth $in/lights.json: is a file, expected a folder"},
    {"LightViewsIsAFile",
     kTwoShadowedLights,
     {"render", "$scene", "-l", "$lights", "-o", "a.png", "--light-views", "$in/lights.json"},
     "--light-views $in/lights.json: is a file, expected a folder"},
    {"UnknownDebugView",
     kTwoShadowedLights,
     {"render", "$scene", "-l", "$lights", "--debug-view", "bogus", "-o", "a.png"},
     "--debug-view: bogus",
     false},
    {"LightNamesClashInDumps",
     kClashingLights,
     {"render", "$scene", "-l", "$lights", "-o", "a.png", "--dump-depth", "d"},
     R"(lights "a b" and "a_b" would write the same files (a_b_*))"},
    {"LightNamesClashInLightViews",
     kClashingLights,
     {"render", "$scene", "-l", "$lights", "-o", "a.png", "--light-views", "v"},
     R"(lights "a b" and "a_b" would write the same files (a_b_*))"},
};

TEST_P(DebugOutputsErrorTest, ExitsWithStatusTwoMessageAndNoOutput) {
  const ErrorCase& c = GetParam();
  writeScene(input("scene.gltf"));
  writeText("lights.json", c.lightsJson);
  const std::vector<std::string> inputsBefore = filesIn(in_);
  const std::string lightsBefore = readFile(input("lights.json"));
  std::vector<std::string> args;
  for (const std::string& arg : c.args) args.push_back(substituted(arg));
  args.insert(args.end(), {"--width", "64", "--height", "48", "--no-gltf-lights"});

  const Run r = run(args);

  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_TRUE(contains(r.err, substituted(c.message)));
  EXPECT_TRUE(r.err.starts_with("omnishadow: ")) << r.err;
  if (c.oneLine) {
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  }
  EXPECT_EQ(r.out, "");
  EXPECT_EQ(filesIn(out_), std::vector<std::string>{}) << "a failed run left files";
  EXPECT_EQ(filesIn(in_), inputsBefore);
  EXPECT_EQ(readFile(input("lights.json")), lightsBefore);
}

// Files named after lights or the AOV must not replace an input: here the lights file itself
// has the name the id sidecar, a light view or a depth dump would get.
TEST_F(DebugOutputsTest, PerLightFilesAndTheIdSidecarNeverOverwriteAnInput) {
  writeScene(input("scene.gltf"));
  const struct {
    const char* lightsFile;
    std::vector<std::string> extra;
  } cases[] = {
      {"a.ids.json", {"--aov", (in_ / "a.exr").string(), "--aov-layers", "objectId"}},
      {"fill_px.png", {"--light-views", in_.string()}},
      {"fill_px.exr", {"--dump-depth", in_.string()}},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.lightsFile);
    const fs::path lights = writeText(c.lightsFile, kTwoShadowedLights);
    std::vector<std::string> args = {"render",
                                     input("scene.gltf").string(),
                                     "-l",
                                     lights.string(),
                                     "-o",
                                     "a.png",
                                     "--width",
                                     "64",
                                     "--height",
                                     "48",
                                     "--no-gltf-lights"};
    args.insert(args.end(), c.extra.begin(), c.extra.end());
    const Run r = run(args);
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_TRUE(contains(r.err, "refusing to overwrite an input file")) << r.err;
    EXPECT_EQ(readFile(lights), kTwoShadowedLights);
    EXPECT_EQ(filesIn(out_), std::vector<std::string>{});
    fs::remove(lights);
  }
}

INSTANTIATE_TEST_SUITE_P(DebugOutputs, DebugOutputsErrorTest, ::testing::ValuesIn(kErrorCases),
                         [](const ::testing::TestParamInfo<ErrorCase>& test) {
                           return test.param.name;
                         });

}  // namespace
}  // namespace omnishadow::debug_outputs_test
