// A batch's jobs of one file share one load (cli/shared_scene_loads.h): a later job takes a copy
// of the scene the first loaded, which keeps its revision (a fresh load would get a new one),
// unless a file it read has changed or the scene was let go.
#include "cli/shared_scene_loads.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "renderer/core/errors.h"
#include "tests/support/temp_folder.h"

namespace omnishadow::cli {
namespace {

namespace fs = std::filesystem;

fs::path thirdParty(const std::string& relative) {
  return fs::path(OMNISHADOW_SOURCE_DIR) / "scenes" / "thirdparty" / relative;
}

RenderJob jobOf(const fs::path& scene) {
  RenderJob job;
  job.scene = scene;
  return job;
}

TEST(SharedSceneLoads, JobsOfOneFileShareItsLoad) {
  test_support::TempFolder folder("shared-loads");
  fs::copy_file(thirdParty("Box/Box.glb"), folder / "box.glb");
  const RenderJob job = jobOf(folder / "box.glb");
  RenderJob sameFileOtherSpelling = jobOf(folder / "." / "box.glb");
  sameFileOtherSpelling.camera.eye = glm::vec3(3.0f);  // the view is not the load's
  SharedSceneLoads loads({job, sameFileOtherSpelling, job});
  const Scene first = loads.scene(job);
  const Scene second = loads.scene(sameFileOtherSpelling);
  EXPECT_NE(first.revision, 0u);
  EXPECT_EQ(second.revision, first.revision);  // a copy, not a load
  EXPECT_EQ(second.meshes.size(), first.meshes.size());
  EXPECT_EQ(second.meshes[0].positions, first.meshes[0].positions);
  // Past its jobs the scene is let go: one job more loads the file again.
  EXPECT_EQ(loads.scene(job).revision, first.revision);
  EXPECT_NE(loads.scene(job).revision, first.revision);
}

TEST(SharedSceneLoads, AJobOfItsOwnAndOtherOptionsLoadTheirOwn) {
  const RenderJob box = jobOf(thirdParty("Box/Box.glb"));
  RenderJob otherScene = box;
  otherScene.sceneIndex = 0;  // another load option: another load
  SharedSceneLoads loads({box, otherScene});
  const Scene a = loads.scene(box);
  const Scene b = loads.scene(otherScene);
  EXPECT_NE(a.revision, b.revision);
}

// A file rewritten between two jobs is read again, and the later job draws what it holds now.
TEST(SharedSceneLoads, AFileChangedSinceItsLoadIsReadAgain) {
  test_support::TempFolder folder("shared-loads");
  fs::copy_file(thirdParty("Box/Box.glb"), folder / "scene.glb");
  const RenderJob job = jobOf(folder / "scene.glb");
  SharedSceneLoads loads({job, job, job});
  const Scene box = loads.scene(job);
  fs::copy_file(thirdParty("BoxTextured/BoxTextured.glb"), folder / "scene.glb",
                fs::copy_options::overwrite_existing);
  const Scene textured = loads.scene(job);
  EXPECT_NE(textured.revision, box.revision);
  EXPECT_TRUE(box.images.empty());
  EXPECT_FALSE(textured.images.empty());
}

// A file that cannot be loaded fails every job that names it, each with the loader's message.
TEST(SharedSceneLoads, AFailedLoadFailsEachJob) {
  test_support::TempFolder folder("shared-loads");
  const RenderJob job = jobOf(folder / "missing.glb");
  SharedSceneLoads loads({job, job});
  for (int i = 0; i < 2; ++i) {
    try {
      loads.scene(job);
      ADD_FAILURE() << "job " << i << " loaded a missing file";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("missing.glb"), std::string::npos) << e.what();
    }
  }
}

// At most two scenes stay loaded: with three files taken in turns, the first file's second job
// reads it again; the third's, taken last, still shares.
TEST(SharedSceneLoads, AtMostTwoScenesStayLoaded) {
  const RenderJob a = jobOf(thirdParty("Box/Box.glb"));
  const RenderJob b = jobOf(thirdParty("BoxTextured/BoxTextured.glb"));
  const RenderJob c = jobOf(thirdParty("Duck/Duck.glb"));
  SharedSceneLoads loads({a, b, c, a, b, c});
  const std::uint64_t aFirst = loads.scene(a).revision;
  loads.scene(b);
  const std::uint64_t cFirst = loads.scene(c).revision;
  EXPECT_NE(loads.scene(a).revision, aFirst);
  EXPECT_EQ(loads.scene(c).revision, cFirst);
}

}  // namespace
}  // namespace omnishadow::cli
