// Compressed, quantized and instanced geometry (KHR_draco_mesh_compression,
// EXT_/KHR_meshopt_compression, KHR_mesh_quantization, EXT_mesh_gpu_instancing; the files are in
// scenes/compressed): decoded world-space triangles match the plain files they were made from
// within the quantization step, the rendered pictures match (coverage exactly, colors within a
// tolerance), instances are drawn and cast shadows, and broken compressed data is an input error
// naming the file, the object and the extension.
#include <gtest/gtest.h>
#include <meshoptimizer.h>
#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <glm/glm.hpp>
#include <iterator>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "renderer/core/errors.h"
#include "renderer/output/image_writer.h"
#include "renderer/scene/gltf_loader.h"
#include "scenes/builder/gltf_builder.h"
#include "tests/support/run_binary.h"
#include "tests/support/temp_folder.h"

namespace omnishadow::compressed_geometry_test {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

const fs::path kScenes = fs::path(OMNISHADOW_SOURCE_DIR) / "scenes";

struct Twin {
  std::string name;
  std::string plain, compressed;  // below scenes/
  int positionBits = 14;          // the encoder's position quantization
  bool render = true;             // also compare rendered pictures (a few seconds each)
  bool sameColors = true;         // false where the variant needs another extension for color
};

void PrintTo(const Twin& twin, std::ostream* os) {
  *os << twin.name;
}

// The Khronos Draco files were made by gltf-pipeline, with 11-bit positions; gltfpack (0.18)
// quantizes to 14 bits. The KHR and fallback variants decode to the same bytes as the EXT one,
// so their geometry is checked and their pictures are not rendered again.
const Twin kTwins[] = {
    {"BoxDraco", "thirdparty/Box/Box.glb", "compressed/Box-Draco/Box.gltf", 11, false},
    {"DuckDraco", "thirdparty/Duck/Duck.glb", "compressed/Duck-Draco/Duck.gltf", 11},
    // Its texture coordinates are quantized too: KHR_texture_transform gives the colors back.
    {"DuckQuantized", "thirdparty/Duck/Duck.glb", "compressed/Duck-Quantized/Duck.gltf", 14},
    {"CornellQuantized", "thirdparty/CornellBoxSuzanne/cornell-box.glb",
     "compressed/CornellBoxSuzanne/quantized.glb"},
    {"CornellQuantizedNormalized", "thirdparty/CornellBoxSuzanne/cornell-box.glb",
     "compressed/CornellBoxSuzanne/quantized-normalized.glb", 14, false},
    {"CornellMeshopt", "thirdparty/CornellBoxSuzanne/cornell-box.glb",
     "compressed/CornellBoxSuzanne/meshopt.glb"},
    {"CornellMeshoptKhr", "thirdparty/CornellBoxSuzanne/cornell-box.glb",
     "compressed/CornellBoxSuzanne/meshopt-khr.glb", 14, false},
    {"CornellMeshoptWithFallback", "thirdparty/CornellBoxSuzanne/cornell-box.glb",
     "compressed/CornellBoxSuzanne/meshopt-fallback.glb", 14, false},
};

std::vector<glm::vec3> worldVertices(const Scene& scene) {
  std::vector<glm::vec3> vertices;
  for (const MeshInstance& instance : scene.instances) {
    const Mesh& mesh = scene.meshes[static_cast<std::size_t>(instance.mesh)];
    for (std::uint32_t index : mesh.indices) {
      vertices.push_back(glm::vec3(instance.world * glm::vec4(mesh.positions[index], 1.0f)));
    }
  }
  return vertices;
}

class CompressedTwin : public ::testing::TestWithParam<Twin> {};

// Every corner of every drawn triangle lies within one quantization step of a corner of the
// plain file's triangles, and the triangle counts agree (the encoders keep every triangle).
// Quantizing positions to N bits over the model's bounds moves a coordinate by at most half of
// extent / (2^N - 1); one full step is the tolerance.
TEST_P(CompressedTwin, DecodedTrianglesMatchThePlainFileWithinTheQuantizationStep) {
  const Scene plain = loadGltf(kScenes / GetParam().plain);
  const Scene compressed = loadGltf(kScenes / GetParam().compressed);
  const std::vector<glm::vec3> a = worldVertices(plain), b = worldVertices(compressed);
  ASSERT_EQ(a.size(), b.size());
  ASSERT_FALSE(a.empty());
  const glm::vec3 extent = plain.bounds.max - plain.bounds.min;
  const float step = std::max({extent.x, extent.y, extent.z}) /
                     static_cast<float>((1 << GetParam().positionBits) - 1);
  EXPECT_LE(glm::length(compressed.bounds.min - plain.bounds.min), 2.0f * step);
  EXPECT_LE(glm::length(compressed.bounds.max - plain.bounds.max), 2.0f * step);
  // Nearest plain corner for each decoded one, on a grid of cells one tolerance wide.
  std::vector<glm::vec3> sorted = a;
  std::sort(sorted.begin(), sorted.end(),
            [](const glm::vec3& p, const glm::vec3& q) { return p.x < q.x; });
  float worst = 0.0f;
  for (const glm::vec3& p : b) {
    float best = std::numeric_limits<float>::max();
    auto it = std::lower_bound(sorted.begin(), sorted.end(), p.x - step,
                               [](const glm::vec3& q, float x) { return q.x < x; });
    for (; it != sorted.end() && it->x <= p.x + step; ++it) {
      best = std::min(best, glm::length(*it - p));
    }
    worst = std::max(worst, best);
  }
  EXPECT_LE(worst, step) << "quantization step " << step;
}

// The same picture at 64x64 with one shadowing point light: coverage (the alpha of the AOVs)
// identical for 14-bit positions, whose step (1e-4 of the model) is far below a pixel (1/40 of
// it); 11-bit Draco moves vertices 8 times as far, and a pixel center that close to an edge may
// change sides, so there 0.1% of the pixels may differ. Colors within 10/255 in all but those
// pixels: 8-bit normals (gltfpack's default; Draco's are finer) tilt a normal by under a degree.
// Light visibility (shadows) may flip in 0.1% of the pixels, where a moved vertex crosses a
// shadow-map texel at a shadow edge.
class CompressedTwinPicture : public ::testing::TestWithParam<Twin> {};

TEST_P(CompressedTwinPicture, RendersTheSamePictureAsThePlainFile) {
  test_support::TempFolder folder("omnishadow-compressed");
  std::ofstream(folder / "lights.json")
      << R"({"lights": [{"name": "lamp", "position": [1.5, 2.5, 2], "shadow": {"resolution": 128}}]})";
  const Scene plain = loadGltf(kScenes / GetParam().plain);
  const glm::vec3 center = (plain.bounds.min + plain.bounds.max) * 0.5f;
  const float radius = glm::length(plain.bounds.max - plain.bounds.min);
  const std::string eye = std::to_string(center.x + radius) + "," +
                          std::to_string(center.y + radius * 0.6f) + "," +
                          std::to_string(center.z + radius * 1.2f);
  const std::string target =
      std::to_string(center.x) + "," + std::to_string(center.y) + "," + std::to_string(center.z);
  std::vector<std::vector<std::string>> renders;
  for (const auto& [scene, stem] : {std::pair{GetParam().plain, std::string("plain")},
                                    std::pair{GetParam().compressed, std::string("compressed")}}) {
    renders.push_back({"render", (kScenes / scene).string(), "-l",
                       (folder / "lights.json").string(), "--eye", eye, "--target", target,
                       "--width", "64", "--height", "64", "-o", (folder / (stem + ".png")).string(),
                       "--aov", (folder / (stem + ".exr")).string()});
  }
  for (const test_support::RunResult& r : test_support::runOmnishadowAll(renders)) {
    ASSERT_EQ(r.status, 0) << r.err;
  }
  const auto diff = [&](const std::string& ext, std::vector<std::string> options) {
    std::vector<std::string> args = {"diff", (folder / ("plain" + ext)).string(),
                                     (folder / ("compressed" + ext)).string()};
    args.insert(args.end(), options.begin(), options.end());
    return test_support::runOmnishadow(args);
  };
  const std::string edgePixels = GetParam().positionBits < 14 ? "0.001" : "0";
  test_support::RunResult r =
      diff(".exr", {"--channels", "A", "--max-failing-fraction", edgePixels});
  EXPECT_EQ(r.status, 0) << "coverage differs:\n" << r.out << r.err;
  r = diff(".exr", {"--channels", "visibility.lamp", "--threshold", "0.5", "--max-failing-fraction",
                    "0.001"});
  EXPECT_EQ(r.status, 0) << "shadows differ:\n" << r.out << r.err;
  if (GetParam().sameColors) {
    // Quantized texture coordinates (gltfpack: 12 bits) move a lookup by up to half a step, which
    // can cross a texel edge: a few pixels in a thousand may differ by more than 10/255.
    r = diff(".png",
             {"--threshold", std::to_string(10.0 / 255.0), "--max-failing-fraction", "0.001"});
    EXPECT_EQ(r.status, 0) << "colors differ:\n" << r.out << r.err;
  }
}

std::string twinName(const ::testing::TestParamInfo<Twin>& twin) {
  return twin.param.name;
}

std::vector<Twin> rendered() {
  std::vector<Twin> twins;
  std::copy_if(std::begin(kTwins), std::end(kTwins), std::back_inserter(twins),
               [](const Twin& twin) { return twin.render; });
  return twins;
}

INSTANTIATE_TEST_SUITE_P(Files, CompressedTwin, ::testing::ValuesIn(kTwins), twinName);
INSTANTIATE_TEST_SUITE_P(Files, CompressedTwinPicture, ::testing::ValuesIn(rendered()), twinName);

// ---------------------------------------------------------------------------------------------
// EXT_mesh_gpu_instancing: SimpleInstancing's 125 cubes are all drawn, and cast shadows on each
// other. With the sun straight above, a face that looks up can only be shadowed by another cube
// (a cube cannot shadow its own top), so shadowed upward faces are shadows cast by instances.

TEST(GpuInstancing, SimpleInstancingDrawsAllCubesAndTheyShadowEachOther) {
  const fs::path file = kScenes / "compressed" / "SimpleInstancing" / "SimpleInstancing.glb";
  const Scene scene = loadGltf(file);
  ASSERT_EQ(scene.instances.size(), 125u);
  std::vector<std::tuple<float, float, float>> origins;
  for (const MeshInstance& instance : scene.instances) {
    origins.emplace_back(instance.world[3].x, instance.world[3].y, instance.world[3].z);
  }
  std::sort(origins.begin(), origins.end());
  EXPECT_EQ(std::unique(origins.begin(), origins.end()), origins.end()) << "instances coincide";

  test_support::TempFolder folder("omnishadow-instancing");
  std::ofstream(folder / "sun.json") << R"({"lights": [{"name": "sun", "type": "directional",
      "direction": [0, -1, 0], "shadow": {"resolution": 256}}]})";
  const test_support::RunResult r = test_support::runOmnishadow(
      {"render", file.string(), "-l", (folder / "sun.json").string(), "--width", "64", "--height",
       "64", "-o", (folder / "beauty.png").string(), "--aov", (folder / "aov.exr").string()});
  ASSERT_EQ(r.status, 0) << r.err;
  const FloatImage aov = readImage(folder / "aov.exr");
  const int a = aov.channelIndex("A"), ny = aov.channelIndex("N.Y");
  const int visibility = aov.channelIndex("visibility.sun");
  ASSERT_GE(std::min({a, ny, visibility}), 0);
  int lit = 0, shadowed = 0;
  for (int y = 0; y < aov.height; ++y) {
    for (int x = 0; x < aov.width; ++x) {
      if (aov.at(x, y, a) < 1.0f || aov.at(x, y, ny) < 0.9f) continue;
      (aov.at(x, y, visibility) > 0.5f ? lit : shadowed)++;
    }
  }
  EXPECT_GT(lit, 10) << shadowed << " shadowed";
  EXPECT_GT(shadowed, 50) << lit << " lit";
}

// ---------------------------------------------------------------------------------------------
// MeshPrimitiveModes: points, lines, line loop and line strip in the upper 5/8 of the picture
// (triangles, strip and fan below) are drawn; before, that part was empty.

TEST(PrimitiveModes, PointsAndLinesAreDrawn) {
  const fs::path file = kScenes / "compressed" / "MeshPrimitiveModes" / "MeshPrimitiveModes.gltf";
  test_support::TempFolder folder("omnishadow-modes");
  const test_support::RunResult r = test_support::runOmnishadow(
      {"render", file.string(), "--width", "128", "--height", "64", "-o",
       (folder / "beauty.png").string(), "--aov", (folder / "aov.exr").string()});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.err.find("not drawn"), std::string::npos) << r.err;
  const FloatImage aov = readImage(folder / "aov.exr");
  const int a = aov.channelIndex("A");
  ASSERT_GE(a, 0);
  int covered = 0;
  for (int y = 0; y < aov.height * 5 / 8; ++y) {
    for (int x = 0; x < aov.width; ++x) covered += aov.at(x, y, a) > 0.0f ? 1 : 0;
  }
  EXPECT_GT(covered, 30);
}

// ---------------------------------------------------------------------------------------------
// Broken compressed data: copies of the real files, edited.

std::string readBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

std::uint32_t le32(const std::string& bytes, std::size_t at) {
  std::uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = v << 8 | static_cast<unsigned char>(bytes[at + i]);
  return v;
}

void putLe32(std::string& out, std::size_t value) {
  for (int shift = 0; shift < 32; shift += 8) out += static_cast<char>((value >> shift) & 0xFF);
}

// Copies a .glb with its JSON edited by `edit`.
void copyGlbEdited(const fs::path& from, const fs::path& to,
                   const std::function<void(Json&)>& edit) {
  const std::string glb = readBytes(from);
  const std::size_t jsonLength = le32(glb, 12);
  Json json = Json::parse(glb.substr(20, jsonLength));
  edit(json);
  std::string text = json.dump();
  text.resize((text.size() + 3) / 4 * 4, ' ');
  const std::string rest = glb.substr(20 + jsonLength);
  std::string out = glb.substr(0, 8);
  putLe32(out, 20 + text.size() + rest.size());
  putLe32(out, text.size());
  out += "JSON";
  out += text + rest;
  std::ofstream(to, std::ios::binary) << out;
}

// Copies Box-Draco (.gltf and .bin) with its JSON edited by `edit`.
fs::path copyBoxDracoEdited(const fs::path& folder, const std::function<void(Json&)>& edit) {
  const fs::path source = kScenes / "compressed" / "Box-Draco";
  fs::copy_file(source / "Box.bin", folder / "Box.bin", fs::copy_options::overwrite_existing);
  Json json = Json::parse(readBytes(source / "Box.gltf"));
  edit(json);
  std::ofstream(folder / "Box.gltf") << json.dump();
  return folder / "Box.gltf";
}

std::string inputError(const fs::path& file) {
  try {
    loadGltf(file);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << file << " loaded";
  return {};
}

Json& dracoExtension(Json& gltf) {
  return gltf["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"];
}

TEST(BrokenDraco, TruncatedStreamIsAnInputErrorNamingThePrimitiveAndTheExtension) {
  test_support::TempFolder folder("omnishadow-draco");
  int view = -1;
  const fs::path file = copyBoxDracoEdited(folder.path(), [&](Json& gltf) {
    view = dracoExtension(gltf)["bufferView"];
    gltf["bufferViews"][view]["byteLength"] =
        gltf["bufferViews"][view]["byteLength"].get<int>() / 2;
  });
  const std::string message = inputError(file);
  EXPECT_EQ(message.rfind(file.string() +
                              ": meshes[0].primitives[0].extensions.KHR_draco_mesh_compression: "
                              "the Draco data in bufferViews[" +
                              std::to_string(view) + "] does not decode: ",
                          0),
            0u)
      << message;
}

TEST(BrokenDraco, CountsThatDoNotMatchTheDecodedMeshAreInputErrors) {
  test_support::TempFolder folder("omnishadow-draco");
  int accessor = -1;
  fs::path file = copyBoxDracoEdited(folder.path(), [&](Json& gltf) {
    accessor = gltf["meshes"][0]["primitives"][0]["attributes"]["POSITION"];
    gltf["accessors"][accessor]["count"] = 25;
  });
  EXPECT_EQ(inputError(file),
            file.string() +
                ": meshes[0].primitives[0].extensions.KHR_draco_mesh_compression.attributes."
                "POSITION: decoded 24 vertices, but accessors[" +
                std::to_string(accessor) + "] has count 25");

  file = copyBoxDracoEdited(folder.path(), [&](Json& gltf) {
    accessor = gltf["meshes"][0]["primitives"][0]["indices"];
    gltf["accessors"][accessor]["count"] = 33;
  });
  EXPECT_EQ(inputError(file),
            file.string() +
                ": meshes[0].primitives[0].extensions.KHR_draco_mesh_compression indices: decoded "
                "12 triangles, but accessors[" +
                std::to_string(accessor) + "] has count 33");

  // The decoder's output does not have the accessor's type.
  file = copyBoxDracoEdited(folder.path(), [&](Json& gltf) {
    accessor = gltf["meshes"][0]["primitives"][0]["attributes"]["NORMAL"];
    gltf["accessors"][accessor]["type"] = "VEC2";
  });
  EXPECT_EQ(inputError(file),
            file.string() +
                ": meshes[0].primitives[0].extensions.KHR_draco_mesh_compression.attributes."
                "NORMAL: decoded 3 components per vertex, but accessors[" +
                std::to_string(accessor) + "] has 2");

  // An attribute id the stream does not have.
  file = copyBoxDracoEdited(folder.path(),
                            [&](Json& gltf) { dracoExtension(gltf)["attributes"]["NORMAL"] = 7; });
  EXPECT_EQ(inputError(file),
            file.string() +
                ": meshes[0].primitives[0].extensions.KHR_draco_mesh_compression.attributes."
                "NORMAL: the Draco data has no attribute with this id");
}

const fs::path kMeshopt = kScenes / "compressed" / "CornellBoxSuzanne" / "meshopt.glb";

// The first bufferView compressed with `mode` and `filter`.
int meshoptView(const Json& gltf, const std::string& mode, const std::string& filter = "NONE") {
  for (std::size_t v = 0; v < gltf["bufferViews"].size(); ++v) {
    const Json& view = gltf["bufferViews"][v];
    if (!view.contains("extensions")) continue;
    const Json& extension = view["extensions"]["EXT_meshopt_compression"];
    if (extension["mode"] == mode && extension.value("filter", "NONE") == filter) {
      return static_cast<int>(v);
    }
  }
  ADD_FAILURE() << "no " << mode << " view";
  return 0;
}

TEST(BrokenMeshopt, TruncatedOrMislabelledStreamsAreInputErrorsNamingTheViewAndTheExtension) {
  test_support::TempFolder folder("omnishadow-meshopt");
  const fs::path file = folder / "broken.glb";
  struct Case {
    std::string mode, filter;
    std::function<std::string(Json& extension, Json& view)> edit;  // returns the expected problem
  };
  const Case cases[] = {
      {"ATTRIBUTES", "NONE",
       [](Json& e, Json&) {
         // Cut to fewer bytes than the stream's tail (a cut in its middle goes unnoticed: the
         // codec has no checksum, and the output is still bounded by the view).
         e["byteLength"] = 8;
         return std::string(
             "the ATTRIBUTES data does not decode: truncated or corrupt "
             "(meshoptimizer error -2)");
       }},
      {"TRIANGLES", "NONE",
       [](Json& e, Json&) {
         e["byteLength"] = e["byteLength"].get<int>() - 20;
         return std::string(
             "the TRIANGLES data does not decode: truncated or corrupt "
             "(meshoptimizer error -2)");
       }},
      {"TRIANGLES", "NONE",
       [](Json& e, Json& view) {
         e["count"] = e["count"].get<int>() - 3;
         return "count " + std::to_string(e["count"].get<int>()) + " times byteStride 2 is not " +
                "the bufferView's byteLength " + std::to_string(view["byteLength"].get<int>());
       }},
      {"ATTRIBUTES", "OCTAHEDRAL",
       [](Json& e, Json&) {
         e["filter"] = "QUATERNION";
         return "byteStride " + std::to_string(e["byteStride"].get<int>()) +
                " must be 8 for filter QUATERNION";
       }},
      {"ATTRIBUTES", "NONE",
       [](Json& e, Json&) {
         e["mode"] = "STRIPS";
         return std::string("unknown mode \"STRIPS\" (ATTRIBUTES, TRIANGLES or INDICES)");
       }},
      {"ATTRIBUTES", "NONE",
       [](Json& e, Json&) {
         e["filter"] = "COLOR";
         return std::string(
             "filter COLOR is not supported by the meshoptimizer this was built with (0.18)");
       }},
  };
  for (const Case& c : cases) {
    int view = -1;
    std::string problem;
    copyGlbEdited(kMeshopt, file, [&](Json& gltf) {
      view = meshoptView(gltf, c.mode, c.filter);
      problem = c.edit(gltf["bufferViews"][view]["extensions"]["EXT_meshopt_compression"],
                       gltf["bufferViews"][view]);
    });
    const std::string message = inputError(file);
    EXPECT_EQ(message.rfind(file.string() + ": bufferViews[" + std::to_string(view) +
                                "].extensions.EXT_meshopt_compression: " + problem +
                                " (reading meshes[0].primitives[",
                            0),
              0u)
        << message;
  }
}

TEST(BrokenMeshopt, AnUncompressedViewOfTheFallbackBufferIsAnInputError) {
  test_support::TempFolder folder("omnishadow-meshopt");
  const fs::path file = folder / "broken.glb";
  int view = -1;
  copyGlbEdited(kMeshopt, file, [&](Json& gltf) {
    view = meshoptView(gltf, "TRIANGLES");
    gltf["bufferViews"][view].erase("extensions");
  });
  EXPECT_EQ(inputError(file).rfind(file.string() + ": accessors[", 0), 0u);
  EXPECT_NE(inputError(file).find(": bufferViews[" + std::to_string(view) +
                                  "] is not compressed, but its buffers[1] is a meshopt fallback "
                                  "buffer without data"),
            std::string::npos)
      << inputError(file);
}

// ---------------------------------------------------------------------------------------------
// What the real files above do not use: mode INDICES and the EXPONENTIAL and QUATERNION filters,
// encoded here with meshoptimizer's own encoders, on positions, indices and the rotations of
// EXT_mesh_gpu_instancing (as gltfpack -cc writes instance data).

// Appends `bytes` to buffer 0 (4-byte aligned) and returns their offset.
std::size_t appendToBuffer(tinygltf::Model& model, const std::vector<unsigned char>& bytes) {
  std::vector<unsigned char>& data = model.buffers.at(0).data;
  while (data.size() % 4 != 0) data.push_back(0);
  const std::size_t offset = data.size();
  data.insert(data.end(), bytes.begin(), bytes.end());
  return offset;
}

// A bufferView of count * stride bytes whose data is `encoded` under EXT_meshopt_compression,
// whose extension object goes to `extensions` (tinygltf 2.7 does not write bufferView
// extensions: they are added to the written file). Its own (fallback) range is buffer 0's start,
// which the loader must never read.
int addCompressedView(tinygltf::Model& model, std::vector<std::pair<int, Json>>& extensions,
                      const std::vector<unsigned char>& encoded, std::size_t count,
                      std::size_t stride, const std::string& mode, const std::string& filter) {
  const std::size_t offset = appendToBuffer(model, encoded);
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteLength = count * stride;
  if (mode == "ATTRIBUTES") view.byteStride = stride;
  model.bufferViews.push_back(view);
  const int index = static_cast<int>(model.bufferViews.size()) - 1;
  extensions.push_back({index,
                        {{"buffer", 0},
                         {"byteOffset", offset},
                         {"byteLength", encoded.size()},
                         {"byteStride", stride},
                         {"count", count},
                         {"mode", mode},
                         {"filter", filter}}});
  return index;
}

std::vector<unsigned char> encodeVertices(const void* data, std::size_t count, std::size_t stride) {
  std::vector<unsigned char> out(meshopt_encodeVertexBufferBound(count, stride));
  out.resize(meshopt_encodeVertexBuffer(out.data(), out.size(), data, count, stride));
  return out;
}

TEST(MeshoptFilters, ExponentialQuaternionAndIndexSequenceDecodeToWhatWasEncoded) {
  builder::GltfBuilder b;
  builder::MeshData triangle;
  triangle.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  triangle.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  triangle.indices = {0, 1, 2};
  const int mesh = b.addMesh(triangle);
  const int node = b.addNode("instanced", {}, mesh);
  tinygltf::Model& model = b.model();
  tinygltf::Primitive& primitive = model.meshes[static_cast<std::size_t>(mesh)].primitives[0];
  std::vector<std::pair<int, Json>> extensions;

  // Positions 0.5, 1.25, 3 (exact in a 23-bit mantissa), as floats through EXPONENTIAL.
  const float positions[] = {0.5f, 0, 0, 1.25f, 0, 0, 0, 3, 0};
  std::vector<std::uint32_t> exponential(9);
  meshopt_encodeFilterExp(exponential.data(), 3, 12, 23, positions);
  const int positionView =
      addCompressedView(model, extensions, encodeVertices(exponential.data(), 3, 12), 3, 12,
                        "ATTRIBUTES", "EXPONENTIAL");
  tinygltf::Accessor& position =
      model.accessors[static_cast<std::size_t>(primitive.attributes["POSITION"])];
  position.bufferView = positionView;
  position.byteOffset = 0;

  // Indices 2, 1, 0 as 16-bit, through INDICES.
  const unsigned int order[] = {2, 1, 0};
  std::vector<unsigned char> sequence(meshopt_encodeIndexSequenceBound(3, 3));
  sequence.resize(meshopt_encodeIndexSequence(sequence.data(), sequence.size(), order, 3));
  tinygltf::Accessor& indices = model.accessors[static_cast<std::size_t>(primitive.indices)];
  indices.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
  indices.byteOffset = 0;
  indices.bufferView = addCompressedView(model, extensions, sequence, 3, 2, "INDICES", "NONE");

  // Two instance rotations, identity and 90 degrees about +Y (x, y, z, w), through QUATERNION
  // into normalized shorts.
  const float h = std::sqrt(0.5f);
  const float rotations[] = {0, 0, 0, 1, 0, h, 0, h};
  std::vector<std::int16_t> quaternions(8);
  meshopt_encodeFilterQuat(quaternions.data(), 2, 8, 16, rotations);
  tinygltf::Accessor rotation;
  rotation.bufferView =
      addCompressedView(model, extensions, encodeVertices(quaternions.data(), 2, 8), 2, 8,
                        "ATTRIBUTES", "QUATERNION");
  rotation.componentType = TINYGLTF_COMPONENT_TYPE_SHORT;
  rotation.normalized = true;
  rotation.type = TINYGLTF_TYPE_VEC4;
  rotation.count = 2;
  model.accessors.push_back(rotation);
  model.nodes[static_cast<std::size_t>(node)].extensions["EXT_mesh_gpu_instancing"] =
      tinygltf::Value(tinygltf::Value::Object{
          {"attributes",
           tinygltf::Value(tinygltf::Value::Object{
               {"ROTATION", tinygltf::Value(static_cast<int>(model.accessors.size()) - 1)}})}});
  model.extensionsUsed = {"EXT_meshopt_compression", "EXT_mesh_gpu_instancing",
                          "KHR_mesh_quantization"};
  model.extensionsRequired = {"EXT_meshopt_compression"};
  // The fallback range (buffer 0's start) is garbage to anyone who reads it.
  std::fill_n(model.buffers[0].data.begin(), 36, 0xFF);

  test_support::TempFolder folder("omnishadow-meshopt-filters");
  b.write(folder / "plain.glb", builder::FileFormat::Glb);
  copyGlbEdited(folder / "plain.glb", folder / "filters.glb", [&](Json& gltf) {
    for (const auto& [view, extension] : extensions) {
      gltf["bufferViews"][view]["extensions"]["EXT_meshopt_compression"] = extension;
    }
  });
  const Scene scene = loadGltf(folder / "filters.glb");
  ASSERT_EQ(scene.meshes.size(), 1u) << (scene.warnings.empty() ? "" : scene.warnings[0]);
  const Mesh& m = scene.meshes[0];
  ASSERT_EQ(m.positions.size(), 3u);
  EXPECT_EQ(m.positions[0], glm::vec3(0.5f, 0, 0));
  EXPECT_EQ(m.positions[1], glm::vec3(1.25f, 0, 0));
  EXPECT_EQ(m.positions[2], glm::vec3(0, 3, 0));
  EXPECT_EQ(m.indices, (std::vector<std::uint32_t>{2, 1, 0}));
  ASSERT_EQ(scene.instances.size(), 2u);
  // +X (1.25, 0, 0) stays, then turns into -Z; 16-bit quaternions are good to about 1e-4.
  const glm::vec3 p0 = scene.instances[0].world * glm::vec4(m.positions[1], 1.0f);
  const glm::vec3 p1 = scene.instances[1].world * glm::vec4(m.positions[1], 1.0f);
  EXPECT_LE(glm::length(p0 - glm::vec3(1.25f, 0, 0)), 1e-3f);
  EXPECT_LE(glm::length(p1 - glm::vec3(0, 0, -1.25f)), 1e-3f);
}

}  // namespace
}  // namespace omnishadow::compressed_geometry_test
