#include "tests/support/textured_triangle.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>

#include "scenes/builder/gltf_builder.h"
#include "tests/support/base64.h"

namespace omnishadow::test_support {

std::filesystem::path writeTexturedTriangle(const std::filesystem::path& folder,
                                            const std::vector<SceneImage>& images,
                                            ImageStorage storage, const std::string& stem) {
  builder::MeshData mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  mesh.uvs = {{0, 0}, {1, 0}, {0, 1}};
  mesh.indices = {0, 1, 2};
  builder::GltfBuilder builder;
  builder.addNode("node", {}, builder.addMesh(mesh));
  tinygltf::Model& model = builder.model();
  for (const SceneImage& image : images) {
    tinygltf::Image source;
    source.name = image.name;
    source.mimeType = image.mimeType;
    if (storage == ImageStorage::BufferView) {
      source.bufferView = builder::appendBufferView(model, image.bytes, 0, 0);
    } else {
      source.uri = image.fileName;
      std::ofstream(folder / image.fileName, std::ios::binary)
          .write(reinterpret_cast<const char*>(image.bytes.data()),
                 static_cast<std::streamsize>(image.bytes.size()));
    }
    const int index = static_cast<int>(model.images.size());
    tinygltf::Texture texture;
    if (image.viaExtension.empty()) {
      texture.source = index;
    } else {
      tinygltf::Value::Object extension{{"source", tinygltf::Value(index)}};
      texture.extensions[image.viaExtension] = tinygltf::Value(std::move(extension));
      for (auto* list : {&model.extensionsUsed, &model.extensionsRequired})
        if (std::find(list->begin(), list->end(), image.viaExtension) == list->end())
          list->push_back(image.viaExtension);
    }
    model.images.push_back(source);
    model.textures.push_back(texture);
  }
  const bool glb = storage == ImageStorage::BufferView;
  const std::filesystem::path path = folder / (stem + (glb ? ".glb" : ".gltf"));
  builder.write(path, glb ? builder::FileFormat::Glb : builder::FileFormat::GltfExternal);
  if (storage == ImageStorage::DataUri) {
    // The files written above become data: URIs (tinygltf writes only PNG and JPEG ones).
    nlohmann::json doc = nlohmann::json::parse(std::ifstream(path));
    for (std::size_t i = 0; i < images.size(); ++i) {
      doc["images"][i]["uri"] = "data:" + images[i].mimeType + ";base64," + base64(images[i].bytes);
      std::filesystem::remove(folder / images[i].fileName);
    }
    std::ofstream(path) << doc.dump();
  }
  return path;
}

}  // namespace omnishadow::test_support
