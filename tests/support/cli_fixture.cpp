#include "tests/support/cli_fixture.h"

#include <fstream>
#include <utility>

namespace fs = std::filesystem;

namespace omnishadow::test_support {

void writeBoxScene(const fs::path& path, const BoxSceneSpec& spec) {
  fs::create_directories(path.parent_path());
  builder::GltfBuilder b;
  std::vector<std::uint8_t> checker;
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) {
      const std::uint8_t v = (x + y) % 2 ? 220 : 90;
      checker.insert(checker.end(), {v, v, v, 255});
    }
  builder::MaterialDesc floor{.name = "floor", .roughness = 0.8f};
  floor.baseColorTexture = b.addTexture(8, 8, checker, "checker");
  const int box = b.addMaterial({.name = "box", .baseColor = {0.8f, 0.2f, 0.1f, 1.0f}});
  b.addNode("floor", {}, b.addMesh(builder::makePlane(6.0f), {.material = b.addMaterial(floor)}));
  b.addNode("box", {.translation = {spec.boxX, 0.5f, 0.0f}},
            b.addMesh(builder::makeBox(glm::vec3(0.5f)), {.material = box}));
  if (spec.cameras) {
    b.addPerspectiveCamera("main", {0.0f, 2.5f, 4.5f}, {0.0f, 0.3f, 0.0f}, 0.8f, spec.aspectRatio);
    b.addPerspectiveCamera("top", {0.0f, 6.0f, 1.0f}, {0.0f, 0.0f, 0.0f}, 0.8f);
  }
  if (spec.gltfLight)
    b.addLight("lamp", "point", {1.5f, 3.0f, 1.0f}, {0.0f, -1.0f, 0.0f}, glm::vec3(1.0f), 30.0f);
  b.write(path, spec.format);
}

std::string distinctResolutionLights(int count) {
  std::string text = R"({"lights": [)";
  for (int i = 0; i < count; ++i)
    text += (i ? ", " : "") + std::string(R"({"position": [)") + std::to_string(i - count / 2) +
            R"(, 3, 1], "shadow": {"resolution": )" + std::to_string(16 + i) + "}}";
  return text + "]}";
}

PngHeader pngHeader(const fs::path& path) {
  const std::string bytes = readFile(path);
  EXPECT_GE(bytes.size(), 33u) << path;
  EXPECT_EQ(bytes.substr(0, 8), "\x89PNG\r\n\x1a\n") << path;
  EXPECT_EQ(bytes.substr(12, 4), "IHDR") << path;
  if (bytes.size() < 33) return {};
  auto u32 = [&](std::size_t at) {
    std::uint32_t v = 0;
    for (std::size_t i = 0; i < 4; ++i) v = v << 8 | static_cast<unsigned char>(bytes[at + i]);
    return v;
  };
  return {u32(16), u32(20), static_cast<unsigned char>(bytes[24]),
          static_cast<unsigned char>(bytes[25])};
}

std::pair<std::uint32_t, std::uint32_t> pngSize(const fs::path& path) {
  const PngHeader header = pngHeader(path);
  return {header.width, header.height};
}

::testing::AssertionResult contains(const std::string& text, const std::string& part) {
  if (text.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "\"" << text << "\" does not contain \"" << part << "\"";
}

::testing::AssertionResult sameBytes(const fs::path& a, const fs::path& b) {
  const std::string x = readFile(a), y = readFile(b);
  if (x.empty()) return ::testing::AssertionFailure() << a << " is empty or missing";
  if (x == y) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << a << " and " << b << " differ";
}

CliFixture::CliFixture(const std::string& prefix) : root_(prefix) {
  fs::create_directory(in_);
  fs::create_directory(out_);
}

CliFixture::Run CliFixture::run(const std::vector<std::string>& args,
                                const std::vector<std::string>& environment) {
  RunOptions options = RunOptions::in(out_);
  options.environment = environment;
  return runOmnishadow(args, options);
}

CliFixture::Run CliFixture::runSucceeding(const std::string& command, std::vector<std::string> args,
                                          const std::vector<std::string>& tail) {
  args.insert(args.begin(), command);
  args.insert(args.end(), tail.begin(), tail.end());
  Run result = run(args);
  EXPECT_EQ(result.status, 0) << result.err;
  return result;
}

std::string CliFixture::substituted(std::string text) const {
  const std::pair<std::string, std::string> names[] = {{"$scene", in("scene.gltf")},
                                                       {"$lights", in("lights.json")},
                                                       {"$in", in_.string()},
                                                       {"$out", out_.string()}};
  for (const auto& [name, value] : names)
    for (std::size_t at; (at = text.find(name)) != std::string::npos;)
      text.replace(at, name.size(), value);
  return text;
}

fs::path CliFixture::writeText(const std::string& name, const std::string& text) {
  fs::create_directories(input(name).parent_path());
  std::ofstream(input(name), std::ios::binary) << text;
  return input(name);
}

}  // namespace omnishadow::test_support
