#include "renderer/scene/gltf_rig.h"

#include <algorithm>
#include <cmath>
#include <glm/gtc/type_ptr.hpp>
#include <limits>
#include <optional>
#include <string>

#include "renderer/scene/gltf_accessors.h"
#include "renderer/scene/gltf_primitives.h"

namespace omnishadow::gltf_detail {
namespace {

RigNode rigNode(const tinygltf::Node& node) {
  RigNode out;
  out.name = node.name;
  out.mesh = node.mesh;
  out.skin = node.skin;
  if (node.matrix.size() == 16) {
    out.hasMatrix = true;
    for (int i = 0; i < 16; ++i)
      glm::value_ptr(out.matrix)[i] = static_cast<float>(node.matrix[static_cast<std::size_t>(i)]);
  }
  out.translation = factor<3>(node.translation, glm::vec3(0.0f));
  const glm::vec4 xyzw = factor<4>(node.rotation, glm::vec4(0, 0, 0, 1));
  out.rotation = glm::quat(xyzw.w, xyzw.x, xyzw.y, xyzw.z);
  out.scale = factor<3>(node.scale, glm::vec3(1.0f));
  return out;
}

// Morph targets of a glTF mesh: all its primitives have the same count (glTF 3.7.2.2).
std::size_t targetCount(const tinygltf::Model& model, int mesh) {
  if (mesh < 0 || static_cast<std::size_t>(mesh) >= model.meshes.size()) return 0;
  std::size_t count = 0;
  for (const tinygltf::Primitive& p : model.meshes[static_cast<std::size_t>(mesh)].primitives)
    count = std::max(count, p.targets.size());
  return count;
}

void readNodes(Context& ctx) {
  SceneRig& rig = ctx.scene.rig;
  const tinygltf::Model& model = ctx.model;
  rig.nodes.reserve(model.nodes.size());
  for (const tinygltf::Node& node : model.nodes) rig.nodes.push_back(rigNode(node));
  for (std::size_t i = 0; i < model.nodes.size(); ++i) {
    for (int child : model.nodes[i].children)
      if (child >= 0 && static_cast<std::size_t>(child) < rig.nodes.size() &&
          rig.nodes[static_cast<std::size_t>(child)].parent < 0 &&
          static_cast<std::size_t>(child) != i)
        rig.nodes[static_cast<std::size_t>(child)].parent = static_cast<int>(i);
    RigNode& node = rig.nodes[i];
    const std::size_t targets = targetCount(model, node.mesh);
    if (targets == 0) continue;
    const tinygltf::Mesh& mesh = model.meshes[static_cast<std::size_t>(node.mesh)];
    const std::vector<double>& source =
        model.nodes[i].weights.size() == targets ? model.nodes[i].weights : mesh.weights;
    node.weights.assign(targets, 0.0f);
    if (source.size() == targets)
      for (std::size_t t = 0; t < targets; ++t) node.weights[t] = static_cast<float>(source[t]);
  }
  for (std::size_t m = 0; m < model.meshes.size(); ++m) {
    const std::size_t targets = targetCount(model, static_cast<int>(m));
    if (targets == 0) continue;
    MorphTargetMesh info{static_cast<int>(m), model.meshes[m].name, static_cast<int>(targets), {}};
    for (double w : model.meshes[m].weights) info.weights.push_back(static_cast<float>(w));
    rig.morphTargetMeshes.push_back(std::move(info));
  }
}

Skin readSkin(Context& ctx, std::size_t s) {
  const tinygltf::Model& model = ctx.model;
  const tinygltf::Skin& source = model.skins[s];
  const std::string object = at("skins", s);
  Skin skin{.name = nameOrDefault(source.name, "skin", s)};
  for (int joint : source.joints) {
    ctx.checkIndex(object + ".joints", "node", joint, model.nodes.size());
    skin.joints.push_back(joint);
  }
  skin.inverseBindMatrices.assign(skin.joints.size(), glm::mat4(1.0f));
  if (source.inverseBindMatrices >= 0) {
    ctx.checkIndex(object + ".inverseBindMatrices", "accessor", source.inverseBindMatrices,
                   model.accessors.size());
    const tinygltf::Accessor& accessor =
        model.accessors[static_cast<std::size_t>(source.inverseBindMatrices)];
    if (accessor.type != TINYGLTF_TYPE_MAT4 ||
        accessor.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT)
      ctx.fail(object + ".inverseBindMatrices", "must be a MAT4 float accessor");
    const AccessorValues values = readAccessor(ctx, source.inverseBindMatrices, Normalize::Never);
    if (values.count < skin.joints.size())
      ctx.fail(object + ".inverseBindMatrices", "has " + std::to_string(values.count) +
                                                    " matrices for " +
                                                    plural(skin.joints.size(), "joint"));
    for (std::size_t j = 0; j < skin.joints.size(); ++j)
      for (int k = 0; k < 16; ++k)
        glm::value_ptr(skin.inverseBindMatrices[j])[k] =
            static_cast<float>(values.get(j, k));  // both column-major
  }
  return skin;
}

void readSkins(Context& ctx) {
  for (std::size_t s = 0; s < ctx.model.skins.size(); ++s)
    ctx.scene.rig.skins.push_back(readSkin(ctx, s));
}

bool allFinite(const std::vector<float>& values) {
  return std::all_of(values.begin(), values.end(), [](float v) { return std::isfinite(v); });
}

// Reads animations[a].samplers[s]; an empty result (with a warning) when it cannot be played.
AnimationSampler readSampler(Context& ctx, std::size_t a, std::size_t s) {
  const tinygltf::AnimationSampler& source = ctx.model.animations[a].samplers[s];
  const std::string object = at("animations", a) + "." + at("samplers", s);
  AnimationSampler sampler;
  if (source.interpolation == "STEP") {
    sampler.interpolation = Interpolation::Step;
  } else if (source.interpolation == "CUBICSPLINE") {
    sampler.interpolation = Interpolation::CubicSpline;
  } else if (source.interpolation == "LINEAR" || source.interpolation.empty()) {
    sampler.interpolation = Interpolation::Linear;
  } else {
    ctx.warn(object + ": unknown interpolation \"" + source.interpolation + "\"; not played");
    return {};
  }
  ctx.checkIndex(object + ".input", "accessor", source.input, ctx.model.accessors.size());
  ctx.checkIndex(object + ".output", "accessor", source.output, ctx.model.accessors.size());
  const AccessorValues input = readAccessor(ctx, source.input, Normalize::Never);
  const AccessorValues output = readAccessor(ctx, source.output, Normalize::AsFlagged);
  if (output.count == 0) {
    ctx.warn(object + ".output: no keyframe values; not played");
    return {};
  }
  if (input.components != 1 || input.count == 0) {
    ctx.warn(object + ".input: expected SCALAR keyframe times; not played");
    return {};
  }
  for (double t : input.values) sampler.times.push_back(static_cast<float>(t));
  for (double v : output.values) sampler.values.push_back(static_cast<float>(v));
  if (!allFinite(sampler.times) || !allFinite(sampler.values)) {
    ctx.warn(object + ": non-finite keyframes; not played");
    return {};
  }
  for (std::size_t k = 1; k < sampler.times.size(); ++k)
    if (!(sampler.times[k] > sampler.times[k - 1])) {
      ctx.warn(object + ".input: keyframe times must increase; not played");
      return {};
    }
  const std::size_t perKey = sampler.interpolation == Interpolation::CubicSpline ? 3 : 1;
  // Elements per keyframe, each of output.components floats; weights outputs have one scalar
  // per morph target, so the width is only known per channel (checked there).
  if (output.count % (input.count * perKey) != 0) {
    ctx.warn(object + ": " + std::to_string(output.count) + " output elements for " +
             std::to_string(input.count) + " keyframes; not played");
    return {};
  }
  sampler.components = output.components * static_cast<int>(output.count / (input.count * perKey));
  return sampler;
}

// A KHR_animation_pointer target that a core channel could name: a node's translation,
// rotation, scale or weights.
struct NodeTarget {
  int node = -1;
  std::string path;
};

// The node property a "pointer" channel animates, or nullopt (with `pointer` set to the JSON
// pointer) when it animates something else. Fails when the extension's object is malformed.
std::optional<NodeTarget> pointerTarget(const Context& ctx,
                                        const tinygltf::AnimationChannel& channel,
                                        const std::string& channelObject, std::string& pointer) {
  const std::string where = channelObject + ".target.extensions.KHR_animation_pointer";
  const auto found = channel.target_extensions.find("KHR_animation_pointer");
  if (found == channel.target_extensions.end())
    ctx.fail(channelObject + ".target", "path \"pointer\" needs a KHR_animation_pointer object");
  const tinygltf::Value& extension = found->second;
  if (!extension.IsObject() || !extension.Get("pointer").IsString())
    ctx.fail(where, "pointer must be a string");
  pointer = extension.Get("pointer").Get<std::string>();
  // "/nodes/<index>/<property>": an index of decimal digits without a sign or leading zeros.
  const std::string prefix = "/nodes/";
  if (pointer.rfind(prefix, 0) != 0) return std::nullopt;
  const std::size_t slash = pointer.find('/', prefix.size());
  if (slash == std::string::npos) return std::nullopt;
  const std::string index = pointer.substr(prefix.size(), slash - prefix.size());
  const std::string property = pointer.substr(slash + 1);
  if (index.empty() || index.size() > 9 || (index.size() > 1 && index[0] == '0') ||
      index.find_first_not_of("0123456789") != std::string::npos)
    return std::nullopt;
  if (property != "translation" && property != "rotation" && property != "scale" &&
      property != "weights")
    return std::nullopt;
  return NodeTarget{std::stoi(index), property};
}

void readAnimations(Context& ctx) {
  const tinygltf::Model& model = ctx.model;
  for (std::size_t a = 0; a < model.animations.size(); ++a) {
    const tinygltf::Animation& source = model.animations[a];
    const std::string object = at("animations", a);
    Animation animation;
    animation.name = nameOrDefault(source.name, "animation", a);
    for (std::size_t s = 0; s < source.samplers.size(); ++s)
      animation.samplers.push_back(readSampler(ctx, a, s));
    bool any = false;
    std::size_t otherPointers = 0;  // KHR_animation_pointer channels of other properties
    std::string firstOtherPointer;
    for (std::size_t c = 0; c < source.channels.size(); ++c) {
      const tinygltf::AnimationChannel& channel = source.channels[c];
      const std::string channelObject = object + "." + at("channels", c);
      int node = channel.target_node;
      std::string path = channel.target_path;
      // KHR_animation_pointer: a node's TRS or weights play as the core channel would.
      if (path == "pointer") {
        std::string pointer;
        const std::optional<NodeTarget> target =
            pointerTarget(ctx, channel, channelObject, pointer);
        if (!target) {
          if (otherPointers++ == 0) firstOtherPointer = pointer;
          continue;
        }
        node = target->node;
        path = target->path;
      }
      if (node < 0) continue;  // targets an extension's object
      ctx.checkIndex(channelObject + ".target", "node", node, model.nodes.size());
      ctx.checkIndex(channelObject, "sampler", channel.sampler, source.samplers.size());
      AnimationChannel out;
      out.node = node;
      out.sampler = channel.sampler;
      int components = 0;
      if (path == "translation") {
        out.property = AnimatedProperty::Translation;
        components = 3;
      } else if (path == "rotation") {
        out.property = AnimatedProperty::Rotation;
        components = 4;
      } else if (path == "scale") {
        out.property = AnimatedProperty::Scale;
        components = 3;
      } else if (path == "weights") {
        out.property = AnimatedProperty::Weights;
        components = static_cast<int>(
            ctx.scene.rig.nodes[static_cast<std::size_t>(out.node)].weights.size());
      } else {
        ctx.warn(channelObject + ": target path \"" + path + "\" is not supported; not played");
        continue;
      }
      const AnimationSampler& sampler =
          animation.samplers[static_cast<std::size_t>(channel.sampler)];
      if (sampler.times.empty()) continue;  // warned about when read
      if (components == 0) {
        ctx.warn(channelObject + ": " + at("nodes", static_cast<std::size_t>(out.node)) +
                 " has no morph targets to weigh; not played");
        continue;
      }
      if (sampler.components != components) {
        ctx.warn(channelObject + ": its sampler has " + std::to_string(sampler.components) +
                 " values per keyframe, the " + path + " of " +
                 at("nodes", static_cast<std::size_t>(out.node)) + " needs " +
                 std::to_string(components) + "; not played");
        continue;
      }
      if (ctx.scene.rig.nodes[static_cast<std::size_t>(out.node)].hasMatrix &&
          out.property != AnimatedProperty::Weights) {
        ctx.warn(channelObject + ": " + at("nodes", static_cast<std::size_t>(out.node)) +
                 " has a matrix, which cannot be animated; not played");
        continue;
      }
      animation.start =
          any ? std::min(animation.start, sampler.times.front()) : sampler.times.front();
      animation.end = any ? std::max(animation.end, sampler.times.back()) : sampler.times.back();
      any = true;
      animation.channels.push_back(out);
    }
    if (otherPointers > 0)
      ctx.warn(object +
               ": KHR_animation_pointer channels of other properties than a node's translation, "
               "rotation, scale or weights are not played: " +
               std::to_string(otherPointers) + " (the first: \"" + firstOtherPointer + "\")");
    ctx.scene.rig.animations.push_back(std::move(animation));
  }
}

template <int N>
std::vector<glm::vec<N, float>> vectorsOf(const AccessorValues& values) {
  std::vector<glm::vec<N, float>> out(values.count, glm::vec<N, float>(0.0f));
  for (std::size_t e = 0; e < values.count; ++e)
    for (int c = 0; c < std::min(N, values.components); ++c)
      out[e][c] = static_cast<float>(values.get(e, c));
  return out;
}

// An attribute (or morph target attribute) with `count` elements of at least `components`;
// empty when absent.
AccessorValues readVertexData(Context& ctx, const std::string& object,
                              const std::map<std::string, int>& attributes,
                              const std::string& semantic, std::size_t count, int components,
                              Normalize normalize) {
  const auto found = attributes.find(semantic);
  if (found == attributes.end()) return {};
  ctx.checkIndex(object + "." + semantic, "accessor", found->second, ctx.model.accessors.size());
  AccessorValues values = readAccessor(ctx, found->second, normalize);
  if (values.count != count || values.components < components)
    ctx.fail(object + "." + semantic, "has " + std::to_string(values.count) + " elements of " +
                                          std::to_string(values.components) +
                                          " components; expected " + std::to_string(count) +
                                          " of " + std::to_string(components));
  return values;
}

void readInfluences(Context& ctx, const tinygltf::Primitive& primitive, const std::string& object,
                    std::size_t vertexCount, std::size_t jointCount, DeformedInstance& out) {
  std::vector<AccessorValues> joints, weights;
  for (int set = 0;; ++set) {
    const std::string suffix = "_" + std::to_string(set);
    if (primitive.attributes.count("JOINTS" + suffix) == 0) break;
    if (primitive.attributes.count("WEIGHTS" + suffix) == 0)
      ctx.fail(object + ".attributes", "JOINTS" + suffix + " without WEIGHTS" + suffix);
    joints.push_back(readVertexData(ctx, object + ".attributes", primitive.attributes,
                                    "JOINTS" + suffix, vertexCount, 4, Normalize::Never));
    weights.push_back(readVertexData(ctx, object + ".attributes", primitive.attributes,
                                     "WEIGHTS" + suffix, vertexCount, 4, Normalize::Integers));
  }
  out.influences = static_cast<int>(4 * joints.size());
  out.joints.resize(vertexCount * joints.size() * 4);
  out.weights.resize(out.joints.size());
  for (std::size_t v = 0; v < vertexCount; ++v) {
    for (std::size_t set = 0; set < joints.size(); ++set) {
      for (int c = 0; c < 4; ++c) {
        const std::size_t slot = v * joints.size() * 4 + set * 4 + static_cast<std::size_t>(c);
        const double joint = joints[set].get(v, c);
        const double weight = weights[set].get(v, c);
        if (weight != 0.0 && !(joint >= 0.0 && joint < static_cast<double>(jointCount)))
          ctx.fail(object + ".attributes.JOINTS_" + std::to_string(set),
                   "joint " + std::to_string(static_cast<long long>(joint)) +
                       " is out of range (the skin has " + plural(jointCount, "joint") + ")");
        out.joints[slot] = weight != 0.0 ? static_cast<std::uint16_t>(joint) : std::uint16_t{0};
        out.weights[slot] = std::isfinite(weight) ? static_cast<float>(weight) : 0.0f;
      }
    }
  }
}

}  // namespace

void readRig(Context& ctx) {
  readNodes(ctx);
  readSkins(ctx);
  readAnimations(ctx);
}

bool isDeformed(const Context& ctx, std::size_t nodeIndex, std::size_t meshIndex,
                std::size_t primIndex) {
  const tinygltf::Primitive& primitive = ctx.model.meshes[meshIndex].primitives[primIndex];
  const bool skinned =
      ctx.model.nodes[nodeIndex].skin >= 0 && primitive.attributes.count("JOINTS_0") > 0;
  return skinned || !primitive.targets.empty();
}

void addDeformedInstance(Context& ctx, std::size_t nodeIndex, std::size_t meshIndex,
                         std::size_t primIndex, int instance) {
  const tinygltf::Primitive& primitive = ctx.model.meshes[meshIndex].primitives[primIndex];
  const std::string object = at("meshes", meshIndex) + "." + at("primitives", primIndex);
  const tinygltf::Node& node = ctx.model.nodes[nodeIndex];
  Scene& scene = ctx.scene;
  const Mesh& mesh = scene.meshes[static_cast<std::size_t>(
      scene.instances[static_cast<std::size_t>(instance)].mesh)];
  DeformedInstance out;
  out.instance = instance;
  out.node = static_cast<int>(nodeIndex);
  const std::map<std::string, int>& attributes = primitive.attributes;
  const AccessorValues positions =
      readAccessor(ctx, attributes.at("POSITION"), Normalize::AsFlagged);
  const std::size_t n = positions.count;
  out.positions = vectorsOf<3>(positions);
  out.normals = vectorsOf<3>(readVertexData(ctx, object + ".attributes", attributes, "NORMAL", n, 3,
                                            Normalize::AsFlagged));
  out.tangents = vectorsOf<4>(readVertexData(ctx, object + ".attributes", attributes, "TANGENT", n,
                                             4, Normalize::AsFlagged));
  for (glm::vec3& normal : out.normals) {
    const float length = glm::length(normal);
    if (length > 0.0f && std::isfinite(length)) normal /= length;
  }
  out.flatNormals = out.normals.empty();
  if (out.flatNormals) {
    out.tangents.clear();  // as the loader does: tangents without normals are ignored
    out.vertexSource = fileTriangleIndices(ctx, meshIndex, primIndex);
  } else {
    out.vertexSource.resize(n);
    for (std::size_t i = 0; i < n; ++i) out.vertexSource[i] = static_cast<std::uint32_t>(i);
  }
  if (out.vertexSource.size() != mesh.positions.size())
    ctx.fail(object, "its vertices cannot be matched for posing");
  if (out.tangents.empty() && !mesh.tangents.empty() && mesh.material >= 0)
    out.generatedTangentUv =
        tangentSpaceNormalMap(scene.materials[static_cast<std::size_t>(mesh.material)]).texCoord;

  if (node.skin >= 0 && attributes.count("JOINTS_0") > 0) {
    ctx.checkIndex(at("nodes", nodeIndex), "skin", node.skin, scene.rig.skins.size());
    out.skin = node.skin;
    readInfluences(ctx, primitive, object, n,
                   scene.rig.skins[static_cast<std::size_t>(node.skin)].joints.size(), out);
  }
  for (std::size_t t = 0; t < primitive.targets.size(); ++t) {
    const std::string targetObject = object + "." + at("targets", t);
    const std::map<std::string, int>& target = primitive.targets[t];
    MorphTarget morph;
    morph.positions = vectorsOf<3>(
        readVertexData(ctx, targetObject, target, "POSITION", n, 3, Normalize::AsFlagged));
    morph.normals = vectorsOf<3>(
        readVertexData(ctx, targetObject, target, "NORMAL", n, 3, Normalize::AsFlagged));
    morph.tangents = vectorsOf<3>(
        readVertexData(ctx, targetObject, target, "TANGENT", n, 3, Normalize::AsFlagged));
    out.targets.push_back(std::move(morph));
  }
  scene.rig.deformed.push_back(std::move(out));
}

}  // namespace omnishadow::gltf_detail
