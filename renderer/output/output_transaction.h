#pragma once

#include <filesystem>
#include <vector>

namespace omnishadow {

// All-or-nothing output: each file is written to a temporary name in its final folder, and
// commit() renames them all into place. If the transaction is destroyed before commit() (an
// exception while encoding, say), the temporaries are removed, so a failed run leaves no
// partial or stray file, and folders that stage() created for it are removed again if empty.
class OutputTransaction {
 public:
  OutputTransaction() = default;
  OutputTransaction(const OutputTransaction&) = delete;
  OutputTransaction& operator=(const OutputTransaction&) = delete;
  ~OutputTransaction();

  // Returns the temporary path to write `finalPath` to. Keeps the extension so that encoders
  // that pick a format by extension still work. Throws RenderError when the folder is missing
  // or not writable.
  std::filesystem::path stage(const std::filesystem::path& finalPath);

  // Renames every staged file onto its final path. Throws RenderError on failure (and removes
  // what was not yet renamed).
  void commit();

  // The final path of a temporary that stage() returned and that is not yet committed or
  // removed, by any transaction of the process; else `path` itself. Encoders name files with
  // it, so that a message says "cannot write out/a.png", not the hidden temporary's name.
  static std::filesystem::path finalPathOf(const std::filesystem::path& path);

  // Removes the temporaries that process `pid` staged for `finalPath` and never committed: what
  // a process killed while writing leaves (a batch worker past --job-timeout, or one that
  // crashed). Errors are ignored: this is cleanup.
  static void removeTemporariesOf(const std::filesystem::path& finalPath, int pid) noexcept;

 private:
  struct Entry {
    std::filesystem::path temporary;
    std::filesystem::path final;
  };
  void removeCreatedFolders() noexcept;
  void forgetNames() noexcept;

  std::vector<Entry> entries_;
  std::vector<std::filesystem::path> createdFolders_;  // by stage(), outermost first
  bool committed_ = false;
};

}  // namespace omnishadow
