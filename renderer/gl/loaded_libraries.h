#pragma once

// Keeping the libraries a GL driver brought into the process loaded once it has them.
//
// Mesa's EGL unloads its driver (dlclose) when the process's last display is terminated, and
// loads it again for the next one. A process that ends its renderers and makes new ones (a
// Python session, a test program) then loads and relocates the driver and LLVM each time, and
// the driver's allocations that only its globals point at are left behind unreachable, which
// LeakSanitizer reports at exit from an "<unknown module>" no suppression can name. Kept loaded,
// the driver's globals stay mapped: a new renderer finds it ready, and its blocks stay reachable.

#include <string>
#include <vector>

namespace omnishadow {

// The names of the shared libraries loaded in this process now, as the loader lists them (file
// names, and the vDSO's; not the program itself).
std::vector<std::string> loadedLibraries();

// Marks each library loaded now and not named in `before` never to be unloaded
// (dlopen(RTLD_NOLOAD | RTLD_NODELETE)): a later dlclose() leaves it and its data mapped.
void keepLibrariesLoadedSince(const std::vector<std::string>& before);

}  // namespace omnishadow
