// `omnishadow render --repeat N`: the steady-state timing mode behind scripts/bench-peers.sh.
#include <gtest/gtest.h>

#include <regex>
#include <string>

#include "tests/support/cli_fixture.h"

namespace omnishadow::steady_frames_test {
namespace {

using test_support::contains;
using test_support::sameBytes;

class SteadyFramesTest : public test_support::CliFixture {
 protected:
  SteadyFramesTest() : CliFixture("omnishadow-steady") {}
};

// The written image is the first frame's, byte for byte; the timed frames render every shadow
// map (a reused one would abort the run) and their medians come as "steady" lines.
TEST_F(SteadyFramesTest, RepeatPrintsMediansAndWritesTheSameImage) {
  test_support::writeBoxScene(input("scene.gltf"));
  const std::vector<std::string> size = {"--width", "64", "--height", "48"};
  runSucceeding("render", {in("scene.gltf"), "-o", "once.png"}, size);
  const Run r =
      runSucceeding("render", {in("scene.gltf"), "-o", "repeated.png", "--repeat", "3"}, size);
  EXPECT_TRUE(sameBytes(output("once.png"), output("repeated.png")));
  EXPECT_TRUE(contains(r.err, "steady frames 3\n"));
  for (const char* stage : {"shadow maps", "lighting", "readback", "frame", "GPU wait: shadow maps",
                            "GPU wait: lighting"})
    EXPECT_TRUE(std::regex_search(
        r.err, std::regex(std::string("\nsteady ") + stage + " +[0-9]+\\.[0-9]\n")))
        << stage << " in " << r.err;
}

// --finish-each-stage off: the GPU's work for the upload and the shadow maps is waited for in
// the lighting stage, so neither has a wait line; the image is the same bytes.
TEST_F(SteadyFramesTest, StagesLeftUnfinishedHaveNoWaitAndTheSameImage) {
  test_support::writeBoxScene(input("scene.gltf"));
  const std::vector<std::string> size = {"--width", "64", "--height", "48", "--stats"};
  const Run on = runSucceeding(
      "render", {in("scene.gltf"), "-o", "on.png", "--finish-each-stage", "on"}, size);
  const Run off = runSucceeding(
      "render", {in("scene.gltf"), "-o", "off.png", "--finish-each-stage", "off", "--repeat", "2"},
      size);
  EXPECT_TRUE(sameBytes(output("on.png"), output("off.png")));
  EXPECT_TRUE(contains(on.err, "\nGPU wait: shadow maps ")) << on.err;
  EXPECT_FALSE(contains(off.err, "GPU wait: shadow maps")) << off.err;
  EXPECT_FALSE(contains(off.err, "GPU wait: upload")) << off.err;
  EXPECT_TRUE(contains(off.err, "\nsteady GPU wait: lighting ")) << off.err;
  const Run bad = run({"render", in("scene.gltf"), "--finish-each-stage", "sometimes"});
  EXPECT_EQ(bad.status, 2) << bad.err;
  EXPECT_TRUE(contains(bad.err, "--finish-each-stage")) << bad.err;
}

TEST_F(SteadyFramesTest, NegativeRepeatIsAUsageError) {
  test_support::writeBoxScene(input("scene.gltf"));
  const Run r = run({"render", in("scene.gltf"), "--repeat", "-1"});
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_TRUE(contains(r.err, "--repeat")) << r.err;
}

}  // namespace
}  // namespace omnishadow::steady_frames_test
