#include "renderer/output/annotation_masks.h"

#include <algorithm>
#include <limits>
#include <map>

#include "renderer/core/errors.h"
#include "renderer/output/png_encoder.h"
#include "renderer/view/instance_coverage.h"

namespace omnishadow {
namespace {

struct InstanceStats {
  std::size_t pixels = 0;
  int xmin = std::numeric_limits<int>::max(), ymin = std::numeric_limits<int>::max();
  int xmax = -1, ymax = -1;  // exclusive
};

std::string gltfMeshName(const Mesh& mesh) {
  return mesh.name.substr(0, mesh.name.rfind('/'));  // Mesh::name is "<mesh name>/<primitive>"
}

}  // namespace

std::string instanceClass(const Scene& scene, const MeshInstance& instance) {
  if (!instance.className.empty()) return instance.className;
  if (!instance.nodeName.empty()) return instance.nodeName;
  const std::string mesh = gltfMeshName(scene.meshes[static_cast<std::size_t>(instance.mesh)]);
  return mesh.empty() ? "node " + std::to_string(instance.node) : mesh;
}

void checkMaskInstances(const Scene& scene, const std::string& source) {
  static_assert(kMaxMaskInstances == std::numeric_limits<std::uint16_t>::max());
  if (scene.instances.size() <= kMaxMaskInstances) return;
  throw InputError((source.empty() ? "" : source + ": ") + "--masks: the scene has " +
                   std::to_string(scene.instances.size()) +
                   " mesh instances, more than the 65535 a 16-bit mask holds");
}

AnnotationMasks annotationMasks(const Scene& scene, const ViewCamera& camera,
                                const FloatImage& aovs) {
  const int objectChannel = aovs.channelIndex("objectId");
  if (objectChannel < 0) throw RenderError("annotation masks need the objectId AOV layer");
  checkMaskInstances(scene);
  // Classes numbered 1.. in name order, so that ids do not depend on the instances' order.
  std::map<std::string, int> classIds;
  for (const MeshInstance& instance : scene.instances) classIds[instanceClass(scene, instance)];
  int nextClass = 1;
  for (auto& [name, id] : classIds) id = nextClass++;

  AnnotationMasks masks;
  masks.width = aovs.width;
  masks.height = aovs.height;
  const std::size_t pixelCount = static_cast<std::size_t>(aovs.width) * aovs.height;
  masks.instances.assign(pixelCount, 0);
  masks.classes.assign(pixelCount, 0);
  std::vector<InstanceStats> stats(scene.instances.size());
  std::vector<int> instanceClassId(scene.instances.size());
  for (std::size_t i = 0; i < scene.instances.size(); ++i)
    instanceClassId[i] = classIds[instanceClass(scene, scene.instances[i])];
  for (int y = 0; y < aovs.height; ++y)
    for (int x = 0; x < aovs.width; ++x) {
      const float value = aovs.at(x, y, objectChannel);
      if (!(value >= 0.0f) || value >= static_cast<float>(scene.instances.size())) continue;
      const auto object = static_cast<std::size_t>(value);
      const std::size_t pixel = static_cast<std::size_t>(y) * aovs.width + x;
      masks.instances[pixel] = static_cast<std::uint16_t>(object + 1);
      masks.classes[pixel] = static_cast<std::uint16_t>(instanceClassId[object]);
      InstanceStats& s = stats[object];
      ++s.pixels;
      s.xmin = std::min(s.xmin, x);
      s.ymin = std::min(s.ymin, y);
      s.xmax = std::max(s.xmax, x + 1);
      s.ymax = std::max(s.ymax, y + 1);
    }

  nlohmann::ordered_json& index = masks.index;
  index["instances"] = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < scene.instances.size(); ++i) {
    const MeshInstance& instance = scene.instances[i];
    const Mesh& mesh = scene.meshes[static_cast<std::size_t>(instance.mesh)];
    const std::size_t material =
        mesh.material >= 0 ? static_cast<std::size_t>(mesh.material) : scene.materials.size();
    const InstanceStats& s = stats[i];
    const std::size_t unoccluded = coveredPixelCount(scene, instance, camera);
    nlohmann::ordered_json entry;
    entry["id"] = i + 1;
    entry["objectId"] = i;
    entry["node"] = instance.node;
    entry["nodeName"] = instance.nodeName;
    entry["mesh"] = gltfMeshName(mesh);
    entry["material"] =
        material < scene.materials.size() ? scene.materials[material].name : "(default)";
    entry["materialId"] = material;
    entry["class"] = instanceClass(scene, instance);
    entry["classId"] = instanceClassId[i];
    entry["pixels"] = s.pixels;
    entry["bbox"] = s.pixels ? nlohmann::ordered_json{s.xmin, s.ymin, s.xmax, s.ymax}
                             : nlohmann::ordered_json(nullptr);
    entry["unoccludedPixels"] = unoccluded;
    entry["visibleFraction"] =
        unoccluded ? nlohmann::ordered_json(std::min(1.0, double(s.pixels) / double(unoccluded)))
                   : nlohmann::ordered_json(nullptr);
    index["instances"].push_back(std::move(entry));
  }
  index["classes"] = nlohmann::ordered_json::array();
  for (const auto& [name, id] : classIds) index["classes"].push_back({{"id", id}, {"name", name}});
  index["background"] = 0;
  return masks;
}

std::vector<std::filesystem::path> annotationMaskFiles(const std::filesystem::path& stem) {
  return {stem.string() + ".instances.png", stem.string() + ".semantic.png",
          stem.string() + ".masks.json"};
}

EncodedAnnotationMasks encodeAnnotationMasks(const AnnotationMasks& masks) {
  return {encodePng16(masks.width, masks.height, masks.instances),
          encodePng16(masks.width, masks.height, masks.classes), masks.index.dump(2) + "\n"};
}

void writeAnnotationMasks(const EncodedAnnotationMasks& files, const std::filesystem::path& stem,
                          OutputTransaction& transaction) {
  const std::vector<std::filesystem::path> paths = annotationMaskFiles(stem);
  writeFileBytes(transaction.stage(paths[0]), files.instances);
  writeFileBytes(transaction.stage(paths[1]), files.semantic);
  writeFileBytes(transaction.stage(paths[2]), files.index);
}

}  // namespace omnishadow
