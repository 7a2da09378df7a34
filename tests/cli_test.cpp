// End-to-end tests of the omnishadow binary: exit statuses and messages, what lands on disk (and
// that nothing does when a run fails), and the images themselves, read back with readImage.
// Every test runs the real executable in a fresh temporary folder:
//   <root>/in   inputs, written with GltfBuilder and as JSON text
//   <root>/out  the working directory of the run, where relative outputs go
//   <root>/stdout, <root>/stderr  what the run printed
// Renders are small (96x64, 64-texel shadow maps): llvmpipe is slow and CI has two cores.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <utility>
#include <vector>

#include "renderer/output/image_writer.h"
#include "scenes/builder/gltf_builder.h"
#include "tests/support/cli_fixture.h"

namespace omnishadow::cli_test {
namespace {

namespace fs = std::filesystem;
using builder::FileFormat;
using builder::GltfBuilder;

// ---------------------------------------------------------------------------------------------
// Inputs

// A point light "key" with a cheap shadow map.
constexpr const char* kKeyLights = R"({
  "lights": [
    {"name": "key", "position": [-1.5, 3, 1.5], "intensity": 20, "shadow": {"resolution": 64}}
  ]
})";

// ---------------------------------------------------------------------------------------------
// Reading results

using SceneSpec = test_support::BoxSceneSpec;
using test_support::contains;
using test_support::filesIn;
using test_support::pngHeader;
using test_support::PngHeader;
using test_support::readFile;
using test_support::sameBytes;
using test_support::writeBoxScene;

std::vector<std::string> sortedChannels(const FloatImage& image) {
  std::vector<std::string> channels = image.channels;
  std::sort(channels.begin(), channels.end());
  return channels;
}

std::vector<std::string> visibilityChannels(const FloatImage& image) {
  std::vector<std::string> channels;
  for (const std::string& c : sortedChannels(image))
    if (c.starts_with("visibility.")) channels.push_back(c);
  return channels;
}

double channelMean(const FloatImage& image, int channel) {
  double sum = 0.0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) sum += image.at(x, y, channel);
  return sum / (static_cast<double>(image.width) * image.height);
}

double channelVariance(const FloatImage& image, int channel) {
  const double mean = channelMean(image, channel);
  double sum = 0.0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) sum += std::pow(image.at(x, y, channel) - mean, 2);
  return sum / (static_cast<double>(image.width) * image.height);
}

// ---------------------------------------------------------------------------------------------
// Running the binary

class CliTest : public test_support::CliFixture {
 protected:
  CliTest() : CliFixture("omnishadow-cli") {}

  // `omnishadow render args... --width 96 --height 64`, expected to succeed.
  Run render(std::vector<std::string> args) {
    return runSucceeding("render", std::move(args), {"--width", "96", "--height", "64"});
  }

  fs::path scene(const std::string& name = "scene.gltf", const SceneSpec& spec = {}) {
    writeBoxScene(input(name), spec);
    return input(name);
  }
};

// ---------------------------------------------------------------------------------------------
// Errors: the status, the message, and no file at all in the output folder afterwards

struct ErrorCase {
  std::string name;
  std::string lightsJson;         // written to in/lights.json
  std::vector<std::string> args;  // "$scene", "$lights" and "$in" are replaced by paths
  int status;
  std::string message;                      // "$..." replaced likewise
  enum { Contains, OneLine, Exact } match;  // OneLine: the message is one "omnishadow: " line
};

// gtest names a failing case by this rather than by a byte dump.
void PrintTo(const ErrorCase& c, std::ostream* os) {
  *os << c.name;
}

class CliErrorTest : public CliTest, public ::testing::WithParamInterface<ErrorCase> {};

const ErrorCase kErrorCases[] = {
    {"NoSubcommand", kKeyLights, {}, 2, "A subcommand is required", ErrorCase::Contains},
    {"UnknownOption", kKeyLights, {"render", "--bogus"}, 2, "--bogus", ErrorCase::Contains},
    {"MissingScene",
     kKeyLights,
     {"render", "$in/nosuch.gltf", "-o", "a.png"},
     2,
     "$in/nosuch.gltf: cannot read glTF file",
     ErrorCase::OneLine},
    {"MissingLightsFile",
     kKeyLights,
     {"render", "$scene", "-l", "$in/nosuch.json"},
     2,
     "$in/nosuch.json: cannot read lights file",
     ErrorCase::OneLine},
    {"BadLightPosition",
     R"({"lights": [{"name": "key", "position": [1, 2]}]})",
     {"render", "$scene", "-l", "$lights", "-o", "a.png"},
     2,
     "omnishadow: $lights: lights[0].position: expected an array of 3 finite numbers\n",
     ErrorCase::Exact},
    {"JsonSyntaxError",
     "{\n  \"lights\": [\n    {\"name\": \"key\",}\n  ]\n}",
     {"render", "$scene", "-l", "$lights", "-o", "a.png"},
     2,
     "$lights:3:20: JSON syntax error",
     ErrorCase::OneLine},
    {"JpegOutput",
     kKeyLights,
     {"render", "$scene", "-o", "out.jpg"},
     2,
     "-o out.jpg: unsupported image format",
     ErrorCase::OneLine},
    {"AovNotExr",
     kKeyLights,
     {"render", "$scene", "--aov", "x.png"},
     2,
     "--aov x.png: AOVs are written as OpenEXR",
     ErrorCase::OneLine},
    {"SameOutputTwice",
     kKeyLights,
     {"render", "$scene", "-o", "a.exr", "--aov", "a.exr"},
     2,
     "the same file is given twice",
     ErrorCase::OneLine},
    {"SameOutputTwiceSpelledDifferently",
     kKeyLights,
     {"render", "$scene", "-o", "a.png", "-o", "./a.png"},
     2,
     "the same file is given twice",
     ErrorCase::OneLine},
    {"NanExposure",
     kKeyLights,
     {"render", "$scene", "--exposure", "nan", "-o", "a.png"},
     2,
     "--exposure nan: expected a finite number",
     ErrorCase::OneLine},
    {"InfiniteExposure",
     kKeyLights,
     {"render", "$scene", "--exposure", "inf", "-o", "a.exr"},
     2,
     "--exposure inf: expected a finite number",
     ErrorCase::OneLine},
    {"UnknownCamera",
     kKeyLights,
     {"render", "$scene", "--camera", "nosuch", "-o", "a.png"},
     2,
     R"($scene has no such camera (cameras: 0 "main", 1 "top"))",
     ErrorCase::OneLine},
    {"EyeWithTwoNumbers",
     kKeyLights,
     {"render", "$scene", "--eye", "1,2", "-o", "a.png"},
     2,
     "--eye 1,2: expected 3 comma-separated finite numbers",
     ErrorCase::OneLine},
    {"UnknownDepthPrepass",
     kKeyLights,
     {"render", "$scene", "--depth-prepass", "yes", "-o", "a.png"},
     2,
     "--depth-prepass: yes not in {auto,on,off}",
     ErrorCase::Contains},
    // A usage error: one line naming --gpu and the EGL devices that exist; no output.
    {"NoSuchGpu",
     kKeyLights,
     {"render", "$scene", "--gpu", "99", "-o", "a.png"},
     2,
     "omnishadow: --gpu 99: there are only ",
     ErrorCase::OneLine},
    // Found only once the GL context is up, just before rendering.
    {"TooManyShadowTextures",
     test_support::distinctResolutionLights(5),
     {"render", "$scene", "-l", "$lights", "--no-gltf-lights", "-o", "a.png", "--aov", "a.exr"},
     2,
     "the point lights' shadow maps need more than 4 textures",
     ErrorCase::OneLine},
    // Found while staging the outputs, after a.png's temporary was created.
    {"UnwritableSecondOutput",
     kKeyLights,
     {"render", "$scene", "--width", "8", "--height", "8", "-o", "a.png", "-o", "$scene/b.png"},
     1,
     "cannot write $scene/b.png",
     ErrorCase::OneLine},
};

TEST_P(CliErrorTest, ExitsWithStatusMessageAndNoOutput) {
  const ErrorCase& c = GetParam();
  scene("scene.gltf");
  writeText("lights.json", c.lightsJson);
  const std::vector<std::string> inputsBefore = filesIn(in_);
  std::vector<std::string> args;
  for (const std::string& arg : c.args) args.push_back(substituted(arg));

  const Run r = run(args);

  EXPECT_EQ(r.status, c.status) << r.err;
  const std::string message = substituted(c.message);
  if (c.match == ErrorCase::Exact) {
    EXPECT_EQ(r.err, message);
  } else {
    EXPECT_TRUE(contains(r.err, message));
  }
  if (c.match == ErrorCase::OneLine) {
    EXPECT_TRUE(r.err.starts_with("omnishadow: ")) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_TRUE(r.err.ends_with("\n")) << r.err;
  }
  EXPECT_EQ(r.out, "");
  EXPECT_EQ(filesIn(out_), std::vector<std::string>{}) << "a failed run left files";
  EXPECT_EQ(filesIn(in_), inputsBefore);
}

INSTANTIATE_TEST_SUITE_P(Cli, CliErrorTest, ::testing::ValuesIn(kErrorCases),
                         [](const ::testing::TestParamInfo<ErrorCase>& test) {
                           return test.param.name;
                         });

// A usage error points at the help of the command it belongs to, whichever command that is.
TEST_F(CliTest, UsageErrorsNameTheirCommandsHelp) {
  for (const std::string command : {"render", "batch", "diff", "verify", "devices", "report"}) {
    const Run r = run({command, "--no-such-option"});
    EXPECT_EQ(r.status, 2) << command;
    EXPECT_TRUE(contains(r.err, "'omnishadow " + command + " --help'")) << r.err;
  }
}

TEST_F(CliTest, OutputThatIsAFolderIsRejectedBeforeRendering) {
  const fs::path scenePath = scene("scene.gltf");
  fs::create_directory(in_ / "folder.png");
  const Run r =
      run({"render", scenePath.string(), "-o", "a.png", "-o", (in_ / "folder.png").string()});
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(contains(r.err, "folder.png: is a folder, expected an image file name")) << r.err;
  EXPECT_EQ(filesIn(out_), std::vector<std::string>{});
}

TEST_F(CliTest, AnEnvironmentImageThatCannotBeReadEndsTheRenderWithStatusTwoAndNoPicture) {
  const fs::path scenePath = scene("scene.gltf");
  const fs::path lightsPath =
      writeText("lights.json", R"({"environment": {"image": "missing.hdr"}})");
  const Run r = run({"render", scenePath.string(), "-l", lightsPath.string(), "--width", "16",
                     "--height", "16", "-o", "a.png"});
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(contains(r.err, lightsPath.string() + ": environment.image: " +
                                  (in_ / "missing.hdr").string() + ": cannot read image"))
      << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_EQ(filesIn(out_), std::vector<std::string>{});
  // A uniform environment as the background: every pixel opaque, no alpha channel needed.
  const fs::path uniform = writeText(
      "uniform.json", R"({"environment": {"color": [0.2, 0.4, 0.8], "background": true}})");
  render({scenePath.string(), "-l", uniform.string(), "-o", "lit.png"});
  EXPECT_EQ(pngHeader(output("lit.png")).colorType, 2);
}

TEST_F(CliTest, RefusesToOverwriteATextureTheSceneReads) {
  writeBoxScene(in_ / "scene.gltf", {.format = FileFormat::GltfExternal});
  const std::vector<std::string> inputs = filesIn(in_);
  const auto texture = std::find_if(inputs.begin(), inputs.end(),
                                    [](const std::string& name) { return name.ends_with(".png"); });
  ASSERT_NE(texture, inputs.end());
  const std::string before = readFile(in_ / *texture);
  const Run r = run({"render", (in_ / "scene.gltf").string(), "-o", (in_ / *texture).string()});
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(contains(r.err, "refusing to overwrite an input file")) << r.err;
  EXPECT_EQ(readFile(in_ / *texture), before);
}

TEST_F(CliTest, FailedRunRemovesTheFoldersItCreated) {
  const fs::path scenePath = scene("scene.gltf");
  const Run r = run({"render", scenePath.string(), "--width", "8", "--height", "8", "-o",
                     "new/deeper/a.png", "-o", (scenePath / "b.png").string()});
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_EQ(filesIn(out_), std::vector<std::string>{});
}

TEST_F(CliTest, WarningsAreStillPrintedWhenTheRunFails) {
  const fs::path scenePath = scene("scene.gltf");
  std::string lights = test_support::distinctResolutionLights(5);
  lights.insert(1, R"("colour": 1, )");
  const fs::path lightsPath = writeText("lights.json", lights);
  const Run r = run({"render", scenePath.string(), "-l", lightsPath.string(), "--no-gltf-lights"});
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(contains(r.err, "colour: unknown field, ignored")) << r.err;
  EXPECT_TRUE(contains(r.err, "use fewer distinct shadow resolutions")) << r.err;
}

TEST_F(CliTest, NoEglContextSaysWhatWasTried) {
  // glvnd finds no vendor library, so every platform fails; the message lists the attempts.
  const fs::path scenePath = scene("scene.gltf");
  const Run r = run({"render", scenePath.string(), "-o", "a.png"},
                    {"__EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent/vendor.json"});
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(
      contains(r.err, "cannot create a headless OpenGL 4.5 core context through EGL; tried:"))
      << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_EQ(filesIn(out_), std::vector<std::string>{});
}

TEST_F(CliTest, ASceneThatCannotLoadIsReportedEvenWhenNoContextCanBeOpenedBesideIt) {
  // The scene loads on a second thread while the context opens; when both fail, the scene's
  // error (the user's to fix) is the one reported, as when they ran in turn.
  const fs::path broken =
      writeText("broken.gltf", "{\"asset\": {\"version\": \"2.0\"}, \"scenes\": 7}");
  const Run r = run({"render", broken.string(), "-o", "a.png"},
                    {"__EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent/vendor.json"});
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_TRUE(contains(r.err, broken.string())) << r.err;
  EXPECT_FALSE(contains(r.err, "EGL")) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_EQ(filesIn(out_), std::vector<std::string>{});
}

TEST_F(CliTest, GpuWhereEglListsNoDeviceIsAUsageError) {
  // Without a vendor library EGL lists no device at all: asking for one is still the user's
  // mistake (exit 2, one line naming --gpu), not a failure of the renderer.
  const fs::path scenePath = scene("scene.gltf");
  const Run r = run({"render", scenePath.string(), "--gpu", "0", "-o", "a.png"},
                    {"__EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent/vendor.json"});
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(contains(r.err, "omnishadow: --gpu 0: there are no EGL devices")) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_EQ(filesIn(out_), std::vector<std::string>{});
}

TEST_F(CliTest, RefusesToOverwriteAnInput) {
  // Outputs are checked before the scene is read, so this input need not even be a scene.
  const fs::path precious = writeText("picture.png", "precious bytes");
  for (const std::string& spelling : std::vector<std::string>{
           precious.string(), (in_ / "sub" / ".." / "picture.png").string(), "../in/picture.png"}) {
    SCOPED_TRACE(spelling);
    const Run r = run({"render", precious.string(), "-o", spelling});
    EXPECT_EQ(r.status, 2);
    EXPECT_TRUE(contains(r.err, spelling + ": refusing to overwrite an input file"));
    EXPECT_EQ(readFile(precious), "precious bytes");
    EXPECT_EQ(filesIn(in_), std::vector<std::string>{"picture.png"});
  }
  // The lights file is an input as well.
  const fs::path lights = writeText("lights.exr", kKeyLights);
  const Run r = run({"render", scene().string(), "-l", lights.string(), "-o", lights.string()});
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(contains(r.err, "refusing to overwrite an input file"));
  EXPECT_EQ(readFile(lights), kKeyLights);
}

// ---------------------------------------------------------------------------------------------
// Outputs

TEST_F(CliTest, WritesPngExrAndAovsInOneRun) {
  const fs::path lights = writeText("lights.json", kKeyLights);
  const Run r = render(
      {scene().string(), "-l", lights.string(), "-o", "a.png", "-o", "b.exr", "--aov", "c.exr"});

  EXPECT_EQ(r.out, "wrote a.png (96x64)\nwrote b.exr (96x64)\nwrote c.exr (AOVs)\n");
  EXPECT_EQ(filesIn(out_), (std::vector<std::string>{"a.png", "b.exr", "c.exr"}));

  const PngHeader png = pngHeader(output("a.png"));
  EXPECT_EQ(png.width, 96u);
  EXPECT_EQ(png.height, 64u);
  EXPECT_EQ(png.bitDepth, 8);
  EXPECT_EQ(png.colorType, 2) << "not RGB";
  EXPECT_EQ(readImage(output("a.png")).channels.size(), 3u);

  const FloatImage beauty = readImage(output("b.exr"));
  EXPECT_EQ(beauty.width, 96);
  EXPECT_EQ(beauty.height, 64);
  EXPECT_EQ(sortedChannels(beauty), (std::vector<std::string>{"A", "B", "G", "R"}));

  // The glTF's lamp and the lights file's key light, merged.
  const FloatImage aovs = readImage(output("c.exr"));
  EXPECT_EQ(sortedChannels(aovs),
            (std::vector<std::string>{"A", "B", "G", "N.X", "N.Y", "N.Z", "P.X", "P.Y", "P.Z", "R",
                                      "Z", "visibility.key", "visibility.lamp"}));
  // The AOV file's colour (float) is the beauty image's (half).
  ASSERT_EQ(aovs.width, beauty.width);
  ASSERT_EQ(aovs.height, beauty.height);
  for (const char* channel : {"R", "G", "B", "A"}) {
    const int a = aovs.channelIndex(channel), b = beauty.channelIndex(channel);
    for (int y = 0; y < beauty.height; ++y)
      for (int x = 0; x < beauty.width; ++x)
        ASSERT_NEAR(aovs.at(x, y, a), beauty.at(x, y, b),
                    1e-3 * std::abs(beauty.at(x, y, b)) + 1e-6)
            << channel << " at " << x << "," << y;
  }
}

TEST_F(CliTest, OutputsAreByteIdenticalAcrossRuns) {
  const fs::path lights = writeText("lights.json", kKeyLights);
  for (const std::string folder : {"first", "second"})
    render({scene().string(), "-l", lights.string(), "-o", folder + "/a.png", "-o",
            folder + "/a.exr", "--aov", folder + "/aov.exr"});
  for (const std::string file : {"a.png", "a.exr", "aov.exr"})
    EXPECT_TRUE(sameBytes(output("first") / file, output("second") / file));
}

// The depth pre-pass changes how a picture is drawn, not what it shows: PNG (the 8-bit beauty
// the lighting pass encodes) and EXR (the float one) alike.
TEST_F(CliTest, DepthPrepassOnAndOffWriteTheSameFiles) {
  const fs::path lights = writeText("lights.json", kKeyLights);
  for (const std::string prepass : {"on", "off", "auto"}) {
    render({scene().string(), "-l", lights.string(), "--depth-prepass", prepass, "-o",
            prepass + "/a.png"});
    render({scene().string(), "-l", lights.string(), "--depth-prepass", prepass, "-o",
            prepass + "/a.exr"});
  }
  for (const std::string file : {"a.png", "a.exr"}) {
    EXPECT_TRUE(sameBytes(output("on") / file, output("off") / file)) << file;
    EXPECT_TRUE(sameBytes(output("on") / file, output("auto") / file)) << file;
  }
}

// Ambient occlusion: the same files across runs and with or without the pre-pass, a debug view
// of it, and a bad field is an input error naming the file and the field, with no picture.
TEST_F(CliTest, AmbientOcclusionIsRepeatableAndItsErrorsEndTheRunWithStatusTwo) {
  const fs::path lights = writeText(
      "occluded.json", R"({"ambient": [0.3, 0.3, 0.3], "ambient_occlusion": {"radius": 0.5},
                          "lights": [{"type": "point", "position": [2, 3, 2]}]})");
  for (const std::string prepass : {"on", "off"})
    for (const std::string run : {"1", "2"})
      render({scene().string(), "-l", lights.string(), "--depth-prepass", prepass, "-o",
              prepass + run + "/a.png", "-o", prepass + run + "/a.exr"});
  for (const std::string file : {"a.png", "a.exr"}) {
    EXPECT_TRUE(sameBytes(output("on1") / file, output("on2") / file)) << file;
    EXPECT_TRUE(sameBytes(output("on1") / file, output("off1") / file)) << file;
  }
  render({scene().string(), "-l", lights.string(), "--debug-view", "occlusion", "-o",
          "occlusion.exr"});
  const FloatImage view = readImage(output("occlusion.exr"));
  float darkest = 1.0f;
  for (int y = 0; y < view.height; ++y)
    for (int x = 0; x < view.width; ++x) {
      if (view.at(x, y, 3) < 1.0f) continue;
      EXPECT_LE(view.at(x, y, 0), 1.0f);
      darkest = std::min(darkest, view.at(x, y, 0));
    }
  EXPECT_LT(darkest, 0.9f);  // the box stands on the floor

  const fs::path bad =
      writeText("bad.json", R"({"ambient_occlusion": {"radius": 0.5, "strength": 2}})");
  const Run r = run({"render", scene().string(), "-l", bad.string(), "-o", "bad.png"});
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.err, "omnishadow: " + bad.string() +
                       ": ambient_occlusion.strength: expected a number in [0, 1], got 2\n");
  EXPECT_FALSE(fs::exists(output("bad.png")));
}

TEST_F(CliTest, ExposureScalesLinearValuesAndBrightensThePng) {
  const std::string path = scene().string();
  render({path, "-o", "zero.exr", "-o", "zero.png"});
  render({path, "-o", "one.exr", "-o", "one.png", "--exposure", "1"});

  const FloatImage zero = readImage(output("zero.exr")), one = readImage(output("one.exr"));
  ASSERT_EQ(zero.channels, one.channels);
  ASSERT_EQ(zero.pixels.size(), one.pixels.size());
  int lit = 0;
  for (std::size_t i = 0; i < zero.pixels.size(); ++i) {
    const bool alpha = zero.channels[i % zero.channels.size()] == "A";
    const float expected = alpha ? zero.pixels[i] : 2.0f * zero.pixels[i];
    ASSERT_NEAR(one.pixels[i], expected, std::abs(expected) / 1024.0f + 1e-7f) << "value " << i;
    lit += !alpha && zero.pixels[i] > 0.01f;
  }
  EXPECT_GT(lit, 1000) << "the image is too dark to tell";

  const FloatImage pngZero = readImage(output("zero.png")), pngOne = readImage(output("one.png"));
  ASSERT_EQ(pngZero.pixels.size(), pngOne.pixels.size());
  for (std::size_t i = 0; i < pngZero.pixels.size(); ++i)
    ASSERT_GE(pngOne.pixels[i], pngZero.pixels[i]) << "value " << i;
  for (int c = 0; c < 3; ++c) EXPECT_GT(channelMean(pngOne, c), channelMean(pngZero, c) + 0.05);
}

// A PNG alone is encoded by the lighting pass, a PNG beside an EXR from the float beauty: the
// bytes are the same, at any exposure.
TEST_F(CliTest, APngAloneIsTheSameAsAPngBesideAnExr) {
  const fs::path lights = writeText("lights.json", kKeyLights);
  for (const std::string exposure : {"0", "1.3", "-0.6"}) {
    SCOPED_TRACE("exposure " + exposure);
    render({scene().string(), "-l", lights.string(), "-o", "alone.png", "--exposure", exposure});
    render({scene().string(), "-l", lights.string(), "-o", "beside.png", "-o", "beside.exr",
            "--exposure", exposure});
    EXPECT_TRUE(sameBytes(output("alone.png"), output("beside.png")));
  }
}

TEST_F(CliTest, StatsNameEveryStage) {
  const Run r = render({scene().string(), "-o", "a.png", "--stats"});
  for (const char* stage :
       {"load", "context", "upload", "shadow maps", "lighting", "readback", "encode", "total"}) {
    EXPECT_TRUE(
        std::regex_search(r.err, std::regex(std::string("(^|\n)") + stage + " +[0-9]+\\.[0-9]\n")))
        << "no time for " << stage << " in:\n"
        << r.err;
  }
}

// The GL stages' waits for the GPU come after the total, each a part of its stage's time.
TEST_F(CliTest, StatsGiveEachGlStagesWaitForTheGpu) {
  const Run r = render({scene().string(), "-o", "a.png", "--stats"});
  auto row = [&](const std::string& name) {
    std::smatch m;
    EXPECT_TRUE(std::regex_search(r.err, m, std::regex("(^|\n)" + name + " +([0-9]+\\.[0-9])\n")))
        << "no row " << name << " in:\n"
        << r.err;
    return m.empty() ? -1.0 : std::stod(m[2].str());
  };
  const std::size_t total = r.err.find("\ntotal ");
  for (const char* stage : {"upload", "shadow maps", "lighting"}) {
    const double wait = row(std::string("GPU wait: ") + stage);
    EXPECT_GE(wait, 0.0) << stage;
    EXPECT_LE(wait, row(stage)) << stage;
    EXPECT_GT(r.err.find(std::string("\nGPU wait: ") + stage), total) << r.err;
    // A line that begins with the stage's name is the stage's own.
    EXPECT_EQ(r.err.find(std::string("\n") + stage + " wait"), std::string::npos) << r.err;
  }
}

// More than 20 lights with AOVs: lighting runs in several passes, yet --stats sums each stage
// into one row.
TEST_F(CliTest, StatsNameEachStageOnceWhenLightingRunsInSeveralPasses) {
  std::string lights = R"({"lights": [)";
  for (int i = 0; i < 24; ++i)
    lights += (i ? ", " : "") + std::string(R"({"position": [)") + std::to_string(i % 6 - 3) +
              ", 3, " + std::to_string(i / 6) + R"(], "intensity": 2, "shadow": false})";
  const fs::path lightsPath = writeText("many.lights.json", lights + "]}");
  const Run r = render({scene().string(), "-l", lightsPath.string(), "--no-gltf-lights", "-o",
                        "a.png", "--aov", "a.exr", "--stats"});
  for (const char* stage :
       {"load", "context", "upload", "lighting", "readback", "encode", "total"}) {
    const std::regex row(std::string("(^|\n)") + stage + " +[0-9]+\\.[0-9]\n");
    const auto rows = std::distance(std::sregex_iterator(r.err.begin(), r.err.end(), row),
                                    std::sregex_iterator());
    EXPECT_EQ(rows, 1) << stage << " in:\n" << r.err;
  }
}

TEST_F(CliTest, VerboseNamesTheGlImplementation) {
  const Run r = render({scene().string(), "-o", "a.png", "-v"});
  // "omnishadow: <vendor> | <renderer> | <version>", e.g. "Mesa | llvmpipe (...) | 4.5 (Core...".
  EXPECT_TRUE(
      std::regex_search(r.err, std::regex("(^|\n)omnishadow: [^|\n]+ \\| [^|\n]+ \\| 4\\.[5-9]")))
      << r.err;
  EXPECT_TRUE(contains(r.err, R"(camera: glTF camera 0 "main", 96x64)"));
}

// ---------------------------------------------------------------------------------------------
// Lights

TEST_F(CliTest, FindsTheLightsFileBesideTheScene) {
  const fs::path path = scene("room.gltf");
  writeText("room.lights.json", kKeyLights);
  render({path.string(), "--aov", "found.exr"});
  EXPECT_EQ(visibilityChannels(readImage(output("found.exr"))),
            (std::vector<std::string>{"visibility.key", "visibility.lamp"}));

  // --lights wins over the file beside the scene.
  const fs::path other = writeText("other.json", R"({"lights": [{"name": "fill",
      "position": [0, 3, 3], "shadow": {"resolution": 64}}]})");
  render({path.string(), "-l", other.string(), "--aov", "given.exr"});
  EXPECT_EQ(visibilityChannels(readImage(output("given.exr"))),
            (std::vector<std::string>{"visibility.fill", "visibility.lamp"}));
}

TEST_F(CliTest, NoGltfLightsDropsTheScenesLights) {
  const fs::path lights = writeText("lights.json", kKeyLights);
  render({scene().string(), "-l", lights.string(), "--no-gltf-lights", "--aov", "a.exr"});
  EXPECT_EQ(visibilityChannels(readImage(output("a.exr"))),
            std::vector<std::string>{"visibility.key"});
}

TEST_F(CliTest, LightsFileLightReplacesTheGltfLightOfTheSameName) {
  // Visibility of covered pixels: (lowest, highest).
  auto visibilityRange = [](const FloatImage& aovs) {
    const int a = aovs.channelIndex("A"), v = aovs.channelIndex("visibility.lamp");
    float lowest = 1.0f, highest = 0.0f;
    for (int y = 0; y < aovs.height; ++y)
      for (int x = 0; x < aovs.width; ++x)
        if (aovs.at(x, y, a) > 0.5f) {
          lowest = std::min(lowest, aovs.at(x, y, v));
          highest = std::max(highest, aovs.at(x, y, v));
        }
    return std::make_pair(lowest, highest);
  };
  const fs::path path = scene();
  render({path.string(), "--aov", "gltf.exr"});
  const FloatImage gltf = readImage(output("gltf.exr"));
  EXPECT_EQ(visibilityChannels(gltf), std::vector<std::string>{"visibility.lamp"});
  EXPECT_EQ(visibilityRange(gltf), std::make_pair(0.0f, 1.0f)) << "the box shadows the floor";

  const fs::path lights = writeText("lights.json", R"({"lights": [{"name": "lamp",
      "position": [1.5, 3, 1], "intensity": 30, "shadow": false}]})");
  render({path.string(), "-l", lights.string(), "--aov", "file.exr"});
  const FloatImage file = readImage(output("file.exr"));
  EXPECT_EQ(visibilityChannels(file), std::vector<std::string>{"visibility.lamp"});
  EXPECT_EQ(visibilityRange(file), std::make_pair(1.0f, 1.0f)) << "the file's lamp is unshadowed";
}

TEST_F(CliTest, RendersWithAHeadlightWhenThereAreNoLights) {
  const Run r =
      render({scene("scene.gltf", {.gltfLight = false}).string(), "-o", "a.png", "--aov", "a.exr"});
  EXPECT_TRUE(contains(r.err, "headlight"));
  EXPECT_EQ(visibilityChannels(readImage(output("a.exr"))),
            std::vector<std::string>{"visibility.headlight"});
  EXPECT_GT(channelMean(readImage(output("a.png")), 0), 0.1);
}

TEST_F(CliTest, UnknownLightsFieldIsAWarning) {
  const fs::path lights = writeText("lights.json", R"({"lights": [{"name": "key",
      "position": [-1.5, 3, 1.5], "colour": [1, 0, 0], "shadow": {"resolution": 64}}]})");
  const Run r = render({scene().string(), "-l", lights.string(), "-o", "a.png"});
  EXPECT_TRUE(contains(r.err, "omnishadow: warning: " + lights.string() +
                                  ": lights[0].colour: unknown field, ignored\n"));
  EXPECT_TRUE(fs::exists(output("a.png")));
}

// ---------------------------------------------------------------------------------------------
// Scenes and cameras

TEST_F(CliTest, EmbeddedExternalAndBinaryScenesRenderAlike) {
  fs::create_directories(input("embedded"));
  fs::create_directories(input("external"));
  fs::create_directories(input("binary"));
  const fs::path embedded = scene("embedded/scene.gltf", {.format = FileFormat::GltfEmbedded});
  const fs::path external = scene("external/scene.gltf", {.format = FileFormat::GltfExternal});
  const fs::path binary = scene("binary/scene.glb", {.format = FileFormat::Glb});
  ASSERT_EQ(filesIn(input("external")),
            (std::vector<std::string>{"scene.bin", "scene.gltf", "scene_image0.png"}));

  render({embedded.string(), "-o", "embedded.png"});
  render({external.string(), "-o", "external.png"});
  render({binary.string(), "-o", "binary.png"});
  EXPECT_TRUE(sameBytes(output("embedded.png"), output("external.png")));
  EXPECT_TRUE(sameBytes(output("embedded.png"), output("binary.png")));
}

TEST_F(CliTest, CameraByNameOrIndex) {
  const std::string path = scene().string();
  render({path, "--camera", "main", "-o", "name.png"});
  render({path, "--camera", "0", "-o", "index.png"});
  render({path, "--camera", "top", "-o", "top.png"});
  EXPECT_TRUE(sameBytes(output("name.png"), output("index.png")));
  EXPECT_NE(readFile(output("name.png")), readFile(output("top.png")));
}

TEST_F(CliTest, SceneWithoutCameraIsFramedAutomatically) {
  render({scene("scene.gltf", {.cameras = false}).string(), "--aov", "a.exr"});
  const FloatImage aovs = readImage(output("a.exr"));
  EXPECT_GT(aovs.at(aovs.width / 2, aovs.height / 2, aovs.channelIndex("A")), 0.5f);
}

TEST_F(CliTest, CameraAspectRatioGivesTheMissingSide) {
  const std::string path = scene("scene.gltf", {.aspectRatio = 2.0f}).string();
  ASSERT_EQ(run({"render", path, "--width", "100", "-o", "wide.png"}).status, 0);
  ASSERT_EQ(run({"render", path, "--height", "30", "-o", "high.png"}).status, 0);
  const PngHeader wide = pngHeader(output("wide.png")), high = pngHeader(output("high.png"));
  EXPECT_EQ(std::make_pair(wide.width, wide.height), std::make_pair(100u, 50u));
  EXPECT_EQ(std::make_pair(high.width, high.height), std::make_pair(60u, 30u));
}

TEST_F(CliTest, BuiltInDemoRendersWithoutArguments) {
  const Run r = run({"render", "--width", "160", "--height", "90", "-o", "demo.png"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out, "wrote demo.png (160x90)\n");
  const FloatImage demo = readImage(output("demo.png"));
  EXPECT_EQ(demo.width, 160);
  EXPECT_EQ(demo.height, 90);
  double variance = 0.0;
  for (int c = 0; c < 3; ++c) variance += channelVariance(demo, c);
  EXPECT_GT(variance, 1e-3) << "a flat image";
}

// ---------------------------------------------------------------------------------------------
// Mesa's shader cache (cli/shader_cache_folder.h)

// A user whose home cannot hold Mesa's cache, as in a container run as a user of its own: Mesa
// keeps the compiled shaders in the CLI's folder instead of nowhere, and prints no "disabling"
// line; where the user turned the cache off, the CLI makes no folder.
TEST_F(CliTest, MesaKeepsItsShadersInTheCliFolderWhereItsOwnPlaceCannotBeWritten) {
  if (std::getenv("MESA_SHADER_CACHE_DIR") || std::getenv("MESA_GLSL_CACHE_DIR") ||
      std::getenv("MESA_SHADER_CACHE_DISABLE") || std::getenv("MESA_GLSL_CACHE_DISABLE"))
    GTEST_SKIP() << "Mesa's shader cache variables are set for the tests";
  writeBoxScene(input("scene.gltf"));
  std::ofstream(root_ / "file") << "not a folder";
  const fs::path tmp = root_ / "tmp";
  fs::create_directory(tmp);
  const std::vector<std::string> environment = {
      "XDG_CACHE_HOME=" + (root_ / "file" / "cache").string(), "TMPDIR=" + tmp.string()};
  const std::vector<std::string> args = {"render", in("scene.gltf"), "-o", "a.png", "--width",
                                         "32",     "--height",       "32", "-v"};
  const Run r = run(args, environment);
  ASSERT_EQ(r.status, 0) << r.err;
  const fs::path cache =
      tmp / ("omnishadow-shader-cache-" + std::to_string(getuid())) / "mesa_shader_cache";
  EXPECT_TRUE(fs::is_regular_file(cache / "index")) << r.err;
  EXPECT_GT(filesIn(cache).size(), 2u) << "the index and no shader";
  EXPECT_TRUE(
      contains(r.err, "omnishadow: shader cache: " + cache.string() + " (Mesa's own place"));
  EXPECT_EQ(r.err.find("disabling"), std::string::npos) << r.err;

  fs::remove_all(tmp);
  fs::create_directory(tmp);
  auto off = environment;
  off.emplace_back("MESA_SHADER_CACHE_DISABLE=true");
  const Run disabled = run(args, off);
  ASSERT_EQ(disabled.status, 0) << disabled.err;
  EXPECT_TRUE(filesIn(tmp).empty());
}

}  // namespace
}  // namespace omnishadow::cli_test
