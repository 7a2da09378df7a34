// Posing: the animation sampler math (glTF 2.0 Appendix C), skins, morph targets and clips,
// checked against values computed by hand from the keyframes of Khronos sample files
// (scenes/khronos, CC0/CC-BY 4.0, see each folder's LICENSE.md).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <glm/gtc/quaternion.hpp>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "renderer/core/errors.h"
#include "renderer/scene/animation_sampler.h"
#include "renderer/scene/gltf_loader.h"
#include "renderer/scene/scene_pose.h"
#include "tests/support/temp_folder.h"

namespace omnishadow::animation_test {
namespace {

namespace fs = std::filesystem;

constexpr float kEps = 1e-5f;

fs::path khronos(const std::string& name) {
  return fs::path(OMNISHADOW_SOURCE_DIR) / "scenes" / "khronos" / name;
}

Scene posed(const std::string& file, std::optional<double> time, const std::string& clip = "") {
  Scene scene = loadGltf(khronos(file));
  poseScene(scene, {time, clip});
  return scene;
}

const MeshInstance& instanceOf(const Scene& scene, int node) {
  for (const MeshInstance& instance : scene.instances)
    if (instance.node == node) return instance;
  throw std::runtime_error("no instance of node " + std::to_string(node));
}

void expectQuat(const glm::mat4& world, glm::quat expected) {
  const glm::mat3 rotation = glm::mat3_cast(expected);
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r)
      EXPECT_NEAR(world[c][r], rotation[c][r], kEps) << "column " << c << " row " << r;
}

// --- the sampler, on keyframes of InterpolationTest ------------------------------------------

AnimationSampler scalar(Interpolation interpolation, std::vector<float> times,
                        std::vector<float> values) {
  return {std::move(times), std::move(values), 1, interpolation};
}

TEST(AnimationSampler, StepHoldsThePreviousKeyframe) {
  // "Step Scale": 1, 0.5, 1, 0.5, 1 at 0.0417, 0.4167, 0.875, 1.25, 1.6667.
  const AnimationSampler s =
      scalar(Interpolation::Step, {0.0416667f, 0.4166667f, 0.875f, 1.25f, 1.6666666f},
             {1, 0.5f, 1, 0.5f, 1});
  EXPECT_EQ(sampleAnimation(s, 0.5)[0], 0.5f);
  EXPECT_EQ(sampleAnimation(s, 0.875)[0], 1.0f);  // on a keyframe: that keyframe
  EXPECT_EQ(sampleAnimation(s, 1.2)[0], 1.0f);
  EXPECT_EQ(sampleAnimation(s, -3.0)[0], 1.0f);  // before the first: clamped
  EXPECT_EQ(sampleAnimation(s, 99.0)[0], 1.0f);  // after the last: clamped
}

TEST(AnimationSampler, LinearInterpolatesScalars) {
  const AnimationSampler s = scalar(Interpolation::Linear, {0.0f, 1.0f, 3.0f}, {1, 0.5f, 1.5f});
  EXPECT_NEAR(sampleAnimation(s, 0.5)[0], 0.75f, kEps);
  EXPECT_NEAR(sampleAnimation(s, 2.5)[0], 1.25f, kEps);  // s = 0.75 over an interval of 2
  EXPECT_EQ(sampleAnimation(s, 7.0)[0], 1.5f);
}

TEST(AnimationSampler, CubicSplineScalesTangentsByTheInterval) {
  // Two keyframes 2 s apart: value 0 with out-tangent 1, value 1 with in-tangent 0. At s = 0.5
  // the Hermite basis gives 0.5 * 0 + 2 * 0.125 * 1 + 0.5 * 1 + 2 * -0.125 * 0 = 0.75 (it would
  // be 0.625 without the interval factor).
  const AnimationSampler s = scalar(Interpolation::CubicSpline, {1.0f, 3.0f}, {9, 0, 1, 0, 1, 9});
  EXPECT_NEAR(sampleAnimation(s, 2.0)[0], 0.75f, kEps);
  // At s = 0.25: h00 = 0.84375, h10 = 0.140625, h01 = 0.15625: 0.28125 + 0.15625.
  EXPECT_NEAR(sampleAnimation(s, 1.5)[0], 0.4375f, kEps);
  EXPECT_EQ(sampleAnimation(s, 5.0)[0], 1.0f);  // the value, not a tangent
}

TEST(AnimationSampler, QuaternionsTakeTheShorterArc) {
  // Identity to -(0, 0, sin 45°, cos 45°), which is +90° about z written with a negative w: the
  // shorter arc's middle is +45°, (0, 0, sin 22.5°, cos 22.5°).
  AnimationSampler s{
      {0.0f, 1.0f}, {0, 0, 0, 1, 0, 0, -0.70710678f, -0.70710678f}, 4, Interpolation::Linear};
  const std::vector<float> q = sampleAnimation(s, 0.5, true);
  EXPECT_NEAR(q[2] * (q[3] < 0 ? -1 : 1), 0.38268343f, kEps);
  EXPECT_NEAR(std::abs(q[3]), 0.92387953f, kEps);
  EXPECT_NEAR(q[0], 0.0f, kEps);
}

// --- InterpolationTest.glb: each clip drives one node ------------------------------------------

TEST(InterpolationTest, StepScale) {
  // Node 0 "Cube": scale keyframes 1, 0.5, 1, ... at 0.0417, 0.4167, 0.875; t = 0.5 holds 0.5.
  const Scene scene = posed("InterpolationTest/InterpolationTest.glb", 0.5, "Step Scale");
  EXPECT_NEAR(instanceOf(scene, 0).world[0][0], 0.5f, kEps);
  EXPECT_NEAR(instanceOf(scene, 0).world[1][1], 0.5f, kEps);
}

TEST(InterpolationTest, LinearScaleHalfwayBetweenKeyframes) {
  // Node 3: 0.5 at 0.41666666 and 1 at 0.875; halfway is 0.75.
  const double t = (0.4166666567325592 + 0.875) / 2;
  const Scene scene = posed("InterpolationTest/InterpolationTest.glb", t, "Linear Scale");
  EXPECT_NEAR(instanceOf(scene, 3).world[2][2], 0.75f, kEps);
  EXPECT_NEAR(instanceOf(scene, 3).world[3][0], -3.2963297f, kEps);  // its translation stays
}

TEST(InterpolationTest, CubicSplineScaleAtAQuarter) {
  // Node 4: values 0.5 (t 0.41666666) and 1 (t 0.875), tangents 0: at s = 0.25,
  // 0.84375 * 0.5 + 0.15625 * 1 = 0.578125.
  const double t = 0.4166666567325592 + 0.25 * (0.875 - 0.4166666567325592);
  const Scene scene = posed("InterpolationTest/InterpolationTest.glb", t, "CubicSpline Scale");
  EXPECT_NEAR(instanceOf(scene, 4).world[0][0], 0.578125f, kEps);
}

TEST(InterpolationTest, StepRotation) {
  // Node 5: at t = 1.0 the keyframe of 0.875 holds: (0, 0, -0.7071068, 0.7071068).
  const Scene scene = posed("InterpolationTest/InterpolationTest.glb", 1.0, "Step Rotation");
  expectQuat(instanceOf(scene, 5).world, glm::quat(0.7071068f, 0, 0, -0.7071068f));
}

TEST(InterpolationTest, LinearRotationIsSlerp) {
  // Node 7: -45° (t 0.41666666) to -90° (t 0.875) about z; halfway is -67.5°:
  // (0, 0, -sin 33.75°, cos 33.75°). Node 7's scale is 0.99999994.
  const double t = (0.4166666567325592 + 0.875) / 2;
  const Scene scene = posed("InterpolationTest/InterpolationTest.glb", t, "Linear Rotation");
  expectQuat(instanceOf(scene, 7).world, glm::quat(0.83146961f, 0, 0, -0.55557023f));
}

TEST(InterpolationTest, CubicSplineRotationUsesScaledTangents) {
  // Node 6, first interval (0 to 0.41666666 s): v0 = identity with out-tangent b0 = (0,0,0,1),
  // v1 = (0,0,-0.38268346,0.92387956) with in-tangent a1 = (0,0,-0.0478909,0.99885267). At
  // s = 0.5: 0.5 v0 + td 0.125 b0 + 0.5 v1 - td 0.125 a1 = (0, 0, -0.18884741, 0.96199953),
  // normalized (0, 0, -0.1926306, 0.98127134). Without td it would be (.., -0.1891814, ..).
  const Scene scene = posed("InterpolationTest/InterpolationTest.glb", 0.4166666567325592 / 2,
                            "CubicSpline Rotation");
  expectQuat(instanceOf(scene, 6).world, glm::quat(0.98127134f, 0, 0, -0.1926306f));
}

TEST(InterpolationTest, Translations) {
  const fs::path file = "InterpolationTest/InterpolationTest.glb";
  // Node 8, STEP: the keyframe of 0.4583333 holds y = 10 until 0.8333333.
  EXPECT_NEAR(instanceOf(posed(file, 0.8, "Step Translation"), 8).world[3][1], 10.0f, kEps);
  // Node 10, LINEAR: y from 10 (0.41666666) to 6 (0.8333333); halfway is 8.
  const double t = (0.4166666567325592 + 0.8333333134651184) / 2;
  EXPECT_NEAR(instanceOf(posed(file, t, "Linear Translation"), 10).world[3][1], 8.0f, kEps);
  // Node 9, CUBICSPLINE with zero tangents: halfway between 10 and 6 is 8 too.
  EXPECT_NEAR(instanceOf(posed(file, t, "CubicSpline Translation"), 9).world[3][1], 8.0f, kEps);
}

TEST(InterpolationTest, TimesClampToTheClip) {
  const fs::path file = "InterpolationTest/InterpolationTest.glb";
  // Node 10's last keyframe (1.6666666) has y = 6, its first (0) y = 6.621014.
  EXPECT_NEAR(instanceOf(posed(file, 100.0, "8"), 10).world[3][1], 6.0f, kEps);
  EXPECT_NEAR(instanceOf(posed(file, -5.0, "8"), 10).world[3][1], 6.621014f, kEps);
}

TEST(InterpolationTest, WithoutATimeNothingMoves) {
  const Scene rest = loadGltf(khronos("InterpolationTest/InterpolationTest.glb"));
  Scene scene = rest;
  poseScene(scene, {std::nullopt, ""});
  for (std::size_t i = 0; i < rest.instances.size(); ++i)
    EXPECT_EQ(scene.instances[i].world, rest.instances[i].world);
  // Posing at a time and back at rest gives the loader's matrices again.
  poseScene(scene, {1.0, ""});
  EXPECT_NE(instanceOf(scene, 10).world, instanceOf(rest, 10).world);
  poseScene(scene, {std::nullopt, ""});
  for (std::size_t i = 0; i < rest.instances.size(); ++i)
    EXPECT_EQ(scene.instances[i].world, rest.instances[i].world);
  EXPECT_EQ(scene.bounds.min, rest.bounds.min);
  EXPECT_EQ(scene.bounds.max, rest.bounds.max);
}

TEST(InterpolationTest, AllClipsPlayTogether) {
  const Scene scene = posed("InterpolationTest/InterpolationTest.glb", 0.8, "all");
  EXPECT_NEAR(instanceOf(scene, 8).world[3][1], 10.0f, kEps);
  EXPECT_NEAR(instanceOf(scene, 0).world[0][0], 0.5f, kEps);
}

TEST(InterpolationTest, UnknownClipIsAnInputError) {
  Scene scene = loadGltf(khronos("InterpolationTest/InterpolationTest.glb"));
  try {
    poseScene(scene, {1.0, "Walk"});
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("--animation Walk: "), std::string::npos) << message;
    EXPECT_NE(message.find("has no such animation"), std::string::npos) << message;
    EXPECT_NE(message.find("0 \"Step Scale\""), std::string::npos) << message;
  }
  EXPECT_THROW(poseScene(scene, {1.0, "9"}), InputError);
}

// --- SimpleSkin: two joints, node 2 rotated about z ---------------------------------------------

// SimpleSkin has no normals, so the loader un-indexes it (flat normals): vertices are found by
// their rest position. Vertex (-0.5, 2, 0) follows joint 1 (node 2, at y = 1) alone; vertex
// (-0.5, 1, 0) is half joint 0 (node 1, the origin), half joint 1. At rest the joints are where
// the inverse bind matrices expect them: the rest pose is the bind pose.
glm::vec3 skinned(const Scene& rest, const Scene& posedScene, glm::vec3 restPosition) {
  const Mesh& before = rest.meshes[static_cast<std::size_t>(rest.instances[0].mesh)];
  const Mesh& after = posedScene.meshes[static_cast<std::size_t>(posedScene.instances[0].mesh)];
  for (std::size_t i = 0; i < before.positions.size(); ++i)
    if (glm::length(before.positions[i] - restPosition) < kEps) return after.positions[i];
  ADD_FAILURE() << "no vertex at the rest position";
  return glm::vec3(NAN);
}

void expectXY(glm::vec3 p, float x, float y) {
  EXPECT_NEAR(p.x, x, kEps);
  EXPECT_NEAR(p.y, y, kEps);
  EXPECT_NEAR(p.z, 0.0f, kEps);
}

TEST(SimpleSkin, VerticesFollowTheJointsAtTwoTimes) {
  const Scene rest = loadGltf(khronos("SimpleSkin/SimpleSkin.gltf"));
  EXPECT_NEAR(rest.bounds.max.y, 2.0f, kEps);
  // t = 1: node 2 turns +90° about z ((0,0,0.707,0.707) normalized). Relative to the joint at
  // (0, 1): (-0.5, 1) -> (-1, -0.5), so (-0.5, 2) goes to (-1, 0.5); (0.5, 2) to (-1, 1.5);
  // (-0.5, 1) to 0.5 (-0.5, 1) + 0.5 (0, 0.5) = (-0.25, 0.75).
  Scene scene = posed("SimpleSkin/SimpleSkin.gltf", 1.0);
  EXPECT_EQ(scene.instances[0].world, glm::mat4(1.0f));
  expectXY(skinned(rest, scene, {-0.5f, 2.0f, 0.0f}), -1.0f, 0.5f);
  expectXY(skinned(rest, scene, {0.5f, 2.0f, 0.0f}), -1.0f, 1.5f);
  expectXY(skinned(rest, scene, {-0.5f, 1.0f, 0.0f}), -0.25f, 0.75f);
  expectXY(skinned(rest, scene, {-0.5f, 0.0f, 0.0f}), -0.5f, 0.0f);  // joint 0 alone: unmoved
  EXPECT_NEAR(scene.bounds.min.x, -1.0f, kEps);
  // Flat normals follow the posed triangles: the strip stays in the z = 0 plane.
  for (const glm::vec3& n : scene.meshes[0].normals) EXPECT_NEAR(std::abs(n.z), 1.0f, kEps);
  // t = 4: -90°: (-0.5, 1) -> (1, 0.5), so (-0.5, 2) goes to (1, 1.5); (0.5, 2) to (1, 0.5).
  poseScene(scene, {4.0, ""});
  expectXY(skinned(rest, scene, {-0.5f, 2.0f, 0.0f}), 1.0f, 1.5f);
  expectXY(skinned(rest, scene, {0.5f, 2.0f, 0.0f}), 1.0f, 0.5f);
  EXPECT_NEAR(scene.bounds.max.x, 1.0f, kEps);
}

// A renderer takes the meshes of a scene with the revision of its last one as that scene's
// (Scene::revision): every load gives a new revision, a copy keeps it, and a pose that moves
// vertices (a skin) gives a new one while a pose that moves only nodes keeps it.
TEST(SceneRevision, NewForEveryLoadAndEveryDeformingPose) {
  Scene skinnedScene = loadGltf(khronos("SimpleSkin/SimpleSkin.gltf"));
  const Scene again = loadGltf(khronos("SimpleSkin/SimpleSkin.gltf"));
  EXPECT_NE(skinnedScene.revision, 0u);
  EXPECT_NE(again.revision, 0u);
  EXPECT_NE(again.revision, skinnedScene.revision);
  const Scene copy = skinnedScene;
  EXPECT_EQ(copy.revision, skinnedScene.revision);
  poseScene(skinnedScene, {1.0, ""});
  EXPECT_NE(skinnedScene.revision, copy.revision);
  EXPECT_NE(skinnedScene.revision, 0u);

  Scene nodesOnly = loadGltf(khronos("InterpolationTest/InterpolationTest.glb"));
  ASSERT_TRUE(nodesOnly.rig.deformed.empty());
  const std::uint64_t loaded = nodesOnly.revision;
  const std::vector<Mesh> meshes = nodesOnly.meshes;
  poseScene(nodesOnly, {1.5, ""});
  EXPECT_EQ(nodesOnly.revision, loaded);
  ASSERT_EQ(nodesOnly.meshes.size(), meshes.size());
  for (std::size_t i = 0; i < meshes.size(); ++i)
    EXPECT_EQ(nodesOnly.meshes[i].positions, meshes[i].positions) << "mesh " << i;
}

// --- morph targets -----------------------------------------------------------------------------

TEST(MorphPrimitivesTest, DefaultMeshWeightsApply) {
  // mesh.weights [0.5]; the target lifts the plane's vertex (-0.25, 0, 0.25) by 0.2, so the
  // flat plane rises to y = 0.1 there (without a time: default weights apply).
  const Scene scene = loadGltf(khronos("MorphPrimitivesTest/MorphPrimitivesTest.glb"));
  ASSERT_EQ(scene.meshes.size(), 2u);
  EXPECT_NEAR(scene.meshes[0].bounds.max.y, 0.1f, kEps);
  EXPECT_NEAR(scene.meshes[0].bounds.min.y, 0.0f, kEps);
  bool found = false;
  for (const glm::vec3& p : scene.meshes[0].positions)
    if (std::abs(p.x + 0.25f) < kEps && std::abs(p.z - 0.25f) < kEps)
      found = found || std::abs(p.y - 0.1f) < kEps;
  EXPECT_TRUE(found);
}

TEST(AnimatedMorphCube, WeightsFollowTheClip) {
  // Vertex 2 is (0.01, -0.01, 0.01); target 0 moves it by 0.018932531 in y, target 1 not.
  const auto y = [](double t) {
    const Scene scene = posed("AnimatedMorphCube/AnimatedMorphCube.glb", t);
    return scene.meshes[static_cast<std::size_t>(scene.instances[0].mesh)].positions[2].y;
  };
  const float base = -0.009999997913837433f, delta = 0.018932530656456947f;
  EXPECT_NEAR(y(0.0), base, kEps);
  // Keyframe 24 (t 0.80000025): weights (0.50000024, 0).
  EXPECT_NEAR(y(0.8000002503395081), base + 0.50000024f * delta, 1e-6f);
  // Halfway between keyframes 60 and 61: w0 = (0.80555612 + 0.77859002) / 2.
  EXPECT_NEAR(y((1.9999994039535522 + 2.0333328247070312) / 2), base + 0.79207307f * delta, 1e-6f);
}

// --- clips that animate the same property -----------------------------------------------------

TEST(ClipConflicts, LowestIndexWinsAndOneWarningNamesTheOthers) {
  // Node 1, child of node 0, places a camera and a light; "Survey" and "Walk" both move it, "Run"
  // too, "Wave" moves node 1.
  Scene scene;
  scene.path = "fox.gltf";
  scene.rig.nodes.resize(2);
  scene.rig.nodes[1].parent = 0;
  Camera camera;
  camera.node = 1;
  scene.cameras.push_back(camera);
  scene.lights.push_back(Light{});  // a KHR_lights_punctual light on node 1 too
  scene.rig.lightNodes = {1};
  const auto clip = [](const char* name, int node, float x) {
    Animation a;
    a.name = name;
    a.samplers.push_back({{0.0f, 1.0f}, {x, 0, 0, x, 0, 0}, 3, Interpolation::Linear});
    a.channels.push_back({node, AnimatedProperty::Translation, 0});
    a.end = 1.0f;
    return a;
  };
  scene.rig.animations = {clip("Survey", 0, 1.0f), clip("Walk", 0, 2.0f), clip("Run", 0, 3.0f),
                          clip("Wave", 1, 0.5f)};
  const std::vector<std::string> warnings = poseScene(scene, {0.5, "all"});
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0],
            "fox.gltf: animation 0 \"Survey\" drives node properties that animations 1 \"Walk\", "
            "2 \"Run\" also animate (no blending: the lowest index wins; pick one with "
            "--animation)");
  EXPECT_NEAR(scene.cameras[0].world[3].x, 1.5f, kEps);  // Survey's 1 plus Wave's 0.5
  EXPECT_NEAR(scene.lights[0].position.x, 1.5f, kEps);
  EXPECT_TRUE(poseScene(scene, {0.5, "Run"}).empty());
  EXPECT_NEAR(scene.cameras[0].world[3].x, 3.0f, kEps);  // Run alone; Wave does not play
}

// --- KHR_animation_pointer ----------------------------------------------------------------------

using Json = nlohmann::json;

// `source` (a .glb) written to `target` with its JSON chunk changed by `edit`.
void rewriteGlb(const fs::path& source, const fs::path& target,
                const std::function<void(Json&)>& edit) {
  std::ifstream in(source, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto le32 = [&](std::size_t at) {
    std::uint32_t v = 0;
    std::memcpy(&v, bytes.data() + at, 4);
    return v;
  };
  const std::uint32_t jsonLength = le32(12);
  Json gltf = Json::parse(bytes.substr(20, jsonLength));
  edit(gltf);
  std::string json = gltf.dump();
  while (json.size() % 4) json += ' ';
  const std::string rest = bytes.substr(20 + jsonLength);  // the BIN chunk, as it was
  std::string out = bytes.substr(0, 12);
  const auto put32 = [&](std::uint32_t v) { out.append(reinterpret_cast<const char*>(&v), 4); };
  put32(static_cast<std::uint32_t>(json.size()));
  put32(0x4E4F534Au);  // "JSON"
  out += json + rest;
  const std::uint32_t total = static_cast<std::uint32_t>(out.size());
  std::memcpy(out.data() + 8, &total, 4);
  std::ofstream(target, std::ios::binary) << out;
}

// Every core channel written as the KHR_animation_pointer channel that names the same property.
void coreToPointers(Json& gltf) {
  for (Json& animation : gltf["animations"])
    for (Json& channel : animation["channels"]) {
      Json& target = channel["target"];
      const std::string pointer = "/nodes/" + std::to_string(target["node"].get<int>()) + "/" +
                                  target["path"].get<std::string>();
      target = {{"path", "pointer"},
                {"extensions", {{"KHR_animation_pointer", {{"pointer", pointer}}}}}};
    }
  gltf["extensionsUsed"].push_back("KHR_animation_pointer");
}

// Every KHR_animation_pointer channel (all of a node's TRS) written as the core channel.
void pointersToCore(Json& gltf) {
  for (Json& animation : gltf["animations"])
    for (Json& channel : animation["channels"]) {
      Json& target = channel["target"];
      const std::string pointer = target["extensions"]["KHR_animation_pointer"]["pointer"];
      const std::size_t slash = pointer.find('/', 7);  // after "/nodes/"
      target = {{"node", std::stoi(pointer.substr(7, slash - 7))},
                {"path", pointer.substr(slash + 1)}};
    }
}

// The posed instances' world matrices and vertex positions of `scene` at `time` (all clips).
struct Pose {
  std::vector<glm::mat4> worlds;
  std::vector<glm::vec3> positions;
};
Pose poseAt(Scene scene, std::optional<double> time, const std::string& clips = "") {
  poseScene(scene, {time, clips});
  Pose pose;
  for (const MeshInstance& instance : scene.instances) pose.worlds.push_back(instance.world);
  for (const Mesh& mesh : scene.meshes)
    pose.positions.insert(pose.positions.end(), mesh.positions.begin(), mesh.positions.end());
  return pose;
}

// A pointer to a node's translation, rotation, scale or morph weights plays exactly as the core
// channel it spells: InterpolationTest (every interpolation of every TRS property) and
// AnimatedMorphCube (weights), rewritten with pointers, pose to the same bits at every time.
TEST(AnimationPointer, NodeChannelsPoseAsTheCoreChannelsTheySpell) {
  test_support::TempFolder folder("omnishadow-animation-pointer");
  for (const char* name :
       {"InterpolationTest/InterpolationTest.glb", "AnimatedMorphCube/AnimatedMorphCube.glb"}) {
    const fs::path pointers = folder / "pointers.glb";
    rewriteGlb(khronos(name), pointers, coreToPointers);
    const Scene core = loadGltf(khronos(name));
    const Scene rewritten = loadGltf(pointers);
    EXPECT_TRUE(rewritten.warnings.empty()) << rewritten.warnings.front();
    ASSERT_EQ(rewritten.rig.animations.size(), core.rig.animations.size());
    for (std::size_t a = 0; a < core.rig.animations.size(); ++a)
      EXPECT_EQ(rewritten.rig.animations[a].channels.size(),
                core.rig.animations[a].channels.size());
    for (const double time : {0.0, 0.3, 0.9, 1.7, 3.5}) {
      const Pose expected = poseAt(core, time), got = poseAt(rewritten, time);
      EXPECT_EQ(got.worlds, expected.worlds) << name << " at " << time;
      EXPECT_EQ(got.positions, expected.positions) << name << " at " << time;
    }
  }
}

// Real data: WhackAMole's 21 clips are all KHR_animation_pointer channels of its nodes' TRS.
// They play, as the same file with core channels does, and move the moles.
TEST(AnimationPointer, WhackAMoleClipsPlayAsTheirCoreTwin) {
  test_support::TempFolder folder("omnishadow-animation-pointer-whackamole");
  const fs::path file =
      fs::path(OMNISHADOW_SOURCE_DIR) / "scenes/thirdparty/WhackAMole/WhackAMole.glb";
  const fs::path core = folder / "core.glb";
  rewriteGlb(file, core, pointersToCore);
  const Scene pointers = loadGltf(file), twin = loadGltf(core);
  ASSERT_EQ(pointers.rig.animations.size(), 21u);
  std::size_t channels = 0;
  for (const Animation& a : pointers.rig.animations) channels += a.channels.size();
  EXPECT_EQ(channels, 91u);
  const Pose rest = poseAt(pointers, std::nullopt);
  for (const char* clip : {"0", "1", "2", "20"})
    for (const double time : {0.25, 0.8}) {
      const Pose got = poseAt(pointers, time, clip);
      EXPECT_EQ(got.worlds, poseAt(twin, time, clip).worlds) << clip << " at " << time;
      EXPECT_NE(got.worlds, rest.worlds) << clip << " at " << time;
    }
}

// Pointers to other properties (a material's color, a light's intensity) are named in one
// warning per animation and do not play; a malformed pointer is an input error naming it.
TEST(AnimationPointer, OtherPropertiesWarnAndMalformedPointersAreInputErrors) {
  test_support::TempFolder folder("omnishadow-animation-pointer-errors");
  const fs::path file = folder / "pointers.glb";
  const fs::path source = khronos("InterpolationTest/InterpolationTest.glb");
  const auto pointerOf = [](Json& gltf, int animation, int channel) -> Json& {
    return gltf["animations"][animation]["channels"][channel]["target"]["extensions"]
               ["KHR_animation_pointer"]["pointer"];
  };
  rewriteGlb(source, file, [&](Json& gltf) {
    coreToPointers(gltf);
    pointerOf(gltf, 0, 0) = "/materials/0/pbrMetallicRoughness/baseColorFactor";
  });
  const Scene scene = loadGltf(file);
  ASSERT_EQ(scene.warnings.size(), 1u);
  EXPECT_EQ(scene.warnings[0],
            file.string() +
                ": animations[0]: KHR_animation_pointer channels of other properties than a "
                "node's translation, rotation, scale or weights are not played: 1 (the first: "
                "\"/materials/0/pbrMetallicRoughness/baseColorFactor\")");
  EXPECT_TRUE(scene.rig.animations[0].channels.empty());

  const std::pair<Json, std::string> bad[] = {
      {Json(3),
       "animations[0].channels[0].target.extensions.KHR_animation_pointer: pointer must "
       "be a string"},
      {Json("/nodes/99/rotation"),
       "animations[0].channels[0].target: node 99 is out of range (the file has 12 nodes)"}};
  for (const auto& [pointer, message] : bad) {
    rewriteGlb(source, file, [&](Json& gltf) {
      coreToPointers(gltf);
      pointerOf(gltf, 0, 0) = pointer;
    });
    try {
      loadGltf(file);
      ADD_FAILURE() << "no InputError for " << pointer;
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()), file.string() + ": " + message);
    }
  }
}

}  // namespace
}  // namespace omnishadow::animation_test
