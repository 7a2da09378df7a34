#include "renderer/scene/gltf_loader.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <string>
#include <string_view>
#include <vector>

#include "renderer/scene/gltf_context.h"
#include "renderer/scene/gltf_materials.h"
#include "renderer/scene/gltf_nodes.h"
#include "renderer/scene/gltf_reader.h"

// The loader's steps live beside it: gltf_reader (the file, .glb container), gltf_file_safety
// (URI policy, image size caps), gltf_accessors, gltf_materials (images, textures, materials),
// gltf_primitives (meshes) and gltf_nodes (hierarchy, cameras, lights).

namespace omnishadow {

namespace {

using gltf_detail::Context;

// Extensions whose meaning we implement; anything else in extensionsRequired cannot be drawn
// correctly, anything else merely used is ignored with a warning.
constexpr std::string_view kSupportedExtensions[] = {"KHR_lights_punctual",
                                                     "KHR_materials_emissive_strength"};

void checkExtensions(const Context& ctx) {
  const auto supported = [](const std::string& name) {
    return std::find(std::begin(kSupportedExtensions), std::end(kSupportedExtensions), name) !=
           std::end(kSupportedExtensions);
  };
  for (const std::string& name : ctx.model.extensionsRequired) {
    if (!supported(name)) ctx.fail("extensionsRequired", name + " is not supported");
  }
  for (const std::string& name : ctx.model.extensionsUsed) {
    if (!supported(name)) ctx.warn("extensionsUsed: " + name + " is not supported; ignored");
  }
}

// asset.minVersion names the least glTF version a reader must implement: a 2.x reader cannot
// draw a file that needs 3.0 or 2.1 correctly.
void checkMinVersion(const Context& ctx) {
  const std::string& minVersion = ctx.model.asset.minVersion;
  if (minVersion.empty() || minVersion == "2.0") return;
  ctx.fail("asset.minVersion",
           "\"" + minVersion.substr(0, 20) + "\" is not supported; this renderer reads glTF 2.0");
}

// The files this scene reads: itself and the external (non data:) URIs of buffers and images.
std::vector<std::string> referencedFiles(const std::filesystem::path& path,
                                         const tinygltf::Model& model) {
  std::vector<std::string> files = {path.string()};
  auto add = [&](const std::string& uri) {
    if (uri.empty() || tinygltf::IsDataURI(uri)) return;
    files.push_back((path.parent_path() / uri).string());
  };
  for (const tinygltf::Buffer& buffer : model.buffers) add(buffer.uri);
  for (const tinygltf::Image& image : model.images) add(image.uri);
  return files;
}

SourceSummary summarize(const tinygltf::Model& model, bool binary) {
  SourceSummary source;
  source.format = binary ? "glb" : "gltf";
  source.version = model.asset.version;
  source.minVersion = model.asset.minVersion;
  source.generator = model.asset.generator;
  source.copyright = model.asset.copyright;
  source.sceneCount = static_cast<int>(model.scenes.size());
  source.fileNodes = static_cast<int>(model.nodes.size());
  source.gltfMeshes = static_cast<int>(model.meshes.size());
  for (const tinygltf::Mesh& mesh : model.meshes) {
    source.gltfPrimitives += static_cast<int>(mesh.primitives.size());
  }
  return source;
}

}  // namespace

Scene loadGltf(const std::filesystem::path& path, const GltfLoadOptions& options) {
  Scene scene;
  scene.path = path.string();
  bool binary = false;
  const tinygltf::Model model =
      gltf_detail::readModel(path, scene.path, scene.warnings, &binary, options.allowExternalUris);
  scene.inputFiles = referencedFiles(path, model);
  scene.source = summarize(model, binary);
  Context ctx{scene.path, model, scene};
  checkMinVersion(ctx);
  checkExtensions(ctx);
  const auto [roots, rootsObject] = gltf_detail::sceneRoots(ctx, options);
  gltf_detail::convertImages(ctx);
  gltf_detail::convertTextures(ctx);
  gltf_detail::convertMaterials(ctx);
  gltf_detail::addNodes(ctx, roots, rootsObject);
  return scene;
}

}  // namespace omnishadow
