// Hostile and broken inputs through the real binary: files outside the scene's folder,
// non-finite data, empty scenes, memory limits. Each refused input: exit status 2, one line,
// no output file.
#include <gtest/gtest.h>
#include <stdlib.h>
#include <sys/wait.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "scenes/builder/gltf_builder.h"

namespace {

namespace fs = std::filesystem;
using omnishadow::builder::FileFormat;
using omnishadow::builder::GltfBuilder;

struct Result {
  int status = -1;
  std::string out, err;
};

std::string quoted(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

std::string readText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

class RobustnessTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string pattern = (fs::temp_directory_path() / "omnishadow-robust-XXXXXX").string();
    ASSERT_NE(::mkdtemp(pattern.data()), nullptr);
    root_ = pattern;
    fs::create_directories(root_ / "scene");
    fs::create_directories(root_ / "out");
  }
  void TearDown() override { fs::remove_all(root_); }

  Result run(std::vector<std::string> args) {
    std::string command =
        "cd " + quoted((root_ / "out").string()) + " && " + quoted(OMNISHADOW_BINARY);
    for (const std::string& arg : args) command += " " + quoted(arg);
    command +=
        " >" + quoted((root_ / "stdout").string()) + " 2>" + quoted((root_ / "stderr").string());
    const int wait = std::system(command.c_str());
    Result r;
    r.status = WIFEXITED(wait) ? WEXITSTATUS(wait) : 128;
    r.out = readText(root_ / "stdout");
    r.err = readText(root_ / "stderr");
    return r;
  }

  // A floor with a box, written as .gltf with an external .bin and PNG texture.
  fs::path writeScene(const std::string& name = "scene.gltf") {
    GltfBuilder b;
    std::vector<std::uint8_t> pixels(4 * 4 * 4, 200);
    omnishadow::builder::MaterialDesc m;
    m.baseColorTexture = b.addTexture(4, 4, pixels, "tex");
    const int material = b.addMaterial(m);
    b.addNode("floor", {}, b.addMesh(omnishadow::builder::makePlane(4.0f), {.material = material}));
    b.addNode("box", {.translation = {0, 0.5f, 0}},
              b.addMesh(omnishadow::builder::makeBox(glm::vec3(0.5f)), {.material = material}));
    const fs::path path = root_ / "scene" / name;
    b.write(path, FileFormat::GltfExternal);
    return path;
  }

  nlohmann::json readJson(const fs::path& path) { return nlohmann::json::parse(readText(path)); }
  void writeJson(const fs::path& path, const nlohmann::json& json) {
    std::ofstream(path) << json.dump(2);
  }

  bool outputEmpty() const { return fs::is_empty(root_ / "out"); }

  Result render(const fs::path& scene, std::vector<std::string> extra = {}) {
    std::vector<std::string> args = {"render",  scene.string(), "-o",       "a.png",
                                     "--width", "32",           "--height", "24"};
    args.insert(args.end(), extra.begin(), extra.end());
    return run(args);
  }

  fs::path root_;
};

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST_F(RobustnessTest, UrisOutsideTheSceneFolderAreRefusedUnlessAllowed) {
  const fs::path scene = writeScene();
  nlohmann::json json = readJson(scene);
  const std::string bin = json["buffers"][0]["uri"];
  // Move the buffer one folder up and point the scene at it with "../".
  fs::rename(root_ / "scene" / bin, root_ / bin);
  json["buffers"][0]["uri"] = "../" + bin;
  writeJson(scene, json);

  Result r = render(scene);
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_TRUE(contains(r.err, "is outside the scene's folder; pass --allow-external-uris"))
      << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_TRUE(outputEmpty());

  r = render(scene, {"--allow-external-uris"});
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(fs::exists(root_ / "out" / "a.png"));
}

TEST_F(RobustnessTest, AbsolutePathsAndOtherSchemesAreRefused) {
  const fs::path scene = writeScene();
  nlohmann::json json = readJson(scene);
  const std::string image = json["images"][0]["uri"];
  const fs::path elsewhere = root_ / "elsewhere.png";
  fs::copy_file(root_ / "scene" / image, elsewhere);
  for (const std::string& uri : {elsewhere.string(), std::string("http://example.invalid/t.png"),
                                 std::string("file:///etc/passwd")}) {
    SCOPED_TRACE(uri);
    json["images"][0]["uri"] = uri;
    writeJson(scene, json);
    const Result r = render(scene);
    EXPECT_EQ(r.status, 2) << r.err;
    // tinygltf never finds such files beside the scene (it joins them to the scene's folder);
    // the image is then an error naming the URI.
    EXPECT_TRUE(contains(r.err, uri)) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_TRUE(outputEmpty());
  }
}

TEST_F(RobustnessTest, NonFinitePositionsAndTransformsAreSkippedWithAWarning) {
  const fs::path scene = writeScene();
  nlohmann::json json = readJson(scene);
  // The box node gets a NaN-free but infinite scale: that subtree is skipped, the floor drawn.
  json["nodes"][1]["scale"] = {1e39, 1, 1};  // beyond float range: +inf once converted
  writeJson(scene, json);
  Result r = render(scene);
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(contains(r.err, "nodes[1]: non-finite transform")) << r.err;

  // A POSITION accessor whose data holds infinities: that primitive is skipped.
  const fs::path scene2 = writeScene("scene2.gltf");
  nlohmann::json json2 = readJson(scene2);
  const std::string bin = json2["buffers"][0]["uri"];
  const int accessor = json2["meshes"][1]["primitives"][0]["attributes"]["POSITION"];
  const int view = json2["accessors"][accessor]["bufferView"];
  const std::size_t offset = json2["bufferViews"][view].value("byteOffset", 0);
  {
    std::fstream data(root_ / "scene" / bin, std::ios::in | std::ios::out | std::ios::binary);
    const float inf = std::numeric_limits<float>::infinity();
    data.seekp(static_cast<std::streamoff>(offset));
    data.write(reinterpret_cast<const char*>(&inf), sizeof inf);
  }
  r = render(scene2);
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(contains(r.err, "meshes[1].primitives[0]: POSITION has non-finite values")) << r.err;
}

TEST_F(RobustnessTest, AnEmptySceneIsAnInputError) {
  const fs::path scene = writeScene();
  nlohmann::json json = readJson(scene);
  json["scenes"][0]["nodes"] = nlohmann::json::array();
  writeJson(scene, json);
  const Result r = render(scene);
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_TRUE(contains(r.err, "the scene draws no triangles")) << r.err;
  EXPECT_TRUE(outputEmpty());
}

TEST_F(RobustnessTest, ShadowMapsBeyondMaxMemoryFailBeforeRendering) {
  const fs::path scene = writeScene();
  std::ofstream(root_ / "scene" / "big.json")
      << R"({"lights": [{"name": "a", "position": [0, 2, 0], "shadow": {"resolution": 8192}},
                        {"name": "b", "position": [1, 2, 0], "shadow": {"resolution": 8192}}]})";
  // 2 x 6 x 8192^2 x 4 bytes = 3072 MiB.
  const Result r =
      render(scene, {"-l", (root_ / "scene" / "big.json").string(), "--max-memory", "1024"});
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_TRUE(contains(r.err, "the shadow maps need 3072 MiB, more than the 1024 MiB allowed"))
      << r.err;
  EXPECT_TRUE(outputEmpty());
}

}  // namespace

namespace {

// The first bytes of a PNG claiming width x height: signature, IHDR length, "IHDR", size.
std::string pngHeader(std::uint32_t width, std::uint32_t height) {
  std::string bytes = "\x89PNG\r\n\x1a\n";
  bytes += std::string("\x00\x00\x00\x0d", 4) + "IHDR";
  for (std::uint32_t v : {width, height})
    for (int shift = 24; shift >= 0; shift -= 8) bytes += static_cast<char>((v >> shift) & 0xff);
  bytes += std::string("\x08\x06\x00\x00\x00", 5) + std::string(64, '\0');
  return bytes;
}

TEST_F(RobustnessTest, HugeImagesAreRefusedBeforeDecoding) {
  // A few bytes on disk, 16 GiB once decoded: refused from the header alone.
  const fs::path scene = writeScene();
  const nlohmann::json json = readJson(scene);
  const std::string image = json["images"][0]["uri"];
  std::ofstream(root_ / "scene" / image, std::ios::binary) << pngHeader(65536, 65536);
  const Result r = render(scene);
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_TRUE(contains(r.err, "images[0]")) << r.err;
  EXPECT_TRUE(outputEmpty());
}

}  // namespace
