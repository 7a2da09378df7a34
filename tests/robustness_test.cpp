// Hostile and broken inputs through the real binary: files outside the scene's folder,
// non-finite data, empty scenes, memory limits, broken glTF and lights files. Each refused
// input: exit status 2, one line, no output file. Then what the environment can break: a full
// disk, a GL error, a lost context (exit status 1, still no output file).
#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "scenes/builder/gltf_builder.h"
#include "tests/support/gl_fault.h"
#include "tests/support/run_binary.h"
#include "tests/support/temp_folder.h"

namespace robustness_test {

namespace {

namespace fs = std::filesystem;
namespace test_support = omnishadow::test_support;
using omnishadow::builder::FileFormat;
using omnishadow::builder::GltfBuilder;

using test_support::filesIn;
using test_support::readFile;
using Result = test_support::RunResult;

std::vector<std::string> glFault(const std::string& fault);

// Under ThreadSanitizer (scripts/test-threads.sh) a worker that the fault-injection library makes
// raise SIGSEGV gets the runtime's own report instead of the crash a batch is checked to survive.
#if defined(__SANITIZE_THREAD__)
constexpr bool kWorkerCrashesAreReports = true;
#else
constexpr bool kWorkerCrashesAreReports = false;
#endif

class RobustnessTest : public ::testing::Test {
 protected:
  void SetUp() override {
    fs::create_directories(root_ / "scene");
    fs::create_directories(root_ / "out");
  }

  // `omnishadow args...` with out/ as the working directory, `environment` ("NAME=value") added
  // to the test's and files limited to `fileSizeLimit` bytes.
  Result run(const std::vector<std::string>& args, const std::vector<std::string>& environment = {},
             std::optional<std::uint64_t> fileSizeLimit = std::nullopt) {
    test_support::RunOptions options;
    options.workingDirectory = root_ / "out";
    options.environment = environment;
    options.fileSizeLimit = fileSizeLimit;
    return test_support::runOmnishadow(args, options);
  }

  // A 32x24 render of `scene` with `lights` while the GL fault library claims a smaller GL
  // limit (`limit`: "OMNISHADOW_GL_MAX_...=N", tests/support/gl_fault.cpp).
  Result renderClaimingGlLimit(const fs::path& scene, const fs::path& lights,
                               const std::string& limit) {
    std::vector<std::string> environment = glFault("none");
    environment.push_back(limit);
    return run({"render", scene.string(), "-l", lights.string(), "-o", "a.png", "--width", "32",
                "--height", "24"},
               environment);
  }

  // A floor with a box, written as .gltf with an external .bin and PNG texture (or as `format`
  // says), and beside it <stem>.lights.json, which a render reads by default: one light with a
  // small shadow map. The texture is 4x4 texels, or the GL fault library's marker size when
  // `glFault`.
  fs::path writeScene(const std::string& name = "scene.gltf",
                      FileFormat format = FileFormat::GltfExternal, bool glFault = false) {
    GltfBuilder b;
    const int w = glFault ? test_support::kGlFaultMarkerWidth : 4;
    const int h = glFault ? test_support::kGlFaultMarkerHeight : 4;
    std::vector<std::uint8_t> pixels(static_cast<std::size_t>(w * h * 4), 200);
    omnishadow::builder::MaterialDesc m;
    m.baseColorTexture = b.addTexture(w, h, pixels, "tex");
    const int material = b.addMaterial(m);
    b.addNode("floor", {}, b.addMesh(omnishadow::builder::makePlane(4.0f), {.material = material}));
    b.addNode("box", {.translation = {0, 0.5f, 0}},
              b.addMesh(omnishadow::builder::makeBox(glm::vec3(0.5f)), {.material = material}));
    const fs::path path = root_ / "scene" / name;
    b.write(path, format);
    std::ofstream(path.parent_path() / (path.stem().string() + ".lights.json"))
        << R"({"lights": [{"name": "key", "position": [1, 3, 1], "shadow": {"resolution": 32}}]})";
    return path;
  }

  // batch/: a.glb and c.glb, and b.glb between them with the GL fault marker texture.
  void writeBatchWithAFaultyMiddleScene() {
    fs::create_directories(root_ / "batch");
    for (const std::string name : {"a", "c"}) {
      const fs::path scene = writeScene(name + ".glb", FileFormat::Glb);
      fs::rename(scene, root_ / "batch" / scene.filename());
    }
    const fs::path bad = writeScene("b.glb", FileFormat::Glb, true);
    fs::rename(bad, root_ / "batch" / "b.glb");
  }

  nlohmann::json readJson(const fs::path& path) { return nlohmann::json::parse(readFile(path)); }
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

  test_support::TempFolder root_{"omnishadow-robust"};
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

// ---------------------------------------------------------------------------------------------
// Broken glTF files through the CLI: one line naming the file and the glTF object or field

namespace {

using Json = nlohmann::json;

std::string at(const std::string& array, int index) {
  return array + "[" + std::to_string(index) + "]";
}

void writeBytes(const fs::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

std::string le32(std::uint32_t v) {
  std::string bytes;
  for (int shift = 0; shift < 32; shift += 8) bytes += static_cast<char>((v >> shift) & 0xff);
  return bytes;
}

std::uint32_t readLe32(const std::string& bytes, std::size_t offset) {
  std::uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = v << 8 | static_cast<unsigned char>(bytes[offset + i]);
  return v;
}

// Edits scene.gltf (written with an external .bin) and returns what the message must say after
// "<scene>: ". Accessor and view indices are looked up, not assumed: the builder decides them.
using GltfEdit = std::function<std::string(Json& gltf, const fs::path& folder)>;
// Edits the bytes of scene.glb likewise.
using GlbEdit = std::function<std::string(std::string& glb)>;

struct BrokenScene {
  std::string name;
  GltfEdit gltf;  // one of the two
  GlbEdit glb;
};

void PrintTo(const BrokenScene& c, std::ostream* os) {
  *os << c.name;
}

// The floor (mesh 0, drawn first) and its accessors.
int floorAttribute(const Json& gltf, const std::string& semantic) {
  return gltf["meshes"][0]["primitives"][0]["attributes"][semantic];
}
int floorIndices(const Json& gltf) {
  return gltf["meshes"][0]["primitives"][0]["indices"];
}
int viewOf(const Json& gltf, int accessor) {
  return gltf["accessors"][accessor]["bufferView"];
}

// Gives the floor's `semantic` accessor a component type the loader must refuse.
GltfEdit floorAttributeAs(const std::string& semantic, int componentType, const std::string& name) {
  return [=](Json& gltf, const fs::path&) {
    const int accessor = floorAttribute(gltf, semantic);
    gltf["accessors"][accessor]["componentType"] = componentType;
    return "meshes[0].primitives[0].attributes." + semantic + ": " + at("accessors", accessor) +
           " has componentType " + name + "; " + semantic + " must be FLOAT";
  };
}

const BrokenScene kBrokenScenes[] = {
    {"MissingBuffer",
     [](Json& gltf, const fs::path& folder) {
       const std::string bin = gltf["buffers"][0]["uri"];
       fs::remove(folder / bin);
       return "buffers[0]: uri \"" + bin + "\": no such file";
     },
     {}},
    {"MissingImage",
     [](Json& gltf, const fs::path& folder) {
       const std::string image = gltf["images"][0]["uri"];
       fs::remove(folder / image);
       return "images[0] \"tex\": cannot read or decode " + image;
     },
     {}},
    {"AccessorPastItsBufferView",
     [](Json& gltf, const fs::path&) {
       const int accessor = floorAttribute(gltf, "NORMAL");
       gltf["accessors"][accessor]["byteOffset"] = 4;
       return at("accessors", accessor) + ": extends past the end of " +
              at("bufferViews", viewOf(gltf, accessor));
     },
     {}},
    {"AccessorCountPastItsBufferView",
     [](Json& gltf, const fs::path&) {
       const int accessor = floorIndices(gltf);
       gltf["accessors"][accessor]["count"] = 600;
       return at("accessors", accessor) + ": extends past the end of " +
              at("bufferViews", viewOf(gltf, accessor));
     },
     {}},
    {"BufferViewPastItsBuffer",
     [](Json& gltf, const fs::path&) {
       const int view = viewOf(gltf, floorIndices(gltf));
       gltf["bufferViews"][view]["byteLength"] = gltf["buffers"][0]["byteLength"].get<int>() + 4;
       return at("bufferViews", view) + ": extends past the end of buffers[0]";
     },
     {}},
    {"StrideSmallerThanTheElement",
     [](Json& gltf, const fs::path&) {
       const int accessor = floorAttribute(gltf, "POSITION");
       const int view = viewOf(gltf, accessor);
       gltf["bufferViews"][view]["byteStride"] = 8;
       return at("accessors", accessor) + ": byteStride 8 of " + at("bufferViews", view) +
              " is smaller than the element size 12";
     },
     {}},
    {"StrideNotAMultipleOf4",
     [](Json& gltf, const fs::path&) {
       const int view = viewOf(gltf, floorAttribute(gltf, "POSITION"));
       gltf["bufferViews"][view]["byteStride"] = 14;
       return at("bufferViews", view) + ": byteStride 14 is not a multiple of 4 from 4 to 252";
     },
     {}},
    {"PositionAsUnsignedByte", floorAttributeAs("POSITION", 5121, "UNSIGNED_BYTE"), {}},
    {"NormalAsShort", floorAttributeAs("NORMAL", 5122, "SHORT"), {}},
    {"IndicesAsFloat",
     [](Json& gltf, const fs::path&) {
       const int accessor = floorIndices(gltf);
       gltf["accessors"][accessor]["componentType"] = 5126;
       return "meshes[0].primitives[0].indices: " + at("accessors", accessor) +
              " must be SCALAR unsigned byte, short or int";
     },
     {}},
    {"IndexNotBelowTheVertexCount",
     [](Json& gltf, const fs::path& folder) {
       const int accessor = floorIndices(gltf);
       EXPECT_EQ(gltf["accessors"][accessor]["componentType"], 5125) << "expected 32-bit indices";
       const Json& view = gltf["bufferViews"][viewOf(gltf, accessor)];
       const std::size_t offset = view.value("byteOffset", std::size_t{0}) +
                                  gltf["accessors"][accessor].value("byteOffset", std::size_t{0});
       const int vertices = gltf["accessors"][floorAttribute(gltf, "POSITION")]["count"];
       std::fstream bin(folder / gltf["buffers"][0]["uri"].get<std::string>(),
                        std::ios::in | std::ios::out | std::ios::binary);
       bin.seekp(static_cast<std::streamoff>(offset));
       bin << le32(static_cast<std::uint32_t>(vertices));
       return "meshes[0].primitives[0]: index " + std::to_string(vertices) + " >= vertex count " +
              std::to_string(vertices);
     },
     {}},
    {"DracoDataThatDoesNotDecode",
     [](Json& gltf, const fs::path&) {
       // The floor's positions are no Draco stream.
       const int view = viewOf(gltf, floorAttribute(gltf, "POSITION"));
       gltf["extensionsUsed"] = {"KHR_draco_mesh_compression"};
       gltf["extensionsRequired"] = {"KHR_draco_mesh_compression"};
       gltf["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"] = {
           {"bufferView", view}, {"attributes", {{"POSITION", 0}}}};
       return "meshes[0].primitives[0].extensions.KHR_draco_mesh_compression: the Draco data in " +
              at("bufferViews", view) + " does not decode: Not a Draco file.";
     },
     {}},
    {"MeshoptDataThatDoesNotDecode",
     [](Json& gltf, const fs::path&) {
       // The floor's positions, said to be compressed: their first byte is no meshopt header.
       const int view = viewOf(gltf, floorAttribute(gltf, "POSITION"));
       const int count = gltf["accessors"][floorAttribute(gltf, "POSITION")]["count"];
       gltf["extensionsUsed"] = {"EXT_meshopt_compression"};
       gltf["extensionsRequired"] = {"EXT_meshopt_compression"};
       gltf["bufferViews"][view]["byteStride"] = 12;
       gltf["bufferViews"][view]["extensions"]["EXT_meshopt_compression"] = {
           {"buffer", 0},      {"byteOffset", gltf["bufferViews"][view].value("byteOffset", 0)},
           {"byteLength", 48}, {"byteStride", 12},
           {"count", count},   {"mode", "ATTRIBUTES"}};
       return at("bufferViews", view) +
              ".extensions.EXT_meshopt_compression: the ATTRIBUTES data does not decode: no "
              "meshopt header (reading meshes[0].primitives[0])";
     },
     {}},
    {"TruncatedGlb",
     {},
     [](std::string& glb) {
       const std::size_t size = glb.size();
       glb.resize(size / 2);
       return "GLB header: length " + std::to_string(size) + " is more than the file's " +
              std::to_string(size / 2) + " bytes (truncated file?)";
     }},
    {"GlbShorterThanItsHeader",
     {},
     [](std::string& glb) {
       glb.resize(10);
       return std::string("truncated .glb: 10 bytes, less than the 12-byte header");
     }},
    {"BadGlbMagic",
     {},
     [](std::string& glb) {
       glb[3] = 'X';
       return std::string("not a binary glTF: it starts with \"glTX\", not the magic \"glTF\"");
     }},
    {"GlbJsonChunkPastTheEnd",
     {},
     [](std::string& glb) {
       const auto length = static_cast<std::uint32_t>(glb.size() * 2);
       glb.replace(12, 4, le32(length));
       return "GLB chunk 0 (JSON) at byte 12: length " + std::to_string(length) +
              " extends past the end of the " + std::to_string(glb.size()) + " bytes of the file";
     }},
    {"GlbBinChunkPastTheEnd",
     {},
     [](std::string& glb) {
       const std::size_t binChunk = 20 + readLe32(glb, 12);
       const auto length = static_cast<std::uint32_t>(glb.size());
       glb.replace(binChunk, 4, le32(length));
       return "GLB chunk 1 (BIN) at byte " + std::to_string(binChunk) + ": length " +
              std::to_string(length) + " extends past the end of the " +
              std::to_string(glb.size()) + " bytes of the file";
     }},
};

class BrokenSceneTest : public RobustnessTest, public ::testing::WithParamInterface<BrokenScene> {};

TEST_P(BrokenSceneTest, FailsWithOneLineNamingTheFileAndTheObject) {
  const BrokenScene& c = GetParam();
  fs::path scene;
  std::string expected;
  if (c.gltf) {
    scene = writeScene("scene.gltf");
    Json gltf = readJson(scene);
    expected = c.gltf(gltf, scene.parent_path());
    writeJson(scene, gltf);
  } else {
    scene = writeScene("scene.glb", FileFormat::Glb);
    std::string glb = readFile(scene);
    expected = c.glb(glb);
    writeBytes(scene, glb);
  }
  const std::vector<std::string> inputs = filesIn(root_ / "scene");

  const Result r = render(scene);

  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_EQ(r.err, "omnishadow: " + scene.string() + ": " + expected + "\n");
  EXPECT_EQ(r.out, "");
  EXPECT_TRUE(outputEmpty());
  EXPECT_EQ(filesIn(root_ / "scene"), inputs);
}

INSTANTIATE_TEST_SUITE_P(Robustness, BrokenSceneTest, ::testing::ValuesIn(kBrokenScenes),
                         [](const ::testing::TestParamInfo<BrokenScene>& test) {
                           return test.param.name;
                         });

// ---------------------------------------------------------------------------------------------
// Lights files

TEST_F(RobustnessTest, DuplicateLightNamesAreAnInputError) {
  const fs::path scene = writeScene();
  const fs::path lights = root_ / "scene" / "lights.json";
  std::ofstream(lights) << R"({"lights": [{"name": "key", "position": [0, 2, 0]},
                                         {"name": "key", "position": [1, 2, 0]}]})";
  const Result r = render(scene, {"-l", lights.string()});
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_EQ(r.err, "omnishadow: " + lights.string() +
                       ": lights[1].name: duplicate name \"key\" (also lights[0])\n");
  EXPECT_TRUE(outputEmpty());
}

// ---------------------------------------------------------------------------------------------
// A full disk: writes fail with EFBIG once a file would pass the limit, as with ENOSPC

TEST_F(RobustnessTest, AFullDiskFailsTheRunAndLeavesNoFile) {
  const fs::path scene = writeScene();
  const std::vector<std::string> args = {"render", scene.string(), "--width", "32",    "--height",
                                         "24",     "-o",           "a.png",   "--aov", "sub/c.exr"};
  // The sizes the outputs have when they can be written: a.png fits in `limit` bytes, c.exr
  // (32-bit float AOVs) does not, so the run fails half-way, with a.png written in full.
  ASSERT_EQ(run(args).status, 0);
  const std::uintmax_t png = fs::file_size(root_ / "out" / "a.png");
  const std::uintmax_t aov = fs::file_size(root_ / "out" / "sub" / "c.exr");
  ASSERT_GT(aov, png + 1);
  fs::remove_all(root_ / "out");
  fs::create_directory(root_ / "out");

  // Nothing fits; a.png would be cut short (the PNG encoder does not notice by itself); a.png
  // fits and c.exr does not.
  for (const std::uintmax_t limit : {std::uintmax_t{0}, png / 2, png}) {
    SCOPED_TRACE("file size limit " + std::to_string(limit));
    const Result r = run(args, {}, limit);
    EXPECT_EQ(r.status, 1) << r.err;
    // The output that could not be written, by the name it was given.
    const std::string failed = limit < png ? "a.png" : "sub/c.exr";
    EXPECT_TRUE(r.err.starts_with("omnishadow: cannot write " + failed + ": ")) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_EQ(filesIn(root_ / "out"), std::vector<std::string>{}) << "partial or temporary files";
  }
}

// ---------------------------------------------------------------------------------------------
// GL errors and lost contexts, made by the GL fault library (tests/support/gl_fault.cpp)

// The environment that preloads the fault library with `fault` ("error", "reset" or "none").
std::vector<std::string> glFault(const std::string& fault) {
  const char* preload = std::getenv("LD_PRELOAD");
  const char* asan = std::getenv("ASAN_OPTIONS");
  return {"OMNISHADOW_GL_FAULT=" + fault,
          std::string("LD_PRELOAD=") + OMNISHADOW_GL_FAULT_LIBRARY +
              (preload && *preload ? std::string(":") + preload : ""),
          // Under AddressSanitizer the runtime no longer comes first; it does not need to. The
          // injected SIGSEGV must kill the worker as it would a plain build, not be turned into
          // an ASan report and exit status.
          std::string("ASAN_OPTIONS=") + (asan && *asan ? std::string(asan) + ":" : "") +
              "verify_asan_link_order=0:handle_segv=0"};
}

TEST_F(RobustnessTest, ShadowResolutionAboveTheGlCubeMapLimitIsAnInputError) {
  // Real GLs allow the largest resolution a lights file may ask for (16384, llvmpipe too), so
  // the library makes this one claim a smaller limit.
  const fs::path scene = writeScene();
  const fs::path lights = root_ / "scene" / "lights.json";
  std::ofstream(lights)
      << R"({"lights": [{"name": "big", "position": [0, 2, 0], "shadow": {"resolution": 512}}]})";
  const Result r =
      renderClaimingGlLimit(scene, lights, "OMNISHADOW_GL_MAX_CUBE_MAP_TEXTURE_SIZE=256");
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_EQ(r.err, "omnishadow: " + lights.string() +
                       ": light \"big\": shadow.resolution 512 exceeds this GL's maximum cube map "
                       "size 256\n");
  EXPECT_TRUE(outputEmpty());
}

TEST_F(RobustnessTest, MoreTransmittanceLayersThanTheGlArrayLimitIsAnInputError) {
  // Two point lights inside a translucent (BLEND) box reach it through all six cube faces
  // each: 12 atlas layers, against a GL that claims 6 array layers (enough for each light's
  // cube map on its own).
  GltfBuilder b;
  omnishadow::builder::MaterialDesc glass;
  glass.baseColor = glm::vec4(0.2f, 0.6f, 1.0f, 0.5f);
  glass.alphaMode = "BLEND";
  glass.doubleSided = true;
  b.addNode("floor", {}, b.addMesh(omnishadow::builder::makePlane(4.0f)));
  b.addNode(
      "glass", {.translation = {0, 1.0f, 0}},
      b.addMesh(omnishadow::builder::makeBox(glm::vec3(1.5f)), {.material = b.addMaterial(glass)}));
  const fs::path scene = root_ / "scene" / "glass.gltf";
  b.write(scene, FileFormat::GltfExternal);
  const fs::path lights = root_ / "scene" / "lights.json";
  std::ofstream(lights) << R"({"lights": [
      {"name": "a", "position": [-0.5, 1, 0], "shadow": {"resolution": 32}},
      {"name": "b", "position": [0.5, 1, 0], "shadow": {"resolution": 32}}]})";
  const Result r = renderClaimingGlLimit(scene, lights, "OMNISHADOW_GL_MAX_ARRAY_TEXTURE_LAYERS=6");
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_EQ(r.err,
            "omnishadow: translucent shadows need 12 transmittance layers, more than this "
            "GL's 6 (GL_MAX_ARRAY_TEXTURE_LAYERS): fewer lights with translucentShadows\n");
  EXPECT_TRUE(outputEmpty());
}

TEST_F(RobustnessTest, AGlErrorFailsTheRenderWithoutOutput) {
  const fs::path scene = writeScene("scene.gltf", FileFormat::GltfExternal, true);
  for (const auto& [fault, message] :
       {std::pair<std::string, std::string>{"error", ": GL_INVALID_OPERATION"},
        std::pair<std::string, std::string>{"reset", "the OpenGL context was lost during "}}) {
    SCOPED_TRACE(fault);
    const Result r = run({"render", scene.string(), "-o", "a.png", "--aov", "a.exr", "--width",
                          "32", "--height", "24"},
                         glFault(fault));
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_TRUE(outputEmpty());
  }
  // Without the marker texture the same library changes nothing.
  const fs::path plain = writeScene("plain.gltf");
  const Result r = run({"render", plain.string(), "-o", "a.png", "--width", "32", "--height", "24"},
                       glFault("error"));
  EXPECT_EQ(r.status, 0) << r.err;
}

TEST_F(RobustnessTest, BatchGoesOnAfterAGlErrorOrALostContext) {
  writeBatchWithAFaultyMiddleScene();

  for (const std::string fault : {"error", "reset"}) {
    SCOPED_TRACE(fault);
    fs::remove_all(root_ / "out");
    fs::create_directory(root_ / "out");
    const Result r = run({"batch", (root_ / "batch").string(), "--out", (root_ / "out").string(),
                          "--width", "32", "--height", "24"},
                         glFault(fault));
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_EQ(filesIn(root_ / "out"), (std::vector<std::string>{"a.png", "c.png"})) << r.out;
    EXPECT_NE(r.out.find("FAILED  b.glb"), std::string::npos) << r.out;
    EXPECT_NE(r.err.find("omnishadow: b.glb: "), std::string::npos) << r.err;
    // The scene after the failure renders as it does on its own, in a fresh context.
    EXPECT_EQ(readFile(root_ / "out" / "c.png"), readFile(root_ / "out" / "a.png"));
  }
}

// From a renderer's second frame on, half of the shadow maps of a frame with two or more are
// drawn in a second GL context (passes/shadow_worker.h). Where that context cannot be made, one
// context draws them all, the same pictures, and the job says so once; an error in it fails
// that frame like any GL error, and the next job renders.
TEST_F(RobustnessTest, TheSecondShadowContextFailingCostsNoPicture) {
  const fs::path scene = writeScene("scene.glb", FileFormat::Glb);
  const fs::path folder = scene.parent_path();
  std::ofstream(folder / "near.lights.json") << R"({"lights": [
      {"name": "key", "position": [1, 3, 1], "shadow": {"resolution": 32}},
      {"name": "fill", "position": [-2, 2, 1], "shadow": {"resolution": 32}}]})";
  std::ofstream(folder / "far.lights.json") << R"({"lights": [
      {"name": "key", "position": [1.5, 3, 1], "shadow": {"resolution": 32}},
      {"name": "fill", "position": [-2, 2.5, 1], "shadow": {"resolution": 32}}]})";
  nlohmann::json manifest;
  for (const auto& [lights, output] :
       {std::pair<std::string, std::string>{"near", "1.png"}, {"far", "2.png"}, {"near", "3.png"}})
    manifest["jobs"].push_back({{"scene", scene.filename().string()},
                                {"lights", lights + ".lights.json"},
                                {"outputs", {output}}});
  writeJson(folder / "jobs.json", manifest);
  // One worker process renders the three jobs in order with one renderer: the first frame in
  // one context, the next two in both.
  auto batch = [&](const std::string& fault) {
    fs::remove_all(root_ / "out");
    fs::create_directory(root_ / "out");
    return run({"batch", (folder / "jobs.json").string(), "--out", (root_ / "out").string(),
                "--width", "32", "--height", "24", "--report", (root_ / "report.json").string()},
               glFault(fault));
  };
  const Result plain = batch("none");
  ASSERT_EQ(plain.status, 0) << plain.err;
  std::vector<std::string> pictures;
  for (const char* name : {"1.png", "2.png", "3.png"})
    pictures.push_back(readFile(root_ / "out" / name));

  const Result oneContext = batch("no-shared-context");
  EXPECT_EQ(oneContext.status, 0) << oneContext.err;
  for (std::size_t i = 0; i < pictures.size(); ++i)
    EXPECT_EQ(readFile(root_ / "out" / (std::to_string(i + 1) + ".png")), pictures[i]) << i;
  nlohmann::json report = readJson(root_ / "report.json");
  ASSERT_EQ(report["jobs"].size(), 3u) << report.dump(2);
  EXPECT_EQ(report["jobs"][0]["warnings"].size(), 0u) << report.dump(2);
  ASSERT_EQ(report["jobs"][1]["warnings"].size(), 1u) << report.dump(2);
  EXPECT_TRUE(report["jobs"][1]["warnings"][0].get<std::string>().starts_with(
      "shadow maps are drawn in one GL context: cannot create a shared GL context: "))
      << report.dump(2);
  EXPECT_EQ(report["jobs"][2]["warnings"].size(), 0u) << report.dump(2);  // not tried again

  const Result failing = batch("error-in-shared-context");
  EXPECT_EQ(failing.status, 1) << failing.err;
  EXPECT_EQ(filesIn(root_ / "out"), (std::vector<std::string>{"1.png", "3.png"})) << failing.out;
  EXPECT_NE(failing.err.find("OpenGL error during the shadow pass of light \"fill\": "
                             "GL_INVALID_OPERATION"),
            std::string::npos)
      << failing.err;
  EXPECT_EQ(readFile(root_ / "out" / "3.png"), pictures[2]);
}

// A crash or a hang in one scene costs that scene only: its worker process is replaced and the
// jobs around it render, in a fresh process, as they do on their own.
TEST_F(RobustnessTest, BatchGoesOnAfterAWorkerCrashOrHang) {
  if (kWorkerCrashesAreReports) GTEST_SKIP() << "ThreadSanitizer reports a worker's crash itself";
  writeBatchWithAFaultyMiddleScene();
  const std::vector<std::string> batch = {"batch",    (root_ / "batch").string(),
                                          "--out",    (root_ / "out").string(),
                                          "--width",  "32",
                                          "--height", "24",
                                          "--report", (root_ / "report.json").string()};

  for (const std::string fault : {"crash", "hang"}) {
    SCOPED_TRACE(fault);
    fs::remove_all(root_ / "out");
    fs::create_directory(root_ / "out");
    std::vector<std::string> args = batch;
    // Generous: a worker's first job also compiles the shaders, slowly under the sanitizers.
    args.insert(args.end(), {"--job-timeout", "8"});
    const Result r = run(args, glFault(fault));
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_EQ(filesIn(root_ / "out"), (std::vector<std::string>{"a.png", "c.png"})) << r.out;
    EXPECT_EQ(readFile(root_ / "out" / "c.png"), readFile(root_ / "out" / "a.png"));
    const nlohmann::json report = readJson(root_ / "report.json");
    ASSERT_EQ(report["jobs"].size(), 3u) << report.dump(2);
    EXPECT_EQ(report["jobs"][0]["status"], "rendered");
    EXPECT_EQ(report["jobs"][1]["status"], "failed");
    EXPECT_EQ(report["jobs"][2]["status"], "rendered");
    const std::string error = report["jobs"][1]["error"];
    if (fault == "hang") {
      EXPECT_EQ(error,
                "timed out after 8 s (--job-timeout) while loading or rendering it; the render "
                "worker was stopped");
    } else {
      EXPECT_EQ(error, "the render worker crashed (signal 11, Segmentation fault)");
    }
    EXPECT_NE(r.out.find("FAILED  b.glb: " + error), std::string::npos) << r.out;
    EXPECT_EQ(report["summary"]["failed"], 1);
  }

  // Resuming renders the one that failed, and only it.
  fs::last_write_time(root_ / "out" / "a.png",
                      fs::file_time_type::clock::now() - std::chrono::hours(1));
  const auto before = fs::last_write_time(root_ / "out" / "a.png");
  std::vector<std::string> args = batch;
  args.push_back("--skip-existing");
  const Result resumed = run(args, glFault("none"));
  EXPECT_EQ(resumed.status, 0) << resumed.err;
  EXPECT_EQ(filesIn(root_ / "out"), (std::vector<std::string>{"a.png", "b.png", "c.png"}));
  EXPECT_EQ(fs::last_write_time(root_ / "out" / "a.png"), before);
  EXPECT_EQ(readJson(root_ / "report.json")["summary"]["skipped"], 2);
}

// A worker that cannot even make its context is not restarted forever: after three deaths in a
// row before any job started, the batch fails, with the reason and without output.
TEST_F(RobustnessTest, BatchGivesUpOnAWorkerThatDiesBeforeAnyJob) {
  if (kWorkerCrashesAreReports) GTEST_SKIP() << "ThreadSanitizer reports a worker's crash itself";
  fs::create_directories(root_ / "batch");
  const fs::path scene = writeScene("a.glb", FileFormat::Glb);
  fs::rename(scene, root_ / "batch" / "a.glb");
  const Result r = run({"batch", (root_ / "batch").string(), "--out", (root_ / "out").string(),
                        "--width", "32", "--height", "24"},
                       glFault("crash-context"));
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_TRUE(contains(r.err,
                       "omnishadow: the render worker crashed (signal 11, Segmentation fault) 3 "
                       "times before it started a job\n"))
      << r.err;
  EXPECT_TRUE(outputEmpty());
}

}  // namespace

}  // namespace robustness_test
