#include "renderer/output/id_index.h"

namespace omnishadow {

nlohmann::ordered_json idIndex(const Scene& scene) {
  nlohmann::ordered_json ids;
  ids["objectId"] = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < scene.instances.size(); ++i) {
    const MeshInstance& instance = scene.instances[i];
    ids["objectId"].push_back(
        {{"id", i}, {"node", instance.node}, {"mesh", scene.meshes[instance.mesh].name}});
  }
  ids["materialId"] = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < scene.materials.size(); ++i)
    ids["materialId"].push_back({{"id", i}, {"name", scene.materials[i].name}});
  ids["materialId"].push_back({{"id", scene.materials.size()}, {"name", "(default)"}});
  ids["background"] = -1;
  return ids;
}

}  // namespace omnishadow
