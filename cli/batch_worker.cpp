#include "cli/batch_worker.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "renderer/core/errors.h"
#include "renderer/render/gpu_choice.h"
#include "renderer/render/gpu_devices.h"

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace omnishadow::cli {
namespace {

using Clock = std::chrono::steady_clock;

// A worker's exit statuses besides 0 (all its jobs done).
constexpr int kExitForFreshContext = 3;  // a render error: the next job gets a new process
constexpr int kExitFatal = 4;            // it sent a "fatal" message first

// How often a worker may die before it reports anything, in a row, before the batch gives up:
// a driver that crashes while making the context would otherwise restart forever.
constexpr int kMaxDeathsWithoutProgress = 3;

const char* statusName(JobStatus status) {
  switch (status) {
    case JobStatus::Rendered:
      return "rendered";
    case JobStatus::Skipped:
      return "skipped";
    case JobStatus::Failed:
      break;
  }
  return "failed";
}

json resultToJson(const JobResult& r) {
  json out;
  out["status"] = statusName(r.status);
  out["error"] = r.error;
  out["outputs"] = json::array();
  // As bytes: a path need not be UTF-8, and the parent must get it back unchanged.
  for (const fs::path& path : r.outputs) {
    const std::string bytes = path.string();
    out["outputs"].push_back(std::vector<unsigned char>(bytes.begin(), bytes.end()));
  }
  out["warnings"] = r.warnings;
  out["stages"] = json::array();
  for (const auto& [stage, ms] : r.times.stages()) out["stages"].push_back({stage, ms});
  out["ms"] = r.milliseconds;
  return out;
}

JobResult resultFromJson(const json& in) {
  JobResult r;
  const std::string status = in.at("status").get<std::string>();
  r.status = status == "rendered"  ? JobStatus::Rendered
             : status == "skipped" ? JobStatus::Skipped
                                   : JobStatus::Failed;
  r.error = in.at("error").get<std::string>();
  for (const json& path : in.at("outputs")) {
    const auto bytes = path.get<std::vector<unsigned char>>();
    r.outputs.emplace_back(std::string(bytes.begin(), bytes.end()));
  }
  r.warnings = in.at("warnings").get<std::vector<std::string>>();
  for (const json& stage : in.at("stages"))
    r.times.add(stage.at(0).get<std::string>(), stage.at(1).get<double>());
  r.milliseconds = in.at("ms").get<double>();
  return r;
}

void writeAll(int fd, const std::string& text) {
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) throw RenderError(std::string("worker pipe: ") + std::strerror(errno));
    done += static_cast<std::size_t>(n);
  }
}

// Splits what arrives on a pipe into lines.
class LineReader {
 public:
  explicit LineReader(int fd) : fd_(fd) {}
  // Reads what is there (one read); false at end of file or on an error.
  bool fill() {
    char buffer[65536];
    ssize_t n;
    do {
      n = ::read(fd_, buffer, sizeof buffer);
    } while (n < 0 && errno == EINTR);
    if (n <= 0) return false;
    pending_.append(buffer, static_cast<std::size_t>(n));
    return true;
  }
  std::optional<std::string> line() {
    const std::size_t end = pending_.find('\n');
    if (end == std::string::npos) return std::nullopt;
    std::string line = pending_.substr(0, end);
    pending_.erase(0, end + 1);
    return line;
  }

 private:
  int fd_;
  std::string pending_;
};

bool readable(int fd, int timeoutMs) {
  pollfd p{fd, POLLIN, 0};
  int n;
  do {
    n = ::poll(&p, 1, timeoutMs);
  } while (n < 0 && errno == EINTR);
  return n > 0;
}

// ---------------------------------------------------------------------------------------------
// The worker's side: job indices come in as lines, events go out as JSON lines.

class PipeFeed : public JobFeed {
 public:
  PipeFeed(int in, int out) : in_(in), reader_(in), out_(out) {}

  std::optional<std::size_t> next(bool wait) override {
    while (true) {
      if (const auto line = reader_.line()) return std::stoul(*line);
      if (ended_ || (!wait && !readable(in_, 0))) return std::nullopt;
      if (!reader_.fill()) ended_ = true;
    }
  }
  void started(std::size_t index) override { send({{"started", index}}); }
  void rendered(std::size_t index) override { send({{"rendered", index}}); }
  void finished(std::size_t index, const JobResult& result) override {
    send({{"finished", index}, {"result", resultToJson(result)}});
  }
  void fatal(const std::string& message, bool usage) {
    send({{"fatal", message}, {"usage", usage}});
  }

 private:
  // Messages and warnings quote file names, which need not be UTF-8; they are for people, so
  // invalid bytes may become U+FFFD.
  void send(const json& message) {
    writeAll(out_, message.dump(-1, ' ', false, json::error_handler_t::replace) + "\n");
  }

  int in_;
  LineReader reader_;
  int out_;
  bool ended_ = false;
};

[[noreturn]] void workerMain(int in, int out, const DeviceOptions& device, const RunJobs& runJobs) {
  // A worker outlives neither its batch nor a parent that stopped reading.
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);
  ::signal(SIGPIPE, SIG_DFL);
  int status = 0;
  PipeFeed feed(in, out);
  try {
    status = runJobs(device, feed) ? kExitForFreshContext : 0;
  } catch (const InputError& e) {
    feed.fatal(e.what(), true);
    status = kExitFatal;
  } catch (const std::exception& e) {
    try {
      feed.fatal(e.what(), false);
    } catch (const std::exception&) {
    }
    status = kExitFatal;
  }
  // Not exit(): the parent's stdio buffers and atexit handlers are the parent's.
  std::fflush(stderr);
  ::_exit(status);
}

// ---------------------------------------------------------------------------------------------
// The batch's side.

std::string describeDeath(int status) {
  if (WIFSIGNALED(status)) {
    const int signal = WTERMSIG(status);
    const char* name = ::strsignal(signal);
    return "the render worker crashed (signal " + std::to_string(signal) +
           (name ? std::string(", ") + name : std::string()) + ")";
  }
  return "the render worker exited with status " + std::to_string(WEXITSTATUS(status));
}

struct Worker {
  pid_t pid = -1;
  int toWorker = -1, fromWorker = -1;
  std::unique_ptr<LineReader> reader;
  std::vector<std::size_t> held;  // sent, not finished; in sending order
  // The job on the worker's GL thread (loading or rendering it), since when.
  std::optional<std::pair<std::size_t, Clock::time_point>> rendering;
  std::vector<std::size_t> encoding;  // rendered, not finished; in order
  Clock::time_point lastEvent;
  bool anyStarted = false;
  bool solo = false;  // runs one suspect alone: nothing else is sent until it finishes
  bool inputClosed = false;
  bool anyResult = false;
  std::optional<std::pair<std::string, bool>> fatal;  // message, usage error
};

class WorkerPool {
 public:
  WorkerPool(const std::vector<std::size_t>& todo, const WorkerPoolOptions& options,
             const RunJobs& runJobs,
             const std::function<void(std::size_t, const JobResult&)>& finished)
      : options_(options),
        runJobs_(runJobs),
        finished_(finished),
        queue_(todo.begin(), todo.end()),
        remaining_(todo.size()),
        slots_(options.devices.size()) {}

  ~WorkerPool() {
    for (Worker& w : slots_)
      if (w.pid > 0) stop(w);
  }

  void run() {
    while (remaining_ > 0) {
      for (std::size_t slot = 0; slot < slots_.size(); ++slot) {
        Worker& w = slots_[slot];
        if (w.pid < 0 && (!queue_.empty() || !suspects_.empty())) spawn(slot);
        if (w.pid > 0) feed(w);
      }
      wait();
    }
  }

 private:
  void spawn(std::size_t slot) {
    int jobs[2], events[2];
    if (::pipe(jobs) != 0) throw RenderError(std::string("pipe: ") + std::strerror(errno));
    if (::pipe(events) != 0) {
      ::close(jobs[0]);
      ::close(jobs[1]);
      throw RenderError(std::string("pipe: ") + std::strerror(errno));
    }
    std::fflush(stdout);
    std::fflush(stderr);
    const pid_t pid = ::fork();
    if (pid < 0) throw RenderError(std::string("fork: ") + std::strerror(errno));
    if (pid == 0) {
      // The other workers' pipes stay with the parent, or those workers would never see EOF.
      for (const Worker& other : slots_)
        if (other.pid > 0) {
          ::close(other.toWorker);
          ::close(other.fromWorker);
        }
      ::close(jobs[1]);
      ::close(events[0]);
      workerMain(jobs[0], events[1], options_.devices[slot], runJobs_);
    }
    ::close(jobs[0]);
    ::close(events[1]);
    Worker& w = slots_[slot];
    w = Worker{};
    w.pid = pid;
    w.toWorker = jobs[1];
    w.fromWorker = events[0];
    w.reader = std::make_unique<LineReader>(events[0]);
  }

  // Hands out jobs up to the worker's share; closes its input when there are none left.
  void feed(Worker& w) {
    if (w.inputClosed || w.solo) return;
    std::string lines;
    if (!suspects_.empty()) {
      // A suspect runs alone, so that a crash names it for sure.
      if (w.held.empty()) {
        const std::size_t job = suspects_.front();
        suspects_.pop_front();
        w.held.push_back(job);
        w.solo = true;
        lines += std::to_string(job) + "\n";
      }
    } else {
      while (!queue_.empty() && w.held.size() < options_.jobsPerWorker) {
        const std::size_t job = queue_.front();
        queue_.pop_front();
        w.held.push_back(job);
        lines += std::to_string(job) + "\n";
      }
    }
    // A write to a worker that just died fails with EPIPE; its EOF is handled in wait().
    if (!lines.empty()) {
      try {
        writeAll(w.toWorker, lines);
      } catch (const RenderError&) {
      }
    }
    if (queue_.empty() && suspects_.empty()) {
      ::close(w.toWorker);
      w.inputClosed = true;
    }
  }

  // When the worker's job will have run past the limit, if it has one in hand: on the GL thread,
  // from when it started there; or, when the GL thread waits for the oldest job's outputs to be
  // written, from the worker's last sign of life.
  std::optional<Clock::time_point> deadline(const Worker& w) const {
    if (options_.jobTimeoutSeconds <= 0.0 || w.pid < 0) return std::nullopt;
    const auto limit = std::chrono::duration_cast<Clock::duration>(
        std::chrono::duration<double>(options_.jobTimeoutSeconds));
    if (w.rendering) return w.rendering->second + limit;
    if (!w.encoding.empty()) return w.lastEvent + limit;
    return std::nullopt;
  }

  int pollTimeoutMs() const {
    std::optional<Clock::time_point> first;
    for (const Worker& w : slots_)
      if (const auto d = deadline(w); d && (!first || *d < *first)) first = d;
    if (!first) return -1;
    const double ms = std::chrono::duration<double, std::milli>(*first - Clock::now()).count();
    return std::max(0, static_cast<int>(std::ceil(ms)));
  }

  void wait() {
    std::vector<pollfd> fds;
    std::vector<Worker*> owners;
    for (Worker& w : slots_)
      if (w.pid > 0) {
        fds.push_back({w.fromWorker, POLLIN, 0});
        owners.push_back(&w);
      }
    if (fds.empty()) return;
    int n;
    do {
      n = ::poll(fds.data(), fds.size(), pollTimeoutMs());
    } while (n < 0 && errno == EINTR);
    for (std::size_t i = 0; i < fds.size(); ++i) {
      if (!(fds[i].revents & (POLLIN | POLLHUP | POLLERR))) continue;
      Worker& w = *owners[i];
      const bool open = w.reader->fill();
      while (const auto line = w.reader->line()) handle(w, *line);
      if (!open) ended(w);
    }
    checkTimeouts();
  }

  void handle(Worker& w, const std::string& line) {
    const json message = json::parse(line);
    w.lastEvent = Clock::now();
    if (message.contains("started")) {
      w.rendering = {message["started"].get<std::size_t>(), w.lastEvent};
      w.anyStarted = true;
    } else if (message.contains("rendered")) {
      w.encoding.push_back(message["rendered"].get<std::size_t>());
      w.rendering.reset();
    } else if (message.contains("finished")) {
      const std::size_t job = message["finished"].get<std::size_t>();
      w.held.erase(std::remove(w.held.begin(), w.held.end(), job), w.held.end());
      w.encoding.erase(std::remove(w.encoding.begin(), w.encoding.end(), job), w.encoding.end());
      w.solo = false;
      w.anyResult = true;
      deathsWithoutProgress_ = 0;
      report(job, resultFromJson(message["result"]));
    } else if (message.contains("fatal")) {
      w.fatal = {message["fatal"].get<std::string>(), message["usage"].get<bool>()};
    }
  }

  void report(std::size_t job, const JobResult& result) {
    --remaining_;
    finished_(job, result);
  }

  void fail(std::size_t job, const std::string& reason) {
    JobResult result;
    result.status = JobStatus::Failed;
    result.error = reason;
    report(job, result);
  }

  // The worker closed its end: it exited, or is about to.
  void ended(Worker& w) {
    int status = 0;
    while (::waitpid(w.pid, &status, 0) < 0 && errno == EINTR) {
    }
    const std::vector<std::size_t> held = w.held;
    const bool solo = w.solo, anyStarted = w.anyStarted, anyResult = w.anyResult;
    const auto fatal = w.fatal;
    const pid_t pid = w.pid;
    release(w);
    if (fatal) {
      if (fatal->second) throw InputError(fatal->first);
      throw RenderError(fatal->first);
    }
    const bool clean = WIFEXITED(status) &&
                       (WEXITSTATUS(status) == 0 || WEXITSTATUS(status) == kExitForFreshContext);
    if (!clean) abandon(held, pid);
    if (clean) {
      // Jobs sent after it stopped for a fresh context: the next worker takes them, in order.
      queue_.insert(queue_.begin(), held.begin(), held.end());
      return;
    }
    if (!anyStarted && !anyResult) {
      // It died before it started a job (making its context, say): no job is to blame.
      if (++deathsWithoutProgress_ >= kMaxDeathsWithoutProgress)
        throw RenderError(describeDeath(status) + " " + std::to_string(deathsWithoutProgress_) +
                          " times before it started a job");
      std::deque<std::size_t>& from = solo ? suspects_ : queue_;
      from.insert(from.begin(), held.begin(), held.end());
      return;
    }
    if (held.size() == 1) {
      fail(held.front(), describeDeath(status));
      return;
    }
    // Several jobs were in flight (loading, rendering, encoding): any of them may have crashed
    // it. Each runs again alone.
    suspects_.insert(suspects_.end(), held.begin(), held.end());
  }

  void checkTimeouts() {
    for (Worker& w : slots_) {
      const auto due = deadline(w);
      if (!due || Clock::now() < *due) continue;
      const bool writing = !w.rendering;
      const std::size_t hung = writing ? w.encoding.front() : w.rendering->first;
      std::vector<std::size_t> others;
      for (std::size_t held : w.held)
        if (held != hung) others.push_back(held);
      const pid_t pid = w.pid;
      const std::vector<std::size_t> held = w.held;
      stop(w);
      abandon(held, pid);
      // Jobs held up behind the one that hangs render again in the next worker.
      queue_.insert(queue_.begin(), others.begin(), others.end());
      char seconds[32];
      std::snprintf(seconds, sizeof seconds, "%g", options_.jobTimeoutSeconds);
      fail(hung, std::string("timed out after ") + seconds + " s (--job-timeout) while " +
                     (writing ? "writing its outputs" : "loading or rendering it") +
                     "; the render worker was stopped");
    }
  }

  void abandon(const std::vector<std::size_t>& jobs, pid_t pid) {
    if (options_.abandoned)
      for (const std::size_t job : jobs) options_.abandoned(job, static_cast<int>(pid));
  }

  void stop(Worker& w) {
    ::kill(w.pid, SIGKILL);
    while (::waitpid(w.pid, nullptr, 0) < 0 && errno == EINTR) {
    }
    release(w);
  }

  void release(Worker& w) {
    if (!w.inputClosed) ::close(w.toWorker);
    ::close(w.fromWorker);
    w = Worker{};
  }

  const WorkerPoolOptions& options_;
  const RunJobs& runJobs_;
  const std::function<void(std::size_t, const JobResult&)>& finished_;
  std::deque<std::size_t> queue_, suspects_;
  std::size_t remaining_;
  std::vector<Worker> slots_;
  int deathsWithoutProgress_ = 0;
};

// Writes to a worker that died must fail with EPIPE, not kill the batch.
class IgnoreSigpipe {
 public:
  IgnoreSigpipe() { previous_ = ::signal(SIGPIPE, SIG_IGN); }
  ~IgnoreSigpipe() { ::signal(SIGPIPE, previous_); }
  IgnoreSigpipe(const IgnoreSigpipe&) = delete;
  IgnoreSigpipe& operator=(const IgnoreSigpipe&) = delete;

 private:
  sighandler_t previous_;
};

}  // namespace

void addBatchWorkerOptions(CLI::App& app, BatchWorkerOptions& o) {
  app.add_option("--job-timeout", o.jobTimeout,
                 "Fail a job that takes longer than this many seconds (its worker is replaced)")
      ->check(CLI::PositiveNumber);
  app.add_flag("--in-process", o.inProcess,
               "Render in the batch's own process: no worker, so a crash or hang stops the batch");
  app.add_option("--gpus", o.gpus,
                 "One worker per device, pulling from one queue: all, or a list of --gpu values "
                 "such as 0,1 or cuda:0,cuda:1 (a device named twice gets two workers)");
}

std::vector<int> resolveGpus(const std::string& list) {
  int pipeFds[2];
  if (::pipe(pipeFds) != 0) throw RenderError(std::string("pipe: ") + std::strerror(errno));
  std::fflush(stdout);
  std::fflush(stderr);
  const pid_t pid = ::fork();
  if (pid < 0) throw RenderError(std::string("fork: ") + std::strerror(errno));
  if (pid == 0) {
    ::close(pipeFds[0]);
    json answer;
    try {
      const char* visible = std::getenv("CUDA_VISIBLE_DEVICES");
      answer["devices"] = chooseGpus(list, listGpuDevices(false),
                                     visible ? std::optional<std::string>(visible) : std::nullopt);
    } catch (const InputError& e) {
      answer = {{"error", e.what()}, {"usage", true}};
    } catch (const std::exception& e) {
      answer = {{"error", e.what()}, {"usage", false}};
    }
    try {
      writeAll(pipeFds[1], answer.dump());
    } catch (const std::exception&) {
    }
    ::_exit(0);
  }
  ::close(pipeFds[1]);
  std::string text;
  char buffer[4096];
  ssize_t n;
  while ((n = ::read(pipeFds[0], buffer, sizeof buffer)) > 0 || (n < 0 && errno == EINTR))
    if (n > 0) text.append(buffer, static_cast<std::size_t>(n));
  ::close(pipeFds[0]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  const json answer = json::parse(text, nullptr, false);
  if (answer.is_discarded() || !answer.is_object())
    throw RenderError("--gpus: listing the EGL devices failed (" + describeDeath(status) + ")");
  if (answer.contains("error")) {
    if (answer["usage"].get<bool>()) throw InputError(answer["error"].get<std::string>());
    throw RenderError(answer["error"].get<std::string>());
  }
  return answer["devices"].get<std::vector<int>>();
}

void runInWorkers(const std::vector<std::size_t>& todo, const WorkerPoolOptions& options,
                  const RunJobs& runJobs,
                  const std::function<void(std::size_t, const JobResult&)>& finished) {
  if (todo.empty()) return;
  const IgnoreSigpipe ignoreSigpipe;
  WorkerPool pool(todo, options, runJobs, finished);
  pool.run();
}

}  // namespace omnishadow::cli
