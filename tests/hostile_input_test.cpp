// Hostile input, round two (issue 16): one regression test per class of failure the attacker
// found, through the real binary. Every input is generated here: deep nesting, FIFOs, /dev/zero,
// odd names. Runs go through `timeout`, so that a hang fails the test (status 137) instead of
// stalling the suite, and every refusal must be exit 2, one line, no output.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/types.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "tests/support/cli_fixture.h"
#include "tests/support/run_binary.h"
#include "tests/support/temp_folder.h"

namespace hostile_input_test {

namespace {

namespace fs = std::filesystem;
using omnishadow::builder::FileFormat;
using omnishadow::test_support::contains;
using omnishadow::test_support::filesIn;
using omnishadow::test_support::readFile;
using omnishadow::test_support::RunResult;
using json = nlohmann::json;

// Far deeper than the limit (128) and than tinygltf's recursion survives (~30,000).
constexpr int kDeep = 100000;

std::string nestedArrays(int depth) {
  return std::string(static_cast<std::size_t>(depth), '[') +
         std::string(static_cast<std::size_t>(depth), ']');
}

int lines(const std::string& text) {
  return static_cast<int>(std::count(text.begin(), text.end(), '\n'));
}

void writeBytes(const fs::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

std::uint32_t le32(const std::string& b, std::size_t at) {
  return std::uint32_t(static_cast<unsigned char>(b[at])) |
         std::uint32_t(static_cast<unsigned char>(b[at + 1])) << 8 |
         std::uint32_t(static_cast<unsigned char>(b[at + 2])) << 16 |
         std::uint32_t(static_cast<unsigned char>(b[at + 3])) << 24;
}

void putLe32(std::string& b, std::size_t at, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) b[at + static_cast<std::size_t>(i)] = static_cast<char>(v >> (8 * i));
}

// A .glb with its JSON chunk replaced by `text` (padded with spaces, as the format says).
std::string glbWithJson(const std::string& glb, std::string text) {
  while (text.size() % 4 != 0) text += ' ';
  const std::uint32_t oldLength = le32(glb, 12);
  std::string out = glb.substr(0, 20) + text + glb.substr(20 + oldLength);
  putLe32(out, 12, static_cast<std::uint32_t>(text.size()));
  putLe32(out, 8, static_cast<std::uint32_t>(out.size()));
  return out;
}

std::uint32_t crc32(const std::string& bytes) {
  std::uint32_t crc = 0xFFFFFFFFu;
  for (unsigned char c : bytes) {
    crc ^= c;
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
  }
  return ~crc;
}

std::string pngChunk(const std::string& type, const std::string& data) {
  std::string chunk(4, '\0');
  for (int i = 0; i < 4; ++i)
    chunk[static_cast<std::size_t>(i)] = static_cast<char>(data.size() >> (24 - 8 * i));
  const std::string body = type + data;
  const std::uint32_t crc = crc32(body);
  chunk += body;
  for (int i = 0; i < 4; ++i) chunk += static_cast<char>(crc >> (24 - 8 * i));
  return chunk;
}

// A small, well-formed PNG header claiming width x height RGBA8: IHDR, a token IDAT, IEND.
std::string pngClaiming(std::uint32_t width, std::uint32_t height) {
  std::string ihdr;
  for (std::uint32_t v : {width, height})
    for (int shift = 24; shift >= 0; shift -= 8) ihdr += static_cast<char>((v >> shift) & 0xff);
  ihdr += std::string("\x08\x06\x00\x00\x00", 5);
  return std::string("\x89PNG\r\n\x1a\n", 8) + pngChunk("IHDR", ihdr) +
         pngChunk("IDAT", std::string("\x78\x9c\x63\x00\x00\x00\x01\x00\x01", 9)) +
         pngChunk("IEND", "");
}

class HostileInputTest : public omnishadow::test_support::CliFixture {
 protected:
  HostileInputTest() : CliFixture("omnishadow-hostile") {}

  // `omnishadow args...` in out/, killed after 60 s: a hang is status 137, not a stuck suite.
  RunResult runBounded(const std::vector<std::string>& args) {
    std::vector<std::string> argv = {"/usr/bin/timeout", "-s", "KILL", "60",
                                     omnishadow::test_support::omnishadowBinary().string()};
    argv.insert(argv.end(), args.begin(), args.end());
    return omnishadow::test_support::runProgram(argv,
                                                omnishadow::test_support::RunOptions::in(out_));
  }

  RunResult render(const fs::path& scene, std::vector<std::string> extra = {}) {
    std::vector<std::string> args = {"render",  scene.string(), "-o",       "a.png",
                                     "--width", "32",           "--height", "24"};
    args.insert(args.end(), extra.begin(), extra.end());
    return runBounded(args);
  }

  // Exit 2, one line naming `part`, nothing written to out/.
  ::testing::AssertionResult refused(const RunResult& r, const std::string& part) {
    if (r.status != 2)
      return ::testing::AssertionFailure() << "status " << r.status << ": " << r.err;
    if (lines(r.err) != 1) return ::testing::AssertionFailure() << "not one line: " << r.err;
    if (!contains(r.err, part)) return ::testing::AssertionFailure() << r.err;
    if (!filesIn(out_).empty()) return ::testing::AssertionFailure() << "output written";
    return ::testing::AssertionSuccess();
  }

  fs::path boxScene(const std::string& name, FileFormat format = FileFormat::GltfEmbedded) {
    const fs::path path = input(name);
    omnishadow::test_support::writeBoxScene(path, {.format = format});
    return path;
  }

  json readJson(const fs::path& path) { return json::parse(readFile(path)); }
  void writeJson(const fs::path& path, const json& value) { std::ofstream(path) << value.dump(); }

  // A FIFO at `path`; whoever opens it for reading without O_NONBLOCK waits for a writer that
  // never comes.
  fs::path fifo(const fs::path& path) {
    fs::create_directories(path.parent_path());
    EXPECT_EQ(::mkfifo(path.c_str(), 0600), 0) << path;
    return path;
  }
};

// ---------------------------------------------------------------------------------------------
// 1. Crashes: deep nesting

TEST_F(HostileInputTest, DeeplyNestedGltfExtrasAreAnInputErrorNotACrash) {
  const fs::path scene = boxScene("s/deep.gltf");
  std::string text = readFile(scene);
  text.insert(1, "\"extras\": " + nestedArrays(kDeep) + ",\n");
  writeBytes(scene, text);
  EXPECT_TRUE(refused(render(scene), "deep.gltf:1:139: JSON nests deeper than 128 levels"));
}

TEST_F(HostileInputTest, DeeplyNestedGlbJsonChunkIsAnInputErrorNotACrash) {
  const fs::path scene = boxScene("s/deep.glb", FileFormat::Glb);
  const std::string glb = readFile(scene);
  std::string text = glb.substr(20, le32(glb, 12));
  text.insert(text.find('{') + 1, "\"extras\": {\"a\": " + nestedArrays(kDeep) + "},");
  writeBytes(scene, glbWithJson(glb, text));
  EXPECT_TRUE(refused(render(scene), "deep.glb: GLB JSON chunk:"));
  EXPECT_TRUE(refused(runBounded({"info", scene.string()}), "JSON nests deeper than 128 levels"));
}

TEST_F(HostileInputTest, NestingUpToTheLimitStillLoads) {
  // The root object is level 1, "extras" adds 127 more: exactly the limit.
  const fs::path scene = boxScene("s/nested.gltf");
  std::string text = readFile(scene);
  text.insert(1, "\"extras\": " + nestedArrays(127) + ",");
  writeBytes(scene, text);
  const RunResult r = runBounded({"info", scene.string()});
  EXPECT_EQ(r.status, 0) << r.err;
}

TEST_F(HostileInputTest, DeeplyNestedLightsFileIsAnInputErrorNotACrash) {
  const fs::path scene = boxScene("s/a.gltf");
  // The value is wrong as well as deep: building its message once crashed in nlohmann's dump().
  const fs::path lights = writeText("deep.json", "{\"lights\": " + nestedArrays(kDeep) + "}");
  EXPECT_TRUE(refused(render(scene, {"-l", lights.string()}),
                      "deep.json:1:139: JSON nests deeper than 128 levels"));
}

TEST_F(HostileInputTest, DeeplyNestedManifestIsAnInputErrorNotACrash) {
  boxScene("m/a.gltf");
  const fs::path manifest =
      writeText("m/manifest.json",
                "{\"jobs\": [{\"scene\": \"a.gltf\", \"extras\": " + nestedArrays(kDeep) + "}]}");
  EXPECT_TRUE(refused(runBounded({"batch", manifest.string(), "--out", out_.string()}),
                      "manifest.json:1:166: JSON nests deeper than 128 levels"));
}

// Found by fuzz_manifest: nlohmann's out_of_range escaped as exit 1 with its own text.
TEST_F(HostileInputTest, AManifestNumberBeyondADoubleIsAnInputError) {
  const fs::path manifest =
      writeText("m/manifest.json", R"({"jobs": [{"scene": "a.gltf", "width": 5e999}]})");
  EXPECT_TRUE(refused(runBounded({"batch", manifest.string(), "--out", out_.string()}),
                      "manifest.json: a number is too large to be read"));
}

// Found by fuzz_manifest: an output name longer than the file system allows made the overwrite
// check's path resolution throw std::filesystem::filesystem_error out of the manifest reader,
// and the confinement check blamed a symbolic link.
TEST_F(HostileInputTest, AManifestOutputNameTooLongIsAnInputErrorNamingIt) {
  const fs::path scene = boxScene("s/a.gltf");
  const std::string longName(300, 'v');
  const fs::path manifest =
      writeText("m/manifest.json", R"({"jobs": [{"scene": ")" + scene.string() +
                                       R"(", "outputs": [")" + longName + R"(.png"]}]})");
  EXPECT_TRUE(refused(runBounded({"batch", manifest.string(), "--out", out_.string()}),
                      "manifest.json: jobs[0].outputs: \"" + longName +
                          ".png\": File name too long; output names are relative to --out"));
}

// A job whose default output name is longer than the file system allows (its scene's name is)
// fails alone, also when --out exists: the check that no two jobs write one file falls back to
// the lexical path (found by CI's fuzz_manifest run: filesystem_error escaped collectJobs).
TEST_F(HostileInputTest, AJobWhoseOutputNameIsTooLongFailsAloneInAnExistingOut) {
  const fs::path scene = boxScene("s/a.gltf");
  const fs::path tooLong = scene.parent_path() / (std::string(300, 'v') + ".gltf");
  const fs::path manifest =
      writeText("m/manifest.json", R"({"jobs": [{"scene": ")" + scene.string() +
                                       R"("}, {"scene": ")" + tooLong.string() + R"("}]})");
  ASSERT_TRUE(fs::is_directory(out_));
  const RunResult r = runBounded(
      {"batch", manifest.string(), "--out", out_.string(), "--width", "32", "--height", "24"});
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_EQ(filesIn(out_), std::vector<std::string>{"a.png"});
  EXPECT_TRUE(contains(r.out, "FAILED  jobs[1]")) << r.out;
  // --skip-existing asks whether that output exists: a name too long for that is not there.
  const RunResult again = runBounded({"batch", manifest.string(), "--out", out_.string(), "--width",
                                      "32", "--height", "24", "--skip-existing"});
  EXPECT_EQ(again.status, 1) << again.err;
  EXPECT_TRUE(contains(again.out, "FAILED  jobs[1]")) << again.out;
}

TEST_F(HostileInputTest, ABatchWithOneDeeplyNestedSceneRendersTheOthersAndReports) {
  boxScene("s/a.gltf");
  const fs::path deep = boxScene("s/b.gltf");
  std::string text = readFile(deep);
  text.insert(1, "\"extras\": " + nestedArrays(kDeep) + ",");
  writeBytes(deep, text);
  const fs::path report = root_ / "report.json";
  const RunResult r = runBounded({"batch", in("s"), "--out", out_.string(), "--width", "32",
                                  "--height", "24", "--report", report.string()});
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_EQ(filesIn(out_), std::vector<std::string>{"a.png"});
  const json doc = json::parse(readFile(report));
  ASSERT_EQ(doc["jobs"].size(), 2u);
  EXPECT_EQ(doc["jobs"][1]["status"], "failed");
  EXPECT_TRUE(contains(doc["jobs"][1]["error"].get<std::string>(), "JSON nests deeper"));
}

// ---------------------------------------------------------------------------------------------
// 2. Hangs: FIFOs, devices, folder policy, filter radius

TEST_F(HostileInputTest, AFifoOrADeviceAsAnInputIsRefusedAtOnce) {
  const fs::path scene = boxScene("s/a.gltf");
  const fs::path pipe = fifo(input("pipe.gltf"));
  const fs::path pipeJson = fifo(input("pipe.json"));
  const fs::path pipePng = fifo(input("pipe.png"));
  EXPECT_TRUE(refused(render(pipe), "pipe.gltf: cannot read glTF file: is a FIFO"));
  EXPECT_TRUE(refused(runBounded({"info", "/dev/zero"}),
                      "/dev/zero: cannot read glTF file: is a character device"));
  EXPECT_TRUE(refused(render(scene, {"-l", pipeJson.string()}),
                      "pipe.json: cannot read lights file: is a FIFO"));
  EXPECT_TRUE(refused(render(scene, {"-l", "/dev/zero"}),
                      "/dev/zero: cannot read lights file: is a character device"));
  EXPECT_TRUE(refused(runBounded({"batch", pipeJson.string(), "--out", out_.string()}),
                      "pipe.json: cannot read manifest: is a FIFO"));
  EXPECT_TRUE(refused(runBounded({"diff", pipePng.string(), pipePng.string()}),
                      "pipe.png: cannot read image: is a FIFO"));
  EXPECT_TRUE(refused(runBounded({"diff", "/dev/zero", "/dev/zero"}),
                      "/dev/zero: cannot read image: is a character device"));
}

TEST_F(HostileInputTest, AFifoAsABufferOrImageUriIsRefusedAtOnce) {
  const fs::path scene = boxScene("s/a.gltf", FileFormat::GltfExternal);
  const json doc = readJson(scene);
  const std::string bin = doc["buffers"][0]["uri"], png = doc["images"][0]["uri"];
  fs::remove(input("s/" + bin));
  fifo(input("s/" + bin));
  EXPECT_TRUE(refused(render(scene), "uri \"" + bin + "\": is a FIFO (named pipe)"));

  fs::remove(input("s/" + bin));
  omnishadow::test_support::writeBoxScene(input("t/a.gltf"), {.format = FileFormat::GltfExternal});
  fs::rename(input("t/" + bin), input("s/" + bin));
  fs::remove(input("s/" + png));
  fifo(input("s/" + png));
  EXPECT_TRUE(refused(render(scene), "uri \"" + png + "\": is a FIFO (named pipe)"));
}

TEST_F(HostileInputTest, UrisOutsideTheFolderAreRefusedBeforeTheyAreOpened) {
  const fs::path scene = boxScene("s/a.gltf", FileFormat::GltfExternal);
  fifo(input("outside/fifo"));
  json doc = readJson(scene);
  // Had the existence check opened it, this run would hang on the FIFO.
  doc["buffers"][0]["uri"] = "../outside/fifo";
  writeJson(scene, doc);
  EXPECT_TRUE(refused(render(scene), "uri \"../outside/fifo\" is outside the scene's folder"));

  // A link inside the folder that leads out is the same.
  fs::create_symlink(input("outside/fifo"), input("s/link.bin"));
  doc["buffers"][0]["uri"] = "link.bin";
  writeJson(scene, doc);
  EXPECT_TRUE(refused(render(scene), "uri \"link.bin\" is outside the scene's folder"));
}

TEST_F(HostileInputTest, UrisInOtherSchemesAreNamedAsSuch) {
  const fs::path scene = boxScene("s/a.gltf");
  json doc = readJson(scene);
  for (const std::string uri : {"file:a.bin", "http:a.bin", "file:///etc/passwd"}) {
    doc["buffers"][0]["uri"] = uri;
    writeJson(scene, doc);
    EXPECT_TRUE(refused(render(scene), "only data: URIs and relative file paths are supported"))
        << uri;
  }
}

TEST_F(HostileInputTest, VsmFilterRadiusHasAnUpperBound) {
  const fs::path scene = boxScene("s/a.gltf");
  const fs::path lights =
      writeText("l.json", R"({"lights": [{"position": [0, 2, 0], "shadow": {"filter": "vsm",
                   "filterRadius": 10000}}]})");
  EXPECT_TRUE(refused(render(scene, {"-l", lights.string()}),
                      "lights[0].shadow.filterRadius: expected a number in [0, 64], got 10000"));
}

// ---------------------------------------------------------------------------------------------
// 3. Unbounded memory

TEST_F(HostileInputTest, DiffRefusesImagesClaimingMoreThanItReadsBeforeDecoding) {
  const fs::path big = input("big.png");
  writeBytes(big, pngClaiming(16384, 16384));
  EXPECT_TRUE(refused(runBounded({"diff", big.string(), big.string()}),
                      "big.png: cannot read image: 16384x16384 with 4 channels is too large"));
}

// ---------------------------------------------------------------------------------------------
// 4. Writes outside --out

TEST_F(HostileInputTest, ManifestOutputsStayInsideTheOutputFolder) {
  boxScene("m/a.gltf");
  const fs::path outside = root_ / "outside";
  fs::create_directories(outside);
  fs::create_directories(out_ / "sub");
  fs::create_symlink(outside, out_ / "sub" / "away");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {R"("outputs": ["../../x.png"])", "\"../../x.png\": \"..\" would leave the output folder"},
      {R"("outputs": ["ok/../../x.png"])", "would leave the output folder"},
      {"\"outputs\": [\"" + (outside / "x.png").string() + "\"]", "an absolute path"},
      {R"("aov": "../a.exr")", "jobs[0].aov: \"../a.exr\""},
      {R"("outputs": ["sub/away/x.png"])", "a symbolic link below --out leads outside it"},
  };
  for (const auto& [field, message] : cases) {
    const fs::path manifest =
        writeText("m/manifest.json", R"({"jobs": [{"scene": "a.gltf", )" + field + "}]}");
    const RunResult r = runBounded({"batch", manifest.string(), "--out", out_.string()});
    EXPECT_EQ(r.status, 2) << field << ": " << r.err;
    EXPECT_TRUE(contains(r.err, message)) << r.err;
    EXPECT_TRUE(contains(r.err, "output names are relative to --out")) << r.err;
    EXPECT_TRUE(fs::is_empty(outside)) << field;
    EXPECT_FALSE(fs::exists(root_ / "x.png"));
    EXPECT_FALSE(fs::exists(root_ / "a.exr"));
  }
  // A link that stays inside --out is followed.
  fs::create_directories(out_ / "real");
  fs::create_symlink(out_ / "real", out_ / "sub" / "here");
  const fs::path manifest = writeText(
      "m/manifest.json",
      R"({"jobs": [{"scene": "a.gltf", "outputs": ["sub/here/x.png"], "width": 32, "height": 24}]})");
  const RunResult r = runBounded({"batch", manifest.string(), "--out", out_.string()});
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(fs::exists(out_ / "real" / "x.png"));
}

// ---------------------------------------------------------------------------------------------
// 5. Silent wrong results

// A triangle (or what `edit` makes of it) as a .gltf with an embedded buffer.
fs::path writeTriangle(const fs::path& path, const std::function<void(json&)>& edit) {
  // Three float positions, then three normals, little-endian: the bytes as base64.
  json doc = json::parse(R"({
    "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
    "nodes": [{"mesh": 0}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                   "min": [0, 0, 0], "max": [1, 1, 0]}],
    "bufferViews": [{"buffer": 0, "byteLength": 36}],
    "buffers": [{"byteLength": 36, "uri":
      "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}]
  })");
  edit(doc);
  fs::create_directories(path.parent_path());
  std::ofstream(path) << doc.dump();
  return path;
}

TEST_F(HostileInputTest, ASceneThatDrawsNoTriangleIsAnInputError) {
  const auto count = [](int n) { return [n](json& doc) { doc["accessors"][0]["count"] = n; }; };
  EXPECT_TRUE(refused(render(writeTriangle(input("one.gltf"), count(1))),
                      "one.gltf: the scene draws no triangles"));
  EXPECT_TRUE(refused(render(writeTriangle(input("two.gltf"),
                                           [&](json& doc) {
                                             count(2)(doc);
                                             doc["meshes"][0]["primitives"][0]["mode"] = 5;
                                           })),
                      "two.gltf: the scene draws no triangles"));
  // The same file with three vertices renders: the refusal is about the triangles.
  const RunResult r = render(writeTriangle(input("three.gltf"), count(3)));
  EXPECT_EQ(r.status, 0) << r.err;
}

TEST_F(HostileInputTest, InstancesAtTheFloatLimitAreAnInputError) {
  const fs::path scene = writeTriangle(input("far.gltf"), [](json& doc) {
    doc["nodes"] = json::parse(R"([{"mesh": 0, "translation": [3e38, 0, 0]},
                                    {"mesh": 0, "translation": [-3e38, 0, 0]}])");
    doc["scenes"][0]["nodes"] = {0, 1};
  });
  EXPECT_TRUE(refused(render(scene), "far.gltf: the scene's bounds are not finite"));
}

TEST_F(HostileInputTest, ForbiddenGltfValuesAreErrorsNamingTheObject) {
  const std::vector<std::pair<std::function<void(json&)>, std::string>> cases = {
      {[](json& d) { d["meshes"][0]["primitives"][0]["mode"] = -5; },
       "meshes[0].primitives[0].mode: -5 is not one of the modes 0 to 6"},
      {[](json& d) { d["asset"]["minVersion"] = "3.0"; },
       "asset.minVersion: \"3.0\" is not supported"},
      {[](json& d) {
         d["extensionsUsed"] = {"KHR_lights_punctual"};
         d["extensions"]["KHR_lights_punctual"]["lights"] = {
             {{"type", "point"}, {"intensity", -5}}};
         d["nodes"][0]["extensions"]["KHR_lights_punctual"]["light"] = 0;
       },
       "KHR_lights_punctual.lights[0]: intensity -5: expected a finite number >= 0"},
      {[](json& d) {
         d["extensionsUsed"] = {"KHR_lights_punctual"};
         d["extensions"]["KHR_lights_punctual"]["lights"] = {
             {{"type", "spot"}, {"spot", {{"innerConeAngle", 0.7}, {"outerConeAngle", 0.3}}}}};
         d["nodes"][0]["extensions"]["KHR_lights_punctual"]["light"] = 0;
       },
       "KHR_lights_punctual.lights[0]: spot innerConeAngle 0.7 and outerConeAngle 0.3"},
  };
  for (const auto& [edit, message] : cases) {
    EXPECT_TRUE(refused(render(writeTriangle(input("bad.gltf"), edit)), "bad.gltf: " + message));
  }
}

// The largest value of the index type restarts the primitive in WebGL, WebGPU and Metal and is
// a vertex elsewhere; glTF forbids it. 255 (u8) and 65535 (u16) name vertices that exist here
// (POSITION without a bufferView: zeros), so only the restart rule can refuse them.
TEST_F(HostileInputTest, ThePrimitiveRestartIndexIsAnInputErrorNamingTheAccessor) {
  const auto indices = [](int componentType, const std::string& base64, int byteLength,
                          int vertices) {
    return [=](json& doc) {
      doc["accessors"][0] = {{"componentType", 5126},
                             {"count", vertices},
                             {"type", "VEC3"},
                             {"min", {0, 0, 0}},
                             {"max", {0, 0, 0}}};
      doc["buffers"][0] = {{"byteLength", byteLength},
                           {"uri", "data:application/octet-stream;base64," + base64}};
      doc["bufferViews"][0]["byteLength"] = byteLength;
      doc["accessors"].push_back(
          {{"bufferView", 0}, {"componentType", componentType}, {"count", 3}, {"type", "SCALAR"}});
      doc["meshes"][0]["primitives"][0]["indices"] = 1;
    };
  };
  // 0, 1, 255 / 65535 / 2^32-1, little-endian, as base64.
  const std::vector<std::tuple<int, std::string, int, int, std::string>> cases = {
      {5121, "AAH/", 3, 256, "255, the primitive restart value of UNSIGNED_BYTE"},
      {5123, "AAABAP//", 6, 65536, "65535, the primitive restart value of UNSIGNED_SHORT"},
      {5125, "AAAAAAEAAAD/////", 12, 3, "4294967295, the primitive restart value of UNSIGNED_INT"},
  };
  for (const auto& [type, base64, length, vertices, value] : cases) {
    EXPECT_TRUE(refused(
        render(writeTriangle(input("restart.gltf"), indices(type, base64, length, vertices))),
        "restart.gltf: meshes[0].primitives[0].indices: accessors[1] element 2 is " + value +
            ", which glTF forbids"));
  }
  // 0, 1, 254: the same file with a vertex index below the restart value loads.
  const RunResult r =
      runBounded({"info", writeTriangle(input("ok.gltf"), indices(5121, "AAH+", 3, 256))});
  EXPECT_EQ(r.status, 0) << r.err;
}

// Float colors outside 0..1 are clamped (integer ones cannot be): the render equals that of the
// same file with the clamped values, and a warning names the accessor.
TEST_F(HostileInputTest, ColorsOutsideZeroToOneAreClampedWithAWarning) {
  const auto withColors = [](const std::string& base64) {
    return [=](json& doc) {
      doc["buffers"][0]["byteLength"] = 72;
      doc["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64;
      doc["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", 36}, {"byteLength", 36}});
      doc["accessors"].push_back(
          {{"bufferView", 1}, {"componentType", 5126}, {"count", 3}, {"type", "VEC3"}});
      doc["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] = 1;
    };
  };
  const std::string positions = "AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA";
  // (1.5, 0, 0), (0, -0.5, 0), (0, 0, 1) and the clamped (1, 0, 0), (0, 0, 0), (0, 0, 1).
  const RunResult outside = render(
      writeTriangle(input("outside.gltf"),
                    withColors(positions + "AADAPwAAAAAAAAAAAAAAAAAAAL8AAAAAAAAAAAAAAAAAAIA/")));
  EXPECT_EQ(outside.status, 0) << outside.err;
  EXPECT_TRUE(contains(outside.err,
                       "outside.gltf: meshes[0].primitives[0].attributes.COLOR_0: accessors[1] has "
                       "2 values outside 0..1 (the first at element 0); clamped to 0..1"))
      << outside.err;
  fs::rename(output("a.png"), output("outside.png"));
  const RunResult clamped = render(
      writeTriangle(input("clamped.gltf"),
                    withColors(positions + "AACAPwAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAIA/")));
  EXPECT_EQ(clamped.status, 0) << clamped.err;
  EXPECT_FALSE(contains(clamped.err, "COLOR_0"));
  EXPECT_TRUE(omnishadow::test_support::sameBytes(output("outside.png"), output("a.png")));
}

// glTF requires min/max on POSITION accessors; nothing reads them (bounds come from the values),
// so the file draws as it says, with a warning naming each accessor.
TEST_F(HostileInputTest, PositionsWithoutMinMaxAreDrawnWithAWarning) {
  const fs::path scene = writeTriangle(input("nobounds.gltf"), [](json& doc) {
    doc["accessors"][0].erase("min");
    doc["accessors"][0].erase("max");
    // A morph target's POSITION (no bufferView: zeros) without them too.
    doc["accessors"].push_back({{"componentType", 5126}, {"count", 3}, {"type", "VEC3"}});
    doc["meshes"][0]["primitives"][0]["targets"] = {{{"POSITION", 1}}};
  });
  const RunResult r = render(scene);
  EXPECT_EQ(r.status, 0) << r.err;
  for (const std::string object :
       {"attributes.POSITION: accessors[0]", "targets[0].POSITION: accessors[1]"}) {
    EXPECT_TRUE(contains(r.err, "nobounds.gltf: meshes[0].primitives[0]." + object +
                                    " has no min/max, which glTF requires; bounds are computed "
                                    "from its values"))
        << r.err;
  }
  EXPECT_TRUE(fs::exists(output("a.png")));
}

// What tinygltf reads as absent (a negative byteStride, a light range of 0) or reports without
// its object is checked on the JSON itself.
TEST_F(HostileInputTest, ValuesTinygltfWouldDropAreErrorsNamingTheObject) {
  const std::vector<std::pair<std::function<void(json&)>, std::string>> cases = {
      {[](json& d) { d["bufferViews"][0]["byteStride"] = -12; },
       "bufferViews[0]: byteStride -12 is not a multiple of 4 from 4 to 252"},
      {[](json& d) {
         d["extensionsUsed"] = {"KHR_lights_punctual"};
         d["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "point"}, {"range", 0}}};
       },
       "KHR_lights_punctual.lights[0].range: 0: expected a number > 0"},
      {[](json& d) { d["accessors"][0]["count"] = "3"; },
       "accessors[0].count: expected an integer >= 1, got \"3\""},
      {[](json& d) { d["accessors"][0]["count"] = 0; },
       "accessors[0].count: expected an integer >= 1, got 0"},
      {[](json& d) { d["meshes"][0]["primitives"][0]["mode"] = "x"; },
       "meshes[0].primitives[0].mode: \"x\" is not one of the modes 0 to 6"},
      // Found by fuzz_gltf: dropped by tinygltf, the primitive after it took its index, and
      // the restored index accessor of a compressed primitive had no primitive to go to.
      {[](json& d) {
         json& primitive = d["meshes"][0]["primitives"][0];
         primitive["aptributes"] = primitive["attributes"];
         primitive.erase("attributes");
       },
       "meshes[0].primitives[0]: has no attributes object (every primitive must have one)"},
      {[](json& d) { d["meshes"][0]["primitives"].push_back(7); },
       "meshes[0].primitives[1]: is not an object"},
      // Found by CI's fuzz_gltf run: an attribute holding an object made tinygltf drop the
      // primitive, and the restored index accessor had no primitive to go to.
      {[](json& d) {
         d["meshes"][0]["primitives"][0]["attributes"]["KHR_draco"] = {{"bufferView", 0}};
       },
       "meshes[0].primitives[0].attributes.KHR_draco: {\"bufferView\":0} is not an accessor "
       "index"},
      // tinygltf skips a collection that is no array: the file loaded as an empty one.
      {[](json& d) { d["scenes"] = 7; }, "scenes: 7 is not an array"},
      {[](json& d) { d["samplers"] = json::object(); }, "samplers: {} is not an array"},
      {[](json& d) { d["scene"] = "x"; }, "scene: \"x\" is not a scene index"},
      {[](json& d) { d["meshes"][0]["primitives"][0]["attributes"]["NORMAL"] = -1; },
       "meshes[0].primitives[0].attributes.NORMAL: -1 is not an accessor index"},
      {[](json& d) {
         d["meshes"][0]["primitives"][0]["targets"] = {{{"POSITION", 0}}, {{"POSITION", 1.5}}};
       },
       "meshes[0].primitives[0].targets[1].POSITION: 1.5 is not an accessor index"},
  };
  for (const auto& [edit, message] : cases) {
    EXPECT_TRUE(refused(runBounded({"info", writeTriangle(input("bad.gltf"), edit).string()}),
                        "bad.gltf: " + message));
  }
}

// ---------------------------------------------------------------------------------------------
// 6. Valid files refused

TEST_F(HostileInputTest, AnIndexAccessorWithoutABufferViewIsZeros) {
  const fs::path scene = writeTriangle(input("zeros.gltf"), [](json& doc) {
    doc["accessors"].push_back({{"componentType", 5123}, {"count", 3}, {"type", "SCALAR"}});
    doc["meshes"][0]["primitives"][0]["indices"] = 1;
  });
  const RunResult r = runBounded({"info", scene.string()});
  EXPECT_EQ(r.status, 0) << r.err;
}

TEST_F(HostileInputTest, ZeroOrNanNormalsAreReplacedWithAWarning) {
  const fs::path scene = writeTriangle(input("normals.gltf"), [](json& doc) {
    // Normals (0,0,0), (nan,0,0) as 0x7FC00000, (0,0,0) after the positions.
    doc["buffers"][0]["byteLength"] = 72;
    doc["buffers"][0]["uri"] =
        "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"
        "AAAAAAAAAAAAAAAAAADAfwAAAAAAAAAAAAAAAAAAAAAAAAAA";
    doc["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", 36}, {"byteLength", 36}});
    doc["accessors"].push_back(
        {{"bufferView", 1}, {"componentType", 5126}, {"count", 3}, {"type", "VEC3"}});
    doc["meshes"][0]["primitives"][0]["attributes"]["NORMAL"] = 1;
  });
  const RunResult r = render(scene);
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(contains(
      r.err, "meshes[0].primitives[0]: 3 NORMAL values are zero or not finite; generated flat"))
      << r.err;
}

// A 1x1 lossless WebP (the glTF-Validator's), in a data: URI, which tinygltf would take for a
// file name.
constexpr const char* kWebpDataUri =
    "data:image/webp;base64,UklGRhwAAABXRUJQVlA4TA8AAAAv/8AfAAcQ/Y/+ByKi/wEA";

// What the specification forbids but can be drawn is drawn, with a warning: a WebP image that
// a core source names, and one without the extension in extensionsUsed.
TEST_F(HostileInputTest, AWebpImageThatACoreSourceNamesIsDrawnWithAWarning) {
  const auto withWebp = [&](bool declared) {
    return [=](json& doc) {
      if (declared) doc["extensionsUsed"] = {"EXT_texture_webp"};
      doc["images"] = {{{"uri", kWebpDataUri}}};
      doc["textures"] = {{{"source", 0}}};
      doc["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}};
      doc["meshes"][0]["primitives"][0]["material"] = 0;
    };
  };
  const RunResult r = render(writeTriangle(input("webp.gltf"), withWebp(true)));
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(contains(r.err,
                       "webp.gltf: textures[0].source: images[0] is WebP, which only "
                       "EXT_texture_webp may name; drawn as it is"))
      << r.err;
  fs::remove(output("a.png"));
  const RunResult undeclared = render(writeTriangle(input("webp.gltf"), withWebp(false)));
  EXPECT_EQ(undeclared.status, 0) << undeclared.err;
  EXPECT_TRUE(contains(undeclared.err,
                       "webp.gltf: images[0]: WebP, but EXT_texture_webp is not in "
                       "extensionsUsed; decoded as WebP"))
      << undeclared.err;
}

TEST_F(HostileInputTest, APlaceholderBufferThatNothingUsesIsIgnored) {
  // The validator's valid_placeholder.glb: buffer 1 has no uri and no bufferView.
  std::string text =
      R"({"asset":{"version":"2.0"},"buffers":[{"byteLength":4},{"byteLength":1024}]})";
  while (text.size() % 4 != 0) text += ' ';
  std::string glb = "glTF" + std::string(8, '\0') + std::string(4, '\0') + "JSON" + text +
                    std::string("\x04\0\0\0BIN\0\xff\xff\xff\xff", 12);
  putLe32(glb, 4, 2);
  putLe32(glb, 8, static_cast<std::uint32_t>(glb.size()));
  putLe32(glb, 12, static_cast<std::uint32_t>(text.size()));
  writeBytes(input("placeholder.glb"), glb);
  const RunResult r = runBounded({"info", in("placeholder.glb")});
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(contains(r.out + r.err, "buffers[1]: no uri and no bufferView uses it; ignored"))
      << r.out << r.err;
}

// tinygltf's text ("buffers[0]: 'uri' is missing from non binary glTF file buffer.") names no
// user and no rule.
TEST_F(HostileInputTest, ABufferWithoutUriThatAViewUsesIsAnInputErrorNamingBoth) {
  const auto withoutUri = [](json& doc) { doc["buffers"][0].erase("uri"); };
  EXPECT_TRUE(refused(runBounded({"info", writeTriangle(input("nouri.gltf"), withoutUri)}),
                      "nouri.gltf: buffers[0]: has no uri, but bufferViews[0] uses it (only the "
                      "first buffer of a .glb, its BIN chunk, may leave uri out)"));
  // In a .glb, only buffer 0 is the BIN chunk.
  const fs::path glb = boxScene("box.glb", FileFormat::Glb);
  std::string bytes = readFile(glb);
  json doc = json::parse(bytes.substr(20, le32(bytes, 12)));
  doc["buffers"].push_back({{"byteLength", 4}});
  doc["bufferViews"].push_back({{"buffer", 1}, {"byteLength", 4}});
  writeBytes(glb, glbWithJson(bytes, doc.dump()));
  EXPECT_TRUE(refused(runBounded({"info", glb.string()}),
                      "box.glb: buffers[1]: has no uri, but bufferViews[" +
                          std::to_string(doc["bufferViews"].size() - 1) + "] uses it"));
}

// The review parses the JSON with long strings (over 256 bytes: data URIs) cut short, so that
// a 40 MB data URI is not parsed twice. What it checks still holds with long strings around.
TEST_F(HostileInputTest, TheJsonReviewSeesPastLongStrings) {
  // 300 bytes after the positions make the data URI long; 36 + 300 = 336 = 112 * 3 bytes.
  std::string base64 = "AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA";
  base64 += std::string(400, 'A');
  const auto longBuffer = [&](json& doc) {
    doc["buffers"][0] = {{"byteLength", 336},
                         {"uri", "data:application/octet-stream;base64," + base64}};
  };
  // A rewrite (a placeholder for an unused buffer without uri) keeps the long data URI whole:
  // the triangle's positions are read from it.
  const RunResult placeholder = render(writeTriangle(input("long.gltf"), [&](json& doc) {
    longBuffer(doc);
    doc["buffers"].push_back({{"byteLength", 4}});
  }));
  EXPECT_EQ(placeholder.status, 0) << placeholder.err;
  EXPECT_TRUE(contains(placeholder.err, "buffers[1]: no uri and no bufferView uses it; ignored"));
  fs::remove(output("a.png"));
  // A long WebP data URI is still recognized by its start, and retyped whole (libwebp reads
  // the RIFF chunk and leaves the zeros after it).
  const std::string webp = kWebpDataUri + std::string(400, 'A');
  const RunResult r = runBounded({"info", writeTriangle(input("webp.gltf"), [&](json& doc) {
                                            longBuffer(doc);
                                            doc["extensionsUsed"] = {"EXT_texture_webp"};
                                            doc["images"] = {{{"uri", webp}}};
                                            doc["textures"] = {{{"source", 0}}};
                                          }).string()});
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(contains(r.out + r.err, "webp.gltf: textures[0].source: images[0] is WebP"))
      << r.out << r.err;
  // A WebP data: URI that is not base64 is refused by name.
  EXPECT_TRUE(refused(
      runBounded({"info", writeTriangle(input("webp.gltf"),
                                        [&](json& doc) {
                                          longBuffer(doc);
                                          doc["images"] = {{{"uri", "data:image/webp,RIFF"}}};
                                        })
                              .string()}),
      "webp.gltf: images[0].uri: \"data:image/webp\": only base64 data: URIs "
      "are supported"));
  // Quotes, backslashes and non-ASCII bytes around the cut points do not hide a forbidden value.
  std::string note;
  for (int i = 0; i < 40; ++i) note += "\"q\" \\ \u00e9 \xc3\xa9 ";
  EXPECT_TRUE(refused(runBounded({"info", writeTriangle(input("escapes.gltf"),
                                                        [&](json& doc) {
                                                          longBuffer(doc);
                                                          doc["extras"] = {{note, note}};
                                                          doc["bufferViews"][0]["byteStride"] = -12;
                                                        })
                                              .string()}),
                      "escapes.gltf: bufferViews[0]: byteStride -12 is not a multiple of 4"));
}

// ---------------------------------------------------------------------------------------------
// 7. Late or cryptic failures

TEST_F(HostileInputTest, AFrameLargerThanTheGlAllocatesIsAnInputErrorNamingTheLimit) {
  const fs::path scene = boxScene("s/a.gltf");
  const RunResult r = runBounded(
      {"render", scene.string(), "-o", "a.png", "--width", "16384", "--height", "16384"});
  // llvmpipe takes at most 1 GiB per texture (about 8192x8192 RGBA32F); a GL that takes more
  // renders it, which this test then only checks for a clean exit.
  if (r.status != 0) {
    EXPECT_TRUE(
        refused(r, "--width/--height 16384x16384: more than this GL allocates for a frame"));
  }
}

// The AOV pass holds 8 RGBA32F targets and a 32-bit depth at once (132 bytes a pixel), the
// layer pass 3 more and a depth (52), and the AOV image 4 bytes a channel (11 fixed, one
// visibility per light: the box scene has one). Their sum is checked against --max-memory
// before any GL allocation; the frame-size check covers one RGBA32F target only.
TEST_F(HostileInputTest, TheAovPassMemoryIsCheckedAgainstMaxMemoryBeforeAllocating) {
  const fs::path scene = boxScene("s/a.gltf");
  const auto aovRender = [&](const std::string& width, const std::string& height,
                             std::vector<std::string> extra) {
    std::vector<std::string> args = {"render", scene.string(), "-o",  "a.png",    "--aov",
                                     "a.exr",  "--width",      width, "--height", height};
    args.insert(args.end(), extra.begin(), extra.end());
    return runBounded(args);
  };
  // 2000x1500: (132 + 12 * 4) * 3e6 bytes = 515 MiB (378 + 137).
  EXPECT_TRUE(refused(aovRender("2000", "1500", {"--max-memory", "64"}),
                      "the AOV pass at 2000x1500 needs 515 MiB (render targets 378 MiB, AOV image "
                      "137 MiB), more than the 64 MiB allowed (--max-memory)"));
  // With albedo: (132 + 52) * 3e6 = 526 MiB of targets, 15 channels = 172 MiB of image.
  EXPECT_TRUE(refused(aovRender("2000", "1500", {"--max-memory", "64", "--aov-layers", "albedo"}),
                      "the AOV pass at 2000x1500 needs 698 MiB (render targets 526 MiB, AOV image "
                      "172 MiB), more than the 64 MiB allowed (--max-memory)"));
  // 64x48 needs 0.53 MiB: within 32 MiB (the shadow maps' own bound needs 24), it renders.
  const RunResult r = aovRender("64", "48", {"--max-memory", "32"});
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(fs::exists(output("a.exr")));
}

// Masks without --aov take no AOV pass: the id pass holds one RG32F target and a 32-bit depth
// (12 bytes a pixel) and four channels of ids and coverage (16 bytes), checked the same way.
TEST_F(HostileInputTest, TheMaskPassMemoryIsCheckedAgainstMaxMemoryBeforeAllocating) {
  const fs::path scene = boxScene("s/a.gltf");
  const auto maskRender = [&](const std::string& width, const std::string& height,
                              const std::string& maxMemory) {
    return runBounded({"render", scene.string(), "-o", "a.png", "--masks", "m", "--width", width,
                       "--height", height, "--max-memory", maxMemory});
  };
  // 2000x1500: 12 * 3e6 bytes = 34 MiB of targets, 16 * 3e6 = 46 MiB of ids.
  EXPECT_TRUE(refused(maskRender("2000", "1500", "64"),
                      "the mask pass at 2000x1500 needs 80 MiB (render targets 34 MiB, id image "
                      "46 MiB), more than the 64 MiB allowed (--max-memory)"));
  const RunResult r = maskRender("2000", "1500", "96");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(fs::exists(output("m.instances.png")));
}

TEST_F(HostileInputTest, TooManyShadowedLightsOfOneResolutionAreToldSo) {
  const fs::path scene = boxScene("s/a.gltf");
  std::string lights = R"({"lights": [)";
  for (int i = 0; i < 1400; ++i) {
    lights += (i ? "," : "") + std::string(R"({"name": "l)") + std::to_string(i) +
              R"(", "position": [0, 2, 0], "shadow": {"resolution": 8}})";
  }
  const fs::path file = writeText("many.json", lights + "]}");
  EXPECT_TRUE(refused(render(scene, {"-l", file.string()}),
                      "use fewer shadowed lights (or \"shadow\": false on some)"));
}

TEST_F(HostileInputTest, MaxMemoryMustBeAPositiveFiniteNumber) {
  const fs::path scene = boxScene("s/a.gltf");
  for (const std::string value : {"nan", "inf", "1e+300", "0", "-5"}) {
    EXPECT_TRUE(refused(render(scene, {"--max-memory", value}),
                        "--max-memory " + value + ": expected a number of MiB in (0, 1048576]"));
  }
}

// Extreme camera numbers, on a glTF camera (the box scene) and on automatic framing (the
// triangle): each renders or is refused naming the option given. --fov 1e-30 was blamed on
// --eye/--target and --eye 3e38 on --up.
TEST_F(HostileInputTest, ExtremeCameraNumbersRenderOrNameTheOption) {
  const fs::path box = boxScene("box.gltf");
  const fs::path triangle = writeTriangle(input("triangle.gltf"), [](json&) {});
  const std::vector<std::pair<std::vector<std::string>, std::string>> refusals = {
      {{"--fov", "1e-30"}, "--fov 1e-30: expected degrees from 0.001 to below 180"},
      {{"--eye", "1,2,3", "--target", "1,2,3"},
       "--eye/--target: the eye and the target are the same point"},
      {{"--eye", "0,5,0", "--target", "0,0,0", "--up", "0,1,0"},
       "--up: the up vector is parallel to the view direction"},
      {{"--eye", "-3e38,-3e38,-3e38", "--target", "3e38,3e38,3e38"},
       "--eye/--target: the eye is too far from the origin"},
      // Off the axes, the view matrix's translation (-dot(axis, eye)) passes 3.4e38.
      {{"--eye", "3e38,3e38,3e38"}, "--eye: the eye is too far from the origin"},
  };
  const std::vector<std::vector<std::string>> renders = {
      {"--fov", "179.9999"}, {"--fov", "0.001"}, {"--eye", "3e38,0,0"}};
  for (const fs::path& scene : {box, triangle}) {
    for (const auto& [options, message] : refusals) {
      EXPECT_TRUE(refused(render(scene, options), message)) << scene << " " << options.front();
    }
    for (const std::vector<std::string>& options : renders) {
      const RunResult r = render(scene, options);
      EXPECT_EQ(r.status, 0) << scene << " " << options.back() << ": " << r.err;
      fs::remove(output("a.png"));
    }
  }
  // A glTF yfov of pi or more turns the picture inside out; 1e-30 loses the scene.
  for (const double yfov : {4.0, 1e-30}) {
    const fs::path scene = writeTriangle(input("yfov.gltf"), [yfov](json& doc) {
      doc["cameras"] = {
          {{"type", "perspective"}, {"perspective", {{"yfov", yfov}, {"znear", 0.1}}}}};
      doc["nodes"].push_back({{"camera", 0}, {"translation", {0.3, 0.3, 3}}});
      doc["scenes"][0]["nodes"] = {0, 1};
    });
    std::ostringstream shown;
    shown << yfov;
    EXPECT_TRUE(refused(render(scene), "yfov.gltf: cameras[0]: perspective yfov " + shown.str() +
                                           " must be from 1.745e-05 (0.001 degrees) to below pi"));
  }
}

TEST_F(HostileInputTest, ACameraAspectRatioThatGivesAHugeImageIsAnInputError) {
  const fs::path scene = writeTriangle(input("wide.gltf"), [](json& doc) {
    doc["cameras"] = json::parse(
        R"([{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1,
             "aspectRatio": 10000}}])");
    doc["nodes"].push_back({{"camera", 0}, {"translation", {0.3, 0.3, 3}}});
    doc["scenes"][0]["nodes"] = {0, 1};
  });
  EXPECT_TRUE(refused(runBounded({"render", scene.string(), "-o", "a.png", "--height", "720"}),
                      "cameras[0]: aspectRatio 10000"));
}

TEST_F(HostileInputTest, ASymlinkLoopInABatchFolderDoesNotStopTheBatch) {
  boxScene("s/a.gltf");
  fs::create_symlink("loop.gltf", input("s/loop.gltf"));
  const RunResult r =
      runBounded({"batch", in("s"), "--out", out_.string(), "--width", "32", "--height", "24"});
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(filesIn(out_), std::vector<std::string>{"a.png"});
}

TEST_F(HostileInputTest, ANonUtf8SceneNameGivesAValidReport) {
  boxScene("s/caf\xe9.gltf");
  const fs::path report = root_ / "report.json";
  const RunResult r = runBounded({"batch", in("s"), "--out", out_.string(), "--width", "32",
                                  "--height", "24", "--report", report.string()});
  EXPECT_EQ(r.status, 0) << r.err;
  const json doc = json::parse(readFile(report));
  EXPECT_EQ(doc["jobs"][0]["name"], "caf\xef\xbf\xbd.gltf");
}

// ---------------------------------------------------------------------------------------------
// 8. Messages

TEST_F(HostileInputTest, MessagesAreOneLineOfBoundedLength) {
  const fs::path scene = boxScene("s/a.gltf");
  json doc = readJson(scene);
  // A URI of 100,000 characters naming no file.
  doc["buffers"][0]["uri"] = std::string(100000, 'x') + ".bin";
  writeJson(scene, doc);
  const RunResult r = render(scene);
  EXPECT_TRUE(refused(r, "a.gltf: ")) << r.err.size();
  EXPECT_LE(r.err.size(), 700u);
  EXPECT_TRUE(contains(r.err, "(message cut at 600 bytes)"));

  // An empty scene file: said so, not "JSON string too short."
  writeBytes(input("empty.gltf"), "");
  EXPECT_TRUE(refused(runBounded({"info", in("empty.gltf")}),
                      "empty.gltf: cannot read glTF file: the file is empty"));

  // A 300-character output name: the system's reason, not "filesystem error: ...".
  const RunResult longName = render(scene, {"-o", std::string(300, 'n') + ".png"});
  EXPECT_EQ(longName.status, 2) << longName.err;
  EXPECT_FALSE(contains(longName.err, "filesystem error")) << longName.err;
  EXPECT_EQ(lines(longName.err), 1) << longName.err;
}

}  // namespace

}  // namespace hostile_input_test
