#pragma once

#include <optional>
#include <string>
#include <vector>

#include "renderer/scene/scene.h"

namespace omnishadow {

// The pose to draw: which clips play and when.
struct PoseRequest {
  // Seconds; nullopt = the rest pose: nothing animated, skins (with the joints' own
  // transforms) and the default morph weights still applied.
  std::optional<double> time;
  // Clips that play: a name, an index or "all"; empty = "all".
  std::string animation;
};

// The animations `selection` (name, index or "all"; empty = all) names, lowest index first.
// Throws InputError naming the file and its clips for a name or index it does not have.
std::vector<int> chooseAnimations(const Scene& scene, const std::string& selection);

// Poses `scene` (loaded by loadGltf()) in place from its rig: node transforms (animated at
// request.time, each clip clamped to its own start and end), then instance matrices, skinned
// and morphed vertices with their normals, tangents and bounds, cameras, glTF lights and the
// scene bounds; a scene whose meshes it deforms gets a new Scene::revision. Where two chosen clips
// animate the same property of a node, the lower index drives it; the others are named in the
// returned warning. Any pose can follow any other: the rig keeps the rest data. Throws InputError
// for an unknown clip.
std::vector<std::string> poseScene(Scene& scene, const PoseRequest& request);

// The checks of poseSceneChecked() on the request alone, for a caller that keeps the scene at
// rest as the loader posed it: an animation needs a time, the time must be finite.
void checkPoseRequest(std::optional<double> time, const std::string& animation);

// poseScene() with the checks both front ends make, in the CLI's words (--time, --animation):
// an animation needs a time, the time must be finite; a time given for a file without
// animations is a warning naming `file`. Returns poseScene()'s warnings, then that one.
std::vector<std::string> poseSceneChecked(Scene& scene, const std::string& file,
                                          std::optional<double> time, const std::string& animation);

}  // namespace omnishadow
