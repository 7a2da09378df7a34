#include "renderer/output/oiio_plugin.h"

#include <dlfcn.h>

#include <system_error>
#include <vector>

#include "renderer/core/errors.h"

namespace omnishadow {
namespace {

namespace fs = std::filesystem;

struct LoadedPlugin {
  OiioReadImage read = nullptr;
  std::string error;  // why there is none
};

std::vector<fs::path> pluginCandidates() {
  std::vector<fs::path> candidates;
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    candidates.push_back(self.parent_path() / kOiioPluginFile);
    candidates.push_back(self.parent_path().parent_path() / "lib" / "omnishadow" / kOiioPluginFile);
  }
#ifdef OMNISHADOW_PLUGIN_DIR
  candidates.push_back(fs::path(OMNISHADOW_PLUGIN_DIR) / kOiioPluginFile);
#endif
  return candidates;
}

LoadedPlugin loadPlugin() {
  LoadedPlugin plugin;
  std::string tried;
  for (const fs::path& candidate : pluginCandidates()) {
    std::error_code ec;
    if (!fs::exists(candidate, ec)) {
      tried += (tried.empty() ? "" : ", ") + candidate.string();
      continue;
    }
    // Never closed: OpenImageIO keeps threads and static state until the process ends.
    void* handle = ::dlopen(candidate.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) {
      plugin.error = ::dlerror();
      return plugin;
    }
    plugin.read = reinterpret_cast<OiioReadImage>(::dlsym(handle, kOiioPluginEntry));
    if (!plugin.read) plugin.error = candidate.string() + " has no " + kOiioPluginEntry;
    return plugin;
  }
  plugin.error = std::string(kOiioPluginFile) + " not found (looked for " + tried + ")";
  return plugin;
}

}  // namespace

FloatImage readImageWithOiioPlugin(const std::filesystem::path& path) {
  // Loaded once per process, on first use; a function-local static is initialized thread-safely.
  static const LoadedPlugin plugin = loadPlugin();
  const std::string name = path.string();
  if (!plugin.read)
    throw InputError(name +
                     ": cannot read image: not PNG or OpenEXR, and the OpenImageIO plugin that "
                     "reads other formats is missing: " +
                     plugin.error);
  FloatImage image;
  std::string error;
  if (!plugin.read(name.c_str(), &image, &error, kOiioPluginAbi))
    throw InputError(name + ": cannot read image: " + error);
  return image;
}

}  // namespace omnishadow
