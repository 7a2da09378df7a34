#pragma once

// Mesa's shader cache kept usable where Mesa's own place for it cannot be written.
//
// llvmpipe compiles each shader variant with LLVM at the first draw that needs it, and Mesa keeps
// what it compiled on disk: the next process loads a variant in under a millisecond instead of
// compiling it again (50-120 ms for a lighting variant, 15-30 for the vertex stage on this
// project's 2-core machines). Mesa puts that cache in $MESA_SHADER_CACHE_DIR, else
// $XDG_CACHE_HOME, else the `.cache` folder of the user's home in the password database, and
// keeps nothing at all where that folder cannot be made or written. That is the usual case in a
// container run as a user of its own (`docker run --user 1000`: no entry in the password
// database; `nobody`: home /nonexistent) or with a read-only home, and there every process
// compiled every shader again: a 320x240 render of Box took 240 ms instead of 120, and Sundial's
// first frame 0.6 s more (docs/performance.md, issue 19).
//
// There the CLI gives Mesa a folder of its own, one per user under $TMPDIR (or /tmp), private to
// that user, before anything loads Mesa; the Python module does when its user asks
// (omnishadow.keep_shader_cache()), never on its own. Where the user chose (MESA_SHADER_CACHE_DIR,
// Mesa's older MESA_GLSL_CACHE_DIR, or turning the cache off with MESA_SHADER_CACHE_DISABLE or
// MESA_GLSL_CACHE_DISABLE), or where Mesa's own place works, nothing changes.

#include <filesystem>
#include <optional>
#include <string>

#include "cli/shard_env.h"

namespace omnishadow::cli {

struct ShaderCacheFolder {
  enum class Source {
    UsersChoice,  // a variable above says where, or that there is no cache
    MesasOwn,     // Mesa's own place can be written: `mesasOwn`
    OwnFallback,  // it cannot: Mesa is given `folder`
    None,         // neither can be used (or there is no home to name Mesa's): Mesa keeps nothing
  };
  Source source = Source::UsersChoice;
  std::filesystem::path mesasOwn;  // where Mesa would keep it; empty without a home or a choice
  std::filesystem::path folder;    // the CLI's own (OwnFallback), or the one refused (None)

  // Where Mesa keeps the shaders (it adds a folder of its own below MESA_SHADER_CACHE_DIR);
  // empty where this does not know (UsersChoice) or Mesa keeps none.
  std::filesystem::path shadersFolder() const {
    if (source == Source::MesasOwn) return mesasOwn;
    if (source == Source::OwnFallback) return folder / "mesa_shader_cache";
    return {};
  }
};

// Decides as above from `environment` (XDG_CACHE_HOME, TMPDIR and Mesa's variables), the home
// the password database gives the user (nullopt: no entry) and the user's id. Makes the folders
// Mesa's own place needs, as Mesa itself would a moment later, and the fallback folder (mode
// 0700); a fallback folder that exists is used only when it is a folder (not a link) of this user
// that no one else may enter.
ShaderCacheFolder chooseShaderCacheFolder(const Environment& environment,
                                          const std::optional<std::filesystem::path>& home,
                                          unsigned uid);

// chooseShaderCacheFolder() for this process, setting MESA_SHADER_CACHE_DIR where it chose the
// fallback. Call it before any other thread starts (setenv is not safe beside another thread's
// getenv) and before EGL loads Mesa.
ShaderCacheFolder keepShaderCacheUsable();

// One line for --verbose: where the shaders are kept, and why there.
std::string describeShaderCacheFolder(const ShaderCacheFolder& choice);

}  // namespace omnishadow::cli
