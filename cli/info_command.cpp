#include "cli/info_command.h"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "cli/info_motion.h"
#include "cli/malloc_heap.h"
#include "cli/render_job.h"
#include "cli/text_table.h"
#include "renderer/scene/gltf_loader.h"
#include "renderer/scene/light.h"
#include "renderer/scene/lights_loader.h"

namespace fs = std::filesystem;

namespace omnishadow::cli {
namespace {

using Json = nlohmann::ordered_json;

// Everything the report shows, gathered before anything is printed.
struct Info {
  std::string file;
  Scene scene;
  std::optional<LightSetup> setup;  // when a lights file was read
  std::vector<Light> lights;        // as a render would use them: glTF, then the file's
  std::vector<std::string> warnings;
  std::uint64_t triangles = 0, drawnTriangles = 0, vertices = 0;
};

Info gather(const InfoOptions& o, std::vector<std::string>& warnings) {
  Info info;
  info.file = o.input.scene;
  const fs::path scenePath(o.input.scene);
  const fs::path lightsPath =
      o.input.lights.empty() ? defaultLightsFile(scenePath) : fs::path(o.input.lights);
  GltfLoadOptions loadOptions;
  loadOptions.sceneIndex = o.input.sceneIndex;
  loadOptions.materialVariant = o.input.materialVariant;
  loadOptions.allowExternalUris = o.input.allowExternalUris;
  info.scene = loadGltf(scenePath, loadOptions);
  warnings.insert(warnings.end(), info.scene.warnings.begin(), info.scene.warnings.end());
  if (!lightsPath.empty()) info.setup = loadLightsFile(lightsPath, warnings);
  info.lights =
      mergeLights(info.scene.lights, info.setup ? info.setup->lights : std::vector<Light>{});
  if (info.lights.empty())
    warnings.push_back(
        "no lights in the scene or a lights file: render uses a headlight at the camera");
  info.warnings = warnings;

  for (const Mesh& mesh : info.scene.meshes) {
    info.triangles += mesh.indices.size() / 3;
    info.vertices += mesh.positions.size();
  }
  for (const MeshInstance& instance : info.scene.instances)
    info.drawnTriangles +=
        info.scene.meshes[static_cast<std::size_t>(instance.mesh)].indices.size() / 3;
  return info;
}

// ---------------------------------------------------------------------------------------------
// Values as both formats show them

Json vec3(const glm::vec3& v) {
  return Json::array({jsonNumber(v.x), jsonNumber(v.y), jsonNumber(v.z)});
}

Json stringOrNull(const std::string& text) {
  return text.empty() ? Json(nullptr) : Json(text);
}

// Six significant digits: enough to read, and free of float noise (0.55, not 0.5500001).
std::string readable(float value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%g", static_cast<double>(value));
  return buffer;
}

std::string text(const glm::vec3& v) {
  return "(" + readable(v.x) + ", " + readable(v.y) + ", " + readable(v.z) + ")";
}

// The lights file's environment light as it will light the frame (null: none).
Json environmentJson(const std::optional<EnvironmentLight>& environment) {
  if (!environment) return Json(nullptr);
  const EnvironmentLight& e = *environment;
  return Json{{"image", e.image.empty() ? Json(nullptr) : Json(e.image.string())},
              {"color", vec3(e.color)},
              {"intensity", jsonNumber(e.intensity)},
              {"rotation", jsonNumber(glm::degrees(e.rotation))},
              {"background", e.background},
              {"sun", e.sun}};
}

std::string environmentText(const EnvironmentLight& e) {
  return (e.image.empty() ? std::string("uniform") : e.image.string()) + ", color " +
         text(e.color) + ", intensity " + readable(e.intensity) + ", rotation " +
         readable(glm::degrees(e.rotation)) + " degrees" + (e.background ? ", background" : "") +
         (e.sun ? ", sun as a light" : "");
}

// The lights file's ambient occlusion as the scene's frames use it: the radius resolved.
Json ambientOcclusionJson(const std::optional<AmbientOcclusion>& occlusion, const Bounds& bounds) {
  if (!occlusion) return Json(nullptr);
  return Json{{"radius", jsonNumber(effectiveRadius(*occlusion, bounds))},
              {"radiusFromScene", !(occlusion->radius > 0.0f)},
              {"strength", jsonNumber(occlusion->strength)}};
}

std::string ambientOcclusionText(const AmbientOcclusion& occlusion, const Bounds& bounds) {
  return "radius " + readable(effectiveRadius(occlusion, bounds)) +
         (occlusion.radius > 0.0f ? ""
                                  : " (" + readable(100.0f * kDefaultAmbientOcclusionShare) +
                                        "% of the scene's diagonal)") +
         ", strength " + readable(occlusion.strength);
}

std::string quoted(const std::string& name) {
  return name.empty() ? "(unnamed)" : "\"" + name + "\"";
}

// Degrees to six significant digits: a yfov of pi/6 in a float is 30, not 30.000002.
float degrees(float radians) {
  return std::strtof(readable(radians * 57.295779513082320876f).c_str(), nullptr);
}

// glTF's spelling, in the order of AlphaMode.
const char* toString(AlphaMode mode) {
  static const char* const names[] = {"OPAQUE", "MASK", "BLEND"};
  return names[static_cast<int>(mode)];
}

// How a material is shaded: the core model or the extension that replaces it.
const char* shadingModel(const Material& m) {
  return m.unlit ? "unlit" : m.specularGlossiness ? "specularGlossiness" : "metallicRoughness";
}

// A material's texture slots in the order the report lists them.
std::vector<std::pair<const char*, const TextureSlot*>> textureSlots(const Material& m) {
  return {{"baseColor", &m.baseColorTexture},
          {"metallicRoughness", &m.metallicRoughnessTexture},
          {"normal", &m.normalTexture},
          {"occlusion", &m.occlusionTexture},
          {"emissive", &m.emissiveTexture}};
}

// A texture slot as the report gives it: the texture index, or null for none.
Json textureIndex(const TextureSlot& slot) {
  return slot.texture >= 0 ? Json(slot.texture) : Json(nullptr);
}

// KHR_materials_sheen as the report gives it: null for a material drawn without a sheen.
Json sheenJson(const Material& m) {
  if (!hasSheen(m)) return nullptr;
  return {{"colorFactor",
           Json::array({jsonNumber(m.sheenColorFactor.r), jsonNumber(m.sheenColorFactor.g),
                        jsonNumber(m.sheenColorFactor.b)})},
          {"roughnessFactor", jsonNumber(m.sheenRoughnessFactor)},
          {"colorTexture", textureIndex(m.sheenColorTexture)},
          {"roughnessTexture", textureIndex(m.sheenRoughnessTexture)}};
}

// KHR_materials_specular as the report gives it: null for a material shaded without it.
Json specularJson(const Material& m) {
  if (!hasDielectricSpecular(m)) return nullptr;
  return {{"factor", jsonNumber(m.specularWeight)},
          {"colorFactor",
           Json::array({jsonNumber(m.specularColorFactor.r), jsonNumber(m.specularColorFactor.g),
                        jsonNumber(m.specularColorFactor.b)})},
          {"texture", textureIndex(m.specularTexture)},
          {"colorTexture", textureIndex(m.specularColorTexture)}};
}

// KHR_materials_clearcoat as the report gives it: null for a material drawn without the layer.
Json clearcoatJson(const Material& m) {
  if (!hasClearcoat(m)) return nullptr;
  return {{"factor", jsonNumber(m.clearcoatFactor)},
          {"roughnessFactor", jsonNumber(m.clearcoatRoughnessFactor)},
          {"texture", textureIndex(m.clearcoatTexture)},
          {"roughnessTexture", textureIndex(m.clearcoatRoughnessTexture)},
          {"normalTexture", textureIndex(m.clearcoatNormalTexture)},
          {"normalScale", jsonNumber(m.clearcoatNormalScale)}};
}

// KHR_materials_transmission as the report gives it: null without a transmission factor; the
// surface is drawn see-through where hasTransmission() says so, and tints shadows either way.
Json transmissionJson(const Material& m) {
  if (!(m.transmissionFactor > 0.0f)) return nullptr;
  return {{"factor", jsonNumber(m.transmissionFactor)},
          {"texture", textureIndex(m.transmissionTexture)},
          {"seeThrough", hasTransmission(m)}};
}

// KHR_materials_volume as the report gives it: null without a thickness (a thin wall); an
// infinite attenuation distance (the default) is null.
Json volumeJson(const Material& m) {
  if (!(m.thicknessFactor > 0.0f)) return nullptr;
  return {
      {"thicknessFactor", jsonNumber(m.thicknessFactor)},
      {"thicknessTexture", textureIndex(m.thicknessTexture)},
      {"attenuationDistance",
       std::isfinite(m.attenuationDistance) ? jsonNumber(m.attenuationDistance) : Json(nullptr)},
      {"attenuationColor",
       Json::array({jsonNumber(m.attenuationColor.r), jsonNumber(m.attenuationColor.g),
                    jsonNumber(m.attenuationColor.b)})},
      {"dispersion", jsonNumber(m.dispersion)},
      {"drawn", hasVolume(m)}};
}

// KHR_materials_anisotropy as the report gives it: null for a material drawn without it.
Json anisotropyJson(const Material& m) {
  if (!hasAnisotropy(m)) return nullptr;
  return {{"strength", jsonNumber(m.anisotropyStrength)},
          {"rotation", jsonNumber(m.anisotropyRotation)},
          {"texture", textureIndex(m.anisotropyTexture)}};
}

// KHR_materials_iridescence as the report gives it: null for a material drawn without a film.
Json iridescenceJson(const Material& m) {
  if (!hasIridescence(m)) return nullptr;
  return {{"factor", jsonNumber(m.iridescenceFactor)},
          {"texture", textureIndex(m.iridescenceTexture)},
          {"ior", jsonNumber(m.iridescenceIor)},
          {"thicknessMinimum", jsonNumber(m.iridescenceThicknessMinimum)},
          {"thicknessMaximum", jsonNumber(m.iridescenceThicknessMaximum)},
          {"thicknessTexture", textureIndex(m.iridescenceThicknessTexture)}};
}

// KHR_materials_diffuse_transmission as the report gives it: null for a material drawn
// without it.
Json diffuseTransmissionJson(const Material& m) {
  if (!hasDiffuseTransmission(m)) return nullptr;
  const glm::vec3& c = m.diffuseTransmissionColorFactor;
  return {{"factor", jsonNumber(m.diffuseTransmissionFactor)},
          {"texture", textureIndex(m.diffuseTransmissionTexture)},
          {"colorFactor", Json::array({jsonNumber(c.r), jsonNumber(c.g), jsonNumber(c.b)})},
          {"colorTexture", textureIndex(m.diffuseTransmissionColorTexture)}};
}

glm::vec3 cameraPosition(const Camera& camera) {
  return glm::vec3(camera.world[3]);
}

glm::vec3 cameraDirection(const Camera& camera) {
  const glm::vec3 d = glm::mat3(camera.world) * glm::vec3(0.0f, 0.0f, -1.0f);
  return glm::length(d) > 0.0f ? glm::normalize(d) : d;
}

bool hasPosition(const Light& light) {
  return light.type != LightType::Directional;
}

bool hasDirection(const Light& light) {
  return light.type != LightType::Point;
}

// ---------------------------------------------------------------------------------------------
// JSON

Json toJson(const Info& info) {
  const Scene& scene = info.scene;
  const SourceSummary& source = scene.source;
  Json doc;
  doc["file"] = info.file;
  doc["format"] = source.format;
  doc["asset"] = {{"version", stringOrNull(source.version)},
                  {"minVersion", stringOrNull(source.minVersion)},
                  {"generator", stringOrNull(source.generator)},
                  {"copyright", stringOrNull(source.copyright)}};
  Json extensions = Json::array();
  for (const ExtensionUse& e : source.extensions) {
    extensions.push_back({{"name", e.name},
                          {"required", e.required},
                          {"supported", e.supported},
                          {"drawnInstead", e.supported ? Json(nullptr) : Json(e.drawnInstead)}});
  }
  doc["extensions"] = extensions;
  doc["scene"] = {{"index", source.sceneIndex >= 0 ? Json(source.sceneIndex) : Json(nullptr)},
                  {"count", source.sceneCount}};
  doc["materialVariants"] = {
      {"names", source.materialVariants},
      {"drawn", source.materialVariant >= 0 ? Json(source.materialVariant) : Json(nullptr)}};
  doc["counts"] = {
      {"nodes",
       {{"file", source.fileNodes},
        {"reached", source.reachedNodes},
        {"hidden", source.hiddenNodes}}},
      {"meshes", source.gltfMeshes},
      {"primitives", {{"file", source.gltfPrimitives}, {"drawn", scene.meshes.size()}}},
      {"instances", scene.instances.size()},
      {"triangles", info.triangles},
      {"drawnTriangles", info.drawnTriangles},
      {"vertices", info.vertices},
      {"materials", scene.materials.size()},
      {"textures", scene.textures.size()},
      {"images", scene.images.size()},
      {"cameras", scene.cameras.size()},
      {"lights", info.lights.size()}};
  if (scene.bounds.empty()) {
    doc["bounds"] = nullptr;
  } else {
    const Bounds& b = scene.bounds;
    doc["bounds"] = {{"min", vec3(b.min)},
                     {"max", vec3(b.max)},
                     {"center", vec3(b.center())},
                     {"size", vec3(b.max - b.min)}};
  }

  Json materials = Json::array();
  for (std::size_t i = 0; i < scene.materials.size(); ++i) {
    const Material& m = scene.materials[i];
    Json textures = Json::object();
    for (const auto& [slot, texture] : textureSlots(m)) textures[slot] = textureIndex(*texture);
    materials.push_back({{"index", i},
                         {"name", m.name},
                         {"alphaMode", toString(m.alphaMode)},
                         {"alphaCutoff", m.alphaMode == AlphaMode::Mask ? jsonNumber(m.alphaCutoff)
                                                                        : Json(nullptr)},
                         {"doubleSided", m.doubleSided},
                         {"model", shadingModel(m)},
                         {"textures", textures},
                         {"ior", jsonNumber(m.ior)},
                         {"specular", specularJson(m)},
                         {"sheen", sheenJson(m)},
                         {"clearcoat", clearcoatJson(m)},
                         {"transmission", transmissionJson(m)},
                         {"volume", volumeJson(m)},
                         {"anisotropy", anisotropyJson(m)},
                         {"iridescence", iridescenceJson(m)},
                         {"diffuseTransmission", diffuseTransmissionJson(m)}});
  }
  doc["materials"] = materials;

  Json textures = Json::array();
  for (std::size_t i = 0; i < scene.textures.size(); ++i) {
    const int image = scene.textures[i].image;
    Json imageJson = nullptr;
    if (image >= 0) {
      const Image& im = scene.images[static_cast<std::size_t>(image)];
      imageJson = {{"index", image},
                   {"name", im.name},
                   {"width", im.width},
                   {"height", im.height},
                   {"format", im.format}};
    }
    textures.push_back({{"index", i}, {"image", imageJson}});
  }
  doc["textures"] = textures;

  Json cameras = Json::array();
  for (const Camera& c : scene.cameras) {
    const Json none = nullptr;
    cameras.push_back({{"index", c.index},
                       {"name", c.name},
                       {"node", c.nodeName},
                       {"type", c.orthographic ? "orthographic" : "perspective"},
                       {"yfovDegrees", c.orthographic ? none : jsonNumber(degrees(c.yfov))},
                       {"aspectRatio",
                        !c.orthographic && c.aspectRatio > 0.0f ? jsonNumber(c.aspectRatio) : none},
                       {"xmag", c.orthographic ? jsonNumber(c.xmag) : none},
                       {"ymag", c.orthographic ? jsonNumber(c.ymag) : none},
                       {"znear", jsonNumber(c.znear)},
                       {"zfar", c.zfar > 0.0f ? jsonNumber(c.zfar) : none},
                       {"position", vec3(cameraPosition(c))},
                       {"direction", vec3(cameraDirection(c))}});
  }
  doc["cameras"] = cameras;

  Json lights = Json::array();
  for (const Light& l : info.lights) {
    const Json none = nullptr;
    const bool spot = l.type == LightType::Spot;
    lights.push_back({{"name", l.name},
                      {"type", toString(l.type)},
                      {"source", l.origin},
                      {"position", hasPosition(l) ? vec3(l.position) : none},
                      {"direction", hasDirection(l) ? vec3(l.direction) : none},
                      {"color", vec3(l.color)},
                      {"intensity", jsonNumber(l.intensity)},
                      {"range", l.range > 0.0f ? jsonNumber(l.range) : none},
                      {"innerConeAngle", spot ? jsonNumber(l.innerConeAngle) : none},
                      {"outerConeAngle", spot ? jsonNumber(l.outerConeAngle) : none},
                      {"shadow",
                       {{"enabled", l.shadow.enabled},
                        {"resolution", l.shadow.resolution},
                        {"filter", toString(l.shadow.filter)},
                        {"near", l.shadow.near > 0.0f ? jsonNumber(l.shadow.near) : none},
                        {"far", l.shadow.far > 0.0f ? jsonNumber(l.shadow.far) : none},
                        {"bias", jsonNumber(l.shadow.bias)},
                        {"slopeBias", jsonNumber(l.shadow.slopeBias)}}}});
  }
  doc["lights"] = lights;
  doc["ambient"] = info.setup ? vec3(info.setup->ambient) : Json(nullptr);
  doc["environment"] = info.setup ? environmentJson(info.setup->environment) : Json(nullptr);
  doc["ambientOcclusion"] =
      info.setup ? ambientOcclusionJson(info.setup->ambientOcclusion, scene.bounds) : Json(nullptr);
  doc["animations"] = animationsJson(scene.rig);
  doc["skins"] = skinsJson(scene.rig);
  doc["morphTargets"] = morphTargetsJson(scene.rig);
  doc["warnings"] = info.warnings;
  return doc;
}

// ---------------------------------------------------------------------------------------------
// Text

void printInfoLine(const char* label, const std::string& value) {
  std::printf("%-11s %s\n", label, value.c_str());
}

std::string plural(std::uint64_t count, const std::string& noun, const std::string& nouns) {
  return std::to_string(count) + " " + (count == 1 ? noun : nouns);
}

void printText(const Info& info) {
  const Scene& scene = info.scene;
  const SourceSummary& source = scene.source;
  printInfoLine("file", info.file);
  std::string format = source.format + ", glTF " + (source.version.empty() ? "?" : source.version);
  if (!source.generator.empty()) format += ", generator \"" + source.generator + "\"";
  printInfoLine("format", format);
  printInfoLine("extensions", source.extensions.empty() ? std::string("none")
                                                        : std::to_string(source.extensions.size()));
  TextTable extensionRows;
  for (const ExtensionUse& e : source.extensions) {
    extensionRows.push_back(
        {e.name, e.required ? "required" : "used",
         e.supported ? "supported" : "not supported: drawn instead: " + e.drawnInstead});
  }
  printTable(extensionRows);
  printInfoLine("scene",
                (source.sceneIndex >= 0 ? std::to_string(source.sceneIndex) : "none") + " (" +
                    plural(static_cast<std::uint64_t>(source.sceneCount), "scene", "scenes") +
                    " in the file)");
  if (!source.materialVariants.empty()) {
    std::string names;
    for (const std::string& name : source.materialVariants)
      names += (names.empty() ? "" : ", ") + quoted(name);
    printInfoLine(
        "variants",
        std::to_string(source.materialVariants.size()) + " (" + names + "); drawn: " +
            (source.materialVariant >= 0
                 ? quoted(source.materialVariants[static_cast<std::size_t>(source.materialVariant)])
                 : std::string("the default materials")));
  }
  printInfoLine("nodes", std::to_string(source.fileNodes) + " in the file, " +
                             std::to_string(source.reachedNodes) + " reached from the scene" +
                             (source.hiddenNodes > 0 ? ", " + std::to_string(source.hiddenNodes) +
                                                           " of them hidden (KHR_node_visibility)"
                                                     : std::string()));
  printInfoLine(
      "meshes",
      plural(static_cast<std::uint64_t>(source.gltfMeshes), "glTF mesh", "glTF meshes") + ", " +
          plural(static_cast<std::uint64_t>(source.gltfPrimitives), "primitive", "primitives") +
          " (" + std::to_string(scene.meshes.size()) + " drawn)");
  printInfoLine("instances", std::to_string(scene.instances.size()));
  printInfoLine("triangles", std::to_string(info.triangles) + " unique, " +
                                 std::to_string(info.drawnTriangles) + " drawn");
  printInfoLine("vertices", std::to_string(info.vertices));
  if (scene.bounds.empty()) {
    printInfoLine("bounds", "empty");
  } else {
    const Bounds& b = scene.bounds;
    printInfoLine("bounds", "min " + text(b.min) + "  max " + text(b.max));
    printInfoLine("", "center " + text(b.center()) + "  size " + text(b.max - b.min));
  }

  printInfoLine("materials", std::to_string(scene.materials.size()));
  TextTable rows;
  for (std::size_t i = 0; i < scene.materials.size(); ++i) {
    const Material& m = scene.materials[i];
    std::string alpha = toString(m.alphaMode);
    if (m.alphaMode == AlphaMode::Mask) alpha += " " + readable(m.alphaCutoff);
    std::string textures;
    for (const auto& [slot, texture] : textureSlots(m))
      if (texture->texture >= 0)
        textures += (textures.empty() ? "" : " ") + std::string(slot) + "=" +
                    std::to_string(texture->texture);
    rows.push_back({std::to_string(i), quoted(m.name), alpha,
                    m.doubleSided ? "double-sided" : "single-sided",
                    textures.empty() ? "no textures" : "textures " + textures});
    // Only materials an extension reshades say so, keeping the common rows short.
    if (m.unlit || m.specularGlossiness) rows.back().push_back(shadingModel(m));
    if (m.ior != 1.5f) rows.back().push_back("ior " + readable(m.ior));
    if (hasDielectricSpecular(m))
      rows.back().push_back(
          "specular " + readable(m.specularWeight) + " color " + readable(m.specularColorFactor.r) +
          "," + readable(m.specularColorFactor.g) + "," + readable(m.specularColorFactor.b));
    if (hasSheen(m))
      rows.back().push_back("sheen " + readable(m.sheenColorFactor.r) + "," +
                            readable(m.sheenColorFactor.g) + "," + readable(m.sheenColorFactor.b) +
                            " roughness " + readable(m.sheenRoughnessFactor));
    if (hasClearcoat(m))
      rows.back().push_back("clearcoat " + readable(m.clearcoatFactor) + " roughness " +
                            readable(m.clearcoatRoughnessFactor));
    if (m.transmissionFactor > 0.0f)
      rows.back().push_back("transmission " + readable(m.transmissionFactor) +
                            (hasTransmission(m) ? "" : " (shadows only)"));
    if (m.thicknessFactor > 0.0f)
      rows.back().push_back("volume thickness " + readable(m.thicknessFactor) +
                            (hasVolume(m) ? "" : " (not drawn)"));
    if (hasAnisotropy(m))
      rows.back().push_back("anisotropy " + readable(m.anisotropyStrength) + " rotation " +
                            readable(m.anisotropyRotation));
    if (hasIridescence(m))
      rows.back().push_back("iridescence " + readable(m.iridescenceFactor) + " ior " +
                            readable(m.iridescenceIor) + " thickness " +
                            readable(m.iridescenceThicknessMinimum) + "-" +
                            readable(m.iridescenceThicknessMaximum));
    if (hasDiffuseTransmission(m))
      rows.back().push_back("diffuse transmission " + readable(m.diffuseTransmissionFactor));
  }
  printTable(rows);

  printInfoLine("textures", std::to_string(scene.textures.size()) + " (" +
                                plural(scene.images.size(), "image", "images") + ")");
  rows.clear();
  for (std::size_t i = 0; i < scene.textures.size(); ++i) {
    const int image = scene.textures[i].image;
    if (image < 0) {
      rows.push_back({std::to_string(i), "no image"});
      continue;
    }
    const Image& im = scene.images[static_cast<std::size_t>(image)];
    rows.push_back({std::to_string(i), "image " + std::to_string(image), quoted(im.name),
                    std::to_string(im.width) + "x" + std::to_string(im.height), im.format});
  }
  printTable(rows);

  printInfoLine("cameras", std::to_string(scene.cameras.size()));
  rows.clear();
  for (const Camera& c : scene.cameras) {
    const std::string lens = c.orthographic
                                 ? "xmag " + readable(c.xmag) + " ymag " + readable(c.ymag)
                                 : "yfov " + readable(degrees(c.yfov)) + " deg";
    rows.push_back({std::to_string(c.index), quoted(c.name),
                    c.orthographic ? "orthographic" : "perspective", lens,
                    "at " + text(cameraPosition(c))});
  }
  printTable(rows);

  printInfoLine("lights", std::to_string(info.lights.size()));
  rows.clear();
  for (const Light& l : info.lights) {
    std::string where;
    if (hasPosition(l)) where = "at " + text(l.position);
    if (hasDirection(l))
      where += (where.empty() ? "" : " ") + std::string("dir ") + text(l.direction);
    const std::string shadow = l.shadow.enabled ? "shadow " + std::to_string(l.shadow.resolution) +
                                                      " " + toString(l.shadow.filter)
                                                : "no shadow";
    rows.push_back({quoted(l.name), toString(l.type), l.origin, where, "color " + text(l.color),
                    "intensity " + readable(l.intensity),
                    l.range > 0.0f ? "range " + readable(l.range) : "range unlimited", shadow});
  }
  printTable(rows);
  printInfoLine("ambient", info.setup ? text(info.setup->ambient) + " (lights file)"
                                      : "none (no lights file)");
  if (info.setup && info.setup->environment)
    printInfoLine("environment", environmentText(*info.setup->environment));
  if (info.setup && info.setup->ambientOcclusion)
    printInfoLine("ambient occlusion",
                  ambientOcclusionText(*info.setup->ambientOcclusion, scene.bounds));

  printMotion(scene.rig);
  printInfoLine("warnings", std::to_string(info.warnings.size()));
  for (const std::string& warning : info.warnings) std::printf("  %s\n", warning.c_str());
}

}  // namespace

void addInfoCommand(CLI::App& app, InfoOptions& o) {
  CLI::App* info = app.add_subcommand(
      "info", "Describe a glTF scene and its lights as a render would use them (no GL needed)");
  addSceneInputOptions(*info, o.input, SceneInputCommand::Info);
  info->add_flag("--json", o.json, "Print one JSON object (schema in the README)");
}

int runInfo(const InfoOptions& o) {
  // The scene's buffers and images are large blocks: the heap set up as for a batch
  // (cli/malloc_heap.h). Sundial took 70-80 ms with malloc as the system has it and 30-40 ms so
  // set up.
  setUpMallocHeap();
  // As in render: the warnings so far may explain a failure.
  return runPrintingWarnings([&](std::vector<std::string>& warnings) {
    const Info info = gather(o, warnings);
    if (o.json)
      std::printf("%s\n", toJson(info).dump(2, ' ', false, Json::error_handler_t::replace).c_str());
    else
      printText(info);
    return 0;
  });
}

}  // namespace omnishadow::cli
