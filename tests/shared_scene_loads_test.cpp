// A batch's jobs of one file share one load (cli/shared_scene_loads.h): a later job takes the
// scene the first loaded, unless a file it read has changed or the scene was let go; then, and
// for a file no other job loads alike, it loads its own (a null scene).
#include "cli/shared_scene_loads.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "renderer/core/errors.h"
#include "tests/support/temp_folder.h"

namespace omnishadow::cli::shared_scene_loads_test {
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
  const std::shared_ptr<const Scene> first = loads.scene(job);
  ASSERT_NE(first, nullptr);
  EXPECT_NE(first->revision, 0u);
  EXPECT_EQ(first->meshes.size(), 1u);
  EXPECT_EQ(loads.scene(sameFileOtherSpelling), first);  // the same scene, not a copy
  EXPECT_EQ(loads.scene(job), first);
  // Past its jobs the scene is let go: one job more loads its own.
  EXPECT_EQ(loads.scene(job), nullptr);
}

// Jobs share the scene at rest; one posed at a time poses a copy and leaves the shared one be.
TEST(SharedSceneLoads, AJobPosedAtATimeLeavesTheSharedSceneAtRest) {
  RenderJob atRest = jobOf(fs::path(OMNISHADOW_SOURCE_DIR) / "scenes" / "khronos" / "RiggedSimple" /
                           "RiggedSimple.glb");
  RenderJob posed = atRest;
  posed.time = 0.5;
  SharedSceneLoads loads({atRest, posed, atRest});
  const LoadedJob first = loadJobTimed(atRest, &loads).job;
  const LoadedJob second = loadJobTimed(posed, &loads).job;
  const LoadedJob third = loadJobTimed(atRest, &loads).job;
  ASSERT_NE(first.shared, nullptr);
  EXPECT_FALSE(first.own.has_value());
  EXPECT_EQ(third.shared, first.shared);
  EXPECT_FALSE(third.own.has_value());
  ASSERT_TRUE(second.own.has_value());
  const LoadedJob alone = loadJob(posed);  // what the posed job draws when it loads alone
  ASSERT_EQ(second.scene().meshes.size(), alone.scene().meshes.size());
  bool moved = false;
  for (std::size_t m = 0; m < alone.scene().meshes.size(); ++m) {
    EXPECT_EQ(second.scene().meshes[m].positions, alone.scene().meshes[m].positions);
    moved = moved || second.scene().meshes[m].positions != first.scene().meshes[m].positions;
  }
  EXPECT_TRUE(moved) << "the pose at 0.5 s moves no vertex: choose another time";
  const LoadedJob restAlone = loadJob(atRest);
  for (std::size_t m = 0; m < restAlone.scene().meshes.size(); ++m)
    EXPECT_EQ(third.scene().meshes[m].positions, restAlone.scene().meshes[m].positions);
}

// Files of their own that hold the same image bytes (a model as glTF-Binary and as a copy)
// decode the picture once while a scene holds it: the batch's loads share a DecodedImageCache.
TEST(SharedSceneLoads, FilesOfTheirOwnShareThePicturesOfTheSameImageBytes) {
  test_support::TempFolder folder("shared-loads");
  fs::copy_file(thirdParty("BoxTextured/BoxTextured.glb"), folder / "a.glb");
  fs::copy_file(thirdParty("BoxTextured/BoxTextured.glb"), folder / "b.glb");
  const RenderJob a = jobOf(folder / "a.glb");
  const RenderJob b = jobOf(folder / "b.glb");
  SharedSceneLoads loads({a, b});
  const LoadedJob first = loadJobTimed(a, &loads).job;
  const LoadedJob second = loadJobTimed(b, &loads).job;
  ASSERT_TRUE(first.own && second.own);  // files of their own: no shared scene
  ASSERT_EQ(first.scene().images.size(), 1u);
  EXPECT_TRUE(second.scene().images[0].rgba.sharesWith(first.scene().images[0].rgba));
  EXPECT_EQ(second.scene().images[0].rgba, loadJob(b).scene().images[0].rgba);
  EXPECT_FALSE(loadJob(b).scene().images[0].rgba.sharesWith(first.scene().images[0].rgba))
      << "a load outside the batch decodes its own";
}

TEST(SharedSceneLoads, AJobOfItsOwnAndOtherOptionsLoadTheirOwn) {
  const RenderJob box = jobOf(thirdParty("Box/Box.glb"));
  RenderJob otherScene = box;
  otherScene.sceneIndex = 0;  // another load option: another load
  SharedSceneLoads loads({box, otherScene});
  EXPECT_EQ(loads.scene(box), nullptr);
  EXPECT_EQ(loads.scene(otherScene), nullptr);
}

// A file rewritten between two jobs is read again, and the later job draws what it holds now.
TEST(SharedSceneLoads, AFileChangedSinceItsLoadIsReadAgain) {
  test_support::TempFolder folder("shared-loads");
  fs::copy_file(thirdParty("Box/Box.glb"), folder / "scene.glb");
  const RenderJob job = jobOf(folder / "scene.glb");
  SharedSceneLoads loads({job, job, job});
  const LoadedJob box = loadJobTimed(job, &loads).job;
  ASSERT_NE(box.shared, nullptr);
  fs::copy_file(thirdParty("BoxTextured/BoxTextured.glb"), folder / "scene.glb",
                fs::copy_options::overwrite_existing);
  const LoadedJob textured = loadJobTimed(job, &loads).job;
  EXPECT_EQ(textured.shared, nullptr);
  EXPECT_TRUE(box.scene().images.empty());
  EXPECT_FALSE(textured.scene().images.empty());
}

// A file that cannot be loaded fails every job that names it, each with the loader's message.
TEST(SharedSceneLoads, AFailedLoadFailsEachJob) {
  test_support::TempFolder folder("shared-loads");
  const RenderJob job = jobOf(folder / "missing.glb");
  SharedSceneLoads loads({job, job});
  for (int i = 0; i < 2; ++i) {
    try {
      loadJobTimed(job, &loads);
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
  const std::shared_ptr<const Scene> aFirst = loads.scene(a);
  ASSERT_NE(aFirst, nullptr);
  ASSERT_NE(loads.scene(b), nullptr);
  const std::shared_ptr<const Scene> cFirst = loads.scene(c);
  ASSERT_NE(cFirst, nullptr);
  const std::shared_ptr<const Scene> aAgain = loads.scene(a);
  ASSERT_NE(aAgain, nullptr);
  EXPECT_NE(aAgain, aFirst);  // loaded again
  EXPECT_NE(aAgain->revision, aFirst->revision);
  EXPECT_EQ(loads.scene(c), cFirst);
}

}  // namespace
}  // namespace omnishadow::cli::shared_scene_loads_test
