// Writes the two focused scenes of scripts/measure-shadow-quality.sh (docs/shadow-quality.md)
// into a folder; the script writes their lights files. Not kept in the repository.
//
//   grazing-plane.glb  a 20 m square plane alone, seen from above: lit at a grazing 80 degrees
//                      from its normal, nothing can shadow it, so every shadowed pixel is acne.
//   thin-caster.glb    a 2 cm thick board (1.5 m x 1 m) standing on a 10 cm thick floor slab,
//                      seen from its shadowed side (camera "contact") and close up at its foot
//                      (camera "foot"): light under the board's foot is a leak (peter-panning).
#include <cstdio>
#include <exception>
#include <filesystem>

#include "scenes/builder/gltf_builder.h"

using namespace omnishadow::builder;

namespace {

int grey(GltfBuilder& b, const char* name, float value) {
  MaterialDesc m;
  m.name = name;
  m.baseColor = {value, value, value, 1.0f};
  m.roughness = 0.8f;
  return b.addMaterial(m);
}

void grazingPlane(const std::filesystem::path& file) {
  GltfBuilder b;
  b.addNode("plane", {}, b.addMesh(makePlane(20.0f, 8), {.material = grey(b, "plane", 0.7f)}));
  b.addPerspectiveCamera("above", {0.0f, 9.0f, 11.0f}, {0.0f, 0.0f, -1.0f}, glm::radians(50.0f),
                         16.0f / 9.0f, 0.05f);
  b.write(file, FileFormat::Glb);
}

void thinCaster(const std::filesystem::path& file) {
  GltfBuilder b;
  b.addNode("floor", {{0.0f, -0.05f, 0.0f}},
            b.addMesh(makeBox({4.0f, 0.05f, 4.0f}), {.material = grey(b, "floor", 0.7f)}));
  // 1.5 m wide, 1 m tall, 2 cm thick, its foot on the floor (y = 0), facing -z and +z.
  b.addNode("board", {{0.0f, 0.5f, 0.0f}},
            b.addMesh(makeBox({0.75f, 0.5f, 0.01f}), {.material = grey(b, "board", 0.5f)}));
  b.addPerspectiveCamera("contact", {1.1f, 0.9f, 1.6f}, {0.0f, 0.05f, 0.25f}, glm::radians(45.0f),
                         16.0f / 9.0f, 0.05f);
  // Close-up of the board's foot from its shadowed side: the middle 80 cm of the contact line
  // and the floor up to about 60 cm behind it, no outer shadow edge in view.
  b.addPerspectiveCamera("foot", {0.25f, 0.3f, 0.6f}, {0.0f, 0.0f, 0.05f}, glm::radians(45.0f),
                         16.0f / 9.0f, 0.01f);
  b.write(file, FileFormat::Glb);
}

}  // namespace

int main(int argc, char** argv) {
  return runGenerator(argc, argv, 1, 1, "make_shadow_quality_scenes FOLDER", [](char** arguments) {
    const std::filesystem::path folder = arguments[1];
    std::filesystem::create_directories(folder);
    grazingPlane(folder / "grazing-plane.glb");
    thinCaster(folder / "thin-caster.glb");
  });
}
