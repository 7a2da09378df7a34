#pragma once
// What /proc/self/smaps says of the process's own mappings: the tests of the CLI's heap set-up
// and memory warm-up check the advice (huge pages or not) a range of the heap carries.
#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <string>

namespace omnishadow::test_support {

// The VmFlags line of the mapping that holds `address` ("" when none does).
inline std::string mappingFlags(const void* address) {
  std::ifstream smaps("/proc/self/smaps");
  const auto at = reinterpret_cast<std::uintptr_t>(address);
  bool inside = false;
  for (std::string line; std::getline(smaps, line);) {
    std::uintptr_t begin = 0, end = 0;
    if (std::sscanf(line.c_str(), "%" SCNxPTR "-%" SCNxPTR " ", &begin, &end) == 2)
      inside = begin <= at && at < end;
    else if (inside && line.rfind("VmFlags:", 0) == 0)
      return line;
  }
  return "";
}

// The name of the mapping that holds `address` ("[heap]", a file's path; "" for an anonymous
// mapping or none).
inline std::string mappingName(const void* address) {
  std::ifstream maps("/proc/self/maps");
  const auto at = reinterpret_cast<std::uintptr_t>(address);
  for (std::string line; std::getline(maps, line);) {
    std::uintptr_t begin = 0, end = 0;
    int nameAt = 0;
    if (std::sscanf(line.c_str(), "%" SCNxPTR "-%" SCNxPTR " %*s %*s %*s %*s %n", &begin, &end,
                    &nameAt) >= 2 &&
        begin <= at && at < end)
      return nameAt > 0 ? line.substr(static_cast<std::size_t>(nameAt)) : "";
  }
  return "";
}

// Whether a VmFlags line has `flag` ("hg": asks for huge pages, "nh": asks for none).
inline bool hasFlag(const std::string& vmFlags, const char* flag) {
  return (vmFlags + " ").find(std::string(" ") + flag + " ") != std::string::npos;
}

// Whether a mapping that overlaps [begin, end) asks for huge pages.
inline bool someMappingAsksForHugePages(std::uintptr_t begin, std::uintptr_t end) {
  std::ifstream smaps("/proc/self/smaps");
  bool overlaps = false;
  for (std::string line; std::getline(smaps, line);) {
    std::uintptr_t from = 0, to = 0;
    if (std::sscanf(line.c_str(), "%" SCNxPTR "-%" SCNxPTR " ", &from, &to) == 2)
      overlaps = from < end && begin < to;
    else if (overlaps && line.rfind("VmFlags:", 0) == 0 && hasFlag(line, "hg"))
      return true;
  }
  return false;
}

inline bool kernelHasHugePages() {
  return std::ifstream("/sys/kernel/mm/transparent_hugepage/enabled").good();
}

}  // namespace omnishadow::test_support
