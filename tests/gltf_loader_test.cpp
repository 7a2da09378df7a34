#include "renderer/scene/gltf_loader.h"

#include <gtest/gtest.h>
#include <tiny_gltf.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <iterator>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "renderer/core/errors.h"
#include "renderer/scene/camera_checks.h"
#include "renderer/scene/drawable_check.h"
#include "scenes/builder/gltf_builder.h"
#include "tests/support/input_error.h"

namespace omnishadow::gltf_loader_test {
namespace {

namespace fs = std::filesystem;
using builder::FileFormat;
using builder::GltfBuilder;
using builder::IndexType;
using builder::MaterialDesc;
using builder::MeshData;
using builder::PrimitiveMode;
using builder::PrimitiveOptions;
using builder::Transform;
using test_support::inputError;

constexpr float kEps = 1e-5f;
constexpr float kPi = std::numbers::pi_v<float>;

::testing::AssertionResult near(glm::vec3 actual, glm::vec3 expected, float eps = kEps) {
  if (glm::all(glm::lessThanEqual(glm::abs(actual - expected), glm::vec3(eps)))) {
    return ::testing::AssertionSuccess();
  }
  return ::testing::AssertionFailure()
         << "(" << actual.x << ", " << actual.y << ", " << actual.z << ") != (" << expected.x
         << ", " << expected.y << ", " << expected.z << ")";
}

::testing::AssertionResult contains(const std::string& text, const std::string& part) {
  if (text.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "\"" << text << "\" does not contain \"" << part << "\"";
}

bool anyWarningContains(const Scene& scene, const std::string& part) {
  return std::any_of(scene.warnings.begin(), scene.warnings.end(),
                     [&](const std::string& w) { return w.find(part) != std::string::npos; });
}

glm::vec3 faceNormal(glm::vec3 a, glm::vec3 b, glm::vec3 c) {
  return glm::normalize(glm::cross(b - a, c - a));
}

// World-space corners of every drawn triangle, in file order.
std::vector<glm::vec3> worldTriangles(const Scene& scene) {
  std::vector<glm::vec3> corners;
  for (const MeshInstance& instance : scene.instances) {
    const Mesh& mesh = scene.meshes[instance.mesh];
    for (std::uint32_t index : mesh.indices) {
      corners.push_back(glm::vec3(instance.world * glm::vec4(mesh.positions[index], 1.0f)));
    }
  }
  return corners;
}

std::size_t drawnTriangles(const Scene& scene) {
  std::size_t count = 0;
  for (const MeshInstance& instance : scene.instances) {
    count += scene.meshes[instance.mesh].indices.size() / 3;
  }
  return count;
}

std::vector<unsigned char> readBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

MeshData triangleMesh() {
  MeshData mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  mesh.indices = {0, 1, 2};
  return mesh;
}

// Each test gets a fresh folder for the files it writes.
class GltfLoaderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("omnishadow_gltf_test_" + std::to_string(::getpid()) + "_" +
                                        info->test_suite_name() + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path path(const std::string& name) const { return dir_ / name; }

  Scene writeAndLoad(GltfBuilder& builder, const GltfLoadOptions& options = {},
                     FileFormat format = FileFormat::Glb) {
    const fs::path file = path(format == FileFormat::Glb ? "scene.glb" : "scene.gltf");
    builder.write(file, format);
    return loadGltf(file, options);
  }

  // What loading `file` says once `builder` is written to it.
  static std::string writeAndLoadError(GltfBuilder& builder, const fs::path& file,
                                       FileFormat format) {
    builder.write(file, format);
    return test_support::inputError([&] { loadGltf(file); });
  }

  fs::path dir_;
};

// Raw buffer access for files the builder cannot express directly.
int addRawView(tinygltf::Model& model, const std::vector<unsigned char>& bytes,
               std::size_t stride = 0) {
  return builder::appendBufferView(model, bytes, 0, stride);
}

int addRawAccessor(tinygltf::Model& model, int view, std::size_t offset, int componentType,
                   int type, std::size_t count, bool normalized = false) {
  tinygltf::Accessor accessor;
  accessor.bufferView = view;
  accessor.byteOffset = offset;
  accessor.componentType = componentType;
  accessor.type = type;
  accessor.count = count;
  accessor.normalized = normalized;
  model.accessors.push_back(accessor);
  return static_cast<int>(model.accessors.size()) - 1;
}

// Makes `accessor` sparse: `count` unsigned short indices and their values, each in a new view.
void makeSparse(tinygltf::Model& model, int accessor, int count,
                const std::vector<unsigned char>& indices,
                const std::vector<unsigned char>& values) {
  auto& sparse = model.accessors[static_cast<std::size_t>(accessor)].sparse;
  sparse.isSparse = true;
  sparse.count = count;
  sparse.indices.bufferView = addRawView(model, indices);
  sparse.indices.byteOffset = 0;
  sparse.indices.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
  sparse.values.bufferView = addRawView(model, values);
  sparse.values.byteOffset = 0;
}

// A triangle, and image 0 (`name`, PNG by its MIME type, `bytes` in a bufferView of its own)
// used by texture 0 and by nothing else; returns the image's bufferView.
int addTriangleWithImageInView(GltfBuilder& builder, const std::string& name,
                               const std::vector<unsigned char>& bytes) {
  builder.addNode("node", {}, builder.addMesh(triangleMesh()));
  tinygltf::Model& model = builder.model();
  tinygltf::Image image;
  image.name = name;
  image.mimeType = "image/png";
  image.bufferView = addRawView(model, bytes);
  model.images.push_back(image);
  tinygltf::Texture texture;
  texture.source = 0;
  model.textures.push_back(texture);
  return image.bufferView;
}

template <typename T>
void append(std::vector<unsigned char>& bytes, const T& value) {
  const auto* p = reinterpret_cast<const unsigned char*>(&value);
  bytes.insert(bytes.end(), p, p + sizeof value);
}

// -----------------------------------------------------------------------------------------------
// The builder's procedural meshes

TEST(GltfBuilderMeshes, AreCounterClockwiseOutwardWithUnitNormalsAndUvs) {
  struct Case {
    const char* name;
    MeshData mesh;
    glm::vec3 inside;  // a point that every face looks away from
    std::size_t triangles;
  };
  const Case cases[] = {
      {"box", builder::makeBox({1.0f, 0.5f, 2.0f}), {0, 0, 0}, 12},
      {"sphere", builder::makeSphere(1.5f, 16, 8), {0, 0, 0}, 16 * 8 * 2 - 2 * 16},
      {"plane", builder::makePlane(2.0f, 2), {0, -1, 0}, 8},
      {"cylinder", builder::makeCylinder(0.5f, 2.0f, 12), {0, 1, 0}, 4 * 12},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const MeshData& m = c.mesh;
    ASSERT_EQ(m.indices.size(), 3 * c.triangles);
    ASSERT_EQ(m.normals.size(), m.positions.size());
    ASSERT_EQ(m.uvs.size(), m.positions.size());
    for (const glm::vec3& n : m.normals) EXPECT_NEAR(glm::length(n), 1.0f, kEps);
    for (const glm::vec2& uv : m.uvs) {
      EXPECT_TRUE(uv.x >= 0.0f && uv.x <= 1.0f && uv.y >= 0.0f && uv.y <= 1.0f);
    }
    for (std::size_t t = 0; t < m.indices.size(); t += 3) {
      const glm::vec3 a = m.positions[m.indices[t]], b = m.positions[m.indices[t + 1]],
                      d = m.positions[m.indices[t + 2]];
      const glm::vec3 face = faceNormal(a, b, d);
      EXPECT_GT(glm::dot(face, (a + b + d) / 3.0f - c.inside), 0.0f) << "triangle " << t / 3;
      for (int k = 0; k < 3; ++k) EXPECT_GT(glm::dot(face, m.normals[m.indices[t + k]]), 0.0f);
    }
  }
}

TEST(GltfBuilderMeshes, RejectIndicesThatDoNotFitTheIndexType) {
  GltfBuilder builder;
  MeshData mesh = builder::makePlane(1.0f, 20);  // 441 vertices
  EXPECT_THROW(builder.addMesh(mesh, {IndexType::U8}), std::out_of_range);
  EXPECT_NO_THROW(builder.addMesh(mesh, {IndexType::U16}));
}

// -----------------------------------------------------------------------------------------------
// File formats

// A textured box, the same for every format.
void buildTexturedBox(GltfBuilder& builder, const std::vector<std::uint8_t>& pixels) {
  MaterialDesc material;
  material.name = "boxMaterial";
  material.baseColorTexture = builder.addTexture(2, 2, pixels, "checker");
  PrimitiveOptions options;
  options.material = builder.addMaterial(material);
  builder.addNode("box", {}, builder.addMesh(builder::makeBox({0.5f, 1.0f, 1.5f}), options, "box"));
}

TEST_F(GltfLoaderTest, EmbeddedExternalAndGlbLoadTheSameSceneAndWriteTheRightFiles) {
  const std::vector<std::uint8_t> pixels = {255, 0, 0,   255, 0,   255, 0,   255,
                                            0,   0, 255, 255, 255, 255, 255, 128};
  std::vector<Scene> scenes;
  const std::pair<const char*, FileFormat> formats[] = {
      {"embedded.gltf", FileFormat::GltfEmbedded},
      {"external.gltf", FileFormat::GltfExternal},
      {"binary.glb", FileFormat::Glb},
  };
  for (const auto& [name, format] : formats) {
    GltfBuilder builder;
    buildTexturedBox(builder, pixels);
    builder.write(path(name), format);
    scenes.push_back(loadGltf(path(name)));
  }

  // External: .bin and PNG next to the .gltf; the others are self-contained.
  std::vector<std::string> files;
  for (const auto& entry : fs::directory_iterator(dir_)) {
    files.push_back(entry.path().filename().string());
  }
  std::sort(files.begin(), files.end());
  EXPECT_EQ(files, (std::vector<std::string>{"binary.glb", "embedded.gltf", "external.bin",
                                             "external.gltf", "external_image0.png"}));
  const std::vector<unsigned char> png = readBytes(path("external_image0.png"));
  ASSERT_GE(png.size(), 8u);
  EXPECT_EQ(std::memcmp(png.data(), "\x89PNG\r\n\x1a\n", 8), 0);
  const std::vector<unsigned char> glb = readBytes(path("binary.glb"));
  EXPECT_EQ(std::memcmp(glb.data(), "glTF", 4), 0);
  const std::vector<unsigned char> embedded = readBytes(path("embedded.gltf"));
  const std::string embeddedText(embedded.begin(), embedded.end());
  EXPECT_TRUE(contains(embeddedText, "data:image/png;base64,"));
  EXPECT_TRUE(contains(embeddedText, "data:application/octet-stream;base64,"));

  for (const Scene& scene : scenes) {
    SCOPED_TRACE(scene.path);
    EXPECT_TRUE(scene.warnings.empty()) << scene.warnings.front();
    ASSERT_EQ(scene.meshes.size(), 1u);
    const Mesh& mesh = scene.meshes[0];
    EXPECT_EQ(mesh.name, "box/0");
    EXPECT_EQ(mesh.positions, scenes[0].meshes[0].positions);
    EXPECT_EQ(mesh.normals, scenes[0].meshes[0].normals);
    EXPECT_EQ(mesh.uv0, scenes[0].meshes[0].uv0);
    EXPECT_EQ(mesh.indices, scenes[0].meshes[0].indices);
    EXPECT_EQ(mesh.indices.size(), 36u);
    EXPECT_TRUE(near(mesh.bounds.max, {0.5f, 1.0f, 1.5f}));
    ASSERT_EQ(scene.images.size(), 1u);
    EXPECT_EQ(scene.images[0].name, "checker");
    EXPECT_EQ(scene.images[0].width, 2);
    EXPECT_EQ(scene.images[0].height, 2);
    EXPECT_EQ(scene.images[0].rgba, pixels);
    ASSERT_EQ(scene.materials.size(), 1u);
    EXPECT_EQ(scene.materials[0].baseColorTexture.texture, 0);
  }
}

TEST_F(GltfLoaderTest, WritingIsDeterministic) {
  const std::vector<std::uint8_t> pixels(4 * 4, 200);
  for (FileFormat format : {FileFormat::GltfEmbedded, FileFormat::GltfExternal, FileFormat::Glb}) {
    for (const char* folder : {"a", "b"}) {
      fs::create_directories(path(folder));
      GltfBuilder builder;
      buildTexturedBox(builder, pixels);
      builder.addLight("lamp", "spot", {1, 2, 3}, {0, -1, 0}, {1, 1, 1}, 10.0f);
      builder.addPerspectiveCamera("cam", {0, 1, 5}, {0, 0, 0}, 0.8f);
      builder.write(path(folder) / "scene.gltf", format);
    }
    for (const auto& entry : fs::directory_iterator(path("a"))) {
      SCOPED_TRACE(entry.path().filename().string());
      EXPECT_EQ(readBytes(entry.path()), readBytes(path("b") / entry.path().filename()));
    }
    fs::remove_all(path("a"));
    fs::remove_all(path("b"));
  }
}

// -----------------------------------------------------------------------------------------------
// Geometry

TEST_F(GltfLoaderTest, NodeHierarchyComposesTrsAndMatrices) {
  GltfBuilder builder;
  MeshData mesh;
  mesh.positions = {{1, 0, 0}, {1, 1, 0}, {1, 0, 1}};
  mesh.indices = {0, 1, 2};
  const int meshIndex = builder.addMesh(mesh);
  Transform parentTransform;
  parentTransform.translation = {1, 2, 3};
  parentTransform.rotation = glm::angleAxis(kPi / 2.0f, glm::vec3(0, 1, 0));
  parentTransform.scale = glm::vec3(2.0f);
  const int parent = builder.addNode("parent", parentTransform);
  const int child = builder.addNodeWithMatrix(
      "child", glm::translate(glm::mat4(1.0f), glm::vec3(0, 0, 1)), meshIndex, parent);

  const Scene scene = writeAndLoad(builder);
  ASSERT_EQ(scene.instances.size(), 1u);
  EXPECT_EQ(scene.instances[0].node, child);
  // (1,0,0) -> child (1,0,1) -> scale (2,0,2) -> 90 degrees about +Y (2,0,-2) -> (3,2,1).
  const glm::vec4 world = scene.instances[0].world * glm::vec4(1, 0, 0, 1);
  EXPECT_TRUE(near(glm::vec3(world), {3, 2, 1}));
  EXPECT_TRUE(near(scene.bounds.min, {3, 2, 1}));
  EXPECT_TRUE(near(scene.bounds.max, {5, 4, 1}));
}

TEST_F(GltfLoaderTest, IndexTypesAndNonIndexedGiveTheSameTriangles) {
  GltfBuilder builder;
  const MeshData indexed = builder::makeBox(glm::vec3(1.0f));
  MeshData unindexed;
  for (std::uint32_t i : indexed.indices) {
    unindexed.positions.push_back(indexed.positions[i]);
    unindexed.normals.push_back(indexed.normals[i]);
  }
  for (IndexType type : {IndexType::U8, IndexType::U16, IndexType::U32}) {
    builder.addNode("indexed", {}, builder.addMesh(indexed, {type}));
  }
  builder.addNode("unindexed", {}, builder.addMesh(unindexed));

  const Scene scene = writeAndLoad(builder);
  ASSERT_EQ(scene.meshes.size(), 4u);
  const std::vector<glm::vec3> all = worldTriangles(scene);
  ASSERT_EQ(all.size(), 4u * 36u);
  for (int m = 1; m < 4; ++m) {
    SCOPED_TRACE(m);
    EXPECT_TRUE(std::equal(all.begin(), all.begin() + 36, all.begin() + 36 * m));
  }
  EXPECT_EQ(scene.meshes[0].indices, scene.meshes[2].indices);
  EXPECT_EQ(scene.meshes[1].indices, scene.meshes[2].indices);
}

TEST_F(GltfLoaderTest, StripsAndFansBecomeCounterClockwiseLists) {
  GltfBuilder builder;
  // A strip of three quads in the XZ plane, facing +Y.
  MeshData strip;
  for (int i = 0; i < 4; ++i) {
    strip.positions.push_back({static_cast<float>(i), 0, 0});
    strip.positions.push_back({static_cast<float>(i), 0, 1});
  }
  // A fan: center, then a ring counter-clockwise seen from +Y.
  MeshData fan;
  fan.positions.push_back({0, 0, 0});
  for (int i = 0; i < 6; ++i) {
    const float a = 2.0f * kPi * static_cast<float>(i) / 6.0f;
    fan.positions.push_back({std::sin(a), 0, std::cos(a)});
  }
  MeshData indexedFan = fan;
  for (std::uint32_t i = 0; i < 7; ++i) indexedFan.indices.push_back(i);
  builder.addNode("strip", {},
                  builder.addMesh(strip, {IndexType::U32, PrimitiveMode::TriangleStrip}));
  builder.addNode("fan", {}, builder.addMesh(fan, {IndexType::U32, PrimitiveMode::TriangleFan}));
  builder.addNode("indexedFan", {},
                  builder.addMesh(indexedFan, {IndexType::U16, PrimitiveMode::TriangleFan}));

  const Scene scene = writeAndLoad(builder);
  ASSERT_EQ(scene.meshes.size(), 3u);
  EXPECT_EQ(scene.meshes[0].indices.size(), 3u * 6u);
  EXPECT_EQ(scene.meshes[1].indices.size(), 3u * 5u);
  EXPECT_EQ(scene.meshes[2].indices.size(), 3u * 5u);
  const std::vector<glm::vec3> corners = worldTriangles(scene);
  for (std::size_t t = 0; t < corners.size(); t += 3) {
    EXPECT_TRUE(near(faceNormal(corners[t], corners[t + 1], corners[t + 2]), {0, 1, 0}))
        << "triangle " << t / 3;
  }
  // No normals in the file: the generated ones agree with the winding.
  for (const Mesh& mesh : scene.meshes) {
    for (const glm::vec3& n : mesh.normals) EXPECT_TRUE(near(n, {0, 1, 0}));
  }
}

TEST_F(GltfLoaderTest, MissingNormalsAreGeneratedFlatAndOutward) {
  GltfBuilder builder;
  MeshData box = builder::makeBox({1.0f, 2.0f, 3.0f});
  box.normals.clear();
  builder.addNode("box", {}, builder.addMesh(box));

  const Scene scene = writeAndLoad(builder);
  ASSERT_EQ(scene.meshes.size(), 1u);
  const Mesh& mesh = scene.meshes[0];
  // Un-indexed: every triangle has its own three corners.
  ASSERT_EQ(mesh.positions.size(), 36u);
  ASSERT_EQ(mesh.normals.size(), 36u);
  ASSERT_EQ(mesh.uv0.size(), 36u);
  for (std::size_t t = 0; t < 36; t += 3) {
    const glm::vec3 a = mesh.positions[mesh.indices[t]], b = mesh.positions[mesh.indices[t + 1]],
                    c = mesh.positions[mesh.indices[t + 2]];
    for (std::size_t k = 0; k < 3; ++k) {
      const glm::vec3 n = mesh.normals[mesh.indices[t + k]];
      EXPECT_NEAR(glm::length(n), 1.0f, kEps);
      EXPECT_NEAR(glm::dot(n, b - a), 0.0f, kEps);
      EXPECT_NEAR(glm::dot(n, c - a), 0.0f, kEps);
      EXPECT_GT(glm::dot(n, (a + b + c) / 3.0f), 0.0f);  // outward from the center
    }
  }
}

TEST_F(GltfLoaderTest, TangentsAreGeneratedOnlyForNormalMappedMaterials) {
  GltfBuilder builder;
  MaterialDesc normalMapped;
  normalMapped.normalTexture = builder.addTexture(1, 1, {128, 128, 255, 255});
  const int mapped = builder.addMaterial(normalMapped);
  const int plain = builder.addMaterial({});
  const MeshData plane = builder::makePlane(2.0f, 1);
  MeshData mirrored = plane;
  for (glm::vec2& uv : mirrored.uvs) uv.x = 1.0f - uv.x;
  PrimitiveOptions options;
  options.material = mapped;
  builder.addNode("mapped", {}, builder.addMesh(plane, options));
  builder.addNode("mirrored", {}, builder.addMesh(mirrored, options));
  options.material = plain;
  builder.addNode("plain", {}, builder.addMesh(plane, options));

  const Scene scene = writeAndLoad(builder);
  ASSERT_EQ(scene.meshes.size(), 3u);
  // u runs along +X, v along +Z: the normal map's "up" (v decreasing) is -Z = cross(N, T).
  ASSERT_EQ(scene.meshes[0].tangents.size(), scene.meshes[0].positions.size());
  for (const glm::vec4& t : scene.meshes[0].tangents) {
    EXPECT_TRUE(near(glm::vec3(t), {1, 0, 0}));
    EXPECT_EQ(t.w, 1.0f);
  }
  // Mirrored UVs flip the tangent and the handedness, not the bitangent.
  ASSERT_EQ(scene.meshes[1].tangents.size(), scene.meshes[1].positions.size());
  for (const glm::vec4& t : scene.meshes[1].tangents) {
    EXPECT_TRUE(near(glm::vec3(t), {-1, 0, 0}));
    EXPECT_EQ(t.w, -1.0f);
  }
  EXPECT_TRUE(scene.meshes[2].tangents.empty());
}

TEST_F(GltfLoaderTest, SharedMeshBecomesOneMeshWithTwoInstancesAndBoundsCoverBoth) {
  GltfBuilder builder;
  const int box = builder.addMesh(builder::makeBox(glm::vec3(0.5f)), {}, "crate");
  Transform left, right;
  left.translation = {-2, 0, 0};
  right.translation = {3, 0, 0};
  right.scale = glm::vec3(2.0f);
  const int leftNode = builder.addNode("left", left, box);
  const int rightNode = builder.addNode("right", right, box);

  const Scene scene = writeAndLoad(builder);
  ASSERT_EQ(scene.meshes.size(), 1u);
  EXPECT_EQ(scene.meshes[0].name, "crate/0");
  ASSERT_EQ(scene.instances.size(), 2u);
  EXPECT_EQ(scene.instances[0].mesh, 0);
  EXPECT_EQ(scene.instances[1].mesh, 0);
  EXPECT_EQ(scene.instances[0].node, leftNode);
  EXPECT_EQ(scene.instances[1].node, rightNode);
  EXPECT_TRUE(near(scene.bounds.min, {-2.5f, -1, -1}));
  EXPECT_TRUE(near(scene.bounds.max, {4, 1, 1}));
}

TEST_F(GltfLoaderTest, ReadsStridedNormalizedAndSparseAccessors) {
  GltfBuilder builder;
  tinygltf::Model& model = builder.model();
  model.buffers.emplace_back();
  // Interleaved: float3 position + normalized u8x4 color per vertex, 16 bytes apart.
  const glm::vec3 positions[] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const std::uint8_t colors[][4] = {{255, 0, 0, 255}, {0, 51, 0, 255}, {0, 0, 255, 0}};
  std::vector<unsigned char> interleaved;
  for (int i = 0; i < 3; ++i) {
    append(interleaved, positions[i]);
    for (std::uint8_t c : colors[i]) interleaved.push_back(c);
  }
  const int view = addRawView(model, interleaved, 16);
  std::vector<unsigned char> uvBytes;
  const std::vector<std::uint16_t> uvs = {0, 65535, 65535, 0, 32768, 32768};
  for (std::uint16_t v : uvs) append(uvBytes, v);
  // Sparse positions on an all-zero base: only vertices 1 and 2 are stored.
  std::vector<unsigned char> sparseIndices, sparseValues;
  const std::vector<std::uint16_t> replaced = {1, 2};
  for (std::uint16_t i : replaced) append(sparseIndices, i);
  for (glm::vec3 p : {glm::vec3(0, 0, 2), glm::vec3(0, 3, 0)}) append(sparseValues, p);
  constexpr int kFloat = TINYGLTF_COMPONENT_TYPE_FLOAT;

  tinygltf::Primitive strided;
  strided.mode = TINYGLTF_MODE_TRIANGLES;
  strided.attributes["POSITION"] = addRawAccessor(model, view, 0, kFloat, TINYGLTF_TYPE_VEC3, 3);
  strided.attributes["COLOR_0"] = addRawAccessor(
      model, view, 12, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_TYPE_VEC4, 3, true);
  strided.attributes["TEXCOORD_0"] =
      addRawAccessor(model, addRawView(model, uvBytes), 0, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                     TINYGLTF_TYPE_VEC2, 3, true);
  tinygltf::Primitive sparse;
  sparse.mode = TINYGLTF_MODE_TRIANGLES;
  const int sparseAccessor = addRawAccessor(model, -1, 0, kFloat, TINYGLTF_TYPE_VEC3, 3);
  makeSparse(model, sparseAccessor, 2, sparseIndices, sparseValues);
  sparse.attributes["POSITION"] = sparseAccessor;
  tinygltf::Mesh mesh;
  mesh.primitives = {strided, sparse};
  model.meshes.push_back(mesh);
  builder.addNode("raw", {}, 0);

  const Scene scene = writeAndLoad(builder, {}, FileFormat::GltfEmbedded);
  ASSERT_EQ(scene.meshes.size(), 2u);
  const Mesh& a = scene.meshes[0];
  ASSERT_EQ(a.positions.size(), 3u);
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(near(a.positions[i], positions[i]));
  ASSERT_EQ(a.colors.size(), 3u);
  EXPECT_EQ(a.colors[0], glm::vec4(1, 0, 0, 1));
  EXPECT_NEAR(a.colors[1].g, 0.2f, kEps);
  EXPECT_EQ(a.colors[2], glm::vec4(0, 0, 1, 0));
  ASSERT_EQ(a.uv0.size(), 3u);
  EXPECT_EQ(a.uv0[0], glm::vec2(0, 1));
  EXPECT_EQ(a.uv0[1], glm::vec2(1, 0));
  EXPECT_NEAR(a.uv0[2].x, 32768.0f / 65535.0f, kEps);
  EXPECT_EQ(a.indices, (std::vector<std::uint32_t>{0, 1, 2}));
  const Mesh& b = scene.meshes[1];
  ASSERT_EQ(b.positions.size(), 3u);
  EXPECT_TRUE(near(b.positions[0], {0, 0, 0}));
  EXPECT_TRUE(near(b.positions[1], {0, 0, 2}));
  EXPECT_TRUE(near(b.positions[2], {0, 3, 0}));
}

// Float COLOR_0 must lie in 0..1 (glTF 3.7.2.1): values outside are clamped, NaN reads as 1.
TEST_F(GltfLoaderTest, FloatColorsOutsideZeroToOneAreClampedWithAWarning) {
  // Positions (0,0,0), (1,0,0), (0,1,0); colors (1.5,0,0), (0,-0.5,0), (NaN,0,0).
  const fs::path file = path("colors.gltf");
  std::ofstream(file) << R"({"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}],
    "nodes": [{"mesh": 0}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "COLOR_0": 1}}]}],
    "accessors": [
      {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
       "min": [0, 0, 0], "max": [1, 1, 0]},
      {"bufferView": 0, "byteOffset": 36, "componentType": 5126, "count": 3, "type": "VEC3"}],
    "bufferViews": [{"buffer": 0, "byteLength": 72}],
    "buffers": [{"byteLength": 72, "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAADAPwAAAAAAAAAAAAAAAAAAAL8AAAAAAADAfwAAAAAAAAAA"}]})";
  const Scene scene = loadGltf(file);
  ASSERT_EQ(scene.meshes.size(), 1u);
  EXPECT_EQ(scene.meshes[0].colors,
            (std::vector<glm::vec4>{{1, 0, 0, 1}, {0, 0, 0, 1}, {1, 0, 0, 1}}));
  EXPECT_EQ(
      std::count(scene.warnings.begin(), scene.warnings.end(),
                 file.string() + ": meshes[0].primitives[0].attributes.COLOR_0: accessors[1] has 3 "
                                 "values outside 0..1 (the first at element 0); clamped to 0..1"),
      1);
}

// Skins and morph targets are applied (tests/animation_test.cpp); what the loader must do is
// give each posed instance a mesh of its own, since two nodes pose a shared mesh differently.
TEST_F(GltfLoaderTest, MorphedInstancesOfASharedMeshGetAMeshEach) {
  GltfBuilder builder;
  const int mesh = builder.addMesh(triangleMesh());
  builder.addPrimitive(mesh, triangleMesh());
  const int a = builder.addNode("a", {}, mesh);
  const int b = builder.addNode("b", {}, mesh);
  tinygltf::Model& model = builder.model();
  for (tinygltf::Primitive& primitive : model.meshes[0].primitives) {
    primitive.targets = {{{"POSITION", primitive.attributes.at("POSITION")}}};
  }
  model.nodes[b].weights = {1.0};  // b doubles its positions, a keeps them
  tinygltf::Skin skin;
  skin.joints = {a};
  model.skins.push_back(skin);
  model.nodes[a].skin = 0;  // without JOINTS_0 a skin changes nothing

  const Scene scene = writeAndLoad(builder);
  ASSERT_EQ(scene.instances.size(), 4u);
  EXPECT_EQ(scene.meshes.size(), 4u);
  const Mesh& ofA = scene.meshes[static_cast<std::size_t>(scene.instances[0].mesh)];
  const Mesh& ofB = scene.meshes[static_cast<std::size_t>(scene.instances[2].mesh)];
  ASSERT_EQ(ofA.positions.size(), ofB.positions.size());
  for (std::size_t i = 0; i < ofA.positions.size(); ++i)
    EXPECT_EQ(ofB.positions[i], 2.0f * ofA.positions[i]);
  for (const std::string& warning : scene.warnings) {
    EXPECT_EQ(warning.find("skins"), std::string::npos) << warning;
    EXPECT_EQ(warning.find("morph targets"), std::string::npos) << warning;
  }
}

TEST_F(GltfLoaderTest, SparseMorphTargetsDisplaceOnlyTheirVertices) {
  GltfBuilder builder;
  const int mesh = builder.addMesh(triangleMesh());
  const int node = builder.addNode("morphed", {}, mesh);
  tinygltf::Model& model = builder.model();
  // A target without a bufferView: zeros, but vertex 2 moves by (0, 0, 1).
  std::vector<unsigned char> indices, values;
  append(indices, std::uint16_t{2});
  append(values, glm::vec3(0, 0, 1));
  const int target =
      addRawAccessor(model, -1, 0, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, 3);
  makeSparse(model, target, 1, indices, values);
  model.meshes[0].primitives[0].targets = {{{"POSITION", target}}};
  model.meshes[0].weights = {1.0};
  model.nodes[static_cast<std::size_t>(node)].weights = {0.5};  // the node's weights win

  const Scene scene = writeAndLoad(builder);
  ASSERT_EQ(scene.meshes.size(), 1u);
  const std::vector<glm::vec3>& p = scene.meshes[0].positions;
  ASSERT_EQ(p.size(), 3u);
  EXPECT_EQ(p[0], glm::vec3(0, 0, 0));
  EXPECT_EQ(p[1], glm::vec3(1, 0, 0));
  EXPECT_EQ(p[2], glm::vec3(0, 1, 0.5f));
  EXPECT_NEAR(scene.bounds.max.z, 0.5f, kEps);
}

// -----------------------------------------------------------------------------------------------
// Materials, cameras, lights

TEST_F(GltfLoaderTest, MaterialsKeepFactorsModesAndTextures) {
  GltfBuilder builder;
  const std::vector<std::uint8_t> base = {10, 20, 30, 40, 50, 60, 70, 80};  // 2x1
  MaterialDesc opaque;
  opaque.name = "opaque";
  opaque.baseColor = {0.8f, 0.2f, 0.1f, 1.0f};
  opaque.metallic = 0.25f;
  opaque.roughness = 0.75f;
  opaque.emissive = {0.5f, 0.25f, 0.0f};
  opaque.baseColorTexture = builder.addTexture(2, 1, base, "base");
  opaque.metallicRoughnessTexture = builder.addTexture(1, 1, {0, 128, 255, 255}, "mr");
  opaque.normalTexture = builder.addTexture(1, 1, {128, 128, 255, 255}, "normal");
  opaque.emissiveTexture = builder.addTexture(1, 1, {99, 99, 99, 255}, "emissive");
  MaterialDesc mask;
  mask.name = "mask";
  mask.alphaMode = "MASK";
  mask.alphaCutoff = 0.3f;
  mask.doubleSided = true;
  MaterialDesc blend;
  blend.name = "blend";
  blend.alphaMode = "BLEND";
  blend.emissive = {4.0f, 2.0f, 0.0f};  // beyond 1: KHR_materials_emissive_strength
  const int mesh = builder.addMesh(
      triangleMesh(), {IndexType::U32, PrimitiveMode::Triangles, builder.addMaterial(opaque)});
  builder.addPrimitive(mesh, triangleMesh(),
                       {IndexType::U32, PrimitiveMode::Triangles, builder.addMaterial(mask)});
  builder.addPrimitive(mesh, triangleMesh(),
                       {IndexType::U32, PrimitiveMode::Triangles, builder.addMaterial(blend)});
  builder.addNode("node", {}, mesh);
  tinygltf::Model& model = builder.model();
  model.materials[0].occlusionTexture.index = 1;
  model.materials[0].occlusionTexture.strength = 0.5;
  model.materials[0].normalTexture.scale = 0.8;
  tinygltf::Sampler nearestClamp;
  nearestClamp.magFilter = TINYGLTF_TEXTURE_FILTER_NEAREST;
  nearestClamp.wrapS = TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE;
  model.samplers.push_back(nearestClamp);
  model.textures[1].sampler = 0;
  // A one-channel image: gray becomes RGB, alpha opaque.
  model.images[3].component = 1;
  model.images[3].image = {99};

  const Scene scene = writeAndLoad(builder);
  ASSERT_EQ(scene.materials.size(), 3u);
  const Material& m0 = scene.materials[0];
  EXPECT_EQ(m0.name, "opaque");
  EXPECT_EQ(m0.baseColorFactor, glm::vec4(0.8f, 0.2f, 0.1f, 1.0f));
  EXPECT_EQ(m0.metallicFactor, 0.25f);
  EXPECT_EQ(m0.roughnessFactor, 0.75f);
  EXPECT_TRUE(near(m0.emissiveFactor, {0.5f, 0.25f, 0.0f}));
  EXPECT_EQ(m0.emissiveStrength, 1.0f);
  EXPECT_EQ(m0.baseColorTexture.texture, 0);
  EXPECT_EQ(m0.metallicRoughnessTexture.texture, 1);
  EXPECT_EQ(m0.normalTexture.texture, 2);
  EXPECT_NEAR(m0.normalScale, 0.8f, kEps);
  EXPECT_EQ(m0.occlusionTexture.texture, 1);
  EXPECT_NEAR(m0.occlusionStrength, 0.5f, kEps);
  EXPECT_EQ(m0.emissiveTexture.texture, 3);
  EXPECT_EQ(m0.baseColorTexture.texCoord, 0);
  EXPECT_EQ(m0.alphaMode, AlphaMode::Opaque);
  EXPECT_FALSE(m0.doubleSided);
  const Material& m1 = scene.materials[1];
  EXPECT_EQ(m1.alphaMode, AlphaMode::Mask);
  EXPECT_NEAR(m1.alphaCutoff, 0.3f, kEps);
  EXPECT_TRUE(m1.doubleSided);
  EXPECT_EQ(m1.baseColorTexture.texture, -1);
  const Material& m2 = scene.materials[2];
  EXPECT_EQ(m2.alphaMode, AlphaMode::Blend);
  EXPECT_TRUE(near(m2.emissiveFactor * m2.emissiveStrength, {4.0f, 2.0f, 0.0f}));
  EXPECT_EQ(m2.emissiveStrength, 4.0f);

  ASSERT_EQ(scene.meshes.size(), 3u);
  EXPECT_EQ(scene.meshes[0].material, 0);
  EXPECT_EQ(scene.meshes[2].material, 2);
  ASSERT_EQ(scene.textures.size(), 4u);
  const SamplerDesc defaults;
  EXPECT_EQ(scene.textures[0].image, 0);
  EXPECT_EQ(scene.textures[0].sampler.magFilter, defaults.magFilter);
  EXPECT_EQ(scene.textures[0].sampler.wrapS, defaults.wrapS);
  EXPECT_EQ(scene.textures[1].sampler.magFilter, TINYGLTF_TEXTURE_FILTER_NEAREST);
  EXPECT_EQ(scene.textures[1].sampler.minFilter, defaults.minFilter);  // unset in the sampler
  EXPECT_EQ(scene.textures[1].sampler.wrapS, TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE);
  EXPECT_EQ(scene.textures[1].sampler.wrapT, TINYGLTF_TEXTURE_WRAP_REPEAT);
  ASSERT_EQ(scene.images.size(), 4u);
  EXPECT_EQ(scene.images[0].width, 2);
  EXPECT_EQ(scene.images[0].height, 1);
  EXPECT_EQ(scene.images[0].rgba, base);
  EXPECT_EQ(scene.images[3].rgba, (std::vector<std::uint8_t>{99, 99, 99, 255}));
}

TEST_F(GltfLoaderTest, CamerasHaveNamesIndicesAndWorldPlacement) {
  GltfBuilder builder;
  builder.addPerspectiveCamera("front", {0, 1, 5}, {0, 1, 0}, 0.7f, 1.5f, 0.1f, 100.0f);
  builder.addPerspectiveCamera("top", {0, 10, 0}, {0, 0, 0}, 0.5f);
  tinygltf::Model& model = builder.model();
  // Camera 0 used a second time, below a moved parent; and a nameless orthographic camera.
  Transform moved;
  moved.translation = {10, 0, 0};
  const int parent = builder.addNode("rig", moved);
  tinygltf::Node second;
  second.name = "secondFront";
  second.camera = 0;
  model.nodes.push_back(second);
  model.nodes[parent].children.push_back(static_cast<int>(model.nodes.size()) - 1);
  tinygltf::Camera ortho;
  ortho.type = "orthographic";
  ortho.orthographic = {};
  ortho.orthographic.xmag = 2.0;
  ortho.orthographic.ymag = 1.0;
  ortho.orthographic.znear = 0.5;
  ortho.orthographic.zfar = 50.0;
  model.cameras.push_back(ortho);
  tinygltf::Node orthoNode;
  orthoNode.name = "orthoNode";
  orthoNode.camera = 2;
  model.nodes.push_back(orthoNode);
  model.scenes[0].nodes.insert(model.scenes[0].nodes.begin(),
                               static_cast<int>(model.nodes.size()) - 1);

  const Scene scene = writeAndLoad(builder);
  ASSERT_EQ(scene.cameras.size(), 4u);
  const Camera& front = scene.cameras[0];
  EXPECT_EQ(front.name, "front");
  EXPECT_EQ(front.nodeName, "front");
  EXPECT_EQ(front.index, 0);
  EXPECT_FALSE(front.orthographic);
  EXPECT_NEAR(front.yfov, 0.7f, kEps);
  EXPECT_NEAR(front.aspectRatio, 1.5f, kEps);
  EXPECT_NEAR(front.znear, 0.1f, kEps);
  EXPECT_NEAR(front.zfar, 100.0f, 1e-3f);
  EXPECT_TRUE(near(glm::vec3(front.world[3]), {0, 1, 5}));
  EXPECT_TRUE(near(-glm::vec3(front.world[2]), {0, 0, -1}));
  EXPECT_TRUE(near(glm::vec3(front.world[1]), {0, 1, 0}));

  const Camera& again = scene.cameras[1];
  EXPECT_EQ(again.name, "front");
  EXPECT_EQ(again.nodeName, "secondFront");
  EXPECT_EQ(again.index, 0);
  EXPECT_TRUE(near(glm::vec3(again.world[3]), {10, 0, 0}));

  const Camera& top = scene.cameras[2];
  EXPECT_EQ(top.name, "top");
  EXPECT_EQ(top.index, 1);
  EXPECT_EQ(top.zfar, 0.0f);
  EXPECT_TRUE(near(glm::vec3(top.world[3]), {0, 10, 0}));
  EXPECT_TRUE(near(-glm::vec3(top.world[2]), {0, -1, 0}));  // straight down, still orthonormal
  EXPECT_NEAR(glm::length(glm::vec3(top.world[1])), 1.0f, kEps);
  EXPECT_NEAR(glm::dot(glm::vec3(top.world[1]), glm::vec3(top.world[2])), 0.0f, kEps);

  const Camera& orthoCamera = scene.cameras[3];
  EXPECT_EQ(orthoCamera.name, "orthoNode");
  EXPECT_EQ(orthoCamera.index, 2);
  EXPECT_TRUE(orthoCamera.orthographic);
  EXPECT_EQ(orthoCamera.xmag, 2.0f);
  EXPECT_EQ(orthoCamera.ymag, 1.0f);
  EXPECT_EQ(orthoCamera.znear, 0.5f);
  EXPECT_EQ(orthoCamera.zfar, 50.0f);
}

// Adds a glTF orthographic camera and a root node that places it; returns the camera index.
int addOrthographicCamera(GltfBuilder& builder, double xmag, double ymag, double znear,
                          double zfar) {
  tinygltf::Model& model = builder.model();
  tinygltf::Camera camera;
  camera.type = "orthographic";
  camera.orthographic.xmag = xmag;
  camera.orthographic.ymag = ymag;
  camera.orthographic.znear = znear;
  camera.orthographic.zfar = zfar;
  model.cameras.push_back(camera);
  const int index = static_cast<int>(model.cameras.size()) - 1;
  builder.addNode("ortho" + std::to_string(index), Transform{});
  model.nodes.back().camera = index;
  return index;
}

TEST_F(GltfLoaderTest, BrokenCamerasLoadWithAWarningAndAreRefusedWhenRenderedFrom) {
  GltfBuilder builder;
  builder.addNode("triangle", Transform{}, builder.addMesh(triangleMesh()));
  builder.addPerspectiveCamera("fine", {0, 0, 5}, {0, 0, 0}, 0.8f, 1.5f, 0.1f, 100.0f);
  addOrthographicCamera(builder, 1.0, 0.0, 0.1, 10.0);                                 // 1
  addOrthographicCamera(builder, 0.0, 1.0, 0.1, 10.0);                                 // 2
  addOrthographicCamera(builder, 1.0, 1.0, 2.0, 2.0);                                  // 3
  addOrthographicCamera(builder, 1.0, 1.0, 5.0, 1.0);                                  // 4
  builder.addPerspectiveCamera("flat", {0, 0, 5}, {0, 0, 0}, 0.8f, 1.5f, 0.5f, 0.5f);  // 5
  builder.addPerspectiveCamera("inside", {0, 0, 5}, {0, 0, 0}, 0.8f, 1.5f, 2.0f, 1.0f);
  addOrthographicCamera(builder, 2.0, 1.0, 0.0, 10.0);  // 7: znear 0 is fine for these
  const fs::path file = path("scene.gltf");
  builder.write(file, FileFormat::GltfEmbedded);

  // The file loads: its triangle and every camera are there.
  const Scene scene = loadGltf(file);
  EXPECT_EQ(drawnTriangles(scene), 1u);
  ASSERT_EQ(scene.cameras.size(), 8u);
  const std::string problems[] = {
      "",
      "orthographic ymag must be non-zero",
      "orthographic xmag must be non-zero",
      "orthographic zfar 2 must be greater than znear 2",
      "orthographic zfar 1 must be greater than znear 5",
      "perspective zfar 0.5 must be greater than znear 0.5",
      "perspective zfar 1 must be greater than znear 2",
      "",
  };
  for (const Camera& camera : scene.cameras) {
    const std::string& problem = problems[camera.index];
    const std::string object = file.string() + ": cameras[" + std::to_string(camera.index) + "]";
    EXPECT_EQ(cameraProblem(camera), problem) << object;
    if (problem.empty()) {
      EXPECT_NO_THROW(checkCameraUsable(scene, camera)) << object;
      EXPECT_FALSE(anyWarningContains(scene, object)) << object;
      // What the projection divides by.
      const float depth = camera.zfar - camera.znear;
      EXPECT_TRUE(camera.orthographic
                      ? std::isfinite(1.0f / camera.ymag) && std::isfinite(1.0f / depth) &&
                            std::isfinite(camera.zfar / depth)
                      : std::isfinite(1.0f / std::tan(camera.yfov * 0.5f)) &&
                            std::isfinite(camera.znear / depth))
          << object;
      continue;
    }
    // Rendering from it fails with a one-line message naming the file and the camera...
    EXPECT_EQ(inputError([&] { checkCameraUsable(scene, camera); }), object + ": " + problem);
    // ...and loading it warned, once.
    const std::string warning = object + ": " + problem + "; rendering from this camera will fail";
    EXPECT_EQ(std::count(scene.warnings.begin(), scene.warnings.end(), warning), 1) << warning;
  }
}

TEST_F(GltfLoaderTest, CameraValuesOutsideFloatRangeAreRefused) {
  Scene scene;
  scene.path = "hand-made.gltf";
  Camera ortho;
  ortho.index = 3;
  ortho.orthographic = true;
  ortho.znear = 0.0f;
  ortho.zfar = 10.0f;
  ortho.ymag = 1e-39f;  // 1 / ymag overflows
  EXPECT_EQ(inputError([&] { checkCameraUsable(scene, ortho); }),
            "hand-made.gltf: cameras[3]: orthographic ymag 1e-39 is too close to zero");
  ortho.ymag = 1.0f;
  ortho.zfar = std::numeric_limits<float>::infinity();
  EXPECT_EQ(cameraProblem(ortho), "orthographic zfar must be a finite number");
  ortho.zfar = 1e-39f;  // greater than znear, but 1 / (zfar - znear) overflows
  EXPECT_EQ(cameraProblem(ortho), "orthographic zfar 1e-39 must be greater than znear 0");

  Camera perspective;
  perspective.index = 0;
  EXPECT_EQ(cameraProblem(perspective), "");  // the defaults: infinite far plane
  perspective.yfov = 0.0f;
  EXPECT_EQ(cameraProblem(perspective), "perspective yfov must be non-zero");
  perspective.yfov = -1.0f;
  EXPECT_EQ(cameraProblem(perspective), "perspective yfov must be positive");
  perspective.yfov = 0.8f;
  perspective.znear = 0.0f;
  EXPECT_EQ(cameraProblem(perspective), "perspective znear must be non-zero");
  perspective.znear = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(cameraProblem(perspective), "perspective znear must be a finite number");
  // yfov from 0.001 degrees to below pi: narrower loses the scene to float precision, pi and
  // wider turn the picture inside out.
  perspective.znear = 0.1f;
  for (const float yfov : {1e-30f, 1.7e-5f, 3.1416f, 4.0f}) {
    perspective.yfov = yfov;
    std::ostringstream shown;
    shown << yfov;
    EXPECT_EQ(
        cameraProblem(perspective),
        "perspective yfov " + shown.str() + " must be from 1.745e-05 (0.001 degrees) to below pi");
  }
  for (const float yfov : {1.75e-5f, 3.1415f}) {
    perspective.yfov = yfov;
    EXPECT_EQ(cameraProblem(perspective), "") << yfov;
  }
}

TEST_F(GltfLoaderTest, PerspectiveCamerasWithoutPositiveYfovOrZnearGetDefaultsAndAWarning) {
  // Written by hand: tinygltf leaves a yfov of 0 out when it writes, and then it is missing.
  const fs::path file = path("scene.gltf");
  std::ofstream(file) << R"({"asset": {"version": "2.0"},
    "cameras": [{"type": "perspective", "perspective": {"yfov": 0, "znear": -1}}],
    "nodes": [{"camera": 0}, {"camera": 0}], "scenes": [{"nodes": [0, 1]}]})";
  const Scene scene = loadGltf(file);
  ASSERT_EQ(scene.cameras.size(), 2u);
  const Camera& camera = scene.cameras[0];
  EXPECT_EQ(camera.yfov, Camera{}.yfov);
  EXPECT_EQ(camera.znear, Camera{}.znear);
  EXPECT_EQ(cameraProblem(camera), "");
  // Once each, although two nodes place the camera.
  const std::string object = file.string() + ": cameras[0]: ";
  EXPECT_EQ(std::count(scene.warnings.begin(), scene.warnings.end(),
                       object + "perspective yfov 0 is not positive; using 0.8"),
            1);
  EXPECT_EQ(std::count(scene.warnings.begin(), scene.warnings.end(),
                       object + "perspective znear -1 is not positive; using 0.01"),
            1);
}

TEST_F(GltfLoaderTest, KhrLightsArePlacedInWorldSpace) {
  GltfBuilder builder;
  builder.addLight("bulb", "point", {1, 2, 3}, {0, -1, 0}, {1.0f, 0.5f, 0.25f}, 100.0f, 10.0f);
  builder.addLight("", "spot", {0, 5, 0}, {0, -1, 0}, glm::vec3(1.0f), 500.0f);
  builder.addLight("sun", "directional", {0, 0, 0}, {1, -1, 0}, glm::vec3(1.0f), 3.0f);
  // Move the bulb below a parent turned 90 degrees about +Y and moved to x = 10.
  tinygltf::Model& model = builder.model();
  Transform turned;
  turned.translation = {10, 0, 0};
  turned.rotation = glm::angleAxis(kPi / 2.0f, glm::vec3(0, 1, 0));
  const int parent = builder.addNode("parent", turned);
  std::vector<int>& roots = model.scenes[0].nodes;
  roots.erase(std::find(roots.begin(), roots.end(), 0));
  model.nodes[parent].children.push_back(0);

  const Scene scene = writeAndLoad(builder);
  ASSERT_EQ(scene.lights.size(), 3u);
  // Traversal order: spot, sun, then the parent's bulb.
  const Light& spot = scene.lights[0];
  EXPECT_EQ(spot.name, "gltf_light1");
  EXPECT_EQ(spot.type, LightType::Spot);
  EXPECT_TRUE(near(spot.position, {0, 5, 0}));
  EXPECT_TRUE(near(spot.direction, {0, -1, 0}));
  EXPECT_EQ(spot.innerConeAngle, 0.0f);
  EXPECT_NEAR(spot.outerConeAngle, kPi / 4.0f, kEps);
  EXPECT_EQ(spot.range, 0.0f);
  EXPECT_EQ(spot.intensity, 500.0f);
  const Light& sun = scene.lights[1];
  EXPECT_EQ(sun.name, "sun");
  EXPECT_EQ(sun.type, LightType::Directional);
  EXPECT_TRUE(near(sun.direction, glm::normalize(glm::vec3(1, -1, 0))));
  const Light& bulb = scene.lights[2];
  EXPECT_EQ(bulb.name, "bulb");
  EXPECT_EQ(bulb.type, LightType::Point);
  EXPECT_TRUE(near(bulb.position, {13, 2, -1}));
  EXPECT_TRUE(near(bulb.color, {1.0f, 0.5f, 0.25f}));
  EXPECT_EQ(bulb.range, 10.0f);
  for (const Light& light : scene.lights) EXPECT_EQ(light.origin, "glTF");
}

// KHR_node_visibility: a hidden node places no mesh and no light, and neither does any node
// below it, even one marked visible; a camera on a hidden node stays; a sibling is drawn.
TEST_F(GltfLoaderTest, HiddenNodesPlaceNoMeshOrLightDownTheirWholeSubtree) {
  GltfBuilder builder;
  tinygltf::Model& model = builder.model();
  const auto setVisible = [&](int node, tinygltf::Value visible) {
    model.nodes[static_cast<std::size_t>(node)].extensions["KHR_node_visibility"] =
        tinygltf::Value(tinygltf::Value::Object{{"visible", std::move(visible)}});
  };
  const int mesh = builder.addMesh(triangleMesh());
  Transform far;
  far.translation = {100, 0, 0};
  const int hidden = builder.addNode("hidden", {}, mesh);
  const int child = builder.addNode("child", far, mesh, hidden);
  builder.addNode("shown", {}, mesh);
  builder.addLight("lamp", "point", {0, 1, 0}, {0, -1, 0}, glm::vec3(1.0f), 1.0f);
  const int lampNode = static_cast<int>(model.nodes.size()) - 1;
  builder.addLight("sun", "directional", {0, 0, 0}, {0, -1, 0}, glm::vec3(1.0f), 1.0f);
  builder.addPerspectiveCamera("watcher", {0, 0, 5}, {0, 0, 0}, 0.8f);
  const int cameraNode = static_cast<int>(model.nodes.size()) - 1;
  setVisible(hidden, tinygltf::Value(false));
  setVisible(child, tinygltf::Value(true));
  setVisible(lampNode, tinygltf::Value(false));
  setVisible(cameraNode, tinygltf::Value(false));
  model.extensionsUsed.push_back("KHR_node_visibility");

  const Scene scene = writeAndLoad(builder);
  ASSERT_EQ(scene.instances.size(), 1u);
  EXPECT_EQ(scene.instances[0].nodeName, "shown");
  ASSERT_EQ(scene.lights.size(), 1u);
  EXPECT_EQ(scene.lights[0].name, "sun");
  ASSERT_EQ(scene.cameras.size(), 1u);
  EXPECT_EQ(scene.cameras[0].name, "watcher");
  EXPECT_EQ(scene.source.reachedNodes, 6);
  EXPECT_EQ(scene.source.hiddenNodes, 4);
  // The child 100 units away is not drawn, so the bounds end at the shown triangle.
  EXPECT_LE(scene.bounds.max.x, 1.0f + kEps);
  EXPECT_TRUE(scene.warnings.empty()) << scene.warnings[0];

  // A hidden node's mesh index is checked all the same.
  model.nodes[static_cast<std::size_t>(child)].mesh = 7;
  EXPECT_TRUE(
      contains(writeAndLoadError(builder, path("scene.glb"), FileFormat::Glb), "nodes[1]: mesh 7"));
  model.nodes[static_cast<std::size_t>(child)].mesh = mesh;

  // Everything hidden: the scene draws nothing, and the message says why.
  builder.model().scenes[0].nodes = {hidden};
  const Scene none = writeAndLoad(builder);
  EXPECT_EQ(none.instances.size(), 0u);
  EXPECT_EQ(test_support::inputError([&] { requireTriangles(none); }),
            path("scene.glb").string() +
                ": the scene draws no triangles (2 nodes reached, 2 of them hidden by "
                "KHR_node_visibility)");
}

// A `visible` that is not a boolean: a warning naming the node, and the node drawn.
TEST_F(GltfLoaderTest, NodeVisibilityThatIsNotABooleanIsWarnedAboutAndDrawn) {
  GltfBuilder builder;
  tinygltf::Model& model = builder.model();
  const int mesh = builder.addMesh(triangleMesh());
  builder.addNode("quoted", {}, mesh);
  builder.addNode("counted", {}, mesh);
  model.nodes[0].extensions["KHR_node_visibility"] =
      tinygltf::Value(tinygltf::Value::Object{{"visible", tinygltf::Value(std::string("no"))}});
  model.nodes[1].extensions["KHR_node_visibility"] =
      tinygltf::Value(tinygltf::Value::Object{{"visible", tinygltf::Value(0)}});
  model.extensionsUsed.push_back("KHR_node_visibility");
  const Scene scene = writeAndLoad(builder);
  EXPECT_EQ(scene.instances.size(), 2u);
  EXPECT_EQ(scene.source.hiddenNodes, 0);
  ASSERT_EQ(scene.warnings.size(), 2u);
  for (int node = 0; node < 2; ++node)
    EXPECT_TRUE(contains(scene.warnings[static_cast<std::size_t>(node)],
                         "nodes[" + std::to_string(node) +
                             "].extensions.KHR_node_visibility.visible is not a boolean; the "
                             "node is drawn"));
}

// The Sundial hides its target marker and its eight buttons (two roots, 13 nodes in all).
TEST_F(GltfLoaderTest, SundialHidesItsTargetAndButtons) {
  const Scene scene = loadGltf(OMNISHADOW_SOURCE_DIR "/scenes/thirdparty/Sundial/Sundial.glb");
  EXPECT_EQ(scene.source.hiddenNodes, 13);
  for (const MeshInstance& instance : scene.instances) {
    EXPECT_EQ(instance.nodeName.find("Button"), std::string::npos) << instance.nodeName;
    EXPECT_NE(instance.nodeName, "Target");
  }
  for (const std::string& warning : scene.warnings)
    EXPECT_EQ(warning.find("KHR_node_visibility"), std::string::npos) << warning;
}

// -----------------------------------------------------------------------------------------------
// Scene choice

TEST_F(GltfLoaderTest, ChoosesTheRequestedOrDefaultScene) {
  GltfBuilder builder;
  builder.addNode("boxNode", {}, builder.addMesh(builder::makeBox(glm::vec3(1.0f)), {}, "box"));
  builder.addNode("sphereNode", {}, builder.addMesh(builder::makeSphere(1.0f, 8, 4), {}, "sphere"));
  tinygltf::Model& model = builder.model();
  model.scenes[0].nodes = {0};
  model.scenes.emplace_back();
  model.scenes[1].nodes = {1};
  const fs::path file = path("scenes.glb");
  builder.write(file, FileFormat::Glb);
  const auto scene = [](int index) {
    GltfLoadOptions options;
    options.sceneIndex = index;
    return options;
  };

  EXPECT_EQ(loadGltf(file).meshes.at(0).name, "box/0");
  EXPECT_EQ(loadGltf(file, scene(1)).meshes.at(0).name, "sphere/0");
  model.defaultScene = 1;
  builder.write(file, FileFormat::Glb);
  EXPECT_EQ(loadGltf(file).meshes.at(0).name, "sphere/0");
  EXPECT_EQ(loadGltf(file, scene(0)).meshes.at(0).name, "box/0");

  const std::string message = inputError([&] { loadGltf(file, scene(3)); });
  EXPECT_EQ(message, file.string() + ": --scene 3: the file has 2 scenes");

  // No scenes at all: every root node is drawn.
  model.scenes.clear();
  model.defaultScene = -1;
  builder.write(file, FileFormat::Glb);
  const Scene all = loadGltf(file);
  EXPECT_EQ(all.meshes.size(), 2u);
  EXPECT_TRUE(anyWarningContains(all, "no scenes"));
}

// -----------------------------------------------------------------------------------------------
// Errors

TEST_F(GltfLoaderTest, MissingGarbageAndTruncatedFilesAreInputErrors) {
  const fs::path missing = path("missing.gltf");
  EXPECT_EQ(inputError([&] { loadGltf(missing); }),
            missing.string() + ": cannot read glTF file: no such file");

  const fs::path garbage = path("garbage.gltf");
  std::ofstream(garbage) << "this is not a glTF file\n";
  EXPECT_TRUE(contains(inputError([&] { loadGltf(garbage); }), garbage.string() + ": "));

  const fs::path fakeBinary = path("fake.glb");
  std::ofstream(fakeBinary, std::ios::binary) << "glTF and then nothing useful at all";
  EXPECT_TRUE(contains(inputError([&] { loadGltf(fakeBinary); }), fakeBinary.string() + ": "));

  GltfBuilder builder;
  builder.addNode("box", {}, builder.addMesh(builder::makeBox(glm::vec3(1.0f))));
  const fs::path truncated = path("truncated.glb");
  builder.write(truncated, FileFormat::Glb);
  fs::resize_file(truncated, fs::file_size(truncated) / 2);
  EXPECT_TRUE(contains(inputError([&] { loadGltf(truncated); }), truncated.string() + ": "));
}

TEST_F(GltfLoaderTest, IndexOutOfRangeNamesThePrimitive) {
  GltfBuilder builder;
  const int mesh = builder.addMesh(triangleMesh());
  MeshData bad = triangleMesh();
  bad.indices = {0, 1, 57};
  builder.addPrimitive(mesh, bad);
  builder.addNode("node", {}, mesh);
  const fs::path file = path("bad.glb");
  EXPECT_EQ(writeAndLoadError(builder, file, FileFormat::Glb),
            file.string() + ": meshes[0].primitives[1]: index 57 >= vertex count 3");
}

TEST_F(GltfLoaderTest, AccessorsAndViewsOutsideTheirBuffersAreInputErrors) {
  GltfBuilder builder;
  builder.addNode("node", {}, builder.addMesh(triangleMesh()));
  const fs::path file = path("bad.gltf");

  builder.model().accessors[1].count = 1000;  // NORMAL
  EXPECT_TRUE(contains(writeAndLoadError(builder, file, FileFormat::GltfEmbedded),
                       file.string() + ": meshes[0].primitives[0].attributes.NORMAL: has 1000"));

  builder.model().accessors[1].count = 3;
  builder.model().accessors[1].byteOffset = 4;
  EXPECT_EQ(writeAndLoadError(builder, file, FileFormat::GltfEmbedded),
            file.string() + ": accessors[1]: extends past the end of bufferViews[1]");

  builder.model().accessors[1].byteOffset = 0;
  builder.model().bufferViews[2].byteLength += 1000;  // indices
  EXPECT_EQ(writeAndLoadError(builder, file, FileFormat::GltfEmbedded),
            file.string() + ": bufferViews[2]: extends past the end of buffers[0]");
}

TEST_F(GltfLoaderTest, UnsupportedExtensionsFailWhenRequiredAndWarnWhenUsed) {
  GltfBuilder builder;
  builder.addNode("node", {}, builder.addMesh(triangleMesh()));
  builder.addLight("lamp", "point", {0, 1, 0}, {0, -1, 0}, glm::vec3(1.0f), 1.0f);
  tinygltf::Model& model = builder.model();
  model.extensionsUsed.push_back("KHR_xmp_json_ld");
  model.extensionsRequired = {"KHR_lights_punctual"};
  const fs::path file = path("scene.gltf");
  builder.write(file, FileFormat::GltfEmbedded);
  const Scene scene = loadGltf(file);
  EXPECT_EQ(scene.lights.size(), 1u);
  ASSERT_EQ(scene.warnings.size(), 1u);
  EXPECT_TRUE(contains(scene.warnings[0], "KHR_xmp_json_ld"));

  model.extensionsUsed.push_back("EXT_lights_image_based");
  model.extensionsRequired.push_back("EXT_lights_image_based");
  EXPECT_EQ(writeAndLoadError(builder, file, FileFormat::GltfEmbedded),
            file.string() + ": extensionsRequired: EXT_lights_image_based is not supported");
}

// KHR_mesh_quantization: each integer component type it allows, normalized or not, reads as
// the spec's formulas say (normalized signed: max(c / (2^(n-1) - 1), -1); unsigned: c / (2^n - 1);
// otherwise the integer itself). Without the extension declared, the same file is refused.
TEST_F(GltfLoaderTest, QuantizedAttributesOfEveryAllowedComponentTypeDequantize) {
  struct Case {
    const char* name;
    int componentType;
    bool normalized;
    std::vector<unsigned char> bytes;  // three VEC3 positions, each element padded to 4 bytes
    std::vector<glm::vec3> expected;
  };
  const int byte = TINYGLTF_COMPONENT_TYPE_BYTE, ubyte = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
  const int i16 = TINYGLTF_COMPONENT_TYPE_SHORT, u16 = TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
  const auto shorts = [](std::initializer_list<int> values) {
    std::vector<unsigned char> bytes;
    for (int v : values) append(bytes, static_cast<std::int16_t>(v));
    return bytes;
  };
  const Case cases[] = {
      {"BYTE",
       byte,
       false,
       {0, 0, 0, 0, 5, 0, 0, 0, 0, 0x80, 0, 0},
       {{0, 0, 0}, {5, 0, 0}, {0, -128, 0}}},
      {"BYTE normalized",
       byte,
       true,
       {0, 0, 0, 0, 127, 0, 0, 0, 0, 0x80, 0, 0},
       {{0, 0, 0}, {1, 0, 0}, {0, -1, 0}}},
      {"UNSIGNED_BYTE",
       ubyte,
       false,
       {0, 0, 0, 0, 200, 0, 0, 0, 0, 3, 0, 0},
       {{0, 0, 0}, {200, 0, 0}, {0, 3, 0}}},
      {"UNSIGNED_BYTE normalized",
       ubyte,
       true,
       {0, 0, 0, 0, 255, 0, 0, 0, 0, 51, 0, 0},
       {{0, 0, 0}, {1, 0, 0}, {0, 0.2f, 0}}},
      {"SHORT",
       i16,
       false,
       shorts({0, 0, 0, 0, 1000, 0, 0, 0, 0, -1000, 0, 0}),
       {{0, 0, 0}, {1000, 0, 0}, {0, -1000, 0}}},
      {"SHORT normalized",
       i16,
       true,
       shorts({0, 0, 0, 0, 32767, 0, 0, 0, 0, -32768, 0, 0}),
       {{0, 0, 0}, {1, 0, 0}, {0, -1, 0}}},
      {"UNSIGNED_SHORT",
       u16,
       false,
       shorts({0, 0, 0, 0, 40000, 0, 0, 0, 0, 7, 0, 0}),
       {{0, 0, 0}, {40000, 0, 0}, {0, 7, 0}}},
      {"UNSIGNED_SHORT normalized",
       u16,
       true,
       shorts({0, 0, 0, 0, 65535, 0, 0, 0, 0, 13107, 0, 0}),
       {{0, 0, 0}, {1, 0, 0}, {0, 0.2f, 0}}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    GltfBuilder builder;
    const int mesh = builder.addMesh(triangleMesh());
    builder.addNode("node", {}, mesh);
    tinygltf::Model& model = builder.model();
    const std::size_t elementSize = c.componentType == byte || c.componentType == ubyte ? 4 : 8;
    const int view = addRawView(model, c.bytes, elementSize);
    const int position =
        addRawAccessor(model, view, 0, c.componentType, TINYGLTF_TYPE_VEC3, 3, c.normalized);
    model.accessors[position].minValues = {};
    model.accessors[position].maxValues = {};
    model.meshes[mesh].primitives[0].attributes["POSITION"] = position;
    // Normals as normalized bytes, texture coordinates as unnormalized unsigned shorts.
    const int normals =
        addRawAccessor(model, addRawView(model, {0, 0, 127, 0, 0, 0, 127, 0, 0, 0, 127, 0}, 4), 0,
                       byte, TINYGLTF_TYPE_VEC3, 3, true);
    model.meshes[mesh].primitives[0].attributes["NORMAL"] = normals;
    const int uvs = addRawAccessor(model, addRawView(model, shorts({0, 0, 2, 0, 0, 3})), 0, u16,
                                   TINYGLTF_TYPE_VEC2, 3);
    model.meshes[mesh].primitives[0].attributes["TEXCOORD_0"] = uvs;
    const fs::path file = path("quantized.glb");
    EXPECT_TRUE(
        contains(writeAndLoadError(builder, file, FileFormat::Glb), "POSITION must be FLOAT"));

    model.extensionsUsed = {"KHR_mesh_quantization"};
    model.extensionsRequired = {"KHR_mesh_quantization"};
    builder.write(file, FileFormat::Glb);
    const Scene scene = loadGltf(file);
    ASSERT_EQ(scene.meshes.size(), 1u);
    const Mesh& m = scene.meshes[0];
    ASSERT_EQ(m.positions.size(), 3u);
    for (std::size_t i = 0; i < 3; ++i) EXPECT_TRUE(near(m.positions[i], c.expected[i], 1e-6f));
    EXPECT_TRUE(near(m.normals[1], {0, 0, 1}));
    EXPECT_EQ(m.uv0[1], glm::vec2(2, 0));  // integers, not normalized: a texture transform scales
    EXPECT_EQ(m.uv0[2], glm::vec2(0, 3));
  }
}

// Points and lines (glTF 3.7.2.1): points as they are; lines in pairs; a strip joins each vertex
// to the next; a loop also joins the last to the first.
TEST_F(GltfLoaderTest, PointsAndLinesBecomePointAndLinePairIndices) {
  MeshData square;
  square.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  square.indices = {0, 1, 2, 3};
  GltfBuilder builder;
  for (int mode = TINYGLTF_MODE_POINTS; mode <= TINYGLTF_MODE_LINE_STRIP; ++mode) {
    const int mesh = builder.addMesh(square);
    builder.model().meshes[mesh].primitives[0].mode = mode;
    builder.addNode("mode" + std::to_string(mode), {}, mesh);
  }
  const Scene scene = writeAndLoad(builder);
  ASSERT_EQ(scene.meshes.size(), 4u);
  for (const Mesh& mesh : scene.meshes) EXPECT_TRUE(mesh.indices.empty());
  EXPECT_EQ(scene.meshes[0].pointIndices, (std::vector<std::uint32_t>{0, 1, 2, 3}));
  EXPECT_EQ(scene.meshes[1].lineIndices, (std::vector<std::uint32_t>{0, 1, 2, 3}));
  EXPECT_EQ(scene.meshes[2].lineIndices, (std::vector<std::uint32_t>{0, 1, 1, 2, 2, 3, 3, 0}));
  EXPECT_EQ(scene.meshes[3].lineIndices, (std::vector<std::uint32_t>{0, 1, 1, 2, 2, 3}));
  EXPECT_TRUE(scene.warnings.empty()) << scene.warnings[0];
}

// EXT_mesh_gpu_instancing: instance i is placed at node * T_i * R_i * S_i, here with TRANSLATION
// as normalized shorts, ROTATION as normalized bytes and SCALE as floats.
TEST_F(GltfLoaderTest, GpuInstancingPlacesOneInstancePerElement) {
  GltfBuilder builder;
  const int mesh = builder.addMesh(triangleMesh());
  const int node = builder.addNode("instanced", {.translation = {10, 0, 0}}, mesh);
  tinygltf::Model& model = builder.model();
  std::vector<unsigned char> translation, rotation, scale;
  // Elements padded to 8 bytes.
  for (int v : {0, 0, 0, 0, 0, 16384, 0, 0}) append(translation, static_cast<std::int16_t>(v));
  for (int v : {0, 0, 0, 127, 0, 127, 0, 127}) append(rotation, static_cast<std::int8_t>(v));
  for (float v : {1.0f, 1.0f, 1.0f, 2.0f, 2.0f, 2.0f}) append(scale, v);
  const int t = addRawAccessor(model, addRawView(model, translation, 8), 0,
                               TINYGLTF_COMPONENT_TYPE_SHORT, TINYGLTF_TYPE_VEC3, 2, true);
  const int r = addRawAccessor(model, addRawView(model, rotation), 0, TINYGLTF_COMPONENT_TYPE_BYTE,
                               TINYGLTF_TYPE_VEC4, 2, true);
  const int s = addRawAccessor(model, addRawView(model, scale), 0, TINYGLTF_COMPONENT_TYPE_FLOAT,
                               TINYGLTF_TYPE_VEC3, 2);
  tinygltf::Value::Object attributes = {{"TRANSLATION", tinygltf::Value(t)},
                                        {"ROTATION", tinygltf::Value(r)},
                                        {"SCALE", tinygltf::Value(s)}};
  model.nodes[node].extensions["EXT_mesh_gpu_instancing"] =
      tinygltf::Value(tinygltf::Value::Object{{"attributes", tinygltf::Value(attributes)}});
  model.extensionsUsed = {"EXT_mesh_gpu_instancing", "KHR_mesh_quantization"};
  const Scene scene = writeAndLoad(builder);
  ASSERT_EQ(scene.instances.size(), 2u);
  const auto place = [&](std::size_t i, glm::vec3 p) {
    return glm::vec3(scene.instances[i].world * glm::vec4(p, 1.0f));
  };
  EXPECT_TRUE(near(place(0, {1, 0, 0}), {11, 0, 0}));
  // 90 degrees about +Y turns +X into -Z; scaled by 2, lifted by 16384 / 32767.
  EXPECT_TRUE(near(place(1, {1, 0, 0}), {10, 16384.0f / 32767.0f, -2}, 1e-5f));
  EXPECT_TRUE(near(scene.bounds.max, {11, 2.0f + 16384.0f / 32767.0f, 0}, 1e-5f));

  // The attributes must agree on the number of instances.
  model.accessors[static_cast<std::size_t>(s)].count = 1;
  const fs::path file = path("instancing.glb");
  EXPECT_EQ(writeAndLoadError(builder, file, FileFormat::Glb),
            file.string() + ": nodes[" + std::to_string(node) +
                "].extensions.EXT_mesh_gpu_instancing.attributes.SCALE: accessors[" +
                std::to_string(s) + "] has 1 elements, but the other attributes have 2");
}

TEST_F(GltfLoaderTest, NodeCyclesAndBadReferencesAreInputErrors) {
  GltfBuilder builder;
  const int mesh = builder.addMesh(triangleMesh());
  const int a = builder.addNode("a", {}, mesh);
  const int b = builder.addNode("b", {}, mesh, a);
  builder.model().nodes[b].children.push_back(a);
  const fs::path file = path("cycle.glb");
  builder.write(file, FileFormat::Glb);
  const std::string message = inputError([&] { loadGltf(file); });
  EXPECT_TRUE(contains(message, file.string() + ": nodes[0]: "));
  EXPECT_TRUE(contains(message, "cycle"));

  builder.model().nodes[b].children = {7};
  EXPECT_EQ(writeAndLoadError(builder, file, FileFormat::Glb),
            file.string() + ": nodes[1].children: node 7 is out of range (the file has 2 nodes)");

  builder.model().nodes[b].children.clear();
  builder.model().nodes[b].mesh = 4;
  EXPECT_EQ(writeAndLoadError(builder, file, FileFormat::Glb),
            file.string() + ": nodes[1]: mesh 4 is out of range (the file has 1 mesh)");
}

TEST_F(GltfLoaderTest, UnreadableImagesAreInputErrorsNamingTheImage) {
  GltfBuilder builder;
  const int texture = builder.addTexture(1, 1, {1, 2, 3, 4}, "checker");
  builder.addNode("node", {}, builder.addTexturedMesh(builder::makeBox(glm::vec3(1.0f)), texture));
  const fs::path file = path("scene.gltf");
  builder.write(file, FileFormat::GltfExternal);
  ASSERT_NO_THROW(loadGltf(file));

  std::ofstream(path("scene_image0.png"), std::ios::binary) << "not a PNG";
  std::string message = inputError([&] { loadGltf(file); });
  EXPECT_TRUE(contains(message, file.string() + ": "));
  EXPECT_TRUE(contains(message, "image[0]"));

  fs::remove(path("scene_image0.png"));
  message = inputError([&] { loadGltf(file); });
  EXPECT_EQ(message,
            file.string() + ": images[0] \"checker\": cannot read or decode scene_image0.png");
}

TEST_F(GltfLoaderTest, ImagesInBufferViewsAreCheckedBeforeDecoding) {
  GltfBuilder builder;
  const int imageView =
      addTriangleWithImageInView(builder, "bad", std::vector<unsigned char>(64, 0x5a));
  tinygltf::Model& model = builder.model();
  const fs::path file = path("images.glb");

  builder.write(file, FileFormat::Glb);
  std::string message = inputError([&] { loadGltf(file); });
  EXPECT_TRUE(contains(message, file.string() + ": images[0] \"bad\": "));

  // Past the end of the buffer: tinygltf alone would let the decoder read there.
  model.bufferViews[imageView].byteLength = 100000;
  builder.write(file, FileFormat::Glb);
  message = inputError([&] { loadGltf(file); });
  EXPECT_TRUE(
      contains(message, file.string() + ": bufferViews[3]: extends past the end of buffers[0]"));
}

// -----------------------------------------------------------------------------------------------
// Real files made by others, copied into scenes/thirdparty with their licenses.

TEST(GltfLoaderThirdParty, LoadsTheSampleScenes) {
  const fs::path root = fs::path(OMNISHADOW_SOURCE_DIR) / "scenes" / "thirdparty";
  struct Expected {
    const char* file;
    std::size_t drawnTriangles;
    std::size_t cameras;
    std::size_t lights;
  };
  const Expected samples[] = {
      {"Box/Box.glb", 12, 0, 0},
      {"Duck/Duck.glb", 4212, 1, 0},
      {"BoxTextured/BoxTextured.glb", 12, 0, 0},
      {"Cameras/Cameras.gltf", 2, 2, 0},
      // 15,546 less the 6,192 of the nodes KHR_node_visibility hides (counted from the file).
      {"Sundial/Sundial.glb", 9354, 1, 1},
      {"CornellBoxSuzanne/cornell-box.glb", 1040, 0, 0},
  };
  for (const Expected& sample : samples) {
    SCOPED_TRACE(sample.file);
    const Scene scene = loadGltf(root / sample.file);
    EXPECT_EQ(drawnTriangles(scene), sample.drawnTriangles);
    EXPECT_EQ(scene.cameras.size(), sample.cameras);
    EXPECT_EQ(scene.lights.size(), sample.lights);
    EXPECT_FALSE(scene.bounds.empty());
    for (const Mesh& mesh : scene.meshes) {
      EXPECT_EQ(mesh.normals.size(), mesh.positions.size());
    }
    for (const Image& image : scene.images) {
      EXPECT_EQ(image.rgba.size(), static_cast<std::size_t>(image.width * image.height * 4));
    }
  }
}

// -----------------------------------------------------------------------------------------------
// Inputs found by the fuzzer (tests/fuzz/fuzz_gltf.cpp)

// A file of 150 bytes declared millions of vertices in an accessor without a bufferView (all
// zeros): seconds of work and hundreds of MB. All reads of such accessors now share one limit,
// however many primitives repeat them.
TEST_F(GltfLoaderTest, AccessorsWithoutBufferViewShareOneCountLimit) {
  const auto write = [&](const std::string& name, std::size_t count, int primitives) {
    std::string list;
    for (int i = 0; i < primitives; ++i) {
      list += std::string(i == 0 ? "" : ",") + R"({"attributes":{"POSITION":0}})";
    }
    const fs::path file = path(name);
    std::ofstream(file) << R"({"asset":{"version":"2.0"},"accessors":[{"componentType":5126,)"
                        << R"("count":)" << count << R"(,"type":"VEC3"}],"meshes":[{"primitives":[)"
                        << list << R"(]}],"nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}]})";
    return file;
  };
  const std::string limit =
      " is too large without a bufferView (accessors without one may hold "
      "262144 elements in all)";
  const fs::path huge = write("huge.gltf", 5555555, 1);
  EXPECT_EQ(inputError([&] { loadGltf(huge); }),
            huge.string() + ": accessors[0]: count 5555555" + limit);
  const fs::path repeated = write("repeated.gltf", 100000, 3);
  EXPECT_EQ(inputError([&] { loadGltf(repeated); }),
            repeated.string() + ": accessors[0]: count 100000" + limit);
  const Scene scene = loadGltf(write("fits.gltf", 100000, 2));
  EXPECT_EQ(scene.meshes.size(), 2u);
}

// Image headers that claim more than their data can hold: stb_image allocates for the claim
// before it finds the data missing (1 GiB for a 400-byte JPEG, past the fuzzer's limit), and a
// JPEG with fill bytes before its frame got past the header check. Only PNG and JPEG reach
// stb_image: its other decoders take almost any bytes (a TGA has no signature) for any size.
std::vector<unsigned char> pngClaiming(std::uint32_t width, std::uint32_t height,
                                       unsigned char depth) {
  std::vector<unsigned char> bytes = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n',
                                      0,    0,   0,   13,  'I',  'H',  'D',  'R'};
  for (std::uint32_t v : {width, height}) {
    for (int shift = 24; shift >= 0; shift -= 8) bytes.push_back((v >> shift) & 0xff);
  }
  bytes.push_back(depth);
  for (int b : {6, 0, 0, 0, 0, 0, 0, 0})
    bytes.push_back(static_cast<unsigned char>(b));  // RGBA, CRC
  bytes.resize(bytes.size() + 64, 0);
  return bytes;
}

TEST_F(GltfLoaderTest, ImagesClaimingMoreThanTheirDataAreRefusedBeforeDecoding) {
  GltfBuilder builder;
  const int imageView = addTriangleWithImageInView(builder, "big", {});
  tinygltf::Model& model = builder.model();
  const fs::path file = path("images.glb");
  const auto loadWith = [&](const std::vector<unsigned char>& bytes) {
    tinygltf::BufferView& view = model.bufferViews[imageView];
    std::vector<unsigned char>& data = model.buffers[0].data;
    data.resize(view.byteOffset);
    data.insert(data.end(), bytes.begin(), bytes.end());
    view.byteLength = bytes.size();
    builder.write(file, FileFormat::Glb);
    return inputError([&] { loadGltf(file); });
  };
  const std::string object = file.string() + ": images[0] \"big\": ";

  EXPECT_TRUE(contains(loadWith(pngClaiming(16384, 16384, 8)),
                       object + "16384x16384 texels cannot be in 97 bytes of PNG (at least "));
  EXPECT_EQ(loadWith(pngClaiming(16384, 16384, 16)),
            object + "16384x16384 texels of 16-bit channels is too large");

  // SOI, a fill byte, SOF0 for 16384 x 16384 with three components, then some data.
  std::vector<unsigned char> jpeg = {0xff, 0xd8, 0xff, 0xff, 0xc0, 0x00, 0x11, 0x08,
                                     0x40, 0x00, 0x40, 0x00, 0x03, 0x01, 0x22, 0x00,
                                     0x02, 0x11, 0x00, 0x03, 0x11, 0x00};
  jpeg.resize(400, 0);
  EXPECT_TRUE(
      contains(loadWith(jpeg), object + "16384x16384 texels cannot be in 400 bytes of JPEG"));
  jpeg[4] = 0xc3;  // lossless SOF3, which stb_image does not decode
  EXPECT_EQ(loadWith(jpeg), object + "no JPEG frame header that can be decoded");

  // A TGA header: no signature, 16384 x 16384 at 32 bits.
  std::vector<unsigned char> tga = {0, 0, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0x40, 0, 0x40, 32, 0};
  tga.resize(400, 0);
  EXPECT_EQ(loadWith(tga), object +
                               "unknown image format: glTF images are PNG or JPEG (or WebP and "
                               "AVIF through their extensions)");

  // The same checks for images read from files (and data: URIs).
  GltfBuilder external;
  const int texture = external.addTexture(1, 1, {1, 2, 3, 4}, "checker");
  external.addNode("node", {}, external.addTexturedMesh(triangleMesh(), texture));
  const fs::path scene = path("scene.gltf");
  external.write(scene, FileFormat::GltfExternal);
  ASSERT_NO_THROW(loadGltf(scene));
  std::ofstream(path("scene_image0.png"), std::ios::binary) << "P6\n8000 8000\n255\n";
  EXPECT_EQ(inputError([&] { loadGltf(scene); }),
            scene.string() +
                ": Unknown image format for image[0]: glTF images are PNG or JPEG (or WebP "
                "and AVIF through their extensions)");
  const std::vector<unsigned char> png = pngClaiming(16384, 16384, 8);
  std::ofstream(path("scene_image0.png"), std::ios::binary)
      .write(reinterpret_cast<const char*>(png.data()), static_cast<std::streamsize>(png.size()));
  EXPECT_TRUE(contains(inputError([&] { loadGltf(scene); }),
                       scene.string() + ": images[0]: 16384x16384 texels cannot be in 97 bytes"));
}

// From the fuzzer: a 1x1 PNG whose IDAT chunk declared 1 GiB (0x4000000d bytes) in a 70-byte
// file; stb_image reserved the 1 GiB before finding the data missing.
TEST_F(GltfLoaderTest, PngChunksPastTheEndOfTheImageAreRefusedBeforeDecoding) {
  std::vector<unsigned char> png = {
      0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48,
      0x44, 0x52, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x01, 0x08, 0x06, 0x00, 0x00,
      0x00, 0x1f, 0x15, 0xc4, 0x89, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x44, 0x41, 0x54, 0x78,
      0x9c, 0x63, 0xe0, 0x12, 0x91, 0xfb, 0x0f, 0x00, 0x01, 0xa4, 0x01, 0x3c, 0x93, 0x8b,
      0x0e, 0xb7, 0x00, 0x00, 0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82};
  GltfBuilder builder;
  const int texture = builder.addTexture(1, 1, {1, 2, 3, 4}, "checker");
  builder.addNode("node", {}, builder.addTexturedMesh(triangleMesh(), texture));
  const fs::path scene = path("scene.gltf");
  builder.write(scene, FileFormat::GltfExternal);
  const auto writeImage = [&] {
    std::ofstream(path("scene_image0.png"), std::ios::binary)
        .write(reinterpret_cast<const char*>(png.data()), static_cast<std::streamsize>(png.size()));
  };
  writeImage();
  ASSERT_EQ(loadGltf(scene).images.size(), 1u);

  png[33] = 0x40;  // IDAT length 0x0000000d -> 0x4000000d
  writeImage();
  EXPECT_EQ(
      inputError([&] { loadGltf(scene); }),
      scene.string() + ": images[0]: a PNG chunk at byte 33 extends past the end of the 70 bytes");
}

}  // namespace
}  // namespace omnishadow::gltf_loader_test
