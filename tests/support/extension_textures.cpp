#include "tests/support/extension_textures.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>

#include "renderer/scene/gltf_loader.h"

namespace omnishadow::test_support {

std::vector<std::uint8_t> cornersPictureRgba(int width, int height) {
  std::vector<std::uint8_t> rgba;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      rgba.push_back(static_cast<std::uint8_t>(20 + 200 * x / (width - 1)));
      rgba.push_back(static_cast<std::uint8_t>(30 + 190 * y / (height - 1)));
      rgba.push_back(static_cast<std::uint8_t>(40 + 100 * (x + y) / (width + height - 2)));
      rgba.push_back(static_cast<std::uint8_t>(255 - 200 * y / (height - 1)));
    }
  return rgba;
}

int largestChannelDifference(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b,
                             int firstChannel, int channels) {
  EXPECT_EQ(a.size(), b.size());
  int largest = 0;
  for (std::size_t i = 0; i + 3 < std::min(a.size(), b.size()); i += 4)
    for (int c = firstChannel; c < firstChannel + channels; ++c)
      largest = std::max(largest, std::abs(int(a[i + c]) - int(b[i + c])));
  return largest;
}

std::filesystem::path withTexturesThrough(
    const std::filesystem::path& scene, const std::filesystem::path& folder,
    const std::string& extension, const std::string& suffix,
    const std::function<std::vector<unsigned char>(const Image&)>& encode) {
  const Scene loaded = loadGltf(scene);
  EXPECT_FALSE(loaded.images.empty());
  nlohmann::json doc = nlohmann::json::parse(std::ifstream(scene));
  std::filesystem::create_directories(folder);
  for (std::size_t i = 0; i < loaded.images.size(); ++i) {
    const std::string name = "texture" + std::to_string(i) + "." + suffix;
    const std::vector<unsigned char> bytes = encode(loaded.images[i]);
    std::ofstream(folder / name, std::ios::binary)
        .write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    doc["images"][i] = {{"uri", name}};
  }
  for (nlohmann::json& texture : doc["textures"]) {
    texture["extensions"][extension]["source"] = texture["source"];
    texture.erase("source");
  }
  doc["extensionsUsed"].push_back(extension);
  doc["extensionsRequired"].push_back(extension);
  const std::filesystem::path path = folder / "scene.gltf";
  std::ofstream(path) << doc.dump();
  return path;
}

}  // namespace omnishadow::test_support
