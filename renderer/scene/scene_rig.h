#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <string>
#include <vector>

#include "renderer/scene/animation_sampler.h"

namespace omnishadow {

// What posing needs beyond the drawn Scene: the glTF node hierarchy, skins, morph targets and
// animations, kept by the loader so that poseScene() can turn the model and a time into the
// plain Scene the renderer draws. Plain data, filled by loadGltf().

struct RigNode {
  std::string name;
  int parent = -1;
  // Local transform: `matrix` when the file gives one (such nodes cannot be animated), else
  // translation, rotation, scale.
  bool hasMatrix = false;
  glm::mat4 matrix{1.0f};
  glm::vec3 translation{0.0f};
  glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};
  glm::vec3 scale{1.0f};
  // Morph target weights: node.weights, else the mesh's default weights, else zeros; one per
  // target of the node's mesh (empty without targets).
  std::vector<float> weights;
  int mesh = -1;  // glTF mesh index
  int skin = -1;  // glTF skin index
};

struct Skin {
  std::string name;
  std::vector<int> joints{};                     // node indices
  std::vector<glm::mat4> inverseBindMatrices{};  // one per joint (identity when the file has none)
};

// POSITION, NORMAL and TANGENT displacements of one morph target; each empty or one per vertex
// of the file's primitive.
struct MorphTarget {
  std::vector<glm::vec3> positions, normals, tangents;
};

// One drawn instance whose vertices posing computes: skinned, morphed or both. The source data
// is in the file's vertex order; the instance's Scene mesh is its own (no other instance draws
// it) and its vertex i comes from source vertex vertexSource[i].
struct DeformedInstance {
  int instance = -1;  // index into Scene::instances
  int node = -1;
  int skin = -1;                              // -1: not skinned
  std::vector<glm::vec3> positions, normals;  // normals empty when the file has none
  std::vector<glm::vec4> tangents;            // empty when the file has none
  // Joint influences: influences entries per vertex (4 per JOINTS_n/WEIGHTS_n set), joint
  // indices into the skin's joint list.
  int influences = 0;
  std::vector<std::uint16_t> joints;
  std::vector<float> weights;
  std::vector<MorphTarget> targets;
  std::vector<std::uint32_t> vertexSource;
  bool flatNormals = false;     // the loader generated flat normals: generate them again
  int generatedTangentUv = -1;  // the loader generated tangents from this UV set: again
};

// A glTF mesh with morph targets, as `info` describes it.
struct MorphTargetMesh {
  int mesh = -1;  // glTF mesh index
  std::string name;
  int targets = 0;
  std::vector<float> weights;  // mesh.weights (empty when the file gives none)
};

enum class AnimatedProperty { Translation, Rotation, Scale, Weights };

struct AnimationChannel {
  int node = -1;
  AnimatedProperty property = AnimatedProperty::Translation;
  int sampler = -1;  // index into Animation::samplers
};

struct Animation {
  std::string name;  // the file's name, or "animation<index>"
  std::vector<AnimationSampler> samplers;
  std::vector<AnimationChannel> channels;
  float start = 0.0f, end = 0.0f;  // first and last keyframe time of all its samplers
};

struct SceneRig {
  std::vector<RigNode> nodes;         // every node of the file, indexed like the file's
  std::vector<int> order;             // drawn nodes, parents before children
  std::vector<int> cameraNodes;       // node of each Scene::cameras entry
  std::vector<int> lightNodes;        // node of each Scene::lights entry
  std::vector<Skin> skins;            // indexed like the file's
  std::vector<Animation> animations;  // indexed like the file's
  std::vector<DeformedInstance> deformed;
  std::vector<MorphTargetMesh> morphTargetMeshes;  // for `info`

  bool animated() const { return !animations.empty(); }
};

}  // namespace omnishadow
