#pragma once

// A glTF scene of one triangle and the given image files, one texture each: what the image
// decoders' tests load.

#include <filesystem>
#include <string>
#include <vector>

namespace omnishadow::test_support {

enum class ImageStorage {
  BufferView,  // a .glb, each image in a bufferView of its own
  File,        // a .gltf, each image in a file of its own beside it
  DataUri,     // a .gltf, each image in a base64 data: URI of its mimeType
};

struct SceneImage {
  std::vector<unsigned char> bytes;  // the file's
  std::string name, mimeType;
  std::string fileName;  // where ImageStorage::File puts it, beside the scene
  // Set (say "EXT_texture_webp"): the texture names the image only through this extension's
  // `source`, and the file lists the extension as used and required.
  std::string viaExtension;
};

// Writes folder/<stem>.glb (BufferView) or folder/<stem>.gltf (File, DataUri) with one texture
// per image. Returns the scene's path.
std::filesystem::path writeTexturedTriangle(const std::filesystem::path& folder,
                                            const std::vector<SceneImage>& images,
                                            ImageStorage storage,
                                            const std::string& stem = "scene");

}  // namespace omnishadow::test_support
