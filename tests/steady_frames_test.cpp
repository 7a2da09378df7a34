// `omnishadow render --repeat N`: the steady-state timing mode behind scripts/bench-peers.sh.
#include <gtest/gtest.h>

#include <regex>
#include <string>

#include "tests/support/cli_fixture.h"

namespace omnishadow {
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
  for (const char* stage :
       {"shadow maps", "lighting", "readback", "frame", "GPU wait: shadow maps", "GPU wait: lighting"})
    EXPECT_TRUE(std::regex_search(
        r.err, std::regex(std::string("\nsteady ") + stage + " +[0-9]+\\.[0-9]\n")))
        << stage << " in " << r.err;
}

TEST_F(SteadyFramesTest, NegativeRepeatIsAUsageError) {
  test_support::writeBoxScene(input("scene.gltf"));
  const Run r = run({"render", in("scene.gltf"), "--repeat", "-1"});
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_TRUE(contains(r.err, "--repeat")) << r.err;
}

}  // namespace
}  // namespace omnishadow
