#include "renderer/output/output_transaction.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <map>
#include <mutex>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#include "renderer/core/errors.h"

namespace omnishadow {
namespace {

namespace fs = std::filesystem;

// Shared by every transaction in the process, so two transactions staging the same final path
// (or one retrying) never pick the same temporary name.
std::atomic<unsigned long> stageCounter{0};

// Temporary -> final path of every staged file not yet committed or removed; batch mode encodes
// on several threads at once.
std::mutex namesMutex;
std::map<fs::path, fs::path>& finalNames() {
  static std::map<fs::path, fs::path> names;
  return names;
}

RenderError cannotWrite(const fs::path& finalPath, const std::string& reason) {
  return RenderError("cannot write " + finalPath.string() + ": " + reason);
}

fs::path folderOf(const fs::path& finalPath) {
  return finalPath.has_parent_path() ? finalPath.parent_path() : fs::path(".");
}

// ".render.png.tmp-<pid>-<n>.png": hidden, so directory watchers and globs skip it, and ending
// in the final extension, so encoders that choose a format by extension still work.
fs::path temporaryName(const fs::path& finalPath) {
  std::string name = "." + finalPath.filename().string() + ".tmp-" + std::to_string(::getpid()) +
                     "-" + std::to_string(stageCounter.fetch_add(1)) +
                     finalPath.extension().string();
  return folderOf(finalPath) / name;
}

// Creating the temporary is the writability check: it is the operation that must succeed
// later anyway, it reserves the name, and unlike access(W_OK) it cannot disagree with what the
// encoder will see. O_EXCL keeps us off a file that belongs to someone else.
fs::path createTemporary(const fs::path& finalPath) {
  constexpr int kAttempts = 16;
  int error = 0;
  for (int attempt = 0; attempt < kAttempts; ++attempt) {
    fs::path candidate = temporaryName(finalPath);
    int fd = ::open(candidate.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd >= 0) {
      ::close(fd);
      return candidate;
    }
    error = errno;
    if (error != EEXIST) break;
  }
  throw cannotWrite(finalPath, std::generic_category().message(error));
}

void removeQuietly(const fs::path& path) noexcept {
  std::error_code ignored;
  fs::remove(path, ignored);
}

// An encoder that failed without throwing may leave the (empty) placeholder; renaming that into
// place would publish a broken file.
void checkWritten(const fs::path& temporary, const fs::path& finalPath) {
  std::error_code error;
  // rename(2) cannot replace a folder; find out before anything is published.
  if (fs::is_directory(finalPath, error)) throw cannotWrite(finalPath, "is a folder");
  auto size = fs::file_size(temporary, error);
  if (error) throw cannotWrite(finalPath, error.message());
  if (size == 0) throw cannotWrite(finalPath, "nothing was written");
}

fs::path identity(const fs::path& path) {
  return fs::absolute(path).lexically_normal();
}

}  // namespace

OutputTransaction::~OutputTransaction() {
  forgetNames();
  if (committed_) return;
  for (const Entry& entry : entries_) removeQuietly(entry.temporary);
  removeCreatedFolders();
}

fs::path OutputTransaction::finalPathOf(const fs::path& path) {
  const std::lock_guard lock(namesMutex);
  const auto found = finalNames().find(path);
  return found == finalNames().end() ? path : found->second;
}

void OutputTransaction::forgetNames() noexcept {
  const std::lock_guard lock(namesMutex);
  for (const Entry& entry : entries_) finalNames().erase(entry.temporary);
}

void OutputTransaction::removeCreatedFolders() noexcept {
  // Deepest first; a folder that has gained other files since is left alone.
  for (auto it = createdFolders_.rbegin(); it != createdFolders_.rend(); ++it) {
    std::error_code ignored;
    if (fs::is_empty(*it, ignored)) fs::remove(*it, ignored);
  }
  createdFolders_.clear();
}

fs::path OutputTransaction::stage(const fs::path& finalPath) {
  if (committed_) throw std::logic_error("OutputTransaction::stage after commit");
  for (const Entry& entry : entries_) {
    // Two outputs on one path would race for the final name; the second would win silently.
    if (identity(entry.final) == identity(finalPath))
      throw cannotWrite(finalPath, "the same file is written twice in one run");
  }
  if (finalPath.filename().empty()) throw cannotWrite(finalPath, "not a file name");

  // Remember the folders this creates, outermost first, to remove them again on failure.
  std::vector<fs::path> missing;
  for (fs::path folder = fs::absolute(folderOf(finalPath)).lexically_normal();
       !folder.empty() && !fs::exists(folder) && folder != folder.parent_path();
       folder = folder.parent_path())
    missing.insert(missing.begin(), folder);
  std::error_code error;
  fs::create_directories(folderOf(finalPath), error);
  if (error) throw cannotWrite(finalPath, error.message());
  createdFolders_.insert(createdFolders_.end(), missing.begin(), missing.end());

  // Reserve first, so that a failing push_back cannot orphan a file on disk.
  entries_.reserve(entries_.size() + 1);
  fs::path temporary = createTemporary(finalPath);
  entries_.push_back({temporary, finalPath});
  const std::lock_guard lock(namesMutex);
  finalNames()[temporary] = finalPath;
  return temporary;
}

void OutputTransaction::commit() {
  if (committed_) return;
  committed_ = true;
  forgetNames();
  std::vector<Entry> pending;
  pending.swap(entries_);

  // Check everything before renaming anything: a failure here publishes no file at all.
  try {
    for (const Entry& entry : pending) checkWritten(entry.temporary, entry.final);
  } catch (...) {
    for (const Entry& entry : pending) removeQuietly(entry.temporary);
    removeCreatedFolders();
    throw;
  }

  for (std::size_t i = 0; i < pending.size(); ++i) {
    std::error_code error;
    // Same folder, hence same filesystem: rename(2) replaces the final atomically.
    fs::rename(pending[i].temporary, pending[i].final, error);
    if (error) {
      for (std::size_t j = i; j < pending.size(); ++j) removeQuietly(pending[j].temporary);
      throw cannotWrite(pending[i].final, error.message());
    }
  }
}

void OutputTransaction::removeTemporariesOf(const fs::path& finalPath, int pid) noexcept {
  // The names temporaryName() gives, for any counter value.
  const std::string prefix =
      "." + finalPath.filename().string() + ".tmp-" + std::to_string(pid) + "-";
  const std::string extension = finalPath.extension().string();
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(folderOf(finalPath), error)) {
    const std::string name = entry.path().filename().string();
    if (name.starts_with(prefix) && name.ends_with(extension)) removeQuietly(entry.path());
  }
}

}  // namespace omnishadow
