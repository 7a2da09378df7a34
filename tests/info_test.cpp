// End-to-end tests of `omnishadow info`: the counts and fields of its JSON report, the schema's
// keys and their order, the text report, errors, and that it needs no GL at all. Every test runs
// the real executable on scenes written with GltfBuilder into a fresh temporary folder:
//   <root>/in   inputs
//   <root>/stdout, <root>/stderr  what the run printed
#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>
#include <vector>

#include "scenes/builder/gltf_builder.h"
#include "tests/support/run_binary.h"
#include "tests/support/temp_folder.h"

namespace omnishadow::info_test {
namespace {

namespace fs = std::filesystem;
using builder::FileFormat;
using builder::GltfBuilder;
using Json = nlohmann::ordered_json;  // keeps the order of keys as printed

// glvnd finds no vendor library with this, so any attempt at an EGL display fails.
constexpr const char* kBrokenEgl = "__EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent.json";

constexpr float kYfov = 0.8f;

// Scene 0 of the test file:
//   crateA, crateB  two nodes sharing mesh 0 "crate": a box (material "floor") and a plane
//                   (material "leaf": MASK, cutoff 0.3, double-sided, base color texture 0)
//   ground          mesh 1, a 10x10 plane without normals (generated flat, with a warning)
//   main            perspective camera at (0, 2, 5), yfov 0.8 rad
//   lamp            KHR_lights_punctual point light at (0, 3, 0)
// Scene 1: node "spare" with mesh 2, a box that scene 0 does not draw.
void writeScene(const fs::path& path, FileFormat format = FileFormat::GltfEmbedded) {
  GltfBuilder b;
  std::vector<std::uint8_t> pixels(4 * 2 * 4, 200);
  const int leaves = b.addTexture(4, 2, pixels, "leaves");
  const int floor = b.addMaterial({.name = "floor"});
  const int leaf = b.addMaterial({.name = "leaf",
                                  .alphaMode = "MASK",
                                  .alphaCutoff = 0.3f,
                                  .doubleSided = true,
                                  .baseColorTexture = leaves});
  const int crate = b.addMesh(builder::makeBox(glm::vec3(0.5f)), {.material = floor}, "crate");
  b.addPrimitive(crate, builder::makePlane(1.0f), {.material = leaf});
  builder::MeshData ground = builder::makePlane(10.0f);
  ground.normals.clear();
  const int groundMesh = b.addMesh(ground, {}, "ground");
  const int spare = b.addMesh(builder::makeBox(glm::vec3(0.25f)), {}, "spare");
  b.addNode("crateA", {.translation = {-1.0f, 0.5f, 0.0f}}, crate);
  b.addNode("crateB", {.translation = {1.0f, 0.5f, 0.0f}}, crate);
  b.addNode("ground", {}, groundMesh);
  b.addPerspectiveCamera("main", {0.0f, 2.0f, 5.0f}, {0.0f, 0.0f, 0.0f}, kYfov);
  b.addLight("lamp", "point", {0.0f, 3.0f, 0.0f}, {0.0f, -1.0f, 0.0f}, {1.0f, 0.5f, 0.25f}, 20.0f,
             10.0f);
  const int spareNode = b.addNode("spare", {}, spare);
  tinygltf::Model& model = b.model();
  std::erase(model.scenes[0].nodes, spareNode);
  model.scenes.emplace_back();
  model.scenes[1].nodes = {spareNode};
  b.write(path, format);
}

// Replaces the glTF light "lamp" (same name) and adds a spot light.
constexpr const char* kLights = R"({
  "ambient": [0.1, 0.2, 0.3],
  "lights": [
    {"name": "key", "type": "spot", "position": [0, 4, 0], "direction": [0, -1, 0],
     "intensity": 50, "shadow": {"resolution": 256, "filter": "hard"}},
    {"name": "lamp", "position": [0, 3, 0], "intensity": 5, "shadow": false}
  ]
})";

using test_support::readFile;

::testing::AssertionResult contains(const std::string& text, const std::string& part) {
  if (text.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "\"" << text << "\" does not contain \"" << part << "\"";
}

std::vector<std::string> keys(const Json& object) {
  std::vector<std::string> names;
  for (const auto& item : object.items()) names.push_back(item.key());
  return names;
}

void expectVec3(const Json& value, glm::vec3 expected) {
  ASSERT_TRUE(value.is_array()) << value;
  ASSERT_EQ(value.size(), 3u) << value;
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(value[i].get<double>(), expected[i], 1e-5) << value;
}

class InfoTest : public ::testing::Test {
 protected:
  using Run = test_support::RunResult;  // not ::testing::Test::Run()

  void SetUp() override { fs::create_directory(in_); }

  // `omnishadow args...` in the test's folder; `environment` ("NAME=value") is set for the run
  // only.
  Run run(const std::vector<std::string>& args, const std::vector<std::string>& environment = {}) {
    test_support::RunOptions options;
    options.workingDirectory = root_.path();
    options.environment = environment;
    return test_support::runOmnishadow(args, options);
  }

  // `omnishadow info args... --json`, expected to succeed with nothing on stderr.
  Json info(std::vector<std::string> args, const std::vector<std::string>& environment = {}) {
    args.insert(args.begin(), "info");
    args.push_back("--json");
    const Run r = run(args, environment);
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(r.err, "");
    try {
      return Json::parse(r.out);
    } catch (const std::exception& e) {
      ADD_FAILURE() << e.what() << "\n" << r.out;
      return Json::object();
    }
  }

  fs::path input(const std::string& name) const { return in_ / name; }

  fs::path writeText(const std::string& name, const std::string& text) {
    std::ofstream(input(name), std::ios::binary) << text;
    return input(name);
  }

  fs::path scene(const std::string& name = "scene.gltf",
                 FileFormat format = FileFormat::GltfEmbedded) {
    writeScene(input(name), format);
    return input(name);
  }

  // A one-line "omnishadow: ..." message on stderr, nothing on stdout, exit status 2.
  void expectInputError(const Run& r, const std::string& message) {
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_TRUE(r.err.starts_with("omnishadow: ")) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_TRUE(contains(r.err, message));
    EXPECT_EQ(r.out, "");
  }

  test_support::TempFolder root_{"omnishadow-info"};
  fs::path in_ = root_ / "in";
};

// ---------------------------------------------------------------------------------------------
// The JSON report

TEST_F(InfoTest, JsonIsPrettyPrintedWithKeysInTheDocumentedOrder) {
  writeText("scene.lights.json", kLights);
  const Run r = run({"info", scene().string(), "--json"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.err, "");
  EXPECT_TRUE(r.out.starts_with("{\n  \"file\": ")) << r.out.substr(0, 40);
  EXPECT_EQ(r.out, Json::parse(r.out).dump(2) + "\n");  // two-space indent, one object
  const Json doc = Json::parse(r.out);
  using Keys = std::vector<std::string>;
  EXPECT_EQ(keys(doc),
            (Keys{"file", "format", "asset", "extensions", "scene", "materialVariants", "counts",
                  "bounds", "materials", "textures", "cameras", "lights", "ambient", "environment",
                  "ambientOcclusion", "animations", "skins", "morphTargets", "warnings"}));
  EXPECT_EQ(keys(doc["materialVariants"]), (Keys{"names", "drawn"}));
  EXPECT_EQ(keys(doc["asset"]), (Keys{"version", "minVersion", "generator", "copyright"}));
  EXPECT_EQ(keys(doc["scene"]), (Keys{"index", "count"}));
  EXPECT_EQ(keys(doc["counts"]),
            (Keys{"nodes", "meshes", "primitives", "instances", "triangles", "drawnTriangles",
                  "vertices", "materials", "textures", "images", "cameras", "lights"}));
  EXPECT_EQ(keys(doc["counts"]["nodes"]), (Keys{"file", "reached", "hidden"}));
  EXPECT_EQ(keys(doc["counts"]["primitives"]), (Keys{"file", "drawn"}));
  EXPECT_EQ(keys(doc["bounds"]), (Keys{"min", "max", "center", "size"}));
  ASSERT_FALSE(doc["materials"].empty());
  EXPECT_EQ(keys(doc["materials"][0]),
            (Keys{"index", "name", "alphaMode", "alphaCutoff", "doubleSided", "model", "textures",
                  "ior", "specular", "sheen", "clearcoat", "transmission", "volume", "anisotropy",
                  "iridescence", "diffuseTransmission"}));
  EXPECT_EQ(keys(doc["materials"][0]["textures"]),
            (Keys{"baseColor", "metallicRoughness", "normal", "occlusion", "emissive"}));
  ASSERT_FALSE(doc["textures"].empty());
  EXPECT_EQ(keys(doc["textures"][0]), (Keys{"index", "image"}));
  EXPECT_EQ(keys(doc["textures"][0]["image"]),
            (Keys{"index", "name", "width", "height", "format"}));
  ASSERT_FALSE(doc["cameras"].empty());
  EXPECT_EQ(keys(doc["cameras"][0]),
            (Keys{"index", "name", "node", "type", "yfovDegrees", "aspectRatio", "xmag", "ymag",
                  "znear", "zfar", "position", "direction"}));
  ASSERT_FALSE(doc["lights"].empty());
  for (const Json& light : doc["lights"]) {
    EXPECT_EQ(keys(light),
              (Keys{"name", "type", "source", "position", "direction", "color", "intensity",
                    "range", "innerConeAngle", "outerConeAngle", "shadow"}));
    EXPECT_EQ(keys(light["shadow"]),
              (Keys{"enabled", "resolution", "filter", "near", "far", "bias", "slopeBias"}));
  }
}

TEST_F(InfoTest, CountsFileSceneAndDrawnParts) {
  const fs::path path = scene();
  const Json doc = info({path.string()});
  EXPECT_EQ(doc["file"], path.string());
  EXPECT_EQ(doc["format"], "gltf");
  EXPECT_EQ(doc["asset"]["version"], "2.0");
  EXPECT_EQ(doc["asset"]["generator"], "omnishadow gltf_builder");
  EXPECT_TRUE(doc["asset"]["minVersion"].is_null());
  EXPECT_TRUE(doc["asset"]["copyright"].is_null());
  EXPECT_EQ(doc["scene"]["index"], 0);
  EXPECT_EQ(doc["scene"]["count"], 2);

  const Json& counts = doc["counts"];
  EXPECT_EQ(counts["nodes"]["file"], 6);
  EXPECT_EQ(counts["nodes"]["reached"], 5);  // not "spare"
  EXPECT_EQ(counts["meshes"], 3);
  EXPECT_EQ(counts["primitives"]["file"], 4);
  EXPECT_EQ(counts["primitives"]["drawn"], 3);  // crate's two and ground's; not spare's
  EXPECT_EQ(counts["instances"], 5);            // 2 x crate's two primitives + ground
  // Box 12 + plane 2 (crate, once) + ground 2; drawn: crate twice.
  EXPECT_EQ(counts["triangles"], 16);
  EXPECT_EQ(counts["drawnTriangles"], 30);
  // Box 24 + plane 4 + ground 6 (un-indexed for its generated flat normals).
  EXPECT_EQ(counts["vertices"], 34);
  EXPECT_EQ(counts["materials"], 2);
  EXPECT_EQ(counts["textures"], 1);
  EXPECT_EQ(counts["images"], 1);
  EXPECT_EQ(counts["cameras"], 1);
  EXPECT_EQ(counts["lights"], 1);

  expectVec3(doc["bounds"]["min"], {-5.0f, 0.0f, -5.0f});
  expectVec3(doc["bounds"]["max"], {5.0f, 1.0f, 5.0f});
  expectVec3(doc["bounds"]["center"], {0.0f, 0.5f, 0.0f});
  expectVec3(doc["bounds"]["size"], {10.0f, 1.0f, 10.0f});
}

TEST_F(InfoTest, ListsMaterialsTexturesAndCameras) {
  const Json doc = info({scene().string()});
  ASSERT_EQ(doc["materials"].size(), 2u);
  const Json& floor = doc["materials"][0];
  EXPECT_EQ(floor["index"], 0);
  EXPECT_EQ(floor["name"], "floor");
  EXPECT_EQ(floor["alphaMode"], "OPAQUE");
  EXPECT_TRUE(floor["alphaCutoff"].is_null());
  EXPECT_EQ(floor["doubleSided"], false);
  for (const auto& slot : floor["textures"].items()) EXPECT_TRUE(slot.value().is_null());
  const Json& leaf = doc["materials"][1];
  EXPECT_EQ(leaf["name"], "leaf");
  EXPECT_EQ(leaf["alphaMode"], "MASK");
  EXPECT_NEAR(leaf["alphaCutoff"].get<double>(), 0.3, 1e-6);
  EXPECT_EQ(leaf["doubleSided"], true);
  EXPECT_EQ(leaf["textures"]["baseColor"], 0);
  EXPECT_TRUE(leaf["textures"]["normal"].is_null());

  ASSERT_EQ(doc["textures"].size(), 1u);
  EXPECT_EQ(doc["textures"][0]["index"], 0);
  EXPECT_EQ(doc["textures"][0]["image"]["index"], 0);
  EXPECT_EQ(doc["textures"][0]["image"]["name"], "leaves");
  EXPECT_EQ(doc["textures"][0]["image"]["width"], 4);
  EXPECT_EQ(doc["textures"][0]["image"]["height"], 2);
  EXPECT_EQ(doc["textures"][0]["image"]["format"], "PNG");

  ASSERT_EQ(doc["cameras"].size(), 1u);
  const Json& camera = doc["cameras"][0];
  EXPECT_EQ(camera["index"], 0);
  EXPECT_EQ(camera["name"], "main");
  EXPECT_EQ(camera["node"], "main");
  EXPECT_EQ(camera["type"], "perspective");
  EXPECT_NEAR(camera["yfovDegrees"].get<double>(), kYfov * 180.0 / std::numbers::pi, 1e-3);
  EXPECT_TRUE(camera["aspectRatio"].is_null());
  EXPECT_TRUE(camera["xmag"].is_null());
  EXPECT_TRUE(camera["ymag"].is_null());
  EXPECT_NEAR(camera["znear"].get<double>(), 0.05, 1e-6);
  EXPECT_TRUE(camera["zfar"].is_null());  // infinite
  expectVec3(camera["position"], {0.0f, 2.0f, 5.0f});
  expectVec3(camera["direction"], glm::normalize(glm::vec3(0.0f, -2.0f, -5.0f)));
}

TEST_F(InfoTest, ListsTheGltfLightAndWarnings) {
  const fs::path path = scene();
  const Json doc = info({path.string()});
  ASSERT_EQ(doc["lights"].size(), 1u);
  const Json& lamp = doc["lights"][0];
  EXPECT_EQ(lamp["name"], "lamp");
  EXPECT_EQ(lamp["type"], "point");
  EXPECT_EQ(lamp["source"], "glTF");
  expectVec3(lamp["position"], {0.0f, 3.0f, 0.0f});
  EXPECT_TRUE(lamp["direction"].is_null());  // a point light has none
  expectVec3(lamp["color"], {1.0f, 0.5f, 0.25f});
  EXPECT_EQ(lamp["intensity"], 20.0);
  EXPECT_EQ(lamp["range"], 10.0);
  EXPECT_TRUE(lamp["innerConeAngle"].is_null());
  EXPECT_EQ(lamp["shadow"]["enabled"], true);
  EXPECT_EQ(lamp["shadow"]["resolution"], 1024);
  EXPECT_EQ(lamp["shadow"]["filter"], "pcf");
  EXPECT_TRUE(doc["ambient"].is_null());  // no lights file

  ASSERT_EQ(doc["warnings"].size(), 1u) << doc["warnings"];
  EXPECT_EQ(doc["warnings"][0],
            path.string() + ": meshes[1].primitives[0]: no normals; generated flat normals");
}

TEST_F(InfoTest, MergesTheLightsFileBesideTheScene) {
  const fs::path lights = writeText("scene.lights.json", kLights);
  const Json doc = info({scene().string()});
  EXPECT_EQ(doc["counts"]["lights"], 2);
  ASSERT_EQ(doc["lights"].size(), 2u);
  // The file's "lamp" replaces the glTF one; the file's lights come in the file's order.
  const Json& key = doc["lights"][0];
  EXPECT_EQ(key["name"], "key");
  EXPECT_EQ(key["type"], "spot");
  EXPECT_EQ(key["source"], lights.string());
  expectVec3(key["position"], {0.0f, 4.0f, 0.0f});
  expectVec3(key["direction"], {0.0f, -1.0f, 0.0f});
  EXPECT_EQ(key["intensity"], 50.0);
  EXPECT_TRUE(key["range"].is_null());  // unlimited
  EXPECT_EQ(key["innerConeAngle"], 0.0);
  EXPECT_NEAR(key["outerConeAngle"].get<double>(), std::numbers::pi / 4.0, 1e-6);
  EXPECT_EQ(key["shadow"]["enabled"], true);
  EXPECT_EQ(key["shadow"]["resolution"], 256);
  EXPECT_EQ(key["shadow"]["filter"], "hard");
  const Json& lamp = doc["lights"][1];
  EXPECT_EQ(lamp["name"], "lamp");
  EXPECT_EQ(lamp["source"], lights.string());
  EXPECT_EQ(lamp["intensity"], 5.0);
  EXPECT_EQ(lamp["shadow"]["enabled"], false);
  expectVec3(doc["ambient"], {0.1f, 0.2f, 0.3f});
}

TEST_F(InfoTest, LightsOptionChoosesAnotherFile) {
  writeText("scene.lights.json", kLights);
  const fs::path other =
      writeText("other.json",
                R"({"lights": [{"name": "sun", "type": "directional", "direction": [0, 0, -2]}]})");
  const Json doc = info({scene().string(), "--lights", other.string()});
  ASSERT_EQ(doc["lights"].size(), 2u);
  EXPECT_EQ(doc["lights"][0]["name"], "lamp");
  EXPECT_EQ(doc["lights"][0]["source"], "glTF");
  const Json& sun = doc["lights"][1];
  EXPECT_EQ(sun["name"], "sun");
  EXPECT_EQ(sun["type"], "directional");
  EXPECT_EQ(sun["source"], other.string());
  EXPECT_TRUE(sun["position"].is_null());
  expectVec3(sun["direction"], {0.0f, 0.0f, -1.0f});
  expectVec3(doc["ambient"], glm::vec3(0.03f));  // the file's default
}

TEST_F(InfoTest, ReportsTheAmbientOcclusionRadiusTheFramesUse) {
  const fs::path given = writeText("given.json", R"({"ambient_occlusion": {"radius": 0.3}})");
  const Json doc = info({scene().string(), "--lights", given.string()});
  EXPECT_EQ(doc["ambientOcclusion"],
            Json({{"radius", 0.3}, {"radiusFromScene", false}, {"strength", 1.0}}));
  EXPECT_TRUE(info({scene().string()})["ambientOcclusion"].is_null());

  // From the scene: 5% of its bounds' diagonal, as info reports the bounds.
  const fs::path fromScene = writeText("scene.json", R"({"ambient_occlusion": true})");
  const Json sized = info({scene().string(), "--lights", fromScene.string()});
  const glm::vec3 low(sized["bounds"]["min"][0], sized["bounds"]["min"][1],
                      sized["bounds"]["min"][2]);
  const glm::vec3 high(sized["bounds"]["max"][0], sized["bounds"]["max"][1],
                       sized["bounds"]["max"][2]);
  EXPECT_NEAR(sized["ambientOcclusion"]["radius"].get<double>(), 0.05 * glm::length(high - low),
              1e-5);
  EXPECT_EQ(sized["ambientOcclusion"]["radiusFromScene"], true);
  const Run r = run({"info", scene().string(), "--lights", fromScene.string()});
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "(5% of the scene's diagonal), strength 1\n")) << r.out;
}

TEST_F(InfoTest, ReportsTheEnvironmentAsItWillLightTheFrame) {
  const fs::path lights =
      writeText("studio.json",
                R"({"environment": {"image": "maps/sky.hdr", "intensity": 2, "rotation": 90}})");
  const Json doc = info({scene().string(), "--lights", lights.string()});
  const Json& environment = doc["environment"];
  EXPECT_EQ(environment["image"], (lights.parent_path() / "maps" / "sky.hdr").string());
  expectVec3(environment["color"], glm::vec3(1.0f));
  EXPECT_EQ(environment["intensity"], 2.0);
  EXPECT_NEAR(environment["rotation"].get<double>(), 90.0, 1e-4);
  EXPECT_EQ(environment["background"], false);
  EXPECT_EQ(environment["sun"], false);
  expectVec3(doc["ambient"], glm::vec3(0.0f));  // the environment stands in for it
  EXPECT_TRUE(info({scene().string()})["environment"].is_null());  // no lights file

  const fs::path uniform = writeText("uniform.json", R"({"environment": {"background": true}})");
  const Run r = run({"info", scene().string(), "--lights", uniform.string()});
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(contains(r.out,
                       "environment uniform, color (1, 1, 1), intensity 1, rotation 0 "
                       "degrees, background\n"));
}

TEST_F(InfoTest, SceneOptionChoosesAnotherScene) {
  const Json doc = info({scene().string(), "--scene", "1"});
  EXPECT_EQ(doc["scene"]["index"], 1);
  EXPECT_EQ(doc["scene"]["count"], 2);
  const Json& counts = doc["counts"];
  EXPECT_EQ(counts["nodes"]["file"], 6);
  EXPECT_EQ(counts["nodes"]["reached"], 1);
  EXPECT_EQ(counts["meshes"], 3);
  EXPECT_EQ(counts["primitives"]["drawn"], 1);
  EXPECT_EQ(counts["instances"], 1);
  EXPECT_EQ(counts["triangles"], 12);
  EXPECT_EQ(counts["drawnTriangles"], 12);
  EXPECT_EQ(counts["cameras"], 0);
  EXPECT_EQ(counts["lights"], 0);
  expectVec3(doc["bounds"]["min"], glm::vec3(-0.25f));
  ASSERT_EQ(doc["warnings"].size(), 1u) << doc["warnings"];
  EXPECT_TRUE(contains(doc["warnings"][0], "no lights"));
}

TEST_F(InfoTest, BinaryFilesAreGlb) {
  const Json doc = info({scene("scene.glb", FileFormat::Glb).string()});
  EXPECT_EQ(doc["format"], "glb");
  EXPECT_EQ(doc["counts"]["drawnTriangles"], 30);
}

// ---------------------------------------------------------------------------------------------
// Text, GL, errors

TEST_F(InfoTest, TextReportHasTheKeyLines) {
  const fs::path path = scene();
  const fs::path lights = writeText("scene.lights.json", kLights);
  const Run r = run({"info", path.string()});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.err, "");
  for (const std::string& line :
       {"file        " + path.string() + "\n",
        std::string("format      gltf, glTF 2.0, generator \"omnishadow gltf_builder\"\n"),
        std::string("scene       0 (2 scenes in the file)\n"),
        std::string("nodes       6 in the file, 5 reached from the scene\n"),
        std::string("meshes      3 glTF meshes, 4 primitives (3 drawn)\n"),
        std::string("instances   5\n"),
        std::string("triangles   16 unique, 30 drawn\n"),
        std::string("vertices    34\n"),
        std::string("bounds      min (-5, 0, -5)  max (5, 1, 5)\n"),
        std::string("materials   2\n"),
        std::string("  1  \"leaf\"   MASK 0.3  double-sided"),
        std::string("textures baseColor=0\n"),
        std::string("textures    1 (1 image)\n"),
        std::string("  0  image 0  \"leaves\"  4x2  PNG\n"),
        std::string("cameras     1\n"),
        std::string("  0  \"main\"  perspective  yfov 45.8366 deg  at (0, 2, 5)\n"),
        std::string("lights      2\n"),
        "  \"key\"   spot   " + lights.string(),
        std::string("shadow 256 hard\n"),
        std::string("no shadow\n"),
        std::string("ambient     (0.1, 0.2, 0.3) (lights file)\n"),
        std::string("warnings    1\n"),
        std::string("no normals; generated flat normals\n")}) {
    EXPECT_TRUE(contains(r.out, line));
  }
}

TEST_F(InfoTest, NeedsNoGlContext) {
  const fs::path path = scene();
  // The same environment makes a render fail at the context: it does break EGL.
  const Run render = run({"render", path.string(), "-o", "a.png"}, {kBrokenEgl});
  EXPECT_EQ(render.status, 1) << render.err;
  EXPECT_TRUE(contains(render.err, "EGL"));
  // JSON with broken EGL: SundialSample.
  const Run text = run({"info", path.string()}, {kBrokenEgl});
  EXPECT_EQ(text.status, 0) << text.err;
  EXPECT_EQ(text.err, "");
  EXPECT_TRUE(contains(text.out, "triangles   16 unique, 30 drawn\n"));
}

TEST_F(InfoTest, ErrorsAreOneLineWithStatus2AsInRender) {
  // A scene without warnings, so that the message is all there is on stderr.
  GltfBuilder b;
  b.addNode("box", {}, b.addMesh(builder::makeBox(glm::vec3(1.0f))));
  const fs::path path = input("plain.gltf");
  b.write(path, FileFormat::GltfEmbedded);
  const std::string missing = input("missing.gltf").string();
  const std::string none = input("none.json").string();
  const fs::path bad = writeText("bad.json", R"({"lights": [{"position": [1, 2]}]})");
  struct Case {
    std::vector<std::string> args;
    std::string message;
    bool compareWithRender;
  };
  const Case cases[] = {
      {{missing}, missing + ": cannot read glTF file: no such file", true},
      {{path.string(), "--lights", bad.string()},
       bad.string() + ": lights[0].position: expected an array of 3 finite numbers",
       true},
      {{path.string(), "-l", none, "--json"}, none + ": cannot read lights file", false},
      {{path.string(), "--scene", "5"}, path.string() + ": --scene 5: the file has 1 scene", false},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.message);
    std::vector<std::string> args = {"info"};
    args.insert(args.end(), c.args.begin(), c.args.end());
    const Run r = run(args);
    expectInputError(r, c.message);
    if (c.compareWithRender) {
      args[0] = "render";
      EXPECT_EQ(r.err, run(args).err);  // word for word
    }
  }
}

// KHR_materials_clearcoat: the factors, the textures (indices) and the normal texture's scale
// for a coated material, null for the others; the text row ends with the factors. And
// KHR_materials_specular's factors and textures.
TEST_F(InfoTest, ReportsEachMaterialsClearcoatAndSpecular) {
  GltfBuilder b;
  const int texture = b.addTexture(1, 1, {255, 128, 0, 255}, "coat");
  const int coated = b.addMaterial({.name = "paint"});
  b.addMaterial({.name = "bare"});
  using Value = tinygltf::Value;
  b.model().materials[coated].extensions["KHR_materials_clearcoat"] = Value(
      Value::Object{{"clearcoatFactor", Value(0.75)},
                    {"clearcoatRoughnessFactor", Value(0.125)},
                    {"clearcoatRoughnessTexture", Value(Value::Object{{"index", Value(texture)}})},
                    {"clearcoatNormalTexture",
                     Value(Value::Object{{"index", Value(texture)}, {"scale", Value(0.5)}})}});
  b.model().materials[coated].extensions["KHR_materials_specular"] = Value(
      Value::Object{{"specularColorTexture", Value(Value::Object{{"index", Value(texture)}})}});
  b.model().extensionsUsed = {"KHR_materials_clearcoat", "KHR_materials_specular"};
  b.addNode("box", {}, b.addMesh(builder::makeBox(glm::vec3(1.0f)), {.material = coated}));
  const fs::path path = input("coated.gltf");
  b.write(path, FileFormat::GltfEmbedded);
  const Json doc = info({path.string()});
  ASSERT_EQ(doc["materials"].size(), 2u);
  EXPECT_EQ(doc["materials"][0]["clearcoat"],
            Json::parse(R"({"factor": 0.75, "roughnessFactor": 0.125, "texture": null,
                            "roughnessTexture": 0, "normalTexture": 0, "normalScale": 0.5})"));
  EXPECT_TRUE(doc["materials"][1]["clearcoat"].is_null());
  EXPECT_EQ(doc["materials"][0]["specular"],
            Json::parse(R"({"factor": 1.0, "colorFactor": [1.0, 1.0, 1.0], "texture": null,
                            "colorTexture": 0})"));
  EXPECT_TRUE(doc["materials"][1]["specular"].is_null());
  const Run r = run({"info", path.string()});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(
      contains(r.out, "no textures  specular 1 color 1,1,1  clearcoat 0.75 roughness 0.125\n"))
      << r.out;
}

// KHR_materials_transmission: the factor and texture, and whether the surface is drawn
// see-through (not when BLEND: its alpha blends it, and the transmission tints shadows alone);
// null without a factor. KHR_materials_volume's thickness and attenuation, null without a
// thickness. The text rows end with the factor and the thickness.
TEST_F(InfoTest, ReportsEachMaterialsTransmission) {
  GltfBuilder b;
  const int texture = b.addTexture(1, 1, {255, 128, 0, 255}, "glass");
  const int glass = b.addMaterial({.name = "glass"});
  builder::MaterialDesc blendDesc{.name = "film"};
  blendDesc.alphaMode = "BLEND";
  const int film = b.addMaterial(blendDesc);
  b.addMaterial({.name = "bare"});
  using Value = tinygltf::Value;
  b.model().materials[glass].extensions["KHR_materials_transmission"] = Value(
      Value::Object{{"transmissionFactor", Value(0.75)},
                    {"transmissionTexture", Value(Value::Object{{"index", Value(texture)}})}});
  b.model().materials[film].extensions["KHR_materials_transmission"] =
      Value(Value::Object{{"transmissionFactor", Value(0.5)}});
  b.model().materials[glass].extensions["KHR_materials_volume"] = Value(
      Value::Object{{"thicknessFactor", Value(0.25)},
                    {"attenuationColor", Value(Value::Array{Value(0.5), Value(1.0), Value(1.0)})}});
  b.model().materials[film].extensions["KHR_materials_volume"] =
      Value(Value::Object{{"thicknessFactor", Value(2.0)}, {"attenuationDistance", Value(4.0)}});
  b.model().extensionsUsed = {"KHR_materials_transmission", "KHR_materials_volume"};
  b.addNode("box", {}, b.addMesh(builder::makeBox(glm::vec3(1.0f)), {.material = glass}));
  const fs::path path = input("glass.gltf");
  b.write(path, FileFormat::GltfEmbedded);
  const Json doc = info({path.string()});
  ASSERT_EQ(doc["materials"].size(), 3u);
  EXPECT_EQ(doc["materials"][0]["transmission"],
            Json::parse(R"({"factor": 0.75, "texture": 0, "seeThrough": true})"));
  EXPECT_EQ(doc["materials"][1]["transmission"],
            Json::parse(R"({"factor": 0.5, "texture": null, "seeThrough": false})"));
  EXPECT_TRUE(doc["materials"][2]["transmission"].is_null());
  // KHR_materials_volume beside it: drawn on the see-through one, not on the blended one.
  EXPECT_EQ(doc["materials"][0]["volume"],
            Json::parse(R"({"thicknessFactor": 0.25, "thicknessTexture": null,
                            "attenuationDistance": null, "attenuationColor": [0.5, 1.0, 1.0],
                            "dispersion": 0.0, "drawn": true})"));
  EXPECT_EQ(doc["materials"][1]["volume"]["attenuationDistance"], 4.0);
  EXPECT_EQ(doc["materials"][1]["volume"]["drawn"], false);
  EXPECT_TRUE(doc["materials"][2]["volume"].is_null());
  const Run r = run({"info", path.string()});
  ASSERT_EQ(r.status, 0) << r.err;
  // The columns are aligned: the glass's transmission is padded to the film's width.
  EXPECT_TRUE(
      contains(r.out, "no textures  transmission 0.75                volume thickness 0.25\n"))
      << r.out;
  EXPECT_TRUE(contains(r.out, "transmission 0.5 (shadows only)  volume thickness 2 (not drawn)\n"))
      << r.out;
}

// KHR_materials_anisotropy: strength, rotation and texture for a material drawn with it, null
// for one without (a strength of 0 is none); the text row ends with the factors.
TEST_F(InfoTest, ReportsEachMaterialsAnisotropy) {
  GltfBuilder b;
  const int texture = b.addTexture(1, 1, {255, 128, 255, 255}, "brushed");
  const int brushed = b.addMaterial({.name = "brushed"});
  const int flat = b.addMaterial({.name = "flat"});
  using Value = tinygltf::Value;
  b.model().materials[brushed].extensions["KHR_materials_anisotropy"] =
      Value(Value::Object{{"anisotropyStrength", Value(0.5)},
                          {"anisotropyRotation", Value(0.25)},
                          {"anisotropyTexture", Value(Value::Object{{"index", Value(texture)}})}});
  b.model().materials[flat].extensions["KHR_materials_anisotropy"] =
      Value(Value::Object{{"anisotropyRotation", Value(1.0)}});
  b.model().extensionsUsed = {"KHR_materials_anisotropy"};
  b.addNode("box", {}, b.addMesh(builder::makeBox(glm::vec3(1.0f)), {.material = brushed}));
  const fs::path path = input("brushed.gltf");
  b.write(path, FileFormat::GltfEmbedded);
  const Json doc = info({path.string()});
  ASSERT_EQ(doc["materials"].size(), 2u);
  EXPECT_EQ(doc["materials"][0]["anisotropy"],
            Json::parse(R"({"strength": 0.5, "rotation": 0.25, "texture": 0})"));
  EXPECT_TRUE(doc["materials"][1]["anisotropy"].is_null());
  const Run r = run({"info", path.string()});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "no textures  anisotropy 0.5 rotation 0.25\n")) << r.out;
}

// KHR_materials_iridescence: factor, texture, the film's index and thickness range for a
// material drawn with the film, null for one without; the text row ends with them.
TEST_F(InfoTest, ReportsEachMaterialsIridescence) {
  GltfBuilder b;
  const int texture = b.addTexture(1, 1, {255, 128, 255, 255}, "film");
  const int soap = b.addMaterial({.name = "soap"});
  b.addMaterial({.name = "plain"});
  using Value = tinygltf::Value;
  b.model().materials[soap].extensions["KHR_materials_iridescence"] = Value(Value::Object{
      {"iridescenceFactor", Value(0.75)},
      {"iridescenceIor", Value(1.5)},
      {"iridescenceThicknessMinimum", Value(200.0)},
      {"iridescenceThicknessTexture", Value(Value::Object{{"index", Value(texture)}})}});
  b.model().extensionsUsed = {"KHR_materials_iridescence"};
  b.addNode("box", {}, b.addMesh(builder::makeBox(glm::vec3(1.0f)), {.material = soap}));
  const fs::path path = input("soap.gltf");
  b.write(path, FileFormat::GltfEmbedded);
  const Json doc = info({path.string()});
  ASSERT_EQ(doc["materials"].size(), 2u);
  EXPECT_EQ(doc["materials"][0]["iridescence"],
            Json::parse(R"({"factor": 0.75, "texture": null, "ior": 1.5, "thicknessMinimum": 200.0,
                            "thicknessMaximum": 400.0, "thicknessTexture": 0})"));
  EXPECT_TRUE(doc["materials"][1]["iridescence"].is_null());
  const Run r = run({"info", path.string()});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "no textures  iridescence 0.75 ior 1.5 thickness 200-400\n"))
      << r.out;
}

// KHR_materials_diffuse_transmission: factor, color and textures for a material drawn with it,
// null for one without; the text row ends with the factor.
TEST_F(InfoTest, ReportsEachMaterialsDiffuseTransmission) {
  GltfBuilder b;
  const int texture = b.addTexture(1, 1, {255, 128, 255, 255}, "leaf");
  const int leaf = b.addMaterial({.name = "leaf"});
  b.addMaterial({.name = "plain"});
  using Value = tinygltf::Value;
  b.model().materials[leaf].extensions["KHR_materials_diffuse_transmission"] = Value(Value::Object{
      {"diffuseTransmissionFactor", Value(0.25)},
      {"diffuseTransmissionColorFactor", Value(Value::Array{Value(1.0), Value(0.5), Value(0.0)})},
      {"diffuseTransmissionColorTexture", Value(Value::Object{{"index", Value(texture)}})}});
  b.model().extensionsUsed = {"KHR_materials_diffuse_transmission"};
  b.addNode("box", {}, b.addMesh(builder::makeBox(glm::vec3(1.0f)), {.material = leaf}));
  const fs::path path = input("leaf.gltf");
  b.write(path, FileFormat::GltfEmbedded);
  const Json doc = info({path.string()});
  ASSERT_EQ(doc["materials"].size(), 2u);
  EXPECT_EQ(doc["materials"][0]["diffuseTransmission"],
            Json::parse(R"({"factor": 0.25, "texture": null, "colorFactor": [1.0, 0.5, 0.0],
                            "colorTexture": 0})"));
  EXPECT_TRUE(doc["materials"][1]["diffuseTransmission"].is_null());
  const Run r = run({"info", path.string()});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "no textures  diffuse transmission 0.25\n")) << r.out;
}

TEST_F(InfoTest, UsageErrorsNameTheInfoHelp) {
  const Run r = run({"info"});
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(contains(r.err, "omnishadow: scene is required\n"));
  EXPECT_TRUE(contains(r.err, "'omnishadow info --help'"));
}

TEST_F(InfoTest, SundialSample) {
  const fs::path path =
      fs::path(OMNISHADOW_SOURCE_DIR) / "scenes" / "thirdparty" / "Sundial" / "Sundial.glb";
  const Json doc = info({path.string()}, {kBrokenEgl});
  EXPECT_EQ(doc["format"], "glb");
  EXPECT_EQ(doc["counts"]["cameras"], 1);
  EXPECT_EQ(doc["counts"]["lights"], 1);
  // 15,546 in the file, less the 6,192 of the 13 nodes KHR_node_visibility hides.
  EXPECT_EQ(doc["counts"]["drawnTriangles"], 9354);
  EXPECT_EQ(doc["counts"]["nodes"]["hidden"], 13);
  for (const Json& e : doc["extensions"])
    if (e["name"] == "KHR_node_visibility") {
      EXPECT_TRUE(e["supported"].get<bool>());
    }
  ASSERT_EQ(doc["lights"].size(), 1u);
  EXPECT_EQ(doc["lights"][0]["type"], "directional");
  EXPECT_EQ(doc["lights"][0]["source"], "glTF");
  ASSERT_EQ(doc["cameras"].size(), 1u);
  EXPECT_EQ(doc["cameras"][0]["type"], "perspective");
}

// Real data with KHR_materials_sheen: the mole's body and teeth, factors only.
TEST_F(InfoTest, WhackAMoleSampleReportsItsSheen) {
  const fs::path path =
      fs::path(OMNISHADOW_SOURCE_DIR) / "scenes" / "thirdparty" / "WhackAMole" / "WhackAMole.glb";
  const Json doc = info({path.string()}, {kBrokenEgl});
  for (const Json& e : doc["extensions"])
    if (e["name"] == "KHR_materials_sheen") {
      EXPECT_TRUE(e["supported"].get<bool>());
    }
  for (const Json& w : doc["warnings"]) EXPECT_FALSE(contains(w.get<std::string>(), "sheen"));
  ASSERT_EQ(doc["materials"].size(), 9u);
  for (const Json& m : doc["materials"]) {
    const Json& sheen = m["sheen"];
    if (m["name"] != "Body" && m["name"] != "Teeth") {
      EXPECT_TRUE(sheen.is_null()) << m["name"];
      continue;
    }
    ASSERT_TRUE(sheen.is_object()) << m["name"];
    EXPECT_EQ(sheen["colorFactor"], Json::array({1.0, 1.0, 1.0}));
    EXPECT_NEAR(sheen["roughnessFactor"].get<double>(), m["name"] == "Body" ? 0.4 : 0.7, 1e-6);
    EXPECT_TRUE(sheen["colorTexture"].is_null());
    EXPECT_TRUE(sheen["roughnessTexture"].is_null());
  }
  for (const Json& m : doc["materials"]) {
    EXPECT_EQ(m["ior"], 1.5);
    EXPECT_TRUE(m["specular"].is_null());
  }
  const Run r = run({"info", path.string()});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "no textures  sheen 1,1,1 roughness 0.4\n"));
  EXPECT_TRUE(contains(r.out, "no textures  sheen 1,1,1 roughness 0.7\n"));
}

}  // namespace
}  // namespace omnishadow::info_test
