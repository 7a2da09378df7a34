// Writes COUNT small random scenes (a floor, a few boxes and spheres, two shadowed point lights
// in "<name>.lights.json", a camera) into a folder, reproducibly from SEED. Used by the
// benchmark scripts; the scenes are not kept in the repository.
#include <cstdio>
#include <exception>
#include <fstream>
#include <random>
#include <string>

#include "scenes/builder/gltf_builder.h"

using namespace omnishadow::builder;

namespace {

void writeScene(const std::filesystem::path& folder, int index, std::mt19937& rng,
                int shadowResolution) {
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  GltfBuilder b;
  MaterialDesc floor;
  floor.name = "floor";
  floor.baseColor = {0.7f, 0.7f, 0.7f, 1.0f};
  b.addNode("floor", {}, b.addMesh(makePlane(10.0f), {.material = b.addMaterial(floor)}));
  const int objects = 3 + static_cast<int>(unit(rng) * 5);
  for (int i = 0; i < objects; ++i) {
    MaterialDesc m;
    m.name = "object" + std::to_string(i);
    m.baseColor = {unit(rng), unit(rng), unit(rng), 1.0f};
    m.roughness = 0.2f + 0.7f * unit(rng);
    const float size = 0.2f + 0.5f * unit(rng);
    const glm::vec3 at{unit(rng) * 6.0f - 3.0f, size, unit(rng) * 6.0f - 3.0f};
    const MeshData mesh = unit(rng) < 0.5f ? makeBox(glm::vec3(size)) : makeSphere(size, 24, 12);
    b.addNode("object" + std::to_string(i), {at}, b.addMesh(mesh, {.material = b.addMaterial(m)}));
  }
  b.addPerspectiveCamera("camera", {0.0f, 5.0f, 8.0f}, {0.0f, 0.0f, 0.0f}, 0.9f);
  const std::string name = "scene" + std::to_string(index);
  b.write(folder / (name + ".glb"), FileFormat::Glb);

  std::ofstream lights(folder / (name + ".lights.json"));
  lights << "{\"lights\": [";
  for (int l = 0; l < 2; ++l) {
    lights << (l ? ", " : "") << "{\"name\": \"l" << l << "\", \"position\": ["
           << unit(rng) * 6.0f - 3.0f << ", " << 2.5f + unit(rng) * 1.5f << ", "
           << unit(rng) * 6.0f - 3.0f
           << "], \"intensity\": 20, \"shadow\": {\"resolution\": " << shadowResolution << "}}";
  }
  lights << "]}\n";
}

}  // namespace

int main(int argc, char** argv) {
  return runGenerator(argc, argv, 3, 4, "make_bench_scenes FOLDER COUNT SEED [SHADOW_RESOLUTION]",
                      [&](char** arguments) {
                        const std::filesystem::path folder = arguments[1];
                        std::filesystem::create_directories(folder);
                        const int count = std::stoi(arguments[2]);
                        std::mt19937 rng(static_cast<unsigned>(std::stoul(arguments[3])));
                        const int resolution = argc > 4 ? std::stoi(arguments[4]) : 256;
                        for (int i = 0; i < count; ++i) writeScene(folder, i, rng, resolution);
                      });
}
