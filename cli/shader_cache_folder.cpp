#include "cli/shader_cache_folder.h"

#include <pwd.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <vector>

namespace omnishadow::cli {

namespace {

namespace fs = std::filesystem;

// Mesa's own rule for each folder of its path: one that exists must be a folder, one that does
// not is made (its parent must exist).
bool makeFolderAsMesaDoes(const fs::path& folder) {
  struct stat info {};
  if (stat(folder.c_str(), &info) == 0) return S_ISDIR(info.st_mode);
  return mkdir(folder.c_str(), 0700) == 0 || errno == EEXIST;
}

// Mesa opens its index in the folder for writing and writes each entry there.
bool writable(const fs::path& folder) {
  return access(folder.c_str(), W_OK | X_OK) == 0;
}

// A folder in a place anyone may write to (/tmp) is the CLI's only if it is a folder, not a link,
// owned by this user and closed to everyone else: else another user could read or plant shaders.
bool ownPrivateFolder(const fs::path& folder, unsigned uid) {
  if (mkdir(folder.c_str(), 0700) != 0 && errno != EEXIST) return false;
  struct stat info {};
  return lstat(folder.c_str(), &info) == 0 && S_ISDIR(info.st_mode) && info.st_uid == uid &&
         (info.st_mode & 077) == 0 && writable(folder);
}

std::optional<fs::path> homeInPasswordDatabase(unsigned uid) {
  std::vector<char> buffer(4096);
  passwd entry{};
  passwd* found = nullptr;
  int error = 0;
  while ((error = getpwuid_r(uid, &entry, buffer.data(), buffer.size(), &found)) == ERANGE &&
         buffer.size() < (std::size_t{1} << 20))
    buffer.resize(buffer.size() * 2);
  if (error != 0 || found == nullptr || entry.pw_dir == nullptr) return std::nullopt;
  return fs::path(entry.pw_dir);
}

}  // namespace

ShaderCacheFolder chooseShaderCacheFolder(const Environment& environment,
                                          const std::optional<fs::path>& home, unsigned uid) {
  ShaderCacheFolder choice;
  for (const char* name : {"MESA_SHADER_CACHE_DIR", "MESA_GLSL_CACHE_DIR",
                           "MESA_SHADER_CACHE_DISABLE", "MESA_GLSL_CACHE_DISABLE"})
    if (environment(name)) return choice;

  // Mesa's own place, made as Mesa makes it: $XDG_CACHE_HOME/mesa_shader_cache, else
  // <home>/.cache/mesa_shader_cache.
  bool made = false;
  if (const auto xdg = environment("XDG_CACHE_HOME")) {
    choice.mesasOwn = fs::path(*xdg) / "mesa_shader_cache";
    made = !xdg->empty() && makeFolderAsMesaDoes(*xdg) && makeFolderAsMesaDoes(choice.mesasOwn);
  } else if (home) {
    choice.mesasOwn = *home / ".cache" / "mesa_shader_cache";
    made = makeFolderAsMesaDoes(*home / ".cache") && makeFolderAsMesaDoes(choice.mesasOwn);
  }
  if (made && writable(choice.mesasOwn)) {
    choice.source = ShaderCacheFolder::Source::MesasOwn;
    return choice;
  }

  const auto tmp = environment("TMPDIR");
  const fs::path base = tmp && fs::path(*tmp).is_absolute() ? fs::path(*tmp) : fs::path("/tmp");
  choice.folder = base / ("omnishadow-shader-cache-" + std::to_string(uid));
  choice.source = ownPrivateFolder(choice.folder, uid) ? ShaderCacheFolder::Source::OwnFallback
                                                       : ShaderCacheFolder::Source::None;
  return choice;
}

ShaderCacheFolder keepShaderCacheUsable() {
  const unsigned uid = getuid();
  ShaderCacheFolder choice =
      chooseShaderCacheFolder(processEnvironment(), homeInPasswordDatabase(uid), uid);
  if (choice.source == ShaderCacheFolder::Source::OwnFallback)
    setenv("MESA_SHADER_CACHE_DIR", choice.folder.c_str(), 1);
  return choice;
}

std::string describeShaderCacheFolder(const ShaderCacheFolder& choice) {
  const std::string why =
      choice.mesasOwn.empty()
          ? "Mesa's own place needs a home, and the password database has "
            "none for this user"
          : "Mesa's own place, " + choice.mesasOwn.string() + ", cannot be written";
  switch (choice.source) {
    case ShaderCacheFolder::Source::UsersChoice:
      return "shader cache: as Mesa's variables set it (MESA_SHADER_CACHE_DIR, "
             "MESA_SHADER_CACHE_DISABLE or their older MESA_GLSL_ names)";
    case ShaderCacheFolder::Source::MesasOwn:
      return "shader cache: " + choice.shadersFolder().string();
    case ShaderCacheFolder::Source::OwnFallback:
      return "shader cache: " + choice.shadersFolder().string() + " (" + why + ")";
    case ShaderCacheFolder::Source::None:
      return "shader cache: none (" + why + ", and " + choice.folder.string() +
             " cannot be made, or is a link, another user's or open to others): every shader "
             "is compiled anew";
  }
  return {};
}

}  // namespace omnishadow::cli
