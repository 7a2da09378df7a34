// Debugging outputs for directional and spot lights (issue 18): the cascade debug view.
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "renderer/core/errors.h"
#include "renderer/render/renderer.h"
#include "renderer/view/camera.h"
#include "scenes/builder/gltf_builder.h"

using namespace omnishadow;

namespace {

Renderer& contextForThisProgram() {
  static Renderer renderer(ContextOptions{});
  return renderer;
}

// A 60 m floor seen from 1.5 m above one end, looking along it.
struct LongFloor {
  Scene scene;
  ViewCamera camera;
  LongFloor() {
    const builder::MeshData plane = builder::makePlane(60.0f);
    Mesh mesh;
    mesh.positions = plane.positions;
    mesh.normals = plane.normals;
    mesh.uv0 = plane.uvs;
    mesh.indices = plane.indices;
    mesh.material = -1;
    for (const glm::vec3& p : mesh.positions) mesh.bounds.extend(p);
    scene.meshes.push_back(mesh);
    scene.instances.push_back({0, glm::mat4(1.0f), -1});
    scene.bounds = mesh.bounds;
    CameraRequest request;
    request.eye = glm::vec3(0.0f, 1.5f, 29.0f);
    request.target = glm::vec3(0.0f, 0.0f, 0.0f);
    request.up = glm::vec3(0.0f, 1.0f, 0.0f);
    request.fovDegrees = 60.0f;
    request.width = 64;
    request.height = 96;
    camera = resolveCamera(scene, request);
  }
};

Light sunWithCascades(int cascades) {
  Light sun;
  sun.name = "sun";
  sun.type = LightType::Directional;
  sun.direction = glm::normalize(glm::vec3(0.3f, -1.0f, -0.2f));
  sun.shadow.cascades = cascades;
  sun.shadow.resolution = 256;
  return sun;
}

// Which hue dominates a pixel: 0 red, 1 green, 2 blue, -1 grey or nothing.
int dominantHue(const FloatImage& image, int x, int y) {
  const float r = image.at(x, y, 0), g = image.at(x, y, 1), b = image.at(x, y, 2);
  if (r > 1.5f * g && r > 1.5f * b) return 0;
  if (g > 1.5f * r && g > 1.5f * b) return 1;
  if (b > 1.5f * r && b > 1.5f * g) return 2;
  return -1;
}

}  // namespace

// Up the middle column, from the nearest floor to the horizon: cascade 0 (red), then 1
// (green), then 2 (blue), never back to a nearer one.
TEST(CascadeDebugView, ColorsTheFloorByCascadeFromNearToFar) {
  const LongFloor floor;
  RenderSettings settings;
  settings.debugView = DebugView::Cascade;
  StageTimes times;
  const Frame frame = contextForThisProgram().render(
      floor.scene, {sunWithCascades(3)}, glm::vec3(0.03f), floor.camera, settings, times);
  const int x = frame.beauty.width / 2;
  std::vector<int> seen;
  for (int y = frame.beauty.height - 1; y >= 0; --y) {
    if (!(frame.beauty.at(x, y, 3) > 0.0f)) continue;  // sky
    const int hue = dominantHue(frame.beauty, x, y);
    ASSERT_GE(hue, 0) << "row " << y;
    if (seen.empty() || seen.back() != hue) seen.push_back(hue);
  }
  EXPECT_EQ(seen, (std::vector<int>{0, 1, 2}));
}

TEST(CascadeDebugView, NeedsAShadowedDirectionalLight) {
  const LongFloor floor;
  Light lamp;
  lamp.name = "lamp";
  lamp.position = {0.0f, 3.0f, 0.0f};
  RenderSettings settings;
  settings.debugView = DebugView::Cascade;
  StageTimes times;
  try {
    contextForThisProgram().render(floor.scene, {lamp}, glm::vec3(0.03f), floor.camera, settings,
                                   times);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "--debug-view cascade: no directional light casts a shadow");
  }
}
