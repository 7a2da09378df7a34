#pragma once

// A glTF scene of one triangle and the given image files, one texture each: what the image
// decoders' tests load.

#include <filesystem>
#include <string>
#include <vector>

namespace omnishadow::test_support {

enum class ImageStorage { BufferView, File };

struct SceneImage {
  std::vector<unsigned char> bytes;  // the file's
  std::string name, mimeType;
  std::string fileName;  // where ImageStorage::File puts it, beside the scene
};

// Writes folder/<stem>.glb with each image in a bufferView of its own, or folder/<stem>.gltf
// with each image in folder/<fileName> (File). Returns the scene's path.
std::filesystem::path writeTexturedTriangle(const std::filesystem::path& folder,
                                            const std::vector<SceneImage>& images,
                                            ImageStorage storage,
                                            const std::string& stem = "scene");

}  // namespace omnishadow::test_support
