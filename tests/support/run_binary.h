#pragma once

// Runs the omnishadow binary (or any program) from a test the way a shell would, without a
// shell: arguments are passed as they are, stdout and stderr are captured through pipes (so the
// run writes no file of its own), and the child can be given a file size limit to simulate a
// full disk.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace omnishadow::test_support {

struct RunResult {
  int status = -1;  // exit status; 128 + signal number when killed by a signal
  std::string out, err;
};

struct RunOptions {
  // Where the child starts; empty: the test's own working directory.
  std::filesystem::path workingDirectory;
  // "NAME=value" entries added to the test's environment (replacing a variable of that name).
  std::vector<std::string> environment;
  // The largest file, in bytes, the child may write (RLIMIT_FSIZE). SIGXFSZ is ignored in the
  // child, so a write beyond it fails with EFBIG the way it does on a full disk instead of
  // killing the process; running as root, this is the one way to make writes fail.
  std::optional<std::uint64_t> fileSizeLimit;

  // Only the working directory set.
  static RunOptions in(std::filesystem::path folder) {
    RunOptions options;
    options.workingDirectory = std::move(folder);
    return options;
  }
};

// Runs `argv` (argv[0] is the program's path, not looked up in PATH) and waits for it.
RunResult runProgram(const std::vector<std::string>& argv, const RunOptions& options = {});

// Runs every command at once and waits for all of them; results in the same order.
std::vector<RunResult> runPrograms(const std::vector<std::vector<std::string>>& argvs,
                                   const RunOptions& options = {});

// The omnishadow binary of this build.
std::filesystem::path omnishadowBinary();

// `omnishadow args...`.
RunResult runOmnishadow(const std::vector<std::string>& args, const RunOptions& options = {});

// `omnishadow args...` for each argument list, all at once.
std::vector<RunResult> runOmnishadowAll(const std::vector<std::vector<std::string>>& argLists,
                                        const RunOptions& options = {});

}  // namespace omnishadow::test_support
