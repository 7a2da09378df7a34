#include "renderer/scene/gltf_nodes.h"

#include <algorithm>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <optional>
#include <set>
#include <sstream>
#include <utility>

#include "renderer/scene/camera_checks.h"
#include "renderer/scene/gltf_instancing.h"
#include "renderer/scene/gltf_primitives.h"
#include "renderer/scene/gltf_rig.h"

namespace omnishadow::gltf_detail {

namespace {

// The node's extras "class" when it is a string (annotation masks group instances by it).
std::string extrasClass(const tinygltf::Node& node) {
  if (!node.extras.IsObject() || !node.extras.Has("class")) return {};
  const tinygltf::Value& value = node.extras.Get("class");
  return value.IsString() ? value.Get<std::string>() : std::string();
}

glm::mat4 localMatrix(const Context& ctx, std::size_t nodeIndex) {
  const tinygltf::Node& node = ctx.model.nodes[nodeIndex];
  const std::string object = at("nodes", nodeIndex);
  if (!node.matrix.empty()) {
    if (node.matrix.size() != 16) ctx.fail(object, "matrix must have 16 numbers");
    glm::mat4 m;
    for (int i = 0; i < 16; ++i) {
      glm::value_ptr(m)[i] = static_cast<float>(node.matrix[static_cast<std::size_t>(i)]);
    }
    return m;  // both column-major
  }
  glm::mat4 m(1.0f);
  if (!node.translation.empty()) {
    if (node.translation.size() != 3) ctx.fail(object, "translation must have 3 numbers");
    m = glm::translate(m, factor<3>(node.translation, glm::vec3(0.0f)));
  }
  if (!node.rotation.empty()) {
    if (node.rotation.size() != 4) ctx.fail(object, "rotation must have 4 numbers");
    const glm::vec4 xyzw = factor<4>(node.rotation, glm::vec4(0, 0, 0, 1));
    glm::quat q(xyzw.w, xyzw.x, xyzw.y, xyzw.z);
    // Exporters round quaternions; mat4_cast expects unit length.
    if (glm::length(q) > 0.0f) m *= glm::mat4_cast(glm::normalize(q));
  }
  if (!node.scale.empty()) {
    if (node.scale.size() != 3) ctx.fail(object, "scale must have 3 numbers");
    m = glm::scale(m, factor<3>(node.scale, glm::vec3(1.0f)));
  }
  return m;
}

// The node's KHR_lights_punctual light index, or -1.
int lightOf(const Context& ctx, std::size_t nodeIndex) {
  const tinygltf::Node& node = ctx.model.nodes[nodeIndex];
  const auto found = node.extensions.find("KHR_lights_punctual");
  if (found == node.extensions.end() || !found->second.IsObject() ||
      !found->second.Get("light").IsNumber()) {
    return -1;
  }
  const int light = found->second.Get("light").GetNumberAsInt();
  ctx.checkIndex(at("nodes", nodeIndex) + ".extensions.KHR_lights_punctual", "light", light,
                 ctx.model.lights.size());
  return light;
}

// KHR_node_visibility: the node's own `visible` (true when absent). Its ancestors' count too
// (SceneBuilder::traverse). A value that is not a boolean is warned about and taken as true:
// the extension is never required for a file to load.
bool ownVisibility(const Context& ctx, std::size_t nodeIndex) {
  const tinygltf::Node& node = ctx.model.nodes[nodeIndex];
  const auto found = node.extensions.find("KHR_node_visibility");
  // tinygltf keeps only extension values that are objects.
  if (found == node.extensions.end() || !found->second.IsObject() || !found->second.Has("visible"))
    return true;
  const tinygltf::Value& visible = found->second.Get("visible");
  if (!visible.IsBool()) {
    ctx.warn(at("nodes", nodeIndex) +
             ".extensions.KHR_node_visibility.visible is not a boolean; the node is drawn");
    return true;
  }
  return visible.Get<bool>();
}

// As a person would write it: -5, not -5.000000.
std::string shortNumber(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

Light convertLight(const Context& ctx, int index, const glm::mat4& world,
                   std::set<std::string>& usedNames) {
  const tinygltf::Light& source = ctx.model.lights[static_cast<std::size_t>(index)];
  const std::string object = "KHR_lights_punctual." + at("lights", static_cast<std::size_t>(index));
  Light light;
  // Light names must be unique within a render; a light placed by two nodes appears twice.
  const std::string base =
      nameOrDefault(source.name, "gltf_light", static_cast<std::size_t>(index));
  light.name = base;
  for (int k = 2; !usedNames.insert(light.name).second; ++k)
    light.name = base + "_" + std::to_string(k);
  if (source.type == "point") {
    light.type = LightType::Point;
  } else if (source.type == "spot") {
    light.type = LightType::Spot;
    light.innerConeAngle = static_cast<float>(source.spot.innerConeAngle);
    light.outerConeAngle = static_cast<float>(source.spot.outerConeAngle);
    // The rules of a lights file (and of KHR_lights_punctual): 0 <= inner < outer <= pi/2.
    constexpr float kHalfPi = 1.5707963267948966f;
    if (!(light.innerConeAngle >= 0.0f && light.innerConeAngle < light.outerConeAngle &&
          light.outerConeAngle <= kHalfPi)) {
      ctx.fail(object, "spot innerConeAngle " + shortNumber(source.spot.innerConeAngle) +
                           " and outerConeAngle " + shortNumber(source.spot.outerConeAngle) +
                           ": expected 0 <= inner < outer <= pi/2");
    }
  } else if (source.type == "directional") {
    light.type = LightType::Directional;
  } else {
    ctx.fail(object, "unknown type \"" + source.type + "\"");
  }
  light.color = factor<3>(source.color, light.color);
  light.intensity = static_cast<float>(source.intensity);
  if (!(light.intensity >= 0.0f) || !std::isfinite(light.intensity)) {
    ctx.fail(object,
             "intensity " + shortNumber(source.intensity) + ": expected a finite number >= 0");
  }
  // tinygltf reads an absent range as 0; a negative one is the file's own.
  if (source.range < 0.0 || !std::isfinite(source.range)) {
    ctx.fail(object, "range " + shortNumber(source.range) + ": expected a number > 0");
  }
  light.range = source.range > 0.0 ? static_cast<float>(source.range) : 0.0f;
  light.position = glm::vec3(world[3]);
  const glm::vec3 direction = glm::mat3(world) * glm::vec3(0.0f, 0.0f, -1.0f);
  if (glm::length(direction) > 0.0f) light.direction = glm::normalize(direction);
  light.origin = "glTF";
  return light;
}

Camera convertCamera(const Context& ctx, std::size_t nodeIndex, const glm::mat4& world) {
  const tinygltf::Node& node = ctx.model.nodes[nodeIndex];
  ctx.checkIndex(at("nodes", nodeIndex), "camera", node.camera, ctx.model.cameras.size());
  const tinygltf::Camera& source = ctx.model.cameras[static_cast<std::size_t>(node.camera)];
  Camera camera;
  camera.name = source.name.empty() ? node.name : source.name;
  camera.nodeName = node.name;
  camera.index = node.camera;
  camera.node = static_cast<int>(nodeIndex);
  camera.world = world;
  if (source.type == "orthographic") {
    camera.orthographic = true;
    camera.xmag = static_cast<float>(source.orthographic.xmag);
    camera.ymag = static_cast<float>(source.orthographic.ymag);
    camera.znear = static_cast<float>(source.orthographic.znear);
    camera.zfar = static_cast<float>(source.orthographic.zfar);
  } else {
    // yfov and znear are required and positive; keep usable defaults when a file breaks that.
    if (source.perspective.yfov > 0.0) camera.yfov = static_cast<float>(source.perspective.yfov);
    if (source.perspective.znear > 0.0) {
      camera.znear = static_cast<float>(source.perspective.znear);
    }
    camera.aspectRatio = static_cast<float>(std::max(source.perspective.aspectRatio, 0.0));
    camera.zfar = static_cast<float>(std::max(source.perspective.zfar, 0.0));
  }
  return camera;
}

std::string number(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

// A broken camera does not fail the load: other viewers load such files, and a camera that is
// never rendered from must not keep the rest of the scene from rendering (see cameraProblem()).
// A perspective camera without a positive yfov or znear gets the default (convertCamera);
// one whose projection would still divide by zero or overflow (orthographic xmag or ymag 0,
// zfar <= znear) is refused by resolveCamera() if a render selects it. Both are warned about.
void warnAboutCamera(const Context& ctx, const Camera& camera) {
  const tinygltf::Camera& source = ctx.model.cameras[static_cast<std::size_t>(camera.index)];
  const std::string object = at("cameras", static_cast<std::size_t>(camera.index));
  if (!camera.orthographic) {
    if (!(source.perspective.yfov > 0.0)) {
      ctx.warn(object + ": perspective yfov " + number(source.perspective.yfov) +
               " is not positive; using " + number(camera.yfov));
    }
    if (!(source.perspective.znear > 0.0)) {
      ctx.warn(object + ": perspective znear " + number(source.perspective.znear) +
               " is not positive; using " + number(camera.znear));
    }
  }
  if (const std::string problem = cameraProblem(camera); !problem.empty()) {
    ctx.warn(object + ": " + problem + "; rendering from this camera will fail");
  }
}

bool isFinite(const glm::mat4& m) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(m[c][r])) return false;
  return true;
}

class SceneBuilder {
 public:
  explicit SceneBuilder(Context& ctx) : ctx_(ctx) {
    for (const tinygltf::Mesh& mesh : ctx.model.meshes) {
      meshOf_.emplace_back(mesh.primitives.size(), kNotConverted);
    }
  }

  // Depth-first, parents before children, without recursion so that deep hierarchies cannot
  // overflow the stack.
  void traverse(const std::vector<int>& roots, const std::string& rootsObject) {
    const std::size_t nodeCount = ctx_.model.nodes.size();
    std::vector<char> onPath(nodeCount, 0), visited(nodeCount, 0);
    struct Frame {
      std::size_t node;
      glm::mat4 world;
      std::size_t nextChild;
      std::string className;  // the node's extras "class", else its nearest ancestor's
      bool visible;           // KHR_node_visibility: the node's and all its ancestors'
    };
    std::vector<Frame> stack;
    const auto enter = [&](int node, const glm::mat4& parentWorld, const std::string& parentClass,
                           bool parentVisible, const std::string& referrer) {
      ctx_.checkIndex(referrer, "node", node, nodeCount);
      const auto index = static_cast<std::size_t>(node);
      if (onPath[index]) ctx_.fail(at("nodes", index), "the node hierarchy has a cycle");
      // glTF nodes have at most one parent; a second path would draw the subtree twice.
      if (visited[index]) ctx_.fail(at("nodes", index), "is reachable along two paths");
      onPath[index] = visited[index] = 1;
      ++ctx_.scene.source.reachedNodes;
      const glm::mat4 world = parentWorld * localMatrix(ctx_, index);
      if (!isFinite(world)) {
        // A NaN or infinite transform would place everything below it nowhere.
        ctx_.warn(at("nodes", index) +
                  ": non-finite transform; the node and its children are "
                  "not drawn");
        onPath[index] = 0;
        return;
      }
      std::string className = extrasClass(ctx_.model.nodes[index]);
      if (className.empty()) className = parentClass;
      const bool visible = parentVisible && ownVisibility(ctx_, index);
      if (!visible) ++ctx_.scene.source.hiddenNodes;
      visit(index, world, className, visible);
      stack.push_back({index, world, 0, std::move(className), visible});
    };
    for (int root : roots) {
      enter(root, glm::mat4(1.0f), std::string(), true, rootsObject);
      while (!stack.empty()) {
        Frame& top = stack.back();
        const std::vector<int>& children = ctx_.model.nodes[top.node].children;
        if (top.nextChild == children.size()) {
          onPath[top.node] = 0;
          stack.pop_back();
          continue;
        }
        const int child = children[top.nextChild++];
        const glm::mat4 parentWorld = top.world;  // `top` dies when the stack grows
        const std::string parentClass = top.className;
        enter(child, parentWorld, parentClass, top.visible, at("nodes", top.node) + ".children");
      }
    }
    // Cameras keep traversal order within one glTF camera.
    std::stable_sort(ctx_.scene.cameras.begin(), ctx_.scene.cameras.end(),
                     [](const Camera& a, const Camera& b) { return a.index < b.index; });
  }

 private:
  static constexpr int kNotConverted = -2;  // -1: converted, but not drawn

  // `className`: the node's extras "class", inherited from its nearest ancestor that has one.
  // A node that is not `visible` (KHR_node_visibility) places no mesh and no light; its camera
  // stays, as the extension says.
  void visit(std::size_t nodeIndex, const glm::mat4& world, const std::string& className,
             bool visible) {
    const tinygltf::Node& node = ctx_.model.nodes[nodeIndex];
    // A hidden node's mesh index is still checked: the file is broken either way.
    if (node.mesh >= 0)
      ctx_.checkIndex(at("nodes", nodeIndex), "mesh", node.mesh, ctx_.model.meshes.size());
    if (node.mesh >= 0 && visible) {
      const auto meshIndex = static_cast<std::size_t>(node.mesh);
      // EXT_mesh_gpu_instancing: one Scene instance per glTF instance.
      std::vector<glm::mat4> inNode = instanceTransforms(ctx_, nodeIndex);
      if (inNode.empty()) inNode.push_back(glm::mat4(1.0f));
      std::vector<glm::mat4> worlds;
      for (const glm::mat4& instance : inNode) worlds.push_back(world * instance);
      for (std::size_t p = 0; p < meshOf_[meshIndex].size(); ++p) {
        int mesh = sceneMesh(meshIndex, p);
        if (mesh < 0) continue;
        const bool deformed = isDeformed(ctx_, nodeIndex, meshIndex, p);
        mesh = instanceMesh(meshIndex, p, deformed);
        for (std::size_t i = 0; i < worlds.size(); ++i) {
          if (!isFinite(worlds[i])) continue;
          ctx_.scene.instances.push_back(
              {mesh, worlds[i], static_cast<int>(nodeIndex), node.name, className, inNode[i]});
          ctx_.scene.bounds.extend(
              ctx_.scene.meshes[static_cast<std::size_t>(mesh)].bounds.transformed(worlds[i]));
          if (deformed)
            addDeformedInstance(ctx_, nodeIndex, meshIndex, p,
                                static_cast<int>(ctx_.scene.instances.size()) - 1);
        }
      }
    }
    if (node.camera >= 0) addCamera(nodeIndex, world);
    if (const int light = lightOf(ctx_, nodeIndex); light >= 0 && visible) {
      ctx_.scene.lights.push_back(convertLight(ctx_, light, world, lightNames_));
      ctx_.scene.rig.lightNodes.push_back(static_cast<int>(nodeIndex));
    }
    ctx_.scene.rig.order.push_back(static_cast<int>(nodeIndex));
  }

  // The Scene mesh an instance draws. Posing rewrites a deformed instance's mesh, so that one
  // is its own; the others share the primitive's rest mesh.
  int instanceMesh(std::size_t meshIndex, std::size_t primIndex, bool deformed) {
    int& slot = meshOf_[meshIndex][primIndex];
    std::vector<Mesh>& meshes = ctx_.scene.meshes;
    posed_.resize(meshes.size(), 0);
    drawn_.resize(meshes.size(), 0);
    const auto index = static_cast<std::size_t>(slot);
    if (!drawn_[index] && (deformed || !posed_[index])) {
      drawn_[index] = 1;
      posed_[index] = deformed;
      return slot;
    }
    if (!deformed && !posed_[index]) return slot;
    meshes.push_back(meshes[index]);  // still the rest mesh: posing runs after the traversal
    posed_.push_back(deformed);
    drawn_.push_back(1);
    const int copy = static_cast<int>(meshes.size()) - 1;
    if (!deformed) slot = copy;  // later plain instances share this copy
    return copy;
  }

  void addCamera(std::size_t nodeIndex, const glm::mat4& world) {
    Camera camera = convertCamera(ctx_, nodeIndex, world);
    // Warned about once per glTF camera, however many nodes place it.
    if (checkedCameras_.insert(camera.index).second) warnAboutCamera(ctx_, camera);
    ctx_.scene.cameras.push_back(std::move(camera));
  }

  // Each glTF primitive becomes one Scene mesh however many nodes use it.
  int sceneMesh(std::size_t meshIndex, std::size_t primIndex) {
    int& slot = meshOf_[meshIndex][primIndex];
    if (slot == kNotConverted) {
      std::optional<Mesh> mesh = convertPrimitive(ctx_, meshIndex, primIndex);
      slot = -1;
      if (mesh) {
        ctx_.scene.meshes.push_back(std::move(*mesh));
        slot = static_cast<int>(ctx_.scene.meshes.size()) - 1;
      }
    }
    return slot;
  }

  Context& ctx_;
  std::vector<std::vector<int>> meshOf_;  // [glTF mesh][primitive] -> Scene::meshes index
  std::set<std::string> lightNames_;
  std::set<int> checkedCameras_;  // glTF camera indices
  std::vector<char> posed_;       // [Scene mesh] drawn by a deformed instance
  std::vector<char> drawn_;       // [Scene mesh] drawn by any instance
};

}  // namespace

// Root nodes of the scene to draw, and how messages name that list.
std::pair<std::vector<int>, std::string> sceneRoots(const Context& ctx,
                                                    const GltfLoadOptions& options) {
  const tinygltf::Model& model = ctx.model;
  const bool chosen = options.sceneIndex >= 0;
  if (model.scenes.empty()) {
    if (options.sceneIndex > 0) {
      ctx.fail("--scene " + std::to_string(options.sceneIndex), "the file has no scenes");
    }
    // The spec allows a file without scenes; drawing every root node is what viewers do.
    std::vector<char> isChild(model.nodes.size(), 0);
    for (const tinygltf::Node& node : model.nodes) {
      for (int child : node.children) {
        if (child >= 0 && static_cast<std::size_t>(child) < isChild.size()) {
          isChild[static_cast<std::size_t>(child)] = 1;
        }
      }
    }
    std::vector<int> roots;
    for (std::size_t i = 0; i < model.nodes.size(); ++i) {
      if (!isChild[i]) roots.push_back(static_cast<int>(i));
    }
    if (!model.nodes.empty()) {
      ctx.warn("the file has no scenes; drawing all " + plural(roots.size(), "root node"));
    }
    return {roots, "nodes"};
  }
  const int index = chosen ? options.sceneIndex : std::max(model.defaultScene, 0);
  if (static_cast<std::size_t>(index) >= model.scenes.size()) {
    ctx.fail(chosen ? "--scene " + std::to_string(index) : "scene " + std::to_string(index),
             "the file has " + plural(model.scenes.size(), "scene"));
  }
  ctx.scene.source.sceneIndex = index;
  const std::string object = at("scenes", static_cast<std::size_t>(index));
  return {model.scenes[static_cast<std::size_t>(index)].nodes, object + ".nodes"};
}

void addNodes(Context& ctx, const std::vector<int>& roots, const std::string& rootsObject) {
  SceneBuilder(ctx).traverse(roots, rootsObject);
}

}  // namespace omnishadow::gltf_detail
