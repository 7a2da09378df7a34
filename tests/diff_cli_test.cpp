// End-to-end tests of `omnishadow diff`: exit statuses, messages, the JSON report, heat maps and
// folder mode. Every test runs the real executable in a fresh temporary folder:
//   <root>/in   inputs, written with writePng / writeExr
//   <root>/out  the working directory of the run, where relative outputs go
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "renderer/output/image_writer.h"
#include "tests/support/run_binary.h"
#include "tests/support/temp_folder.h"

namespace omnishadow::diff_cli_test {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

constexpr int kWidth = 8, kHeight = 4;

using test_support::filesIn;
using test_support::readFile;
using test_support::RunResult;

::testing::AssertionResult contains(const std::string& text, const std::string& part) {
  if (text.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "\"" << text << "\" does not contain \"" << part << "\"";
}

// An RGB gradient, with `changes` (x, y, channel, new 8-bit value) applied.
struct Change {
  int x, y, c;
  std::uint8_t value;
};

std::vector<std::uint8_t> rgb(const std::vector<Change>& changes = {}, int w = kWidth,
                              int h = kHeight) {
  std::vector<std::uint8_t> pixels;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      pixels.insert(pixels.end(),
                    {static_cast<std::uint8_t>(x * 30), static_cast<std::uint8_t>(y * 60),
                     static_cast<std::uint8_t>(100)});
  for (const Change& change : changes)
    pixels[(static_cast<std::size_t>(change.y) * w + change.x) * 3 + change.c] = change.value;
  return pixels;
}

// An EXR beauty with AOV-like channels: R, G, B, A, P.X, P.Y, P.Z, N.X.
FloatImage aovImage(float offsetR = 0.0f, float offsetP = 0.0f,
                    std::vector<std::string> channels = {"R", "G", "B", "A", "P.X", "P.Y", "P.Z",
                                                         "N.X"}) {
  FloatImage image;
  image.width = kWidth;
  image.height = kHeight;
  image.channels = std::move(channels);
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x)
      for (const std::string& name : image.channels) {
        float value = 0.1f * x + 0.2f * y;
        if (name == "R") value += offsetR;
        if (name.starts_with("P.")) value = 10.0f * value + offsetP;
        image.pixels.push_back(value);
      }
  return image;
}

class DiffCliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    fs::create_directory(in_);
    fs::create_directory(out_);
  }

  // `omnishadow diff args...` for each argument list, all at once (each run pays OpenImageIO's
  // start-up, most of its time), with out/ as the working directory.
  std::vector<RunResult> diffAll(std::vector<std::vector<std::string>> runs) {
    for (std::vector<std::string>& args : runs) args.insert(args.begin(), "diff");
    return test_support::runOmnishadowAll(runs, test_support::RunOptions::in(out_));
  }

  RunResult diff(const std::vector<std::string>& args) { return diffAll({args})[0]; }

  Json diffJson(std::vector<std::string> args, int expectedStatus) {
    args.push_back("--json");
    const RunResult r = diff(args);
    EXPECT_EQ(r.status, expectedStatus) << r.err;
    return Json::parse(r.out);
  }

  std::string png(const std::string& name, const std::vector<std::uint8_t>& pixels, int w = kWidth,
                  int h = kHeight) {
    const fs::path path = in_ / name;
    fs::create_directories(path.parent_path());
    writePng(path, w, h, 3, pixels);
    return path.string();
  }

  std::string exr(const std::string& name, const FloatImage& image) {
    const fs::path path = in_ / name;
    fs::create_directories(path.parent_path());
    writeExr(path, image, ExrPixelType::Float);
    return path.string();
  }

  // The message is one "omnishadow: ..." line that contains `part`.
  static void expectOneLineError(const RunResult& r, const std::string& part) {
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_TRUE(r.err.starts_with("omnishadow: ")) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_TRUE(contains(r.err, part));
  }

  test_support::TempFolder root_{"omnishadow-diff"};
  fs::path in_ = root_ / "in", out_ = root_ / "out";
};

TEST_F(DiffCliTest, ExitStatusFollowsTheTolerances) {
  // One pixel of 32 off by 51/255 = 0.2 in G.
  const std::string a = png("a.png", rgb()), b = png("b.png", rgb({{1, 2, 1, 120 + 51}}));
  const std::vector<RunResult> r =
      diffAll({{a, b},
               {a, b, "--max-abs", "0.1"},
               {a, b, "--max-abs", "0.25", "--per-channel"},
               {a, b, "--max-failing-fraction", "0.01"},
               {a, b, "--max-failing-fraction", "0", "--threshold", "0.3"}});
  const int expected[] = {1, 1, 0, 1, 0};
  for (std::size_t i = 0; i < r.size(); ++i) {
    EXPECT_EQ(r[i].status, expected[i]) << i << ": " << r[i].out << r[i].err;
    EXPECT_EQ(r[i].err, "") << i;
    EXPECT_TRUE(contains(r[i].out, expected[i] ? "\nFAIL " : "\nPASS")) << i;
  }
  EXPECT_TRUE(contains(r[0].out, "\ncompared   R,G,B "));
  EXPECT_TRUE(contains(r[0].out, "no tolerance given"));
  EXPECT_TRUE(contains(r[0].out, " 1,2\n"));  // where the largest difference is
  EXPECT_TRUE(contains(r[1].out, "max abs 0.2 > --max-abs 0.1"));
  EXPECT_TRUE(contains(r[2].out, "\n  G "));  // a row per channel
  EXPECT_TRUE(contains(r[3].out, "failing fraction 0.03125 > --max-failing-fraction 0.01"));
}

TEST_F(DiffCliTest, InputAndUsageErrorsExitWithTwoAndWriteNothing) {
  const std::string a = png("a.png", rgb()), b = png("b.png", rgb({{0, 0, 0, 9}}));
  std::ofstream(in_ / "broken.png") << "not a png";
  const std::string small = png("small.png", rgb({}, 4, 4), 4, 4);
  const std::string p = exr("p.exr", aovImage(0, 0, {"P.X", "P.Y", "P.Z"}));
  const std::vector<RunResult> r = diffAll({
      {a, (in_ / "broken.png").string(), "--out", "heat0.png"},
      {a, small, "--out", "heat2.png"},
      {a, p, "--out", "heat3.png"},
      {a, b, "--channels", "R,Q", "--out", "heat4.png"},
      {a, in_.string()},
      {a, b, "--metric", "flip", "--out", "heat6.png"},
      {a, b, "--out", "heat8.png", "--threshold", "-1"},
  });
  const std::string messages[] = {
      (in_ / "broken.png").string() + ": cannot read image",
      small + ": size 4x4 differs from " + a + "'s 8x4",
      a + " and " + p + " share no channel (" + a + ": R,G,B; " + p + ": P.X,P.Y,P.Z)",
      a + ": no channel \"Q\" (has R,G,B)",
      in_.string() + ": is a folder but " + a + " is not",
      "--metric flip: not implemented",
  };
  for (std::size_t i = 0; i < std::size(messages); ++i) {
    EXPECT_EQ(r[i].status, 2) << i << ": " << r[i].err;
    EXPECT_TRUE(r[i].err.starts_with("omnishadow: " + messages[i])) << r[i].err;
    EXPECT_EQ(std::count(r[i].err.begin(), r[i].err.end(), '\n'), 1) << r[i].err;
    EXPECT_EQ(r[i].out, "") << i;
  }
  EXPECT_EQ(r[6].status, 2);
  EXPECT_TRUE(contains(r[6].err, "omnishadow diff --help"));
  EXPECT_EQ(filesIn(out_), std::vector<std::string>{});
}

TEST_F(DiffCliTest, JsonReportAndHeatMap) {
  const std::string a = png("a.png", rgb()), b = png("b.png", rgb({{2, 1, 2, 0}, {6, 3, 0, 0}}));
  const std::vector<RunResult> r = diffAll({
      {a, b, "--json", "--per-channel", "--threshold", "0.4", "--max-abs", "1"},
      {a, a, "--json"},
      {a, b, "--json", "--out", "maps/heat.png"},
  });
  for (int i = 0; i < 3; ++i) EXPECT_EQ(r[i].status, i == 0 || i == 1 ? 0 : 1) << r[i].err;

  const Json j = Json::parse(r[0].out);
  std::vector<std::string> keys;
  for (const auto& [key, value] : j.items()) keys.push_back(key);
  EXPECT_EQ(keys,
            (std::vector<std::string>{"mode", "a", "b", "channels", "threshold", "peak",
                                      "tolerance", "overall", "perChannel", "heatMap", "pass"}));
  EXPECT_EQ(j["mode"], "files");
  EXPECT_EQ(j["a"],
            (Json{{"file", a}, {"width", 8}, {"height", 4}, {"channels", {"R", "G", "B"}}}));
  EXPECT_EQ(j["b"]["file"], b);
  EXPECT_EQ(j["channels"], Json::array({"R", "G", "B"}));
  EXPECT_EQ(j["threshold"], 0.4);
  EXPECT_EQ(j["peak"], 1.0);
  EXPECT_EQ(j["tolerance"], (Json{{"maxAbs", 1.0}, {"maxFailingFraction", nullptr}}));
  const Json& all = j["overall"];
  std::vector<std::string> statKeys;
  for (const auto& [key, value] : all.items()) statKeys.push_back(key);
  EXPECT_EQ(statKeys, (std::vector<std::string>{"channels", "maxAbs", "meanAbs", "rmse", "psnr",
                                                "failingPixels", "failingFraction", "maxAt"}));
  // R at (6, 3) was 6 * 30, B at (2, 1) was 100; 96 samples.
  const double r6 = 180 / 255.0, b2 = 100 / 255.0, samples = 96;
  EXPECT_NEAR(all["maxAbs"].get<double>(), r6, 1e-6);
  EXPECT_NEAR(all["meanAbs"].get<double>(), (r6 + b2) / samples, 1e-6);
  EXPECT_NEAR(all["rmse"].get<double>(), std::sqrt((r6 * r6 + b2 * b2) / samples), 1e-6);
  EXPECT_NEAR(all["psnr"].get<double>(), -10 * std::log10((r6 * r6 + b2 * b2) / samples), 1e-4);
  EXPECT_EQ(all["failingPixels"], 1);  // only the first is above 0.4
  EXPECT_EQ(all["failingFraction"], 1.0 / 32);
  EXPECT_EQ(all["maxAt"], Json::array({6, 3}));
  ASSERT_EQ(j["perChannel"].size(), 3u);
  EXPECT_EQ(j["perChannel"][0]["channels"], Json::array({"R"}));
  EXPECT_EQ(j["perChannel"][0]["maxAt"], Json::array({6, 3}));
  EXPECT_EQ(j["perChannel"][1]["maxAbs"], 0.0);
  EXPECT_TRUE(j["perChannel"][1]["maxAt"].is_null());
  EXPECT_TRUE(j["perChannel"][1]["psnr"].is_null());  // infinite
  EXPECT_EQ(j["perChannel"][2]["maxAt"], Json::array({2, 1}));
  EXPECT_TRUE(j["heatMap"].is_null());
  EXPECT_EQ(j["pass"], true);

  const Json same = Json::parse(r[1].out);
  EXPECT_TRUE(same["overall"]["psnr"].is_null());
  EXPECT_EQ(same["overall"]["maxAbs"], 0.0);
  EXPECT_EQ(same["tolerance"], (Json{{"maxAbs", 0.0}, {"maxFailingFraction", 0.0}}));
  EXPECT_EQ(same["perChannel"], Json::array());
  EXPECT_EQ(same["pass"], true);

  // The heat map: black where equal, the top of the ramp (#fcffa4) at the largest difference.
  const Json mapped = Json::parse(r[2].out);
  EXPECT_EQ(mapped["pass"], false);
  EXPECT_EQ(mapped["heatMap"]["file"], "maps/heat.png");
  EXPECT_NEAR(mapped["heatMap"]["scale"].get<double>(), r6, 1e-6);
  EXPECT_EQ(filesIn(out_), (std::vector<std::string>{"maps", "maps/heat.png"}));
  const FloatImage heat = readImage(out_ / "maps/heat.png");
  ASSERT_EQ(heat.width, kWidth);
  ASSERT_EQ(heat.height, kHeight);
  ASSERT_EQ(heat.channels.size(), 3u);
  for (int c = 0; c < 3; ++c) EXPECT_EQ(heat.at(0, 0, c), 0.0f);
  EXPECT_FLOAT_EQ(heat.at(6, 3, 0), 252 / 255.0f);
  EXPECT_FLOAT_EQ(heat.at(6, 3, 1), 255 / 255.0f);
  EXPECT_FLOAT_EQ(heat.at(6, 3, 2), 164 / 255.0f);
  EXPECT_GT(heat.at(2, 1, 0), 0.0f);
  EXPECT_LT(heat.at(2, 1, 1), heat.at(6, 3, 1));
}

TEST_F(DiffCliTest, ExrComparesOnlySharedChannels) {
  // A has an AOV that B lacks (N.X) and B one that A lacks (Z); P.* differs by 2, R by 0.125.
  const std::string a = exr("a.exr", aovImage());
  const std::string b =
      exr("b.exr", aovImage(0.125f, 2.0f, {"R", "G", "B", "A", "P.X", "P.Y", "P.Z", "Z"}));
  const std::vector<RunResult> r = diffAll({
      {a, b, "--json", "--per-channel"},
      {a, b, "--json", "--channels", "B,R", "--max-abs", "0.13"},
  });
  ASSERT_EQ(r[0].status, 1) << r[0].err;
  Json j = Json::parse(r[0].out);
  EXPECT_EQ(j["channels"], Json::array({"R", "G", "B", "A", "P.X", "P.Y", "P.Z"}));
  EXPECT_EQ(j["overall"]["maxAbs"], 2.0);
  ASSERT_EQ(j["perChannel"].size(), 7u);
  EXPECT_NEAR(j["perChannel"][0]["maxAbs"].get<double>(), 0.125, 1e-6);
  EXPECT_EQ(j["perChannel"][1]["maxAbs"], 0.0);
  EXPECT_EQ(j["perChannel"][4]["channels"], Json::array({"P.X"}));
  EXPECT_NEAR(j["perChannel"][4]["maxAbs"].get<double>(), 2.0, 1e-5);
  // The peak of a float reference is its largest compared value: P at (7, 3) = 10 * 1.3.
  EXPECT_NEAR(j["peak"].get<double>(), 13.0, 1e-5);

  ASSERT_EQ(r[1].status, 0) << r[1].err;
  j = Json::parse(r[1].out);
  EXPECT_EQ(j["channels"], Json::array({"B", "R"}));
  EXPECT_NEAR(j["overall"]["maxAbs"].get<double>(), 0.125, 1e-6);
}

TEST_F(DiffCliTest, Folders) {
  // a/ and b/: a pair that passes, one that differs, an EXR pair, a file on either side only.
  png("a/same.png", rgb());
  png("b/same.png", rgb());
  png("a/sub/changed.png", rgb());
  png("b/sub/changed.png", rgb({{7, 0, 2, 0}}));
  exr("a/sub/aov.exr", aovImage());
  exr("b/sub/aov.exr", aovImage());
  png("a/only-a.png", rgb());
  png("b/deep/only-b.png", rgb());
  std::ofstream(in_ / "a/notes.txt") << "not an image";
  // c/ and d/: paired, within --max-abs 0.5. e/ and f/: one unreadable image.
  png("c/x.png", rgb());
  png("d/x.png", rgb({{7, 0, 2, 0}}));
  png("e/x.png", rgb());
  png("e/y.png", rgb());
  png("f/x.png", rgb());
  std::ofstream(in_ / "f/y.png") << "broken";
  auto dir = [&](const char* name) { return (in_ / name).string(); };

  const std::vector<RunResult> r = diffAll({
      {dir("a"), dir("b")},
      {dir("a"), dir("b"), "--json", "--out", "maps"},
      {dir("c"), dir("d"), "--max-abs", "0.5"},
      {dir("e"), dir("f"), "--out", "maps2"},
  });
  EXPECT_EQ(r[0].status, 1) << r[0].err;
  EXPECT_TRUE(contains(r[0].out, "sub/changed.png"));
  EXPECT_TRUE(contains(r[0].out, "\nonly in A  only-a.png\n"));
  EXPECT_TRUE(contains(r[0].out, "\nonly in B  deep/only-b.png\n"));
  EXPECT_FALSE(contains(r[0].out, "notes.txt"));

  EXPECT_EQ(r[1].status, 1) << r[1].err;
  const Json j = Json::parse(r[1].out);
  EXPECT_EQ(j["mode"], "folders");
  ASSERT_EQ(j["pairs"].size(), 3u);
  EXPECT_EQ(j["pairs"][0]["path"], "same.png");
  EXPECT_EQ(j["pairs"][0]["result"], "PASS");
  EXPECT_EQ(j["pairs"][0]["heatMap"]["file"], "maps/same.png");
  EXPECT_EQ(j["pairs"][1]["path"], "sub/aov.exr");
  EXPECT_EQ(j["pairs"][1]["result"], "PASS");
  EXPECT_EQ(j["pairs"][2]["path"], "sub/changed.png");
  EXPECT_EQ(j["pairs"][2]["result"], "FAIL");
  EXPECT_EQ(j["pairs"][2]["overall"]["maxAt"], Json::array({7, 0}));
  EXPECT_EQ(j["onlyInA"], Json::array({"only-a.png"}));
  EXPECT_EQ(j["onlyInB"], Json::array({"deep/only-b.png"}));
  EXPECT_EQ(j["pass"], false);
  EXPECT_EQ(filesIn(out_ / "maps"),
            (std::vector<std::string>{"same.png", "sub", "sub/aov.exr.png", "sub/changed.png"}));

  EXPECT_EQ(r[2].status, 0) << r[2].out << r[2].err;

  EXPECT_EQ(r[3].status, 2);
  EXPECT_EQ(r[3].err, "omnishadow: " + dir("f") + "/y.png: cannot read image: " +
                          r[3].err.substr(r[3].err.find("image: ") + 7));
  EXPECT_TRUE(contains(r[3].out, "ERROR"));
  EXPECT_FALSE(fs::exists(out_ / "maps2"));
}

}  // namespace
}  // namespace omnishadow::diff_cli_test
