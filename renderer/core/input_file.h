// Reading a file the user (or a scene) names as input: regular files only, never blocking, never
// more than a stated number of bytes. A FIFO, /dev/zero or a terminal named as a scene, a lights
// file, a manifest, a diff input or a glTF buffer would otherwise block in open() or read until
// memory runs out.
#pragma once

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <string_view>

#include "renderer/core/errors.h"

namespace omnishadow {

// What a file that is not a regular file is, for messages.
inline std::string describeFileType(mode_t mode) {
  if (S_ISDIR(mode)) return "is a directory";
  if (S_ISFIFO(mode)) return "is a FIFO (named pipe), not a regular file";
  if (S_ISCHR(mode)) return "is a character device, not a regular file";
  if (S_ISBLK(mode)) return "is a block device, not a regular file";
  if (S_ISSOCK(mode)) return "is a socket, not a regular file";
  return "is not a regular file";
}

// Why a file is refused: empty when `path` is a regular file (symbolic links followed), else the
// reason ("no such file", "is a FIFO (named pipe), not a regular file", ...). Looks, never opens.
inline std::string notRegularFile(const std::filesystem::path& path) {
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) {
    return errno == ENOENT ? std::string("no such file") : std::string(std::strerror(errno));
  }
  return S_ISREG(info.st_mode) ? std::string() : describeFileType(info.st_mode);
}

// Reads all of `path` into `content`; returns empty on success, else why not (as above, or
// "N bytes, more than the limit of M"). The type is checked before open() and again on the open
// descriptor (the file may be replaced in between); O_NONBLOCK makes even that open of a FIFO
// return at once.
// `errorNumber`, when given, receives the errno behind the reason (ENOENT, EISDIR, ...) or 0
// where there is none (a FIFO, a file too large), for callers that word those themselves.
inline std::string readRegularFile(const std::filesystem::path& path, std::uint64_t maxBytes,
                                   std::string& content, int* errorNumber = nullptr) {
  if (errorNumber) *errorNumber = 0;
  struct stat before {};
  if (::stat(path.c_str(), &before) != 0 || S_ISDIR(before.st_mode)) {
    const int error = S_ISDIR(before.st_mode) ? EISDIR : errno;
    if (errorNumber) *errorNumber = error;
    if (error == EISDIR) return "is a directory";
    return error == ENOENT ? std::string("no such file") : std::string(std::strerror(error));
  }
  if (!S_ISREG(before.st_mode)) return describeFileType(before.st_mode);
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  if (fd < 0) {
    if (errorNumber) *errorNumber = errno;
    return errno == ENOENT ? std::string("no such file") : std::string(std::strerror(errno));
  }
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};
  struct stat info {};
  if (::fstat(fd, &info) != 0) return std::strerror(errno);
  if (!S_ISREG(info.st_mode)) return describeFileType(info.st_mode);
  const auto tooLarge = [&](std::uint64_t size) {
    return std::to_string(size) + " bytes, more than the limit of " + std::to_string(maxBytes);
  };
  if (static_cast<std::uint64_t>(info.st_size) > maxBytes) return tooLarge(info.st_size);
  content.clear();
  content.reserve(static_cast<std::size_t>(info.st_size));
  // A file in /proc says size 0 and may grow while read: the bound applies to what is read.
  char buffer[64 * 1024];
  for (;;) {
    const ::ssize_t got = ::read(fd, buffer, sizeof buffer);
    if (got < 0) {
      if (errno == EINTR) continue;
      if (errorNumber) *errorNumber = errno;
      return std::strerror(errno);
    }
    if (got == 0) break;
    if (content.size() + static_cast<std::size_t>(got) > maxBytes) {
      return tooLarge(content.size() + static_cast<std::size_t>(got));
    }
    content.append(buffer, static_cast<std::size_t>(got));
  }
  return {};
}

// The same, throwing InputError "<path>: cannot read <what>: <reason>".
inline std::string readInputFile(const std::filesystem::path& path, std::uint64_t maxBytes,
                                 std::string_view what) {
  std::string content;
  if (const std::string why = readRegularFile(path, maxBytes, content); !why.empty()) {
    throw InputError(path.string() + ": cannot read " + std::string(what) + ": " + why);
  }
  return content;
}

}  // namespace omnishadow
