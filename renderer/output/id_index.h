#pragma once

#include <nlohmann/json.hpp>

#include "renderer/scene/scene.h"

namespace omnishadow {

// What the objectId and materialId AOV values stand for: {"objectId": [{id, node, mesh}...],
// "materialId": [{id, name}...] (the last is the default material), "background": -1}. The CLI
// writes it as "<aov stem>.ids.json"; the Python module returns it as a dict.
nlohmann::ordered_json idIndex(const Scene& scene);

}  // namespace omnishadow
