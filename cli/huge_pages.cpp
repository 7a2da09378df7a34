#include "cli/huge_pages.h"

#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <iterator>

namespace omnishadow::cli {
namespace {

constexpr std::string_view kTunable = "glibc.malloc.hugetlb";

}  // namespace

std::optional<std::string> hugePageTunables(std::string_view command,
                                            const Environment& environment,
                                            std::string_view kernelPolicy) {
  if (command != "render" && command != "batch" && command != "verify") return std::nullopt;
  // "[always]": large mappings get huge pages already; "[never]": none will.
  if (kernelPolicy.find("[madvise]") == std::string_view::npos) return std::nullopt;
  if (environment("OMNISHADOW_HUGE_PAGES") == "0") return std::nullopt;
  if (environment("LD_PRELOAD").value_or("").find("vgpreload") != std::string::npos)
    return std::nullopt;
  const std::string tunables = environment("GLIBC_TUNABLES").value_or("");
  if (tunables.find(kTunable) != std::string::npos) return std::nullopt;
  return (tunables.empty() ? "" : tunables + ":") + std::string(kTunable) + "=1";
}

void runWithHugePages(int argc, char** argv) {
  if (argc < 2) return;
  std::ifstream file("/sys/kernel/mm/transparent_hugepage/enabled");
  const std::string policy{std::istreambuf_iterator<char>(file), {}};
  const Environment environment = processEnvironment();
  const std::optional<std::string> tunables = hugePageTunables(argv[1], environment, policy);
  if (!tunables) return;
  const std::optional<std::string> before = environment("GLIBC_TUNABLES");
  if (setenv("GLIBC_TUNABLES", tunables->c_str(), 1) != 0) return;
  execv("/proc/self/exe", argv);
  // Still here: the exec failed (no /proc, say). Go on as we are.
  if (before)
    setenv("GLIBC_TUNABLES", before->c_str(), 1);
  else
    unsetenv("GLIBC_TUNABLES");
}

}  // namespace omnishadow::cli
