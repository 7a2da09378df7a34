#pragma once

// A fresh folder per test under the system's temporary directory, removed with everything in it
// when the test ends, and the two ways the end-to-end tests look at what a run left there.

#include <filesystem>
#include <string>
#include <vector>

namespace omnishadow::test_support {

class TempFolder {
 public:
  // Creates <temporary directory>/<prefix>-XXXXXX; throws std::runtime_error when it cannot.
  explicit TempFolder(const std::string& prefix);
  ~TempFolder();
  TempFolder(const TempFolder&) = delete;
  TempFolder& operator=(const TempFolder&) = delete;

  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::filesystem::path& name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
};

// The file's bytes; empty when it is missing or unreadable.
std::string readFile(const std::filesystem::path& path);

// Files and folders below `dir` (recursively), relative to it, sorted; empty when `dir` does
// not exist.
std::vector<std::string> filesIn(const std::filesystem::path& dir);

}  // namespace omnishadow::test_support
