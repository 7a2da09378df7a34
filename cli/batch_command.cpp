#include "cli/batch_command.h"

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <deque>
#include <fstream>
#include <future>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <numeric>
#include <thread>

#include "cli/batch_jobs.h"
#include "cli/batch_worker.h"
#include "cli/common_options.h"
#include "cli/malloc_heap.h"
#include "cli/shard_env.h"
#include "cli/shared_scene_loads.h"
#include "renderer/core/errors.h"
#include "renderer/core/message_text.h"
#include "renderer/output/image_writer.h"
#include "renderer/output/output_transaction.h"
#include "renderer/render/gpu_choice.h"
#include "renderer/render/renderer.h"

namespace fs = std::filesystem;

namespace omnishadow::cli {
namespace {

using Clock = std::chrono::steady_clock;

using Status = JobStatus;

bool allOutputsExist(const RenderJob& job) {
  for (const fs::path& path : job.outputFiles())
    if (!pathExists(path)) return false;
  return true;
}

BatchDefaults defaultsFromOptions(const BatchOptions& o) {
  BatchDefaults d;
  d.out = o.out;
  d.lights = o.input.lights;
  d.png = !o.noPng;
  d.exr = o.exr;
  d.aov = o.aov || !o.aovLayers.empty();
  d.masks = o.masks;
  RenderJob& job = d.job;
  applySceneSettings(o.input, job);
  job.camera = cameraRequest(o.view);
  job.layers = parseLayers(o.aovLayers);
  job.exposure = o.exposure;
  job.shading = o.shading == "phong" ? Shading::Phong : Shading::Pbr;
  job.antialiasing = o.antialiasing;
  return d;
}

// Progress on a terminal: one line rewritten in place.
class Progress {
 public:
  Progress(std::size_t total, bool live, bool quiet)
      : total_(total), live_(live), quiet_(quiet), start_(Clock::now()) {}

  void finished(const std::string& name, const JobResult& result) {
    ++done_;
    if (result.status == Status::Failed)
      std::fprintf(stderr, "%somnishadow: %s: %s\n", live_ ? "\r\033[K" : "", name.c_str(),
                   result.error.c_str());
    if (quiet_) return;
    if (live_) {
      const double seconds = millisecondsSince(start_) / 1000.0;
      const double rate = seconds > 0.0 ? static_cast<double>(done_) / seconds : 0.0;
      const double eta = rate > 0.0 ? static_cast<double>(total_ - done_) / rate : 0.0;
      const int width = 30;
      const int filled = static_cast<int>(width * done_ / std::max<std::size_t>(total_, 1));
      std::printf("\r[%s%s] %zu/%zu  %.1f scenes/s  ETA %d:%02d", std::string(filled, '#').c_str(),
                  std::string(width - filled, '.').c_str(), done_, total_, rate,
                  static_cast<int>(eta) / 60, static_cast<int>(eta) % 60);
    } else if (result.status == Status::Rendered) {
      std::printf("ok      %s (%.0f ms)\n", name.c_str(), result.milliseconds);
    } else if (result.status == Status::Skipped) {
      std::printf("skipped %s\n", name.c_str());
    } else {
      std::printf("FAILED  %s: %s\n", name.c_str(), result.error.c_str());
    }
    std::fflush(stdout);
  }

  void summary(std::size_t rendered, std::size_t skipped, std::size_t failed) {
    if (quiet_) return;
    std::printf("%s%zu rendered, %zu skipped, %zu failed in %.1f s\n", live_ ? "\n" : "", rendered,
                skipped, failed, millisecondsSince(start_) / 1000.0);
  }

 private:
  std::size_t total_, done_ = 0;
  bool live_, quiet_;
  Clock::time_point start_;
};

void writeReport(const fs::path& path, const std::vector<BatchEntry>& jobs,
                 const std::vector<JobResult>& results, const std::string& shard, double seconds) {
  nlohmann::ordered_json report;
  std::size_t counts[3] = {0, 0, 0};
  for (const JobResult& r : results) ++counts[static_cast<int>(r.status)];
  report["summary"] = {{"jobs", jobs.size()},
                       {"rendered", counts[0]},
                       {"skipped", counts[1]},
                       {"failed", counts[2]},
                       {"seconds", seconds}};
  report["shard"] = shard.empty() ? nlohmann::ordered_json() : nlohmann::ordered_json(shard);
  report["jobs"] = nlohmann::ordered_json::array();
  const char* statusNames[] = {"rendered", "skipped", "failed"};
  for (std::size_t i = 0; i < jobs.size(); ++i) {
    const JobResult& r = results[i];
    nlohmann::ordered_json job;
    job["name"] = jobs[i].name;
    job["scene"] = jobs[i].job.scene.string();
    job["status"] = statusNames[static_cast<int>(r.status)];
    job["error"] = r.error.empty() ? nlohmann::ordered_json() : nlohmann::ordered_json(r.error);
    job["outputs"] = nlohmann::ordered_json::array();
    for (const fs::path& output : r.outputs) job["outputs"].push_back(output.string());
    job["warnings"] = r.warnings;
    job["stages"] = nlohmann::ordered_json::object();
    for (const auto& [stage, ms] : r.times.stages())
      job["stages"][stage] = job["stages"].value(stage, 0.0) + ms;
    report["jobs"].push_back(std::move(job));
  }
  std::ofstream out(path);
  // File names need not be UTF-8; JSON must be (invalid bytes become U+FFFD).
  out << report.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace) << "\n";
  if (!out.flush()) throw RenderError("cannot write the report " + path.string());
}

std::vector<RenderJob> renderJobsOf(const std::vector<BatchEntry>& entries) {
  std::vector<RenderJob> jobs;
  jobs.reserve(entries.size());
  for (const BatchEntry& entry : entries) jobs.push_back(entry.job);
  return jobs;
}

// Renders the feed's jobs in order on this (the GL) thread. Loading runs up to `workers` jobs
// ahead and encoding up to `workers` jobs behind, on other threads; with 0 workers everything
// runs here. Jobs of one scene file share its load (SharedSceneLoads). Results go to the feed
// in the order the jobs came.
class BatchRunner {
 public:
  // `stopOnRenderError`: after a render error (the context may be lost) stop and let a fresh
  // process go on, rather than make a new context here.
  BatchRunner(const std::vector<BatchEntry>& jobs, const BatchOptions& options,
              const DeviceOptions& device, bool stopOnRenderError)
      : jobs_(jobs),
        options_(options),
        device_(device),
        stopOnRenderError_(stopOnRenderError),
        results_(jobs.size()),
        sharedLoads_(renderJobsOf(jobs)) {
    workers_ = options.jobs >= 0
                   ? options.jobs
                   : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  }

  // Returns true when it stopped early after a render error.
  bool run(JobFeed& feed) {
    makeRenderer();
    std::deque<std::size_t> upcoming;
    bool stopped = false;
    while (true) {
      topUp(feed, upcoming);
      if (upcoming.empty()) {
        // Nothing ready: hand back what is finished before waiting, since a feed may hand out
        // the next jobs only once results come back.
        while (!encoding_.empty()) finishOldest(feed);
        const std::optional<std::size_t> next = feed.next(true);
        if (!next) break;
        upcoming.push_back(*next);
        topUp(feed, upcoming);
      }
      prefetch(upcoming);
      const std::size_t i = upcoming.front();
      upcoming.pop_front();
      feed.started(i);
      const bool rendered = renderOne(i);
      feed.rendered(i);
      if (!rendered && stopOnRenderError_) {
        stopped = true;
        break;
      }
      // With no workers this finishes each job at once (its encoding was deferred to here).
      while (encoding_.size() > static_cast<std::size_t>(workers_)) finishOldest(feed);
    }
    while (!encoding_.empty()) finishOldest(feed);
    return stopped;
  }

 private:
  struct Pending {
    std::size_t index;
    std::future<std::vector<fs::path>> outputs;
  };

  void makeRenderer() {
    renderer_.reset();
    renderer_ = openRenderer(device_);
  }

  // Takes the jobs the feed has ready, up to the ones to load ahead.
  void topUp(JobFeed& feed, std::deque<std::size_t>& upcoming) {
    while (upcoming.size() <= static_cast<std::size_t>(workers_))
      if (const std::optional<std::size_t> next = feed.next(false)) {
        upcoming.push_back(*next);
      } else {
        return;
      }
  }

  bool skipped(std::size_t i) const {
    return options_.skipExisting && allOutputsExist(jobs_[i].job);
  }

  void prefetch(const std::deque<std::size_t>& upcoming) {
    if (workers_ == 0) return;
    for (const std::size_t i : upcoming) {
      if (loading_.count(i) || skipped(i)) continue;
      const RenderJob& job = jobs_[i].job;
      loading_.emplace(i, std::async(std::launch::async,
                                     [this, &job] { return loadJobTimed(job, &sharedLoads_); }));
    }
  }

  // False after a render error.
  bool renderOne(std::size_t i) {
    JobResult& result = results_[i];
    if (skipped(i)) {
      result.status = Status::Skipped;
      encoding_.push_back({i, {}});
      return true;
    }
    try {
      TimedLoad loaded;
      if (auto it = loading_.find(i); it != loading_.end()) {
        loaded = it->second.get();
        loading_.erase(it);
      } else {
        loaded = loadJobTimed(jobs_[i].job, &sharedLoads_);
      }
      result.times.add("load", loaded.milliseconds);
      // Shared with the encoder, which may run after this job's turn.
      auto job = std::make_shared<LoadedJob>(std::move(loaded.job));
      auto frame = std::make_shared<Frame>(renderJob(*renderer_, jobs_[i].job, *job, result.times));
      result.warnings = job->warnings;
      result.warnings.insert(result.warnings.end(), frame->warnings.begin(), frame->warnings.end());
      const RenderJob& description = jobs_[i].job;
      auto encode = [&description, job, frame, &result] {
        const Clock::time_point encodeStart = Clock::now();
        std::vector<fs::path> written = writeJobOutputs(description, *job, *frame);
        result.times.add("encode", millisecondsSince(encodeStart));
        return written;
      };
      encoding_.push_back(
          {i, workers_ == 0 ? deferred(encode) : std::async(std::launch::async, encode)});
      result.status = Status::Rendered;
    } catch (const RenderError& e) {
      // A GL error or a lost context may leave the context unusable: start a fresh one.
      fail(i, e.what());
      if (!stopOnRenderError_) makeRenderer();
      return false;
    } catch (const std::exception& e) {
      fail(i, e.what());
    }
    return true;
  }

  template <typename F>
  static std::future<std::vector<fs::path>> deferred(F f) {
    return std::async(std::launch::deferred, std::move(f));
  }

  void fail(std::size_t i, const std::string& message) {
    results_[i].status = Status::Failed;
    results_[i].error = oneLineMessage(message);
    encoding_.push_back({i, {}});
  }

  void finishOldest(JobFeed& feed) {
    Pending pending = std::move(encoding_.front());
    encoding_.pop_front();
    JobResult& result = results_[pending.index];
    if (pending.outputs.valid()) {
      try {
        result.outputs = pending.outputs.get();
      } catch (const std::exception& e) {
        result.status = Status::Failed;
        result.error = oneLineMessage(e.what());
      }
    }
    if (result.status != Status::Skipped) result.milliseconds = result.times.total();
    feed.finished(pending.index, result);
  }

  const std::vector<BatchEntry>& jobs_;
  const BatchOptions& options_;
  const DeviceOptions& device_;
  bool stopOnRenderError_;
  std::vector<JobResult> results_;
  int workers_ = 0;
  std::unique_ptr<Renderer> renderer_;
  SharedSceneLoads sharedLoads_;  // before loading_, whose loads use it
  std::map<std::size_t, std::future<TimedLoad>> loading_;
  std::deque<Pending> encoding_;
};

}  // namespace

void addBatchCommand(CLI::App& app, BatchOptions& o) {
  CLI::App* batch = app.add_subcommand(
      "batch", "Render many scenes with one GL context: folders, globs, scene files, manifests");
  batch
      ->add_option("inputs", o.inputs,
                   "Folders (all .gltf/.glb below), quoted globs, scene files or manifest .json")
      ->required();
  batch->add_option("-o,--out", o.out, "Output folder; mirrors the input tree")->required();
  addSceneInputOptions(*batch, o.input, SceneInputCommand::Batch);
  batch->add_flag("--exr", o.exr, "Also write <name>.exr (linear half RGBA)");
  batch->add_flag("--no-png", o.noPng, "Do not write <name>.png");
  batch->add_flag("--aov", o.aov, "Also write <name>.aov.exr");
  batch->add_option("--aov-layers", o.aovLayers, "Extra AOV layers, as for render (implies --aov)");
  batch->add_flag("--masks", o.masks,
                  "Also write annotation masks as render --masks does: <name>.instances.png, "
                  "<name>.semantic.png, <name>.masks.json");
  batch
      ->add_option("--aa", o.antialiasing,
                   "Anti-aliased beauty as for render: 1 (default), 4, 8 or 16 samples per pixel")
      ->check(CLI::IsMember({1, 4, 8, 16}));
  addViewOptions(*batch, o.view);
  batch->add_option("--exposure", o.exposure, "Exposure in stops");
  batch->add_option("--shading", o.shading, "pbr or phong")->check(CLI::IsMember({"pbr", "phong"}));
  batch->add_flag("--skip-existing", o.skipExisting, "Skip jobs whose outputs all exist (resume)");
  batch->add_option("--shard", o.shard,
                    "Render only shard K of N (K/N, 0 <= K < N), or auto: from the Slurm array "
                    "or Kubernetes indexed Job variables");
  batch->add_option("--shard-count", o.shardCount, "N for --shard auto (needed on Kubernetes)")
      ->check(CLI::Range(1, 1 << 20));
  batch
      ->add_option("--jobs", o.jobs,
                   "Worker threads for loading and encoding (default: cores; 0 = none)")
      ->check(CLI::Range(0, 256));
  batch->add_option("--report", o.report, "Write a JSON report of every job");
  batch->add_flag("-q,--quiet", o.quiet, "No progress or log lines (failures still on stderr)");
  addDeviceOptions(*batch, o.device, false);
  addBatchWorkerOptions(*batch, o.worker);
}

int runBatch(const BatchOptions& o) {
  const Clock::time_point start = Clock::now();
  const BatchDefaults defaults = defaultsFromOptions(o);
  std::vector<BatchEntry> jobs = collectJobs(o.inputs, defaults);
  const std::string shard = resolveShard(o.shard, o.shardCount, processEnvironment());
  if (!shard.empty()) jobs = selectShard(std::move(jobs), parseShard(shard));
  if (!o.report.empty() && fs::is_directory(o.report))
    throw InputError("--report " + o.report + ": is a folder, expected a file name");

  if (o.worker.inProcess && o.worker.jobTimeout > 0.0)
    throw InputError("--job-timeout: needs a worker process; leave out --in-process");
  if (o.worker.inProcess && !o.worker.gpus.empty())
    throw InputError("--gpus: needs worker processes; leave out --in-process");
  if (!o.worker.gpus.empty() && o.device.gpu != "auto")
    throw InputError("--gpus: chooses the devices itself; leave out --gpu");
  parseGpuRequest(o.device.gpu);  // a malformed --gpu is a usage error before any worker starts

  setEncoderThreads(0);  // the batch's own workers encode in parallel already
  // Before any worker is forked, which inherits the heap and its advice: the jobs' loads and
  // frames carve fresh memory from the heap's top until the batch reaches its peak.
  setUpMallocHeap();
  Progress progress(jobs.size(), ::isatty(STDOUT_FILENO) != 0, o.quiet);
  std::vector<JobResult> results(jobs.size());
  const auto finished = [&](std::size_t i, const JobResult& result) {
    results[i] = result;
    progress.finished(jobs[i].name, result);
  };
  if (o.worker.inProcess) {
    ListFeed feed(jobs.size(), finished);
    BatchRunner(jobs, o, o.device, false).run(feed);
  } else {
    WorkerPoolOptions pool;
    pool.devices = {o.device};
    if (!o.worker.gpus.empty()) {
      pool.devices.clear();
      for (const int index : resolveGpus(o.worker.gpus)) {
        DeviceOptions device = o.device;
        device.gpu = std::to_string(index);
        pool.devices.push_back(device);
      }
    }
    pool.jobTimeoutSeconds = o.worker.jobTimeout;
    pool.abandoned = [&jobs](std::size_t i, int pid) {
      for (const fs::path& output : jobs[i].job.outputFiles())
        OutputTransaction::removeTemporariesOf(output, pid);
    };
    const int threads =
        o.jobs >= 0 ? o.jobs : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    pool.jobsPerWorker = 2 * static_cast<std::size_t>(threads) + 2;
    std::vector<std::size_t> todo(jobs.size());
    std::iota(todo.begin(), todo.end(), std::size_t{0});
    runInWorkers(
        todo, pool,
        [&](const DeviceOptions& device, JobFeed& feed) {
          return BatchRunner(jobs, o, device, true).run(feed);
        },
        finished);
  }

  std::size_t counts[3] = {0, 0, 0};
  for (const JobResult& r : results) ++counts[static_cast<int>(r.status)];
  progress.summary(counts[0], counts[1], counts[2]);
  if (!o.report.empty())
    writeReport(o.report, jobs, results, shard, millisecondsSince(start) / 1000.0);
  return counts[2] == 0 ? 0 : 1;
}

}  // namespace omnishadow::cli
