#include "cli/info_motion.h"

#include <cstdio>
#include <string>

#include "cli/common_options.h"
#include "cli/text_table.h"

namespace omnishadow::cli {
namespace {

using Json = nlohmann::ordered_json;

std::string seconds(float value) {
  return shortestDecimal(value) + " s";
}

// "2 translation, 1 rotation": the animated properties of a clip's channels.
std::string channelSummary(const Animation& animation) {
  static const char* const names[] = {"translation", "rotation", "scale", "weights"};
  int counts[4] = {};
  for (const AnimationChannel& channel : animation.channels)
    ++counts[static_cast<int>(channel.property)];
  std::string text;
  for (int i = 0; i < 4; ++i)
    if (counts[i] > 0)
      text += (text.empty() ? "" : ", ") + std::to_string(counts[i]) + " " + names[i];
  return text.empty() ? "nothing playable" : text;
}

void printLine(const char* label, const std::string& value) {
  std::printf("%-11s %s\n", label, value.c_str());
}

}  // namespace

Json animationsJson(const SceneRig& rig) {
  Json list = Json::array();
  for (std::size_t i = 0; i < rig.animations.size(); ++i) {
    const Animation& a = rig.animations[i];
    list.push_back({{"index", i},
                    {"name", a.name},
                    {"channels", a.channels.size()},
                    {"start", jsonNumber(a.start)},
                    {"end", jsonNumber(a.end)},
                    {"duration", jsonNumber(a.end - a.start)}});
  }
  return list;
}

Json skinsJson(const SceneRig& rig) {
  Json list = Json::array();
  for (std::size_t i = 0; i < rig.skins.size(); ++i)
    list.push_back(
        {{"index", i}, {"name", rig.skins[i].name}, {"joints", rig.skins[i].joints.size()}});
  return list;
}

Json morphTargetsJson(const SceneRig& rig) {
  Json list = Json::array();
  for (const MorphTargetMesh& m : rig.morphTargetMeshes) {
    Json weights = Json::array();
    for (float w : m.weights) weights.push_back(jsonNumber(w));
    list.push_back(
        {{"mesh", m.mesh}, {"name", m.name}, {"targets", m.targets}, {"weights", weights}});
  }
  return list;
}

void printMotion(const SceneRig& rig) {
  printLine("animations", std::to_string(rig.animations.size()));
  TextTable rows;
  for (std::size_t i = 0; i < rig.animations.size(); ++i) {
    const Animation& a = rig.animations[i];
    rows.push_back({std::to_string(i), "\"" + a.name + "\"",
                    std::to_string(a.channels.size()) + " channels (" + channelSummary(a) + ")",
                    seconds(a.start) + " to " + seconds(a.end),
                    "duration " + seconds(a.end - a.start)});
  }
  printTable(rows);
  printLine("skins", std::to_string(rig.skins.size()));
  rows.clear();
  for (std::size_t i = 0; i < rig.skins.size(); ++i)
    rows.push_back({std::to_string(i), "\"" + rig.skins[i].name + "\"",
                    std::to_string(rig.skins[i].joints.size()) + " joints"});
  printTable(rows);
  printLine("morph", std::to_string(rig.morphTargetMeshes.size()) + " meshes with targets");
  rows.clear();
  for (const MorphTargetMesh& m : rig.morphTargetMeshes) {
    std::string weights;
    for (float w : m.weights) weights += (weights.empty() ? "" : ", ") + shortestDecimal(w);
    rows.push_back({"mesh " + std::to_string(m.mesh),
                    m.name.empty() ? "(unnamed)" : "\"" + m.name + "\"",
                    std::to_string(m.targets) + " targets",
                    m.weights.empty() ? "weights 0" : "weights [" + weights + "]"});
  }
  printTable(rows);
}

}  // namespace omnishadow::cli
