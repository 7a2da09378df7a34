#pragma once

// The scenes of a batch's jobs that name the same file, loaded once.
//
// A manifest often renders one scene many times (cameras, lights, variants of a shot). Each job
// loaded its file again: Avocado's three 2048^2 PNGs decode in about 85 ms, where its frame at
// 640x360 takes about 10. Jobs that read the same file with the same load options now share one
// scene loaded at rest, read-only (a job posed at a time poses a copy of its own); its
// Scene::revision tells the renderer that it hashed these meshes and images before.

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
#include "renderer/scene/decoded_image_cache.h"
#include "renderer/scene/scene.h"

namespace omnishadow::cli {

class SharedSceneLoads {
 public:
  // `jobs`: every job the batch may run. Only files that two or more of them load alike are
  // kept.
  explicit SharedSceneLoads(const std::vector<RenderJob>& jobs);

  // The scene `job` names, at rest, as loadJobScene() loads it, for a file other jobs load too:
  // the one loaded for the first of them (by this call when it is the first). Null where the
  // job loads its own: a file no other job loads alike, a scene let go, a file read since that
  // has changed (size or modification time), a shared load that failed (the job meets the
  // error itself). The last job that needs a scene lets it go. Thread-safe. Throws what
  // loadJobScene() throws.
  std::shared_ptr<const Scene> scene(const RenderJob& job);
  // The pictures the batch's loads decoded, while some scene holds them: a folder with one
  // model as glTF, glTF-Binary and glTF-Draco decodes each picture once. Thread-safe.
  DecodedImageCache* decodedImages() { return &decodedImages_; }

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
  std::shared_ptr<const Loaded> load(const RenderJob& job);
  // Under the lock: the shared load of `key` (invalid for a file no other job shares), which
  // this call makes with `made` (`loads` set) when no job asked for it before.
  std::shared_future<std::shared_ptr<const Loaded>> claim(
      const std::string& key, std::promise<std::shared_ptr<const Loaded>>& made, bool& loads);

  std::mutex mutex_;
  std::map<std::string, Entry> entries_;  // by keyOf(), for files two or more jobs load
  std::uint64_t clock_ = 0;
  DecodedImageCache decodedImages_;
};

}  // namespace omnishadow::cli
