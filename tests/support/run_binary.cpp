#include "tests/support/run_binary.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

extern char** environ;

namespace omnishadow::test_support {
namespace {

std::runtime_error systemError(const std::string& what) {
  return std::runtime_error(what + ": " + std::strerror(errno));
}

// The test's environment with `extra` ("NAME=value") added or replacing.
std::vector<std::string> childEnvironment(const std::vector<std::string>& extra) {
  std::vector<std::string> entries;
  for (char** entry = environ; *entry != nullptr; ++entry) entries.emplace_back(*entry);
  for (const std::string& add : extra) {
    const std::string name = add.substr(0, add.find('=') + 1);
    std::erase_if(entries, [&](const std::string& e) { return e.starts_with(name); });
    entries.push_back(add);
  }
  return entries;
}

std::vector<char*> pointers(std::vector<std::string>& strings) {
  std::vector<char*> out;
  for (std::string& s : strings) out.push_back(s.data());
  out.push_back(nullptr);
  return out;
}

struct Child {
  pid_t pid = -1;
  int out = -1, err = -1;  // read ends of the pipes; -1 once at end of file
  RunResult result;
};

// Everything the child needs is prepared before fork(): between fork() and exec() only
// async-signal-safe calls are made, since the test process may have threads (OpenEXR's pool).
Child start(std::vector<std::string> argv, const RunOptions& options) {
  if (argv.empty()) throw std::invalid_argument("runProgram: empty command");
  std::vector<std::string> environment = childEnvironment(options.environment);
  std::vector<char*> argvPointers = pointers(argv);
  std::vector<char*> envPointers = pointers(environment);
  const std::string directory = options.workingDirectory.string();
  rlimit limit{};
  if (options.fileSizeLimit) limit.rlim_cur = limit.rlim_max = *options.fileSizeLimit;

  int out[2], err[2];
  if (::pipe2(out, O_CLOEXEC) != 0) throw systemError("pipe2");
  if (::pipe2(err, O_CLOEXEC) != 0) {
    ::close(out[0]);
    ::close(out[1]);
    throw systemError("pipe2");
  }
  const int devNull = ::open("/dev/null", O_RDONLY | O_CLOEXEC);

  Child child;
  child.pid = ::fork();
  if (child.pid == 0) {
    // The child. A failure here is reported on its stderr and as status 127, like a shell's.
    const auto die = [](const char* what) {
      const char* reason = std::strerror(errno);
      (void)!::write(2, what, std::strlen(what));
      (void)!::write(2, ": ", 2);
      (void)!::write(2, reason, std::strlen(reason));
      (void)!::write(2, "\n", 1);
      ::_exit(127);
    };
    if (::dup2(out[1], 1) < 0 || ::dup2(err[1], 2) < 0) ::_exit(127);
    if (devNull >= 0) ::dup2(devNull, 0);
    if (!directory.empty() && ::chdir(directory.c_str()) != 0) die("chdir");
    if (options.fileSizeLimit) {
      // An ignored signal stays ignored across exec().
      ::signal(SIGXFSZ, SIG_IGN);
      if (::setrlimit(RLIMIT_FSIZE, &limit) != 0) die("setrlimit");
    }
    ::execve(argvPointers[0], argvPointers.data(), envPointers.data());
    die(argvPointers[0]);
  }
  const int forkErrno = errno;
  ::close(out[1]);
  ::close(err[1]);
  if (devNull >= 0) ::close(devNull);
  if (child.pid < 0) {
    ::close(out[0]);
    ::close(err[0]);
    errno = forkErrno;
    throw systemError("fork");
  }
  child.out = out[0];
  child.err = err[0];
  return child;
}

// Reads every child's stdout and stderr until all are closed, then reaps them. All pipes are
// drained together: a child blocked on a full pipe would otherwise never exit.
void finish(std::vector<Child>& children) {
  for (;;) {
    std::vector<pollfd> fds;
    std::vector<std::pair<std::size_t, bool>> owners;  // child, is stdout
    for (std::size_t i = 0; i < children.size(); ++i) {
      if (children[i].out >= 0) {
        fds.push_back({children[i].out, POLLIN, 0});
        owners.emplace_back(i, true);
      }
      if (children[i].err >= 0) {
        fds.push_back({children[i].err, POLLIN, 0});
        owners.emplace_back(i, false);
      }
    }
    if (fds.empty()) break;
    if (::poll(fds.data(), fds.size(), -1) < 0) {
      if (errno == EINTR) continue;
      throw systemError("poll");
    }
    for (std::size_t k = 0; k < fds.size(); ++k) {
      if (fds[k].revents == 0) continue;
      Child& child = children[owners[k].first];
      int& fd = owners[k].second ? child.out : child.err;
      std::string& text = owners[k].second ? child.result.out : child.result.err;
      char buffer[65536];
      const ssize_t n = ::read(fd, buffer, sizeof buffer);
      if (n > 0) {
        text.append(buffer, static_cast<std::size_t>(n));
      } else if (n == 0 || errno != EINTR) {
        ::close(fd);
        fd = -1;
      }
    }
  }
  for (Child& child : children) {
    int wait = 0;
    while (::waitpid(child.pid, &wait, 0) < 0) {
      if (errno != EINTR) throw systemError("waitpid");
    }
    if (WIFEXITED(wait)) child.result.status = WEXITSTATUS(wait);
    if (WIFSIGNALED(wait)) child.result.status = 128 + WTERMSIG(wait);
  }
}

std::vector<std::string> withBinary(const std::vector<std::string>& args) {
  std::vector<std::string> argv = {omnishadowBinary().string()};
  argv.insert(argv.end(), args.begin(), args.end());
  return argv;
}

}  // namespace

std::vector<RunResult> runPrograms(const std::vector<std::vector<std::string>>& argvs,
                                   const RunOptions& options) {
  std::vector<Child> children;
  try {
    for (const std::vector<std::string>& argv : argvs) children.push_back(start(argv, options));
  } catch (...) {
    finish(children);  // no zombies and no open pipes left behind by a half-started batch
    throw;
  }
  finish(children);
  std::vector<RunResult> results;
  for (Child& child : children) results.push_back(std::move(child.result));
  return results;
}

RunResult runProgram(const std::vector<std::string>& argv, const RunOptions& options) {
  return runPrograms({argv}, options).front();
}

std::filesystem::path omnishadowBinary() {
  return OMNISHADOW_BINARY;
}

RunResult runOmnishadow(const std::vector<std::string>& args, const RunOptions& options) {
  return runProgram(withBinary(args), options);
}

std::vector<RunResult> runOmnishadowAll(const std::vector<std::vector<std::string>>& argLists,
                                        const RunOptions& options) {
  std::vector<std::vector<std::string>> argvs;
  for (const std::vector<std::string>& args : argLists) argvs.push_back(withBinary(args));
  return runPrograms(argvs, options);
}

}  // namespace omnishadow::test_support
