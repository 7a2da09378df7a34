// Transparent huge pages for the commands that render (cli/huge_pages.h): when the command runs
// itself again with glibc's tunable, and that doing so changes no output and no error.
#include "cli/huge_pages.h"

#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <vector>

#include "tests/support/cli_fixture.h"

namespace omnishadow::cli {
namespace {

using test_support::contains;
using test_support::sameBytes;

using Variables = std::map<std::string, std::string>;

Environment environment(Variables variables) {
  return [variables](const std::string& name) -> std::optional<std::string> {
    const auto it = variables.find(name);
    return it == variables.end() ? std::nullopt : std::optional<std::string>(it->second);
  };
}

constexpr const char* kMadvise = "always [madvise] never\n";

TEST(HugePageTunables, AskedForOnceByTheCommandsThatRender) {
  for (const char* command : {"render", "batch", "verify"})
    EXPECT_EQ(hugePageTunables(command, environment({}), kMadvise), "glibc.malloc.hugetlb=1")
        << command;
  for (const char* command : {"info", "diff", "devices", "report", "--version", "--help", ""})
    EXPECT_EQ(hugePageTunables(command, environment({}), kMadvise), std::nullopt) << command;
  // Once: the run that has the tunable (whatever its value) goes on as it is.
  for (const char* set : {"glibc.malloc.hugetlb=1", "glibc.malloc.hugetlb=0",
                          "glibc.malloc.check=0:glibc.malloc.hugetlb=1"})
    EXPECT_EQ(hugePageTunables("render", environment({{"GLIBC_TUNABLES", set}}), kMadvise),
              std::nullopt)
        << set;
}

TEST(HugePageTunables, KeepsTheTunablesAlreadySet) {
  EXPECT_EQ(hugePageTunables("render", environment({{"GLIBC_TUNABLES", "glibc.malloc.check=0"}}),
                             kMadvise),
            "glibc.malloc.check=0:glibc.malloc.hugetlb=1");
}

TEST(HugePageTunables, OnlyWhereTheKernelGivesHugePagesOnRequest) {
  EXPECT_EQ(hugePageTunables("render", environment({}), "[always] madvise never\n"), std::nullopt);
  EXPECT_EQ(hugePageTunables("render", environment({}), "always madvise [never]\n"), std::nullopt);
  EXPECT_EQ(hugePageTunables("render", environment({}), ""), std::nullopt);  // no such file
}

TEST(HugePageTunables, NotWhenTurnedOffOrUnderValgrind) {
  EXPECT_EQ(hugePageTunables("render", environment({{"OMNISHADOW_HUGE_PAGES", "0"}}), kMadvise),
            std::nullopt);
  EXPECT_EQ(hugePageTunables("render", environment({{"OMNISHADOW_HUGE_PAGES", "1"}}), kMadvise),
            "glibc.malloc.hugetlb=1");
  EXPECT_EQ(
      hugePageTunables(
          "render",
          environment({{"LD_PRELOAD", "/usr/libexec/valgrind/vgpreload_core-amd64-linux.so"}}),
          kMadvise),
      std::nullopt);
}

class HugePagesCliTest : public test_support::CliFixture {
 protected:
  HugePagesCliTest() : CliFixture("omnishadow-huge-pages") {}

  // How many times the dynamic loader started a program in `r` (LD_DEBUG=files).
  static int programStarts(const Run& r) {
    int count = 0;
    for (std::size_t at = r.err.find("initialize program:"); at != std::string::npos;
         at = r.err.find("initialize program:", at + 1))
      ++count;
    return count;
  }
  static bool kernelGivesOnRequest() {
    std::ifstream file("/sys/kernel/mm/transparent_hugepage/enabled");
    const std::string policy{std::istreambuf_iterator<char>(file), {}};
    return policy.find("[madvise]") != std::string::npos;
  }
};

// The same image whether the render started again with huge pages or not, and the run started
// again only where it should.
TEST_F(HugePagesCliTest, TheRunThatStartsAgainWritesTheSameImage) {
  test_support::writeBoxScene(input("scene.gltf"));
  const std::vector<std::string> size = {"--width", "64", "--height", "48"};
  const auto render = [&](const std::string& out, std::vector<std::string> environment) {
    environment.push_back("LD_DEBUG=files");
    std::vector<std::string> args = {"render", in("scene.gltf"), "-o", out};
    args.insert(args.end(), size.begin(), size.end());
    const Run r = run(args, environment);
    EXPECT_EQ(r.status, 0) << r.err;
    return programStarts(r);
  };
  EXPECT_EQ(render("default.png", {}), kernelGivesOnRequest() ? 2 : 1);
  EXPECT_EQ(render("off.png", {"OMNISHADOW_HUGE_PAGES=0"}), 1);
  EXPECT_EQ(render("set.png", {"GLIBC_TUNABLES=glibc.malloc.hugetlb=0"}), 1);
  EXPECT_TRUE(sameBytes(output("default.png"), output("off.png")));
  EXPECT_TRUE(sameBytes(output("default.png"), output("set.png")));
}

// An error is reported once, with the same status, by the run that started again.
TEST_F(HugePagesCliTest, AnErrorIsReportedOnceWithItsStatus) {
  const Run r = run({"render", in("missing.gltf"), "-o", "a.png"});
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.err, "omnishadow: " + in("missing.gltf") + ": cannot read glTF file: no such file\n");
  EXPECT_FALSE(std::filesystem::exists(output("a.png")));
}

}  // namespace
}  // namespace omnishadow::cli
