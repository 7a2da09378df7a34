#include "renderer/scene/scene_pose.h"

#include <algorithm>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <map>
#include <utility>

#include "renderer/core/errors.h"
#include "renderer/scene/mesh_deform.h"

namespace omnishadow {
namespace {

struct NodePose {
  glm::vec3 translation;
  glm::quat rotation;
  glm::vec3 scale;
  std::vector<float> weights;
};

// The same arithmetic as the loader's, so that an unanimated pose reproduces its matrices.
glm::mat4 localMatrix(const RigNode& node, const NodePose& pose) {
  if (node.hasMatrix) return node.matrix;
  glm::mat4 m = glm::translate(glm::mat4(1.0f), pose.translation);
  if (glm::length(pose.rotation) > 0.0f) m *= glm::mat4_cast(glm::normalize(pose.rotation));
  return glm::scale(m, pose.scale);
}

// World matrices of every node, parents first; a parent chain longer than the node count (a
// cycle among nodes the scene does not draw) is cut.
std::vector<glm::mat4> worldMatrices(const SceneRig& rig, const std::vector<NodePose>& poses) {
  const std::size_t count = rig.nodes.size();
  std::vector<glm::mat4> world(count);
  std::vector<char> done(count, 0);
  std::vector<std::size_t> chain;
  for (std::size_t start = 0; start < count; ++start) {
    chain.clear();
    for (std::size_t node = start; !done[node] && chain.size() <= count;) {
      chain.push_back(node);
      const int parent = rig.nodes[node].parent;
      if (parent < 0) break;
      node = static_cast<std::size_t>(parent);
    }
    for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
      if (done[*it]) continue;
      const int parent = rig.nodes[*it].parent;
      const glm::mat4 local = localMatrix(rig.nodes[*it], poses[*it]);
      world[*it] = parent >= 0 && done[static_cast<std::size_t>(parent)]
                       ? world[static_cast<std::size_t>(parent)] * local
                       : local;
      done[*it] = 1;
    }
  }
  return world;
}

// Applies the chosen clips at `time`; returns the warning about clips that were overruled.
std::string animate(const SceneRig& rig, const std::vector<int>& clips, double time,
                    std::vector<NodePose>& poses) {
  std::map<std::pair<int, AnimatedProperty>, int> driver;  // (node, property) -> clip
  std::map<int, std::vector<int>> overruled;               // clip -> clips it overruled
  for (int clip : clips) {
    const Animation& animation = rig.animations[static_cast<std::size_t>(clip)];
    const double t =
        std::clamp(time, static_cast<double>(animation.start), static_cast<double>(animation.end));
    for (const AnimationChannel& channel : animation.channels) {
      const auto [it, first] = driver.try_emplace({channel.node, channel.property}, clip);
      if (!first) {
        if (it->second != clip) {
          std::vector<int>& list = overruled[it->second];
          if (std::find(list.begin(), list.end(), clip) == list.end()) list.push_back(clip);
        }
        if (it->second != clip) continue;
      }
      const AnimationSampler& sampler =
          animation.samplers[static_cast<std::size_t>(channel.sampler)];
      const std::vector<float> v =
          sampleAnimation(sampler, t, channel.property == AnimatedProperty::Rotation);
      NodePose& pose = poses[static_cast<std::size_t>(channel.node)];
      switch (channel.property) {
        case AnimatedProperty::Translation:
          pose.translation = glm::vec3(v[0], v[1], v[2]);
          break;
        case AnimatedProperty::Rotation:
          pose.rotation = glm::quat(v[3], v[0], v[1], v[2]);
          break;
        case AnimatedProperty::Scale:
          pose.scale = glm::vec3(v[0], v[1], v[2]);
          break;
        case AnimatedProperty::Weights:
          pose.weights = v;
          break;
      }
    }
  }
  std::string warning;
  for (const auto& [winner, losers] : overruled) {
    const std::string& name = rig.animations[static_cast<std::size_t>(winner)].name;
    std::string names;
    for (int loser : losers)
      names += (names.empty() ? "" : ", ") + std::to_string(loser) + " \"" +
               rig.animations[static_cast<std::size_t>(loser)].name + "\"";
    warning += (warning.empty() ? "" : "; ") + std::string("animation ") + std::to_string(winner) +
               " \"" + name + "\" drives node properties that " +
               (losers.size() == 1 ? "animation " : "animations ") + names +
               " also animate (no blending: the lowest index wins; pick one with --animation)";
  }
  return warning;
}

Light posedLight(Light light, const glm::mat4& world) {
  light.position = glm::vec3(world[3]);
  const glm::vec3 direction = glm::mat3(world) * glm::vec3(0.0f, 0.0f, -1.0f);
  if (glm::length(direction) > 0.0f) light.direction = glm::normalize(direction);
  return light;
}

}  // namespace

std::vector<int> chooseAnimations(const Scene& scene, const std::string& selection) {
  const std::vector<Animation>& animations = scene.rig.animations;
  std::vector<int> chosen;
  if (selection.empty() || selection == "all") {
    for (std::size_t i = 0; i < animations.size(); ++i) chosen.push_back(static_cast<int>(i));
    return chosen;
  }
  for (std::size_t i = 0; i < animations.size(); ++i)
    if (animations[i].name == selection) return {static_cast<int>(i)};
  const bool digits =
      selection.size() <= 9 &&
      std::all_of(selection.begin(), selection.end(), [](char c) { return c >= '0' && c <= '9'; });
  if (digits && static_cast<std::size_t>(std::stoi(selection)) < animations.size())
    return {std::stoi(selection)};
  std::string known;
  for (std::size_t i = 0; i < animations.size(); ++i)
    known += (known.empty() ? "" : ", ") + std::to_string(i) + " \"" + animations[i].name + "\"";
  throw InputError("--animation " + selection + ": " + scene.path + " has no such animation" +
                   (known.empty() ? " (it has none)" : " (animations: " + known + ")"));
}

std::vector<std::string> poseScene(Scene& scene, const PoseRequest& request) {
  const SceneRig& rig = scene.rig;
  std::vector<NodePose> poses;
  poses.reserve(rig.nodes.size());
  for (const RigNode& node : rig.nodes)
    poses.push_back({node.translation, node.rotation, node.scale, node.weights});
  std::vector<std::string> warnings;
  if (request.time) {
    const std::vector<int> clips = chooseAnimations(scene, request.animation);
    const std::string warning = animate(rig, clips, *request.time, poses);
    if (!warning.empty()) warnings.push_back(scene.path + ": " + warning);
  } else if (rig.deformed.empty() && !rig.animated()) {
    return warnings;  // nothing in the file moves: the loader's matrices are this pose
  }
  const std::vector<glm::mat4> world = worldMatrices(rig, poses);

  // Plain instances, cameras and lights move only in files with animations (a pose at rest
  // after one at a time must put them back); files without any keep the loader's matrices.
  if (rig.animated()) {
    for (MeshInstance& instance : scene.instances)
      instance.world = world[static_cast<std::size_t>(instance.node)] * instance.inNode;
    for (Camera& camera : scene.cameras)
      if (camera.node >= 0) camera.world = world[static_cast<std::size_t>(camera.node)];
    for (std::size_t i = 0; i < scene.lights.size() && i < rig.lightNodes.size(); ++i)
      scene.lights[i] =
          posedLight(scene.lights[i], world[static_cast<std::size_t>(rig.lightNodes[i])]);
  }
  for (const DeformedInstance& source : rig.deformed) {
    MeshInstance& instance = scene.instances[static_cast<std::size_t>(source.instance)];
    const glm::mat4& nodeWorld = world[static_cast<std::size_t>(source.node)];
    DeformedVertices vertices = morph(source, poses[static_cast<std::size_t>(source.node)].weights);
    if (source.skin >= 0) {
      const Skin& skinData = rig.skins[static_cast<std::size_t>(source.skin)];
      std::vector<glm::mat4> joints;
      joints.reserve(skinData.joints.size());
      for (std::size_t j = 0; j < skinData.joints.size(); ++j)
        joints.push_back(world[static_cast<std::size_t>(skinData.joints[j])] *
                         skinData.inverseBindMatrices[j]);
      skin(source, joints, nodeWorld, vertices);
      // Skinned vertices are in world space: the mesh node's own transform does not apply.
      instance.world = glm::mat4(1.0f);
    } else {
      instance.world = nodeWorld * instance.inNode;
    }
    writeDeformedMesh(source, vertices, scene.meshes[static_cast<std::size_t>(instance.mesh)]);
  }
  if (!rig.deformed.empty()) scene.revision = newSceneRevision();
  scene.bounds = Bounds{};
  for (const MeshInstance& instance : scene.instances)
    scene.bounds.extend(
        scene.meshes[static_cast<std::size_t>(instance.mesh)].bounds.transformed(instance.world));
  return warnings;
}

void checkPoseRequest(std::optional<double> time, const std::string& animation) {
  if (!animation.empty() && !time)
    throw InputError("--animation " + animation + ": needs --time SECONDS");
  if (time && !std::isfinite(*time))
    throw InputError("--time: expected a finite number of seconds");
}

std::vector<std::string> poseSceneChecked(Scene& scene, const std::string& file,
                                          std::optional<double> time,
                                          const std::string& animation) {
  checkPoseRequest(time, animation);
  std::vector<std::string> warnings = poseScene(scene, {time, animation});
  if (time && scene.rig.animations.empty())
    warnings.push_back(file + ": has no animations; --time changes nothing");
  return warnings;
}

}  // namespace omnishadow
