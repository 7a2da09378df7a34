#include "renderer/gl/loaded_libraries.h"

#include <dlfcn.h>
#include <link.h>

#include <algorithm>
#include <cstddef>

namespace omnishadow {

std::vector<std::string> loadedLibraries() {
  std::vector<std::string> names;
  dl_iterate_phdr(
      [](dl_phdr_info* info, std::size_t, void* data) {
        // The program has no file name here.
        if (info->dlpi_name != nullptr && info->dlpi_name[0] != '\0')
          static_cast<std::vector<std::string>*>(data)->emplace_back(info->dlpi_name);
        return 0;
      },
      &names);
  return names;
}

void keepLibrariesLoadedSince(const std::vector<std::string>& before) {
  for (const std::string& name : loadedLibraries()) {
    if (std::find(before.begin(), before.end(), name) != before.end()) continue;
    // Takes a reference that is never given back; RTLD_NOLOAD loads nothing that was unloaded
    // meanwhile (then it returns null, and there is nothing to keep).
    ::dlopen(name.c_str(), RTLD_LAZY | RTLD_NOLOAD | RTLD_NODELETE);
  }
}

}  // namespace omnishadow
