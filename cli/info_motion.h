#pragma once

#include <nlohmann/json.hpp>

#include "renderer/scene/scene.h"

namespace omnishadow::cli {

// What `info` says about a scene's motion: its animations (name, channels, start, end,
// duration), skins (joint counts) and meshes with morph targets.
nlohmann::ordered_json animationsJson(const SceneRig& rig);
nlohmann::ordered_json skinsJson(const SceneRig& rig);
nlohmann::ordered_json morphTargetsJson(const SceneRig& rig);

// The same as the text report's "animations", "skins" and "morph" sections.
void printMotion(const SceneRig& rig);

}  // namespace omnishadow::cli
