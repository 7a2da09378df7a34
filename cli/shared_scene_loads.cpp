#include "cli/shared_scene_loads.h"

#include <algorithm>
#include <exception>
#include <system_error>
#include <utility>

namespace omnishadow::cli {

namespace fs = std::filesystem;

SharedSceneLoads::SharedSceneLoads(const std::vector<RenderJob>& jobs) {
  std::map<std::string, int> counts;
  for (const RenderJob& job : jobs) ++counts[keyOf(job)];
  for (const auto& [key, count] : counts)
    if (count > 1) entries_[key].users = count;
}

std::string SharedSceneLoads::keyOf(const RenderJob& job) {
  // What loadJobScene() reads the file with; the pose comes after, per job.
  return resolvedPath(job.scene).string() + '\n' + std::to_string(job.sceneIndex) + '\n' +
         job.materialVariant + '\n' + (job.allowExternalUris ? "1" : "0");
}

SharedSceneLoads::FileStamp SharedSceneLoads::stampOf(const fs::path& file) {
  std::error_code error;
  FileStamp stamp{file, fs::file_size(file, error), {}};
  if (!error) stamp.modified = fs::last_write_time(file, error);
  if (error) stamp.size = static_cast<std::uintmax_t>(-1);  // gone: never equal to a file
  return stamp;
}

std::shared_ptr<const SharedSceneLoads::Loaded> SharedSceneLoads::load(const RenderJob& job) {
  auto loaded = std::make_shared<Loaded>();
  loaded->scene = loadJobScene(job, &decodedImages_);
  for (const std::string& file : loaded->scene.inputFiles) loaded->stamps.push_back(stampOf(file));
  return loaded;
}

std::shared_future<std::shared_ptr<const SharedSceneLoads::Loaded>> SharedSceneLoads::claim(
    const std::string& key, std::promise<std::shared_ptr<const Loaded>>& made, bool& loads) {
  const std::lock_guard<std::mutex> lock(mutex_);
  const auto it = entries_.find(key);
  if (it == entries_.end()) return {};  // a file of its own, or let go
  Entry& entry = it->second;
  if (!entry.loaded.valid()) {
    entry.loaded = made.get_future().share();
    loads = true;
    // Only the latest kKept scenes stay loaded: the others' next jobs load them again.
    std::vector<std::pair<std::uint64_t, std::string>> loadedOnes;
    for (const auto& [otherKey, other] : entries_)
      if (other.loaded.valid() && otherKey != key) loadedOnes.emplace_back(other.used, otherKey);
    std::sort(loadedOnes.begin(), loadedOnes.end());
    for (std::size_t i = 0; i + kKept < loadedOnes.size() + 1; ++i)
      entries_[loadedOnes[i].second].loaded = {};
  }
  entry.used = ++clock_;
  std::shared_future<std::shared_ptr<const Loaded>> shared = entry.loaded;
  if (--entry.users <= 0) entries_.erase(it);
  return shared;
}

std::shared_ptr<const Scene> SharedSceneLoads::scene(const RenderJob& job) {
  std::promise<std::shared_ptr<const Loaded>> made;
  bool loads = false;  // this call loads the scene the others wait for
  const std::shared_future<std::shared_ptr<const Loaded>> shared = claim(keyOf(job), made, loads);
  if (!shared.valid()) return nullptr;
  if (loads) {
    try {
      made.set_value(load(job));
    } catch (...) {
      made.set_exception(std::current_exception());
      throw;
    }
  }
  std::shared_ptr<const Loaded> loaded;
  try {
    loaded = shared.get();
  } catch (...) {  // the first job's load failed: this job tries again and reports its own
    return nullptr;
  }
  for (const FileStamp& stamp : loaded->stamps)
    if (stampOf(stamp.path) != stamp) return nullptr;  // changed since: read again
  return {loaded, &loaded->scene};
}

}  // namespace omnishadow::cli
