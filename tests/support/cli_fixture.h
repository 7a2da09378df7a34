#pragma once
// What the end-to-end tests of the CLI share: the small floor-and-box scene most of them render,
// PNG headers, text and file assertions, and a fixture that runs the binary in a fresh folder:
//   <root>/in   inputs, written with GltfBuilder and as JSON text
//   <root>/out  the working directory of the run, where relative outputs go
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "scenes/builder/gltf_builder.h"
#include "tests/support/run_binary.h"
#include "tests/support/temp_folder.h"

namespace omnishadow::test_support {

struct BoxSceneSpec {
  bool cameras = true;       // "main" (glTF camera 0) and "top" (camera 1)
  float aspectRatio = 0.0f;  // of "main"; 0 = none
  bool gltfLight = true;     // KHR_lights_punctual point light "lamp", above and right
  builder::FileFormat format = builder::FileFormat::GltfEmbedded;
  float boxX = 0.0f;  // moves the box, so that scenes of one test render differently
};

// A textured floor and a box standing on it; the lamp casts the box's shadow onto the floor.
// Creates the file's folder.
void writeBoxScene(const std::filesystem::path& path, const BoxSceneSpec& spec = {});

// A lights file of `count` shadowed point lights in a row, of distinct resolutions: past four,
// more cube map arrays than a frame samples, an error found only once the GL context is up.
std::string distinctResolutionLights(int count);

// The IHDR fields of a PNG, read from the file itself; checked to be a PNG.
struct PngHeader {
  std::uint32_t width = 0, height = 0;
  int bitDepth = 0, colorType = 0;  // color type 2 = RGB
};
PngHeader pngHeader(const std::filesystem::path& path);
// Width and height from a PNG's IHDR.
std::pair<std::uint32_t, std::uint32_t> pngSize(const std::filesystem::path& path);

::testing::AssertionResult contains(const std::string& text, const std::string& part);
// Both files exist, are not empty, and hold the same bytes.
::testing::AssertionResult sameBytes(const std::filesystem::path& a,
                                     const std::filesystem::path& b);

// A fresh <root>/in and <root>/out per test; runs `omnishadow` in out/.
class CliFixture : public ::testing::Test {
 protected:
  using Run = RunResult;  // not ::testing::Test::Run()

  explicit CliFixture(const std::string& prefix);

  // `omnishadow args...` with out/ as the working directory; `environment` ("NAME=value") is
  // set for the run only.
  Run run(const std::vector<std::string>& args, const std::vector<std::string>& environment = {});
  // `omnishadow command args... tail...`, expected to succeed (exit 0).
  Run runSucceeding(const std::string& command, std::vector<std::string> args,
                    const std::vector<std::string>& tail);

  std::filesystem::path input(const std::string& name) const { return in_ / name; }
  std::filesystem::path output(const std::string& name) const { return out_ / name; }
  std::string in(const std::string& name) const { return input(name).string(); }

  // `text` with "$scene", "$lights", "$in" and "$out" replaced by the paths of in/scene.gltf,
  // in/lights.json, in/ and out/: for tables of cases written before the folders exist.
  std::string substituted(std::string text) const;

  // Writes in/<name> (creating its folder) and returns its path.
  std::filesystem::path writeText(const std::string& name, const std::string& text);

  TempFolder root_;
  std::filesystem::path in_ = root_ / "in", out_ = root_ / "out";
};

}  // namespace omnishadow::test_support
