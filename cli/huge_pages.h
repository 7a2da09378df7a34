#pragma once

// Transparent huge pages for the commands that render.
//
// A first frame spends much of its time in page faults: llvmpipe zeroes every new texture (a
// 1024² depth cube map is 24 MB) and the kernel maps each 4 KiB page on first touch, about
// 25,000 faults for Box and 59,000 for Sundial. Where the kernel gives huge pages only to memory
// that asks for them (transparent_hugepage "madvise", Debian's default), glibc's malloc asks
// when its tunable glibc.malloc.hugetlb=1 is set, and the faults drop four- to fivefold. glibc
// reads tunables only when a process starts, so the command starts itself again once with it.

#include <optional>
#include <string>
#include <string_view>

#include "cli/process_environment.h"

namespace omnishadow::cli {

// The GLIBC_TUNABLES to run `command` again with, or nothing to go on as is. Something only for
// `render`, `batch` and `verify`, when the kernel's policy (the text of
// /sys/kernel/mm/transparent_hugepage/enabled) is "madvise", GLIBC_TUNABLES does not set
// glibc.malloc.hugetlb already (so it happens once), OMNISHADOW_HUGE_PAGES is not "0", and no
// valgrind tool is loaded (it would not follow the exec). Other tunables are kept.
std::optional<std::string> hugePageTunables(std::string_view command,
                                            const Environment& environment,
                                            std::string_view kernelPolicy);

// Replaces the process with itself, same arguments, when hugePageTunables() says so; returns,
// changing nothing, when it does not or when the exec fails.
void runWithHugePages(int argc, char** argv);

}  // namespace omnishadow::cli
