// End-to-end tests of `omnishadow batch`: which jobs the inputs (folders, globs, scene files,
// manifests) make, where their outputs land, which lights each scene gets, the log, the report,
// resuming, sharding, failure isolation and byte-identical outputs whatever the thread count.
// Every test runs the real executable in a fresh temporary folder:
//   <root>/in   inputs, written with GltfBuilder and as JSON text
//   <root>/out  the working directory of the run, and the --out folder unless a test says other
//   <root>/stdout, <root>/stderr  what the run printed; reports go to <root> as well
// Renders are tiny (64x48, 32-texel shadow maps): llvmpipe is slow and CI has two cores.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "renderer/output/image_writer.h"
#include "scenes/builder/gltf_builder.h"
#include "tests/support/cli_fixture.h"

namespace omnishadow::batch_test {
namespace {

namespace fs = std::filesystem;
using builder::FileFormat;
using builder::GltfBuilder;
using nlohmann::json;

// ---------------------------------------------------------------------------------------------
// Inputs

// A lights file with one cheaply shadowed point light; `extra` is spliced into the light.
std::string lightsJson(const std::string& name, const std::string& position = "-1.5, 3, 1.5",
                       const std::string& extra = "") {
  return R"({"lights": [{"name": ")" + name + R"(", "position": [)" + position +
         R"(], "intensity": 20, )" + extra + R"("shadow": {"resolution": 32}}]})";
}

// ---------------------------------------------------------------------------------------------
// Reading results

using SceneSpec = test_support::BoxSceneSpec;
using test_support::contains;
using test_support::distinctResolutionLights;
using test_support::filesIn;
using test_support::pngSize;
using test_support::readFile;
using test_support::sameBytes;
using test_support::writeBoxScene;

using Names = std::vector<std::string>;

Names visibilityChannels(const fs::path& aovFile) {
  const FloatImage image = readImage(aovFile);
  Names channels;
  for (const std::string& c : image.channels)
    if (c.starts_with("visibility.")) channels.push_back(c);
  std::sort(channels.begin(), channels.end());
  return channels;
}

double meanOfRgb(const fs::path& path) {
  const FloatImage image = readImage(path);
  double sum = 0.0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      for (int c = 0; c < 3; ++c) sum += image.at(x, y, c);
  return sum / (3.0 * image.width * image.height);
}

std::vector<std::string> linesOf(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// The stdout of a batch run, checked line by line and normalised: job lines become
// "ok      <name>", "skipped <name>" or "FAILED  <name>" (in any order: jobs may finish out of
// order), the last line "<R> rendered, <S> skipped, <F> failed".
::testing::AssertionResult logIs(const std::string& out, Names jobs, const std::string& summary) {
  if (!out.ends_with("\n")) return ::testing::AssertionFailure() << "no final newline:\n" << out;
  std::vector<std::string> lines = linesOf(out);
  const std::regex last(
      R"(([0-9]+ rendered, [0-9]+ skipped, [0-9]+ failed) in [0-9]+(\.[0-9]+)? s)");
  std::smatch m;
  if (lines.empty() || !std::regex_match(lines.back(), m, last))
    return ::testing::AssertionFailure() << "no summary line at the end of:\n" << out;
  if (m[1] != summary)
    return ::testing::AssertionFailure()
           << "summary \"" << m[1] << "\", expected \"" << summary << "\" in:\n"
           << out;
  lines.pop_back();
  const std::regex ok(R"(ok      (.+) \([0-9]+(\.[0-9]+)? ms\))"), skipped(R"(skipped .+)"),
      failed(R"((FAILED  .+?): .+)");
  Names normalised;
  for (const std::string& line : lines) {
    if (std::regex_match(line, m, ok)) {
      normalised.push_back("ok      " + m[1].str());
    } else if (std::regex_match(line, m, skipped)) {
      normalised.push_back(line);
    } else if (std::regex_match(line, m, failed)) {
      normalised.push_back(m[1]);
    } else {
      return ::testing::AssertionFailure() << "unexpected line \"" << line << "\" in:\n" << out;
    }
  }
  std::sort(normalised.begin(), normalised.end());
  std::sort(jobs.begin(), jobs.end());
  if (normalised == jobs) return ::testing::AssertionSuccess();
  ::testing::AssertionResult failure = ::testing::AssertionFailure();
  failure << "job lines of:\n" << out << "expected:\n";
  for (const std::string& job : jobs) failure << "  " << job << "\n";
  return failure;
}

// The <message> of "FAILED  <name>: <message>" on stdout; empty when there is no such line.
std::string failureMessage(const std::string& out, const std::string& name) {
  for (const std::string& line : linesOf(out))
    if (line.starts_with("FAILED  " + name + ": ")) return line.substr(10 + name.size());
  return "";
}

std::set<std::string> keysOf(const json& object) {
  std::set<std::string> keys;
  for (const auto& [key, value] : object.items()) keys.insert(key);
  return keys;
}

// ---------------------------------------------------------------------------------------------
// Running the binary

class BatchTest : public test_support::CliFixture {
 protected:
  BatchTest() : CliFixture("omnishadow-batch") {}

  // `omnishadow batch args... --width 64 --height 48`; --out is the caller's.
  Run batch(std::vector<std::string> args) {
    args.insert(args.begin(), "batch");
    args.insert(args.end(), {"--width", "64", "--height", "48"});
    return run(args);
  }

  fs::path scene(const std::string& name, const SceneSpec& spec = {}) {
    writeBoxScene(input(name), spec);
    return input(name);
  }

  json report(const std::string& name = "report.json") const {
    const std::string text = readFile(root_ / name);
    EXPECT_FALSE(text.empty()) << "no report " << name;
    return json::parse(text, nullptr, false);
  }
  std::string reportPath(const std::string& name = "report.json") const {
    return (root_ / name).string();
  }

  // A path from a report: relative ones are taken from the working directory (out/).
  fs::path resolved(const json& path) const {
    const fs::path p = path.get<std::string>();
    return fs::weakly_canonical(p.is_absolute() ? p : out_ / p);
  }
};

// ---------------------------------------------------------------------------------------------
// Inputs and outputs

TEST_F(BatchTest, FolderInputMirrorsTheTreeAndFindsTheLightsFiles) {
  scene("scenes/a.gltf");                                // lamp + key (a.lights.json)
  writeText("scenes/a.lights.json", lightsJson("key"));  // beside a: wins over lights.json
  writeText("scenes/lights.json", lightsJson("ceiling", "0, 4, 0"));
  scene("scenes/c.glb", {.gltfLight = false, .format = FileFormat::Glb});  // ceiling
  scene("scenes/sub/b.gltf", {.gltfLight = false});                        // fill, its only light
  writeText("scenes/sub/lights.json", lightsJson("fill", "1, 3, 2"));
  scene("scenes/sub/deeper/d.gltf", {.gltfLight = false});  // nothing: the parent's file is not
  const Names inputs = filesIn(in_);

  const Run r = batch({in("scenes"), "--out", out_.string(), "--aov"});

  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(filesIn(out_),
            (Names{"a.aov.exr", "a.png", "c.aov.exr", "c.png", "sub", "sub/b.aov.exr", "sub/b.png",
                   "sub/deeper", "sub/deeper/d.aov.exr", "sub/deeper/d.png"}));
  EXPECT_TRUE(logIs(
      r.out, {"ok      a.gltf", "ok      c.glb", "ok      sub/b.gltf", "ok      sub/deeper/d.gltf"},
      "4 rendered, 0 skipped, 0 failed"));
  EXPECT_EQ(filesIn(in_), inputs) << "the inputs changed";

  EXPECT_EQ(visibilityChannels(output("a.aov.exr")), (Names{"visibility.key", "visibility.lamp"}));
  EXPECT_EQ(visibilityChannels(output("c.aov.exr")), Names{"visibility.ceiling"});
  EXPECT_EQ(visibilityChannels(output("sub/b.aov.exr")), Names{"visibility.fill"})
      << "lights.json in the scene's folder is not used, or a headlight was added";
  EXPECT_GT(meanOfRgb(output("sub/b.png")), 0.05) << "lit by the folder's lights.json alone";
  EXPECT_EQ(visibilityChannels(output("sub/deeper/d.aov.exr")), Names{"visibility.headlight"});
  for (const char* png : {"a.png", "c.png", "sub/deeper/d.png"})
    EXPECT_EQ(pngSize(output(png)), std::make_pair(64u, 48u)) << png;
}

TEST_F(BatchTest, GlobAndSingleFileInputsAndOneLightsFileForAll) {
  scene("g/x.glb", {.format = FileFormat::Glb});
  scene("g/y.glb", {.format = FileFormat::Glb, .boxX = 1.0f});
  scene("g/z.gltf");                                // not *.glb
  scene("g/s/w.glb", {.format = FileFormat::Glb});  // not in g/ itself
  scene("one/c.gltf", {.gltfLight = false});
  writeText("one/c.lights.json", lightsJson("key"));  // -l wins over it
  const fs::path fill = writeText("fill.json", lightsJson("fill", "1, 3, 2"));

  const Run r = batch(
      {in("g") + "/*.glb", in("one/c.gltf"), "-o", out_.string(), "-l", fill.string(), "--aov"});

  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(filesIn(out_),
            (Names{"c.aov.exr", "c.png", "x.aov.exr", "x.png", "y.aov.exr", "y.png"}));
  EXPECT_TRUE(logIs(r.out, {"ok      x.glb", "ok      y.glb", "ok      c.gltf"},
                    "3 rendered, 0 skipped, 0 failed"));
  EXPECT_EQ(visibilityChannels(output("c.aov.exr")), Names{"visibility.fill"});
  EXPECT_EQ(visibilityChannels(output("x.aov.exr")), (Names{"visibility.fill", "visibility.lamp"}));
  EXPECT_NE(readFile(output("x.png")), readFile(output("y.png")));
}

TEST_F(BatchTest, GlobOutputsAreRelativeToItsFolderWithoutWildcards) {
  scene("g/s/w.glb", {.format = FileFormat::Glb});
  scene("g/t/v.gltf");
  scene("g/top.glb", {.format = FileFormat::Glb});  // not matched by g/*/*.glb

  const Run r = batch({in("g") + "/*/*.gl*", "--out", out_.string()});

  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(filesIn(out_), (Names{"s", "s/w.png", "t", "t/v.png"}));
  EXPECT_TRUE(
      logIs(r.out, {"ok      s/w.glb", "ok      t/v.gltf"}, "2 rendered, 0 skipped, 0 failed"));
}

TEST_F(BatchTest, OutputFormatFlags) {
  scene("s/a.gltf");
  const Run r = batch(
      {in("s"), "--out", out_.string(), "--exr", "--no-png", "--aov", "--aov-layers", "albedo"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(filesIn(out_), (Names{"a.aov.exr", "a.exr"}));
  const FloatImage beauty = readImage(output("a.exr"));
  EXPECT_EQ(std::make_pair(beauty.width, beauty.height), std::make_pair(64, 48));
  EXPECT_GE(readImage(output("a.aov.exr")).channelIndex("albedo.R"), 0);
}

TEST_F(BatchTest, MasksFlagAloneWritesTheAnnotationMasks) {
  scene("s/a.gltf");
  const Run r = batch({in("s"), "--out", out_.string(), "--no-png", "--masks", "--aa", "4"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(filesIn(out_), (Names{"a.instances.png", "a.masks.json", "a.semantic.png"}));
  const FloatImage instances = readImage(output("a.instances.png"));
  EXPECT_EQ(std::make_pair(instances.width, instances.height), std::make_pair(64, 48));
}

TEST_F(BatchTest, ManifestJobsOverrideTheBatchOptions) {
  scene("m/scenes/a.glb", {.format = FileFormat::Glb});
  scene("m/b.gltf", {.gltfLight = false});
  writeText("m/key.json", lightsJson("key"));
  const fs::path manifest = writeText("m/manifest.json", R"({"jobs": [
    {"scene": "scenes/a.glb", "outputs": ["x/main.png"], "camera": "main"},
    {"scene": "scenes/a.glb", "outputs": ["x/top.png"]},
    {"scene": "scenes/a.glb", "outputs": ["x/small.png", "x/small.exr"], "aov": "x/small.aov.exr",
     "aovLayers": "albedo", "lights": "key.json", "width": 80, "height": 40},
    {"scene": "b.gltf", "width": 32, "height": 24},
    {"scene": "b.gltf", "outputs": ["e/every.png"], "eye": [0, 2.5, 4.5], "target": [0, 0.3, 0],
     "up": [0, 1, 0], "fov": 46, "exposure": 0.5, "shading": "phong", "sceneIndex": 0,
     "noGltfLights": true, "lights": "key.json"}
  ]})");

  // Without "camera", a job takes the batch's --camera.
  const Run r = batch({manifest.string(), "--out", out_.string(), "--camera", "top"});

  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(filesIn(out_), (Names{"b.png", "e", "e/every.png", "x", "x/main.png", "x/small.aov.exr",
                                  "x/small.exr", "x/small.png", "x/top.png"}));
  EXPECT_TRUE(
      logIs(r.out,
            {"ok      jobs[0] scenes/a.glb", "ok      jobs[1] scenes/a.glb",
             "ok      jobs[2] scenes/a.glb", "ok      jobs[3] b.gltf", "ok      jobs[4] b.gltf"},
            "5 rendered, 0 skipped, 0 failed"));

  EXPECT_EQ(pngSize(output("x/main.png")), std::make_pair(64u, 48u));
  EXPECT_EQ(pngSize(output("x/small.png")), std::make_pair(80u, 40u));
  EXPECT_EQ(pngSize(output("b.png")), std::make_pair(32u, 24u));
  EXPECT_EQ(visibilityChannels(output("x/small.aov.exr")),
            (Names{"visibility.key", "visibility.lamp"}));
  EXPECT_GE(readImage(output("x/small.aov.exr")).channelIndex("albedo.R"), 0);
  EXPECT_GT(meanOfRgb(output("e/every.png")), 0.02);

  // The cameras, checked against `render`.
  for (const std::string camera : {"main", "top"}) {
    const Run single = run({"render", in("m/scenes/a.glb"), "--camera", camera, "--width", "64",
                            "--height", "48", "-o", (root_ / (camera + ".png")).string()});
    ASSERT_EQ(single.status, 0) << single.err;
    EXPECT_TRUE(sameBytes(output("x/" + camera + ".png"), root_ / (camera + ".png")));
  }
  EXPECT_NE(readFile(output("x/main.png")), readFile(output("x/top.png")));
}

// Under --no-png a manifest's jobs write what they name: masks or AOVs without an image, and
// images named in their "outputs". An empty "outputs" asks for no image without --no-png.
TEST_F(BatchTest, ManifestJobsWithoutAnImageWriteTheirMasksAndAovs) {
  scene("m/a.glb", {.format = FileFormat::Glb});
  const fs::path manifest = writeText("m/manifest.json", R"({"jobs": [
    {"scene": "a.glb", "masks": "ids/a"},
    {"scene": "a.glb", "aov": "aov/a.aov.exr", "aovLayers": "albedo"},
    {"scene": "a.glb", "outputs": ["img/a.png"], "masks": "img/a"}
  ]})");
  const Run r = batch({manifest.string(), "--out", out_.string(), "--no-png"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(filesIn(out_),
            (Names{"aov", "aov/a.aov.exr", "ids", "ids/a.instances.png", "ids/a.masks.json",
                   "ids/a.semantic.png", "img", "img/a.instances.png", "img/a.masks.json",
                   "img/a.png", "img/a.semantic.png"}));
  // The masks drawn without a picture are those drawn with one.
  for (const char* suffix : {".instances.png", ".semantic.png", ".masks.json"})
    EXPECT_TRUE(
        sameBytes(output(std::string("ids/a") + suffix), output(std::string("img/a") + suffix)))
        << suffix;
  EXPECT_GE(readImage(output("aov/a.aov.exr")).channelIndex("albedo.R"), 0);

  const fs::path empty = writeText("m/empty.json", R"({"jobs": [
    {"scene": "a.glb", "outputs": [], "masks": "a"}]})");
  const fs::path again = root_ / "again";
  const Run e = batch({empty.string(), "--out", again.string()});
  ASSERT_EQ(e.status, 0) << e.err;
  EXPECT_EQ(filesIn(again), (Names{"a.instances.png", "a.masks.json", "a.semantic.png"}));
  EXPECT_TRUE(sameBytes(again / "a.instances.png", output("img/a.instances.png")));
}

TEST_F(BatchTest, ManifestFieldsUndoBatchFlags) {
  scene("m/a.glb", {.format = FileFormat::Glb});  // its only light is the glTF's lamp
  const fs::path manifest = writeText("m/manifest.json", R"({"jobs": [
    {"scene": "a.glb", "outputs": ["on.png"], "aov": "on.aov.exr", "noGltfLights": false},
    {"scene": "a.glb", "outputs": ["off.png"], "aov": "off.aov.exr"}
  ]})");
  const Run r = batch({manifest.string(), "--out", out_.string(), "--no-gltf-lights"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(visibilityChannels(output("on.aov.exr")), Names{"visibility.lamp"});
  EXPECT_EQ(visibilityChannels(output("off.aov.exr")), Names{"visibility.headlight"});
}

// ---------------------------------------------------------------------------------------------
// Failures, resuming, the report

TEST_F(BatchTest, FailedScenesAreReportedAndTheOthersStillRender) {
  scene("s/a.gltf");
  writeText("s/bad.gltf", "this is not glTF");
  scene("s/many.gltf");  // fails once the GL context is up: too many shadow textures
  writeText("s/many.lights.json", distinctResolutionLights(5));
  scene("s/z.gltf");  // the same as a.gltf, rendered after both failures

  const Run r = batch({in("s"), "--out", out_.string(), "--report", reportPath()});

  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_EQ(filesIn(out_), (Names{"a.png", "z.png"}));
  EXPECT_TRUE(sameBytes(output("a.png"), output("z.png"))) << "a failure changed later renders";
  EXPECT_TRUE(logIs(r.out,
                    {"ok      a.gltf", "FAILED  bad.gltf", "FAILED  many.gltf", "ok      z.gltf"},
                    "2 rendered, 0 skipped, 2 failed"));
  const std::string badMessage = failureMessage(r.out, "bad.gltf");
  const std::string manyMessage = failureMessage(r.out, "many.gltf");
  EXPECT_FALSE(badMessage.empty());
  EXPECT_TRUE(contains(manyMessage, "use fewer distinct shadow resolutions"));
  EXPECT_TRUE(contains(r.err, "omnishadow: bad.gltf: " + badMessage + "\n"));
  EXPECT_TRUE(contains(r.err, "omnishadow: many.gltf: " + manyMessage + "\n"));

  const json jobs = report()["jobs"];
  ASSERT_EQ(jobs.size(), 4u) << jobs.dump(2);
  EXPECT_EQ(jobs[1]["name"], "bad.gltf");
  EXPECT_EQ(jobs[1]["status"], "failed");
  EXPECT_EQ(jobs[1]["error"], badMessage);
  EXPECT_EQ(jobs[1]["outputs"], json::array());
  EXPECT_EQ(jobs[2]["name"], "many.gltf");
  EXPECT_EQ(jobs[2]["status"], "failed");
  EXPECT_EQ(jobs[2]["error"], manyMessage);
  EXPECT_EQ(jobs[2]["outputs"], json::array());
  for (int i : {0, 3}) {
    EXPECT_EQ(jobs[i]["status"], "rendered");
    EXPECT_EQ(jobs[i]["error"], nullptr);
  }
  EXPECT_EQ(report()["summary"]["failed"], 2);
}

TEST_F(BatchTest, SkipExistingLeavesFinishedJobsAlone) {
  scene("s/a.gltf");
  scene("s/b.glb", {.format = FileFormat::Glb});
  scene("s/sub/c.gltf", {.boxX = 1.0f});
  const std::vector<std::string> args = {in("s"), "--out",    out_.string(),
                                         "--aov", "--report", reportPath()};
  ASSERT_EQ(batch(args).status, 0);
  const Names files = {"a.aov.exr", "a.png",         "b.aov.exr", "b.png",
                       "sub",       "sub/c.aov.exr", "sub/c.png"};
  ASSERT_EQ(filesIn(out_), files);
  // Back-date every output, so that a rewrite shows even on a coarse clock.
  const auto past = fs::file_time_type::clock::now() - std::chrono::hours(24);
  std::map<std::string, std::string> bytes;
  for (const std::string& file : files)
    if (!fs::is_directory(output(file))) {
      fs::last_write_time(output(file), past);
      bytes[file] = readFile(output(file));
    }

  std::vector<std::string> skipping = args;
  skipping.push_back("--skip-existing");
  const Run again = batch(skipping);
  ASSERT_EQ(again.status, 0) << again.err;
  EXPECT_TRUE(logIs(again.out, {"skipped a.gltf", "skipped b.glb", "skipped sub/c.gltf"},
                    "0 rendered, 3 skipped, 0 failed"));
  const json skippedReport = report();  // named: a range-for over report()["jobs"] would dangle
  for (const json& job : skippedReport["jobs"]) EXPECT_EQ(job["status"], "skipped") << job.dump();
  EXPECT_EQ(report()["summary"]["skipped"], 3);
  EXPECT_EQ(filesIn(out_), files);
  for (const auto& [file, content] : bytes) {
    EXPECT_EQ(readFile(output(file)), content) << file;
    EXPECT_EQ(fs::last_write_time(output(file)), past) << file << " was rewritten";
  }

  // A job with one output missing renders again; only that one.
  fs::remove(output("sub/c.png"));
  const Run resumed = batch(skipping);
  ASSERT_EQ(resumed.status, 0) << resumed.err;
  EXPECT_TRUE(logIs(resumed.out, {"skipped a.gltf", "skipped b.glb", "ok      sub/c.gltf"},
                    "1 rendered, 2 skipped, 0 failed"));
  const json jobs = report()["jobs"];
  ASSERT_EQ(jobs.size(), 3u);
  EXPECT_EQ(jobs[0]["status"], "skipped");
  EXPECT_EQ(jobs[1]["status"], "skipped");
  EXPECT_EQ(jobs[2]["status"], "rendered");
  EXPECT_EQ(filesIn(out_), files);
  EXPECT_TRUE(fs::exists(output("sub/c.png")));
  for (const std::string file : {"a.png", "a.aov.exr", "b.png", "b.aov.exr"})
    EXPECT_EQ(fs::last_write_time(output(file)), past) << file << " was rewritten";
}

TEST_F(BatchTest, ReportHasEveryJobWithItsOutputsWarningsAndStages) {
  scene("s/a.gltf");
  writeText("s/a.lights.json", lightsJson("key", "-1.5, 3, 1.5", R"("colour": [1, 0, 0], )"));
  scene("s/b.glb", {.format = FileFormat::Glb});

  const Run r = batch({in("s"), "--out", out_.string(), "--exr", "--report", reportPath()});

  ASSERT_EQ(r.status, 0) << r.err;
  const json doc = report();
  ASSERT_TRUE(doc.is_object()) << readFile(reportPath());
  EXPECT_EQ(keysOf(doc), (std::set<std::string>{"summary", "shard", "jobs"}));
  EXPECT_EQ(doc["shard"], nullptr);
  const json& summary = doc["summary"];
  EXPECT_EQ(keysOf(summary),
            (std::set<std::string>{"jobs", "rendered", "skipped", "failed", "seconds"}));
  EXPECT_EQ(summary["jobs"], 2);
  EXPECT_EQ(summary["rendered"], 2);
  EXPECT_EQ(summary["skipped"], 0);
  EXPECT_EQ(summary["failed"], 0);
  EXPECT_TRUE(summary["seconds"].is_number() && summary["seconds"] >= 0) << summary.dump();

  const json& jobs = doc["jobs"];
  ASSERT_EQ(jobs.size(), 2u);
  const std::pair<std::string, std::string> expected[] = {{"a.gltf", "a"}, {"b.glb", "b"}};
  for (std::size_t i = 0; i < 2; ++i) {
    const json& job = jobs[i];
    const auto& [name, stem] = expected[i];
    SCOPED_TRACE(job.dump(2));
    EXPECT_EQ(keysOf(job), (std::set<std::string>{"name", "scene", "status", "error", "outputs",
                                                  "warnings", "stages"}));
    EXPECT_EQ(job["name"], name);
    ASSERT_TRUE(job["scene"].is_string());
    EXPECT_EQ(resolved(job["scene"]), fs::weakly_canonical(input("s/" + name)));
    EXPECT_EQ(job["status"], "rendered");
    EXPECT_EQ(job["error"], nullptr);
    std::set<fs::path> outputs;
    for (const json& path : job["outputs"]) outputs.insert(resolved(path));
    EXPECT_EQ(outputs, (std::set<fs::path>{fs::weakly_canonical(output(stem + ".png")),
                                           fs::weakly_canonical(output(stem + ".exr"))}));
    EXPECT_TRUE(job["warnings"].is_array());
    ASSERT_TRUE(job["stages"].is_object());
    EXPECT_FALSE(job["stages"].empty());
    for (const auto& [stage, ms] : job["stages"].items())
      EXPECT_TRUE(ms.is_number() && ms >= 0) << stage;
  }
  const json& warnings = jobs[0]["warnings"];
  EXPECT_TRUE(std::any_of(warnings.begin(), warnings.end(), [](const json& w) {
    return w.is_string() && contains(w.get<std::string>(), "lights[0].colour: unknown field");
  })) << warnings.dump();
  EXPECT_EQ(jobs[1]["warnings"], json::array());
}

// ---------------------------------------------------------------------------------------------
// Threads and shards

TEST_F(BatchTest, OutputsDoNotDependOnTheNumberOfThreads) {
  scene("s/a.gltf");
  scene("s/b.glb", {.format = FileFormat::Glb, .boxX = -1.0f});
  scene("s/c.gltf", {.gltfLight = false, .format = FileFormat::GltfExternal, .boxX = 1.0f});
  writeText("s/c.lights.json", lightsJson("key"));
  scene("s/sub/d.gltf", {.boxX = 0.5f});
  scene("s/sub/e.glb", {.gltfLight = false, .format = FileFormat::Glb, .boxX = -0.5f});
  writeText("s/sub/lights.json", lightsJson("fill", "1, 3, 2"));
  scene("s/sub/f.gltf", {.boxX = 1.5f});

  for (const std::string jobs : {"0", "1", "4"}) {
    const Run r = batch(
        {in("s"), "--out", output("jobs" + jobs).string(), "--jobs", jobs, "--exr", "--aov", "-q"});
    ASSERT_EQ(r.status, 0) << "--jobs " << jobs << ": " << r.err;
  }
  const Names files = filesIn(output("jobs0"));
  EXPECT_EQ(files.size(), 6u * 3u + 1u) << "6 scenes, 3 files each, and sub/";
  EXPECT_EQ(filesIn(output("jobs1")), files);
  EXPECT_EQ(filesIn(output("jobs4")), files);
  for (const std::string& file : files) {
    if (fs::is_directory(output("jobs0") / file)) continue;
    EXPECT_TRUE(sameBytes(output("jobs0") / file, output("jobs1") / file));
    EXPECT_TRUE(sameBytes(output("jobs0") / file, output("jobs4") / file));
  }
}

TEST_F(BatchTest, ShardsPartitionTheSortedJobList) {
  for (const std::string name : {"e.gltf", "a.gltf", "d.glb", "c.gltf", "b.gltf"})
    scene("s/" + name,
          {.format = name.ends_with(".glb") ? FileFormat::Glb : FileFormat::GltfEmbedded});
  const std::vector<Names> expected = {{"a.png", "d.png"}, {"b.png", "e.png"}, {"c.png"}};
  const std::vector<Names> names = {{"a.gltf", "d.glb"}, {"b.gltf", "e.gltf"}, {"c.gltf"}};
  for (int k = 0; k < 3; ++k) {
    SCOPED_TRACE("shard " + std::to_string(k));
    const std::string dir = "shard" + std::to_string(k);
    const Run r = batch({in("s"), "--out", output(dir).string(), "--shard",
                         std::to_string(k) + "/3", "--report", reportPath(dir + ".json")});
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(filesIn(output(dir)), expected[k]);
    const json doc = report(dir + ".json");
    EXPECT_EQ(doc["shard"], std::to_string(k) + "/3");
    Names reported;
    for (const json& job : doc["jobs"]) {
      reported.push_back(job["name"]);
      EXPECT_EQ(job["status"], "rendered");
    }
    EXPECT_EQ(reported, names[k]);
  }
}

TEST_F(BatchTest, BadShardsAreUsageErrors) {
  scene("s/a.gltf");
  for (const std::string shard : {"3/3", "x/2", "1/0", "-1/3", "1/2/3"}) {
    SCOPED_TRACE(shard);
    const Run r = batch({in("s"), "--out", output("o").string(), "--shard=" + shard});
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_TRUE(r.err.starts_with("omnishadow: ")) << r.err;
    EXPECT_EQ(r.out, "");
    EXPECT_EQ(filesIn(out_), Names{});
  }
}

// ---------------------------------------------------------------------------------------------
// Usage errors: status 2, a message, nothing rendered

struct UsageCase {
  std::string name;
  std::vector<std::string> args;  // "$in" and "$out" are replaced by the folders' paths
  std::string message;            // "$in" replaced likewise; "" = any one-line message
  bool oneLine = true;            // the message is one "omnishadow: " line
};

void PrintTo(const UsageCase& c, std::ostream* os) {
  *os << c.name;
}

// Inputs of every case: in/s/a.gltf, in/s/b.glb, in/t/a.glb, in/empty/ and the manifests below.
const std::pair<const char*, const char*> kManifests[] = {
    {"same-outputs.json", R"({"jobs": [{"scene": "s/a.gltf", "outputs": ["x/a.png"]},
                                       {"scene": "s/b.glb", "outputs": ["x/a.png"]}]})"},
    {"same-spelled-differently.json",
     R"({"jobs": [{"scene": "s/a.gltf", "outputs": ["x/a.png"]},
                  {"scene": "s/b.glb", "outputs": ["x/../x/./a.png"]}]})"},
    {"same-stems.json", R"({"jobs": [{"scene": "s/a.gltf"}, {"scene": "t/a.glb"}]})"},
    {"png-and-aov.json",
     R"({"jobs": [{"scene": "s/a.gltf", "outputs": ["a.exr"]},
                  {"scene": "s/b.glb", "outputs": ["b.png"], "aov": "a.exr"}]})"},
    {"bad-width.json",
     R"({"jobs": [{"scene": "s/a.gltf"}, {"scene": "s/b.glb", "width": "wide"}]})"},
    {"bad-eye.json", R"({"jobs": [{"scene": "s/a.gltf", "eye": [1, 2]}]})"},
    {"no-scene.json", R"({"jobs": [{"scene": "s/a.gltf"}, {"outputs": ["b.png"]}]})"},
    {"syntax.json", "{\"jobs\": [{\"scene\": \"s/a.gltf\",}]}"},
    {"jobs-not-array.json", R"({"jobs": {"scene": "s/a.gltf"}})"},
    {"jpeg.json", R"({"jobs": [{"scene": "s/a.gltf", "outputs": ["a.jpg"]}]})"},
    {"huge-scene-index.json",
     R"({"jobs": [{"scene": "s/a.gltf"}, {"scene": "s/b.glb", "sceneIndex": 1e12}]})"},
    {"bad-aa.json", R"({"jobs": [{"scene": "s/a.gltf", "aa": 3}]})"},
    {"masks-outside.json", R"({"jobs": [{"scene": "s/a.gltf", "masks": "../m"}]})"},
    {"nothing-to-write.json",
     R"({"jobs": [{"scene": "s/a.gltf", "masks": "a"}, {"scene": "s/b.glb", "outputs": []}]})"},
    {"images-left-out.json",
     R"({"jobs": [{"scene": "s/a.gltf", "masks": "a"}, {"scene": "s/b.glb"}]})"},
    {"masks-only.json", R"({"jobs": [{"scene": "s/a.gltf", "masks": "a"}]})"},
    {"outputs-not-names.json", R"({"jobs": [{"scene": "s/a.gltf", "outputs": [1]}]})"},
};

const UsageCase kUsageCases[] = {
    {"NoInputs", {"--out", "$out/o"}, "", false},
    {"NoOut", {"$in/s"}, "", false},
    {"EmptyFolder", {"$in/empty", "--out", "$out/o"}, ""},
    {"GlobMatchingNothing", {"$in/s/*.nothing", "--out", "$out/o"}, ""},
    {"MissingScene", {"$in/nosuch.gltf", "--out", "$out/o"}, ""},
    {"FolderAndFileWriteTheSamePng", {"$in/s", "$in/s/a.gltf", "--out", "$out/o"}, ""},
    {"SameOutputsInAManifest", {"$in/same-outputs.json", "--out", "$out/o"}, ""},
    {"SameOutputsSpelledDifferently", {"$in/same-spelled-differently.json", "--out", "$out/o"}, ""},
    {"SameStemsInAManifest", {"$in/same-stems.json", "--out", "$out/o"}, ""},
    {"ExrOfOneJobIsAovOfAnother", {"$in/png-and-aov.json", "--out", "$out/o"}, ""},
    {"ManifestFieldOfTheWrongType",
     {"$in/bad-width.json", "--out", "$out/o"},
     "$in/bad-width.json: jobs[1].width: expected "},
    {"ManifestEyeOfTwoNumbers",
     {"$in/bad-eye.json", "--out", "$out/o"},
     "$in/bad-eye.json: jobs[0].eye"},
    {"ManifestJobWithoutScene",
     {"$in/no-scene.json", "--out", "$out/o"},
     "$in/no-scene.json: jobs[1].scene"},
    {"ManifestSyntaxError", {"$in/syntax.json", "--out", "$out/o"}, "$in/syntax.json:"},
    {"ManifestJobsNotAnArray",
     {"$in/jobs-not-array.json", "--out", "$out/o"},
     "$in/jobs-not-array.json: jobs"},
    {"ManifestJpegOutput", {"$in/jpeg.json", "--out", "$out/o"}, ""},
    // Larger than any int: refused before the conversion, not converted.
    {"ManifestSceneIndexBeyondInt",
     {"$in/huge-scene-index.json", "--out", "$out/o"},
     "$in/huge-scene-index.json: jobs[1].sceneIndex: expected an integer in [0, "},
    {"ManifestAaNotASampleCount",
     {"$in/bad-aa.json", "--out", "$out/o"},
     "$in/bad-aa.json: jobs[0].aa: expected 1, 4, 8 or 16"},
    {"ManifestMasksOutsideOut",
     {"$in/masks-outside.json", "--out", "$out/o"},
     "$in/masks-outside.json: jobs[0].masks: \"../m\": "},
    {"AaNotASampleCount", {"$in/s", "--out", "$out/o", "--aa", "3"}, "", false},
    {"NoPngAloneOnAFolder",
     {"$in/s", "--out", "$out/o", "--no-png"},
     "--no-png: nothing left to write; add --exr, --aov or --masks"},
    // The manifest's job writes masks; the scene file beside it has nothing left.
    {"NoPngAloneOnASceneBesideAManifest",
     {"$in/masks-only.json", "$in/s/b.glb", "--out", "$out/o", "--no-png"},
     "--no-png: nothing left to write; add --exr, --aov or --masks"},
    {"ManifestJobWithNothingToWrite",
     {"$in/nothing-to-write.json", "--out", "$out/o"},
     "$in/nothing-to-write.json: jobs[1]: nothing to write; name images in \"outputs\", or "
     "give \"aov\" or \"masks\"\n"},
    {"ManifestJobWhoseImagesNoPngLeavesOut",
     {"$in/images-left-out.json", "--out", "$out/o", "--no-png"},
     "$in/images-left-out.json: jobs[1]: nothing to write; name images in \"outputs\", or "
     "give \"aov\" or \"masks\" (--no-png leaves out the images)\n"},
    {"ManifestOutputsNotNames",
     {"$in/outputs-not-names.json", "--out", "$out/o"},
     "$in/outputs-not-names.json: jobs[0].outputs: expected an array of file names"},
};

class BatchUsageTest : public BatchTest, public ::testing::WithParamInterface<UsageCase> {};

TEST_P(BatchUsageTest, ExitsWithStatus2AndRendersNothing) {
  const UsageCase& c = GetParam();
  scene("s/a.gltf");
  scene("s/b.glb", {.format = FileFormat::Glb});
  scene("t/a.glb", {.format = FileFormat::Glb});
  fs::create_directories(input("empty"));
  for (const auto& [name, text] : kManifests) writeText(name, text);
  const Names inputs = filesIn(in_);
  std::vector<std::string> args = {"batch"};
  for (const std::string& arg : c.args) args.push_back(substituted(arg));

  const Run r = run(args);

  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_TRUE(r.err.starts_with("omnishadow: ")) << r.err;
  if (!c.message.empty()) {
    EXPECT_TRUE(r.err.starts_with("omnishadow: " + substituted(c.message))) << r.err;
  }
  if (c.oneLine) {
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_TRUE(r.err.ends_with("\n")) << r.err;
  }
  EXPECT_EQ(r.out, "");
  EXPECT_EQ(filesIn(out_), Names{}) << "a usage error left files";
  EXPECT_EQ(filesIn(in_), inputs);
}

INSTANTIATE_TEST_SUITE_P(Batch, BatchUsageTest, ::testing::ValuesIn(kUsageCases),
                         [](const ::testing::TestParamInfo<UsageCase>& test) {
                           return test.param.name;
                         });

// ---------------------------------------------------------------------------------------------
// --quiet

TEST_F(BatchTest, QuietPrintsNothingButFailures) {
  scene("s/a.gltf");
  const Run ok = batch({in("s"), "--out", output("ok").string(), "-q"});
  EXPECT_EQ(ok.status, 0) << ok.err;
  EXPECT_EQ(ok.out, "");
  EXPECT_EQ(filesIn(output("ok")), Names{"a.png"});

  writeText("s/bad.gltf", "this is not glTF");
  const Run failed = batch({in("s"), "--out", output("failed").string(), "--quiet"});
  EXPECT_EQ(failed.status, 1) << failed.err;
  EXPECT_EQ(failed.out, "");
  EXPECT_TRUE(contains(failed.err, "omnishadow: bad.gltf: ")) << failed.err;
  EXPECT_EQ(filesIn(output("failed")), Names{"a.png"});
}

}  // namespace
}  // namespace omnishadow::batch_test
