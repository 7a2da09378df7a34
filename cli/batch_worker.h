#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <vector>

#include "cli/batch_result.h"
#include "cli/common_options.h"

namespace CLI {
class App;
}

namespace omnishadow::cli {

// How `batch` runs its jobs, as given on the command line.
struct BatchWorkerOptions {
  double jobTimeout = 0.0;  // seconds; 0 = no limit
  bool inProcess = false;   // render in the batch's own process: no isolation, no timeout
  std::string gpus;         // "all" or a list of --gpu values: one worker each; "" = --gpu's
};

// Adds --job-timeout, --in-process and --gpus.
void addBatchWorkerOptions(CLI::App& app, BatchWorkerOptions& options);

// Where a batch runner takes its jobs from and where it sends what became of them: a list in
// this process, or the pipes of a worker process.
class JobFeed {
 public:
  virtual ~JobFeed() = default;
  // The index of the next job; nullopt when the feed has ended, or, without `wait`, when no job
  // is ready yet.
  virtual std::optional<std::size_t> next(bool wait) = 0;
  // The GL thread starts on the job (loading it, if no worker thread has, then rendering it).
  virtual void started(std::size_t index) = 0;
  // The GL thread is done with it; its outputs may still be being written.
  virtual void rendered(std::size_t index) = 0;
  virtual void finished(std::size_t index, const JobResult& result) = 0;
};

// The jobs 0..count-1 in order, in this process; `finished` gets each result.
class ListFeed : public JobFeed {
 public:
  ListFeed(std::size_t count, std::function<void(std::size_t, const JobResult&)> finished)
      : count_(count), finished_(std::move(finished)) {}
  std::optional<std::size_t> next(bool) override {
    return next_ < count_ ? std::optional<std::size_t>(next_++) : std::nullopt;
  }
  void started(std::size_t) override {}
  void rendered(std::size_t) override {}
  void finished(std::size_t index, const JobResult& result) override { finished_(index, result); }

 private:
  std::size_t count_, next_ = 0;
  std::function<void(std::size_t, const JobResult&)> finished_;
};

// The EGL device indices --gpus names (renderer/render/gpu_choice.h), under this process's
// CUDA_VISIBLE_DEVICES. The devices are listed in a short-lived child process: loading a GPU
// driver here would make every later fork unsafe. Throws InputError like chooseGpus.
std::vector<int> resolveGpus(const std::string& list);

// Renders the feed's jobs on `device` in the calling process. Returns true when it stopped early
// after a render error (the context may be lost) so that a fresh process carries on.
using RunJobs = std::function<bool(const DeviceOptions& device, JobFeed& feed)>;

struct WorkerPoolOptions {
  std::vector<DeviceOptions> devices;  // one worker process each
  double jobTimeoutSeconds = 0.0;      // 0 = no limit
  std::size_t jobsPerWorker = 8;       // handed out ahead: enough to keep its threads busy
  // Called for each job a worker held when it was killed or died: removes what it may have
  // half written (its temporaries; the final names are only ever renamed into place).
  std::function<void(std::size_t job, int pid)> abandoned;
};

// Runs the jobs `todo` (indices into the caller's job list) in worker processes forked from this
// one, which must have no other thread and no GL context: a fork copies neither. Jobs go out
// from one queue to whichever worker has room. A worker that dies from a signal, or whose job
// runs past the timeout, is replaced and the remaining jobs go on: a job that timed out, or
// that was the only one in flight when its worker crashed, is reported failed with the reason;
// the other jobs a crashed worker held are run again one at a time to find the culprit. A
// worker's own fatal error (no GL context, a --gpu that does not exist) is rethrown here, as
// InputError or RenderError. `finished` is called once per job, in the order jobs finish.
void runInWorkers(const std::vector<std::size_t>& todo, const WorkerPoolOptions& options,
                  const RunJobs& runJobs,
                  const std::function<void(std::size_t, const JobResult&)>& finished);

}  // namespace omnishadow::cli
