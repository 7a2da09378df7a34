#include "renderer/scene/gltf_loader.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "renderer/scene/gltf_context.h"
#include "renderer/scene/gltf_extension_policy.h"
#include "renderer/scene/gltf_material_variants.h"
#include "renderer/scene/gltf_materials.h"
#include "renderer/scene/gltf_nodes.h"
#include "renderer/scene/gltf_reader.h"
#include "renderer/scene/gltf_rig.h"
#include "renderer/scene/scene_pose.h"

// The loader's steps live beside it: gltf_reader (the file, .glb container), gltf_file_safety
// (URI policy, image size caps), gltf_extension_policy (which extensions are refused or
// ignored; the table is gltf_extensions), gltf_accessors, gltf_materials (images, textures,
// materials; their extensions in gltf_material_extensions),
// gltf_primitives (meshes) and gltf_nodes (hierarchy, cameras, lights). Geometry extensions:
// gltf_compressed_json (what tinygltf cannot parse in compressed files), gltf_draco,
// gltf_meshopt, gltf_instancing.

namespace omnishadow {

namespace {

using gltf_detail::Context;

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
  gltf_detail::CompressionFixups fixups;
  const tinygltf::Model model = gltf_detail::readModel(path, scene.path, scene.warnings, &binary,
                                                       options.allowExternalUris, fixups);
  scene.inputFiles = referencedFiles(path, model);
  scene.source = summarize(model, binary);
  Context ctx{scene.path, model, scene};
  ctx.fixups = std::move(fixups);
  ctx.decodedImages = options.decodedImages;
  ctx.quantized = std::find(model.extensionsUsed.begin(), model.extensionsUsed.end(),
                            "KHR_mesh_quantization") != model.extensionsUsed.end();
  checkMinVersion(ctx);
  scene.source.extensions = gltf_detail::checkExtensions(ctx);
  const auto [roots, rootsObject] = gltf_detail::sceneRoots(ctx, options);
  gltf_detail::chooseMaterialVariant(ctx, options.materialVariant);
  gltf_detail::convertImages(ctx);
  gltf_detail::convertTextures(ctx);
  gltf_detail::convertMaterials(ctx);
  gltf_detail::readRig(ctx);
  gltf_detail::addNodes(ctx, roots, rootsObject);
  poseScene(scene, {});  // skins and default morph weights apply without a time too
  scene.revision = newSceneRevision();
  return scene;
}

}  // namespace omnishadow
