#pragma once

// The scenes of a batch's jobs that name the same file, loaded once.
//
// A manifest often renders one scene many times (cameras, lights, variants of a shot). Each job
// loaded its file again: Avocado's three 2048^2 PNGs decode in about 85 ms, where its frame at
// 640x360 takes about 10. Jobs that read the same file with the same load options now take
// copies of one scene loaded at rest; a copy keeps its Scene::revision, so the renderer also
// takes its meshes and images as the ones it hashed before.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <future>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "cli/render_job.h"
#include "renderer/scene/scene.h"

namespace omnishadow::cli {

class SharedSceneLoads {
 public:
  // `jobs`: every job the batch may run. Only files that two or more of them load alike are
  // kept; a job of its own loads its scene as before, with no copy.
  explicit SharedSceneLoads(const std::vector<RenderJob>& jobs);

  // The scene `job` names, at rest, as loadJobScene() loads it: for a file other jobs load too,
  // a copy of the one loaded for the first of them, as long as no file it read has changed
  // since (size or modification time); loaded anew otherwise. The last job that needs it lets
  // it go. Thread-safe. Throws what loadJobScene() throws (and a job after a failed load tries
  // again).
  Scene scene(const RenderJob& job);

 private:
  struct FileStamp {
    std::filesystem::path path;
    std::uintmax_t size = 0;
    std::filesystem::file_time_type modified;
    bool operator==(const FileStamp&) const = default;
  };
  struct Loaded {
    Scene scene;
    std::vector<FileStamp> stamps;  // the scene file and every file it read, once loaded
  };
  struct Entry {
    std::shared_future<std::shared_ptr<const Loaded>> loaded;  // valid once a job asked
    int users = 0;                                             // jobs still to take it
    std::uint64_t used = 0;  // when a job last asked, for keeping the latest kKept loaded
  };
  // Scenes kept loaded at most: a shard of a batch may run only some of a file's jobs.
  static constexpr std::size_t kKept = 2;
  static std::string keyOf(const RenderJob& job);
  static FileStamp stampOf(const std::filesystem::path& file);
  static std::shared_ptr<const Loaded> load(const RenderJob& job);
  // Under the lock: the shared load of `key` (invalid for a file no other job shares), which
  // this call makes with `made` (`loads` set) when no job asked for it before.
  std::shared_future<std::shared_ptr<const Loaded>> claim(
      const std::string& key, std::promise<std::shared_ptr<const Loaded>>& made, bool& loads);

  std::mutex mutex_;
  std::map<std::string, Entry> entries_;  // by keyOf(), for files two or more jobs load
  std::uint64_t clock_ = 0;
};

}  // namespace omnishadow::cli
