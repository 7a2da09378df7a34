// `--time`, `--animation` and `info` on animated files, end to end: the skinned caster's shadow
// follows the pose and agrees with the exact reference (`omnishadow verify`).
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfStandardAttributes.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "renderer/output/image_writer.h"
#include "tests/support/base64.h"
#include "tests/support/run_binary.h"
#include "tests/support/temp_folder.h"

namespace omnishadow::motion_cli_test {
namespace {

namespace fs = std::filesystem;
using test_support::base64;
using test_support::filesIn;
using test_support::runOmnishadow;
using test_support::RunOptions;
using test_support::RunResult;
using test_support::TempFolder;

fs::path khronos(const std::string& name) {
  return fs::path(OMNISHADOW_SOURCE_DIR) / "scenes" / "khronos" / name;
}

class MotionCli : public ::testing::Test {
 protected:
  RunResult run(const std::vector<std::string>& args) {
    return runOmnishadow(args, RunOptions::in(folder_.path()));
  }

  // SimpleSkin (a strip in the z = 0 plane whose upper half bends about (0, 1) over time) in
  // front of a wall at z = -1, lit from the front: the strip's shadow lies on the wall.
  fs::path skinBeforeWall() {
    for (const char* bin :
         {"inverseBindMatrices.bin", "skinAnimation.bin", "skinGeometry.bin", "skinningData.bin"})
      fs::copy_file(khronos("SimpleSkin") / bin, folder_ / bin);
    std::ifstream in(khronos("SimpleSkin/SimpleSkin.gltf"));
    nlohmann::json gltf = nlohmann::json::parse(in);
    // The wall: 4 float3 positions then 6 u16 indices, base64 below.
    const std::vector<float> wall = {-3, -1, -1, 3, -1, -1, 3, 4, -1, -3, 4, -1};
    const std::vector<std::uint16_t> indices = {0, 1, 2, 0, 2, 3};
    std::string bytes(reinterpret_cast<const char*>(wall.data()), wall.size() * 4);
    bytes.append(reinterpret_cast<const char*>(indices.data()), indices.size() * 2);
    gltf["buffers"].push_back({{"byteLength", bytes.size()},
                               {"uri", "data:application/octet-stream;base64," + base64(bytes)}});
    const int buffer = static_cast<int>(gltf["buffers"].size()) - 1;
    const int views = static_cast<int>(gltf["bufferViews"].size());
    gltf["bufferViews"].push_back({{"buffer", buffer}, {"byteOffset", 0}, {"byteLength", 48}});
    gltf["bufferViews"].push_back({{"buffer", buffer}, {"byteOffset", 48}, {"byteLength", 12}});
    const int accessors = static_cast<int>(gltf["accessors"].size());
    gltf["accessors"].push_back({{"bufferView", views},
                                 {"componentType", 5126},
                                 {"count", 4},
                                 {"type", "VEC3"},
                                 {"min", {-3, -1, -1}},
                                 {"max", {3, 4, -1}}});
    gltf["accessors"].push_back(
        {{"bufferView", views + 1}, {"componentType", 5123}, {"count", 6}, {"type", "SCALAR"}});
    gltf["meshes"].push_back(
        {{"primitives",
          {{{"attributes", {{"POSITION", accessors}}}, {"indices", accessors + 1}}}}});
    gltf["nodes"].push_back({{"mesh", static_cast<int>(gltf["meshes"].size()) - 1}});
    gltf["scenes"][0]["nodes"].push_back(static_cast<int>(gltf["nodes"].size()) - 1);
    std::ofstream(folder_ / "skin_wall.gltf") << gltf.dump();
    std::ofstream(folder_ / "skin_wall.lights.json")
        << R"({"lights": [{"name": "lamp", "position": [0, 1, 3], "intensity": 20,
                "shadow": {"resolution": 1024}}]})";
    return folder_ / "skin_wall.gltf";
  }

  // Shadowed wall pixels (visibility below 0.5 where P.z is the wall's -1) left and right of
  // x = 0, by their world position: what the camera sees of the shadow, wherever it lands in
  // the image.
  static std::pair<int, int> shadowLeftRight(const FloatImage& aov) {
    const int v = aov.channelIndex("visibility.lamp");
    const int px = aov.channelIndex("P.X"), pz = aov.channelIndex("P.Z");
    const int a = aov.channelIndex("A");
    EXPECT_GE(std::min({v, px, pz, a}), 0);
    int left = 0, right = 0;
    for (int y = 0; y < aov.height; ++y)
      for (int x = 0; x < aov.width; ++x)
        if (aov.at(x, y, a) > 0.5f && aov.at(x, y, pz) < -0.99f && aov.at(x, y, v) < 0.5f)
          (aov.at(x, y, px) < 0.0f ? left : right)++;
    return {left, right};
  }

  TempFolder folder_{"omnishadow-motion"};
};

// From above the lamp, so that the strip hides little of its shadow.
const std::vector<std::string> kView = {"--eye",   "0,4,5", "--target", "0,1,-1",
                                        "--width", "96",    "--height", "96"};

TEST_F(MotionCli, SkinnedCastersShadowFollowsThePoseAndAgreesWithTheRays) {
  const fs::path scene = skinBeforeWall();
  std::vector<std::pair<int, int>> shadows;
  for (const char* time : {"0", "1", "4"}) {
    std::vector<std::string> args = {"render", scene.string(), "--time",
                                     time,     "--aov",        std::string("aov_") + time + ".exr"};
    args.insert(args.end(), kView.begin(), kView.end());
    const RunResult render = run(args);
    ASSERT_EQ(render.status, 0) << render.err;
    shadows.push_back(shadowLeftRight(readImage(folder_ / (std::string("aov_") + time + ".exr"))));
    args = {"verify", scene.string(), "--time", time, "--json", "--max-error", "0.01"};
    args.insert(args.end(), kView.begin(), kView.end());
    const RunResult verify = run(args);
    EXPECT_EQ(verify.status, 0) << verify.out << verify.err;
    EXPECT_TRUE(nlohmann::json::parse(verify.out)["pass"].get<bool>()) << verify.out;
  }
  // At rest (t = 0) the strip stands upright: its shadow is symmetric. At t = 1 the upper half
  // bends to -x, at t = 4 to +x, and the shadow with it.
  const auto [left0, right0] = shadows[0];
  EXPECT_GT(left0 + right0, 200);
  EXPECT_NEAR(left0, right0, (left0 + right0) / 10);
  EXPECT_GT(shadows[1].first, shadows[1].second * 2)
      << shadows[1].first << " " << shadows[1].second;
  EXPECT_GT(shadows[2].second, shadows[2].first * 2)
      << shadows[2].first << " " << shadows[2].second;
}

TEST_F(MotionCli, AnimationOptionsAreCheckedBeforeAnythingIsWritten) {
  const std::string scene = khronos("InterpolationTest/InterpolationTest.glb").string();
  RunResult r = run({"render", scene, "--animation", "1", "-o", "a.png"});
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.err, "omnishadow: --animation 1: needs --time SECONDS\n");
  r = run({"render", scene, "--time", "1", "--animation", "Walk", "-o", "a.png"});
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--animation Walk: " + scene +
                       " has no such animation (animations: 0 "
                       "\"Step Scale\", 1 \"Linear Scale\""),
            std::string::npos)
      << r.err;
  EXPECT_TRUE(filesIn(folder_.path()).empty());
  r = run({"render", scene, "--time", "nan", "-o", "a.png"});
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_TRUE(filesIn(folder_.path()).empty());
}

TEST_F(MotionCli, TimeOnAFileWithoutAnimationsWarns) {
  const RunResult r =
      run({"render", khronos("MorphPrimitivesTest/MorphPrimitivesTest.glb").string(), "--time", "1",
           "--width", "32", "--height", "32", "-o", "a.png"});
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("has no animations; --time changes nothing"), std::string::npos) << r.err;
}

TEST_F(MotionCli, InfoListsAnimationsSkinsAndMorphTargets) {
  RunResult r = run({"info", khronos("RiggedSimple/RiggedSimple.glb").string(), "--json"});
  ASSERT_EQ(r.status, 0) << r.err;
  nlohmann::json doc = nlohmann::json::parse(r.out);
  ASSERT_EQ(doc["animations"].size(), 1u);
  EXPECT_EQ(doc["animations"][0]["channels"], 3);
  EXPECT_GT(doc["animations"][0]["duration"].get<double>(), 0.0);
  ASSERT_EQ(doc["skins"].size(), 1u);
  EXPECT_EQ(doc["skins"][0]["joints"], 2);
  EXPECT_TRUE(doc["morphTargets"].empty());

  r = run({"info", khronos("AnimatedMorphCube/AnimatedMorphCube.glb").string()});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(
      r.out.find("animations  1\n  0  \"Square\"  1 channels (1 weights)  0 s to 4.1999974 s  "
                 "duration 4.1999974 s\n"),
      std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("morph       1 meshes with targets\n  mesh 0  \"Cube\"  2 targets  "
                       "weights [0, 0]\n"),
            std::string::npos)
      << r.out;
}

TEST_F(MotionCli, SequenceWritesNumberedFilesWithTheirCameraSidecars) {
  const std::string scene = khronos("AnimatedMorphCube/AnimatedMorphCube.glb").string();
  const RunResult r = run({"render", scene, "--times", "0,1.5,3", "--width", "32", "--height", "32",
                           "-o", "f/m_##.png", "--aov", "f/a_##.exr", "--camera-json"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("wrote 3 frames (32x32): f/m_00.png ... f/m_02.png"), std::string::npos)
      << r.out;
  EXPECT_EQ(
      filesIn(folder_ / "f"),
      (std::vector<std::string>{"a_00.exr", "a_01.exr", "a_02.exr", "m_00.camera.json", "m_00.png",
                                "m_01.camera.json", "m_01.png", "m_02.camera.json", "m_02.png"}));
  const nlohmann::json sidecar =
      nlohmann::json::parse(test_support::readFile(folder_ / "f/m_01.camera.json"));
  EXPECT_EQ(sidecar["time"], 1.5);
  EXPECT_EQ(sidecar["width"], 32);
  // The cube's morph weights change between the frames, and so do the images.
  EXPECT_NE(test_support::readFile(folder_ / "f/a_00.exr"),
            test_support::readFile(folder_ / "f/a_01.exr"));
}

TEST_F(MotionCli, SequenceOutputsNeedAFrameNumberPattern) {
  const std::string scene = khronos("AnimatedMorphCube/AnimatedMorphCube.glb").string();
  RunResult r = run({"render", scene, "--time-range", "0:1", "-o", "m.png"});
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("-o m.png: a sequence or camera set writes one file per frame; put ####"),
            std::string::npos)
      << r.err;
  r = run({"render", scene, "--time-range", "2:1", "-o", "m_#.png"});
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--time-range 2:1: END is before START"), std::string::npos) << r.err;
  r = run({"render", scene, "--orbit", "3", "--times", "1,2", "-o", "m_#.png"});
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_TRUE(filesIn(folder_.path()).empty());
}

TEST_F(MotionCli, OrbitViewsAreNumberedAndTheSidecarReprojectsEachPixel) {
  const std::string scene = khronos("MorphPrimitivesTest/MorphPrimitivesTest.glb").string();
  const RunResult r = run({"render", scene, "--orbit", "3", "--width", "48", "--height", "32",
                           "--aov", "o_#.exr", "--camera-json"});
  ASSERT_EQ(r.status, 0) << r.err;
  for (int k = 0; k < 3; ++k) {
    const std::string n = std::to_string(k);
    const FloatImage aov = readImage(folder_ / ("o_" + n + ".exr"));
    const nlohmann::json camera =
        nlohmann::json::parse(test_support::readFile(folder_ / ("o_" + n + ".camera.json")));
    const nlohmann::json& m = camera["opencv"]["worldToCamera"];
    const nlohmann::json& k3 = camera["intrinsics"];
    const Imf::InputFile exr((folder_ / ("o_" + n + ".exr")).c_str());
    ASSERT_TRUE(Imf::hasWorldToNDC(exr.header()));
    ASSERT_TRUE(Imf::hasWorldToCamera(exr.header()));
    const Imath::M44f worldToNdc = Imf::worldToNDC(exr.header());
    const Imath::M44f worldToCamera = Imf::worldToCamera(exr.header());
    const int a = aov.channelIndex("A"), px = aov.channelIndex("P.X");
    int checked = 0;
    for (int y = 0; y < aov.height; ++y)
      for (int x = 0; x < aov.width; ++x) {
        if (aov.at(x, y, a) < 1.0f) continue;
        // The surface point drawn at this pixel's center, back through the sidecar's K [R|t].
        const double p[4] = {aov.at(x, y, px), aov.at(x, y, px + 1), aov.at(x, y, px + 2), 1.0};
        double c[3] = {0, 0, 0};
        for (int row = 0; row < 3; ++row)
          for (int col = 0; col < 4; ++col) c[row] += m[row][col].get<double>() * p[col];
        ASSERT_GT(c[2], 0.0);
        const double u = k3["fx"].get<double>() * c[0] / c[2] + k3["cx"].get<double>();
        const double v = k3["fy"].get<double>() * c[1] / c[2] + k3["cy"].get<double>();
        EXPECT_NEAR(u, x + 0.5, 0.02) << "view " << k << " pixel " << x << "," << y;
        EXPECT_NEAR(v, y + 0.5, 0.02) << "view " << k << " pixel " << x << "," << y;
        // The EXR header's worldToNDC (Imath: row vectors) says the same; worldToCamera puts
        // the point in front (+z).
        const Imath::V3f point(p[0], p[1], p[2]);
        Imath::V3f ndc, inCamera;
        worldToNdc.multVecMatrix(point, ndc);
        worldToCamera.multVecMatrix(point, inCamera);
        EXPECT_NEAR((ndc.x + 1) * 0.5 * aov.width, x + 0.5, 0.02);
        EXPECT_NEAR((1 - ndc.y) * 0.5 * aov.height, y + 0.5, 0.02);
        EXPECT_GT(inCamera.z, 0.0f);
        ++checked;
      }
    EXPECT_GT(checked, 50) << "view " << k;
  }
}

TEST_F(MotionCli, BatchManifestJobsTakeATimeOrATimeRange) {
  const std::string scene = khronos("AnimatedMorphCube/AnimatedMorphCube.glb").string();
  std::ofstream(folder_ / "m.json") << R"({"jobs": [
      {"scene": ")" + scene + R"(", "time": "0:1", "fps": 2, "width": 16, "height": 16,
       "outputs": ["cube_##.png"]},
      {"scene": ")" + scene + R"(", "time": 1, "width": 16, "height": 16,
       "outputs": ["one.png"]}]})";
  RunResult r = run({"batch", "m.json", "--out", "out", "-q"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(filesIn(folder_ / "out"),
            (std::vector<std::string>{"cube_00.png", "cube_01.png", "cube_02.png", "one.png"}));
  // Frame 2 of the range is t = 1: the same pose as the single job.
  EXPECT_EQ(test_support::readFile(folder_ / "out/cube_02.png"),
            test_support::readFile(folder_ / "out/one.png"));
  std::ofstream(folder_ / "bad.json")
      << R"({"jobs": [{"scene": ")" + scene + R"(", "time": "0:1", "outputs": ["c.png"]}]})";
  r = run({"batch", "bad.json", "--out", "out2"});
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("bad.json: jobs[0].outputs: c.png: a time range writes one file per "
                       "frame"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(folder_ / "out2"));
}

}  // namespace
}  // namespace omnishadow::motion_cli_test
