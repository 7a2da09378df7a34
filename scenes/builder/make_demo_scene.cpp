// Writes the built-in demo scene, scenes/demo/room.gltf: a room with a few objects and a
// cut-out lattice screen, lit by the two point lights of scenes/demo/room.lights.json.
// Regenerate with scripts/make-demo-scene.sh.
#include <cmath>
#include <cstdio>
#include <exception>
#include <glm/gtc/quaternion.hpp>

#include "scenes/builder/gltf_builder.h"

using namespace omnishadow::builder;

namespace {

std::vector<std::uint8_t> checkerTexture(int size, int tiles, glm::vec3 a, glm::vec3 b) {
  std::vector<std::uint8_t> rgba(static_cast<std::size_t>(size) * size * 4);
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      const bool odd = ((x * tiles / size) + (y * tiles / size)) % 2 == 1;
      const glm::vec3 c = odd ? a : b;
      std::uint8_t* p = &rgba[(static_cast<std::size_t>(y) * size + x) * 4];
      for (int i = 0; i < 3; ++i) p[i] = static_cast<std::uint8_t>(std::lround(c[i] * 255.0f));
      p[3] = 255;
    }
  }
  return rgba;
}

// Wooden lattice: round holes with zero alpha, for alphaMode MASK (cut-out shadows).
std::vector<std::uint8_t> latticeTexture(int size, int holes) {
  std::vector<std::uint8_t> rgba(static_cast<std::size_t>(size) * size * 4);
  const float cell = static_cast<float>(size) / static_cast<float>(holes);
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      const float u = std::fmod(static_cast<float>(x) + 0.5f, cell) / cell - 0.5f;
      const float v = std::fmod(static_cast<float>(y) + 0.5f, cell) / cell - 0.5f;
      const bool hole = u * u + v * v < 0.36f * 0.36f;
      std::uint8_t* p = &rgba[(static_cast<std::size_t>(y) * size + x) * 4];
      p[0] = 176;
      p[1] = 124;
      p[2] = 74;
      p[3] = hole ? 0 : 255;
    }
  }
  return rgba;
}

glm::quat yaw(float degrees) {
  return glm::angleAxis(glm::radians(degrees), glm::vec3(0, 1, 0));
}

void build(GltfBuilder& b) {
  auto material = [&](const std::string& name, glm::vec3 color, float roughness,
                      float metallic = 0.0f) {
    MaterialDesc m;
    m.name = name;
    m.baseColor = glm::vec4(color, 1.0f);
    m.roughness = roughness;
    m.metallic = metallic;
    return b.addMaterial(m);
  };

  // Room: 8 m wide, 4 m high, reaching from the back wall at z = -4 to behind the camera.
  MaterialDesc floor;
  floor.name = "floor tiles";
  floor.roughness = 0.7f;
  floor.baseColorTexture =
      b.addTexture(256, 256, checkerTexture(256, 8, {0.78f, 0.76f, 0.72f}, {0.62f, 0.60f, 0.57f}),
                   "floor checker");
  const int floorMaterial = b.addMaterial(floor);
  const int wallMaterial = material("plaster", {0.80f, 0.78f, 0.74f}, 0.9f);
  const int redMaterial = material("red plaster", {0.70f, 0.18f, 0.14f}, 0.9f);
  const int greenMaterial = material("green plaster", {0.20f, 0.55f, 0.42f}, 0.9f);
  const float t = 0.1f;  // wall thickness
  const float halfDepth = 6.5f, centerZ = 2.5f;
  b.addNode("floor", {{0, -t, centerZ}},
            b.addMesh(makeBox({4, t, halfDepth}), {.material = floorMaterial}, "floor"));
  b.addNode("ceiling", {{0, 4 + t, centerZ}},
            b.addMesh(makeBox({4, t, halfDepth}), {.material = wallMaterial}, "ceiling"));
  b.addNode("back wall", {{0, 2, -4 - t}},
            b.addMesh(makeBox({4, 2, t}), {.material = wallMaterial}, "back wall"));
  b.addNode("left wall", {{-4 - t, 2, centerZ}},
            b.addMesh(makeBox({t, 2, halfDepth}), {.material = redMaterial}, "left wall"));
  b.addNode("right wall", {{4 + t, 2, centerZ}},
            b.addMesh(makeBox({t, 2, halfDepth}), {.material = greenMaterial}, "right wall"));

  // Objects on the floor.
  const int white = material("white ceramic", {0.85f, 0.85f, 0.82f}, 0.35f);
  const int blue = material("blue paint", {0.15f, 0.30f, 0.75f}, 0.5f);
  const int gold = material("brushed gold", {1.0f, 0.78f, 0.34f}, 0.3f, 1.0f);
  const int stone = material("stone", {0.55f, 0.52f, 0.48f}, 0.8f);
  b.addNode("sphere", {{-1.6f, 0.7f, -0.6f}},
            b.addMesh(makeSphere(0.7f, 48, 24), {.material = white}, "sphere"));
  b.addNode("tall box", {{1.7f, 1.0f, -1.6f}, yaw(28.0f)},
            b.addMesh(makeBox({0.45f, 1.0f, 0.45f}), {.material = blue}, "tall box"));
  b.addNode("column", {{0.2f, 0.0f, -2.6f}},
            b.addMesh(makeCylinder(0.3f, 2.6f, 40), {.material = stone}, "column"));
  b.addNode("gold ball", {{0.9f, 0.35f, 0.9f}},
            b.addMesh(makeSphere(0.35f, 40, 20), {.material = gold}, "gold ball"));
  b.addNode("small box", {{-0.2f, 0.25f, 1.4f}, yaw(-20.0f)},
            b.addMesh(makeBox({0.25f, 0.25f, 0.25f}), {.material = blue}, "small box"));

  // A cut-out lattice screen near the red wall: alphaMode MASK, double-sided.
  MaterialDesc lattice;
  lattice.name = "lattice";
  lattice.alphaMode = "MASK";
  lattice.alphaCutoff = 0.5f;
  lattice.doubleSided = true;
  lattice.roughness = 0.6f;
  lattice.baseColorTexture = b.addTexture(128, 128, latticeTexture(128, 6), "lattice");
  const int latticeMaterial = b.addMaterial(lattice);
  // The plane faces +Y; stand it up facing +X, 2 m wide and 2 m tall.
  const glm::quat standUp = glm::angleAxis(glm::radians(-90.0f), glm::vec3(0, 0, 1));
  b.addNode("lattice", {{-3.0f, 1.2f, 1.3f}, yaw(-15.0f) * standUp, {1.0f, 1.0f, 1.0f}},
            b.addMesh(makePlane(2.0f), {.material = latticeMaterial}, "lattice"));

  b.addPerspectiveCamera("front", {0.0f, 2.1f, 8.2f}, {0.0f, 1.3f, -1.0f}, glm::radians(48.0f),
                         16.0f / 9.0f, 0.05f);
}

}  // namespace

int main(int argc, char** argv) {
  return runGenerator(argc, argv, 1, 1, "make_demo_scene OUTPUT.gltf", [](char** arguments) {
    GltfBuilder builder;
    build(builder);
    builder.write(arguments[1], FileFormat::GltfEmbedded);
  });
}
