// Where Mesa keeps the shaders it compiles (cli/shader_cache_folder.h): Mesa's own place where it
// can be written, the user's choice always, and else a private folder of the CLI's own. (That
// Mesa then keeps its shaders there: ShaderCacheCli in cli_test.cpp.)
#include "cli/shader_cache_folder.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include "tests/support/environment_map.h"
#include "tests/support/temp_folder.h"

namespace omnishadow::cli::shader_cache_folder_test {
namespace {

namespace fs = std::filesystem;
using Source = ShaderCacheFolder::Source;
using test_support::TempFolder;
using test_support::Variables;

Environment environment(const Variables& variables) {
  return test_support::environmentOf(variables);
}

unsigned permissions(const fs::path& path) {
  struct stat info {};
  return lstat(path.c_str(), &info) == 0 ? info.st_mode & 07777 : 0;
}

class ShaderCacheFolderTest : public ::testing::Test {
 protected:
  TempFolder temp{"shader-cache"};
  const unsigned uid = getuid();
  fs::path tmp() const { return temp / "tmp"; }
  fs::path fallback() const { return tmp() / ("omnishadow-shader-cache-" + std::to_string(uid)); }
  // A path below a plain file: no one, root included, can make a folder there.
  fs::path unmakeable() const {
    std::ofstream(temp / "file") << "not a folder";
    return temp / "file" / "cache";
  }
  void SetUp() override { fs::create_directory(tmp()); }
};

TEST_F(ShaderCacheFolderTest, EveryVariableOfMesasIsTheUsersChoice) {
  for (const char* name : {"MESA_SHADER_CACHE_DIR", "MESA_GLSL_CACHE_DIR",
                           "MESA_SHADER_CACHE_DISABLE", "MESA_GLSL_CACHE_DISABLE"}) {
    SCOPED_TRACE(name);
    const ShaderCacheFolder choice = chooseShaderCacheFolder(
        environment({{name, "1"}, {"XDG_CACHE_HOME", unmakeable()}, {"TMPDIR", tmp()}}),
        std::nullopt, uid);
    EXPECT_EQ(choice.source, Source::UsersChoice);
    EXPECT_FALSE(fs::exists(fallback()));
  }
}

TEST_F(ShaderCacheFolderTest, MesasOwnPlaceIsKeptWhereItCanBeWritten) {
  // $XDG_CACHE_HOME, made as Mesa would make it.
  const ShaderCacheFolder xdg = chooseShaderCacheFolder(
      environment({{"XDG_CACHE_HOME", temp / "xdg"}, {"TMPDIR", tmp()}}), std::nullopt, uid);
  EXPECT_EQ(xdg.source, Source::MesasOwn);
  EXPECT_EQ(xdg.mesasOwn, temp / "xdg" / "mesa_shader_cache");
  EXPECT_TRUE(fs::is_directory(xdg.mesasOwn));

  // Else the home's .cache.
  fs::create_directory(temp / "home");
  const ShaderCacheFolder home =
      chooseShaderCacheFolder(environment({{"TMPDIR", tmp()}}), temp / "home", uid);
  EXPECT_EQ(home.source, Source::MesasOwn);
  EXPECT_EQ(home.mesasOwn, temp / "home" / ".cache" / "mesa_shader_cache");
  EXPECT_TRUE(fs::is_directory(home.mesasOwn));
  EXPECT_FALSE(fs::exists(fallback()));
}

TEST_F(ShaderCacheFolderTest, APrivateFolderOfItsOwnWhereMesasPlaceCannotBeMade) {
  const Environment variables = environment({{"TMPDIR", tmp()}});
  // A user without an entry in the password database (docker run --user 1000).
  const ShaderCacheFolder noHome = chooseShaderCacheFolder(variables, std::nullopt, uid);
  EXPECT_EQ(noHome.source, Source::OwnFallback);
  EXPECT_EQ(noHome.folder, fallback());
  EXPECT_TRUE(noHome.mesasOwn.empty());
  EXPECT_EQ(permissions(fallback()), 0700u);
  EXPECT_NE(describeShaderCacheFolder(noHome).find(fallback().string()), std::string::npos);

  // A home that does not exist (nobody's /nonexistent), and an $XDG_CACHE_HOME below a file; the
  // folder made the first time is used again.
  const ShaderCacheFolder missingHome =
      chooseShaderCacheFolder(variables, temp / "nonexistent", uid);
  EXPECT_EQ(missingHome.source, Source::OwnFallback);
  EXPECT_EQ(missingHome.mesasOwn, temp / "nonexistent" / ".cache" / "mesa_shader_cache");
  EXPECT_FALSE(fs::exists(temp / "nonexistent"));
  const ShaderCacheFolder badXdg = chooseShaderCacheFolder(
      environment({{"XDG_CACHE_HOME", unmakeable()}, {"TMPDIR", tmp()}}), temp / "home", uid);
  EXPECT_EQ(badXdg.source, Source::OwnFallback);
  EXPECT_EQ(badXdg.folder, fallback());

  // Mesa makes no folder named by an empty $XDG_CACHE_HOME either.
  EXPECT_EQ(chooseShaderCacheFolder(environment({{"XDG_CACHE_HOME", ""}, {"TMPDIR", tmp()}}),
                                    temp / "home", uid)
                .source,
            Source::OwnFallback);
}

TEST_F(ShaderCacheFolderTest, AFolderOthersMayEnterOrALinkIsNotTaken) {
  const Environment variables = environment({{"TMPDIR", tmp()}});
  fs::create_directory(fallback());
  fs::permissions(fallback(), fs::perms::owner_all | fs::perms::group_all | fs::perms::others_all);
  const ShaderCacheFolder open = chooseShaderCacheFolder(variables, std::nullopt, uid);
  EXPECT_EQ(open.source, Source::None);
  EXPECT_NE(describeShaderCacheFolder(open).find("compiled anew"), std::string::npos);

  fs::remove(fallback());
  fs::create_directory(temp / "elsewhere");
  fs::permissions(temp / "elsewhere", fs::perms::owner_all, fs::perm_options::replace);
  fs::create_directory_symlink(temp / "elsewhere", fallback());
  EXPECT_EQ(chooseShaderCacheFolder(variables, std::nullopt, uid).source, Source::None);

  // A $TMPDIR where no folder can be made.
  const ShaderCacheFolder nowhere =
      chooseShaderCacheFolder(environment({{"TMPDIR", unmakeable()}}), std::nullopt, uid);
  EXPECT_EQ(nowhere.source, Source::None);
  EXPECT_NE(describeShaderCacheFolder(nowhere).find("cannot be made"), std::string::npos);

  // A folder with the name of another user's (made here, so it is this user's, not theirs).
  const ShaderCacheFolder others = chooseShaderCacheFolder(variables, std::nullopt, uid + 1);
  EXPECT_EQ(others.source, Source::None);
  EXPECT_EQ(others.folder, tmp() / ("omnishadow-shader-cache-" + std::to_string(uid + 1)));
}

}  // namespace
}  // namespace omnishadow::cli::shader_cache_folder_test
