// Cube map face conventions and camera math, against the GL specification's tables.
#include <gtest/gtest.h>

#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <random>

#include "renderer/camera.h"
#include "renderer/cube_faces.h"
#include "renderer/errors.h"

using namespace omnishadow;

namespace {

glm::vec3 project(const glm::mat4& viewProjection, const glm::vec3& p) {
  const glm::vec4 clip = viewProjection * glm::vec4(p, 1.0f);
  return glm::vec3(clip) / clip.w;
}

}  // namespace

// OpenGL 4.5 core, table 8.19: the major axis picks the face; (sc, tc, ma) per face.
TEST(CubeLookup, AxisDirectionsHitFaceCenters) {
  const struct {
    glm::vec3 direction;
    CubeFace face;
  } cases[] = {{{1, 0, 0}, CubeFace::PosX}, {{-1, 0, 0}, CubeFace::NegX},
               {{0, 1, 0}, CubeFace::PosY}, {{0, -1, 0}, CubeFace::NegY},
               {{0, 0, 1}, CubeFace::PosZ}, {{0, 0, -1}, CubeFace::NegZ}};
  for (const auto& c : cases) {
    const CubeLookup lookup = cubeLookup(c.direction);
    EXPECT_EQ(lookup.face, c.face);
    EXPECT_FLOAT_EQ(lookup.st.x, 0.5f);
    EXPECT_FLOAT_EQ(lookup.st.y, 0.5f);
  }
}

TEST(CubeLookup, MatchesSpecificationTableOffAxis) {
  // For each face, a direction tilted towards +s and +t must land in the (s>0.5, t>0.5)
  // quadrant; the tilt axes come straight from table 8.19.
  const struct {
    glm::vec3 direction;
    CubeFace face;
    float s, t;
  } cases[] = {
      // +X: sc = -rz, tc = -ry
      {{1, -0.5f, -0.25f}, CubeFace::PosX, 0.5f * (0.25f + 1), 0.5f * (0.5f + 1)},
      // -X: sc = +rz, tc = -ry
      {{-1, -0.5f, 0.25f}, CubeFace::NegX, 0.5f * (0.25f + 1), 0.5f * (0.5f + 1)},
      // +Y: sc = +rx, tc = +rz
      {{0.25f, 1, 0.5f}, CubeFace::PosY, 0.5f * (0.25f + 1), 0.5f * (0.5f + 1)},
      // -Y: sc = +rx, tc = -rz
      {{0.25f, -1, -0.5f}, CubeFace::NegY, 0.5f * (0.25f + 1), 0.5f * (0.5f + 1)},
      // +Z: sc = +rx, tc = -ry
      {{0.25f, -0.5f, 1}, CubeFace::PosZ, 0.5f * (0.25f + 1), 0.5f * (0.5f + 1)},
      // -Z: sc = -rx, tc = -ry
      {{-0.25f, -0.5f, -1}, CubeFace::NegZ, 0.5f * (0.25f + 1), 0.5f * (0.5f + 1)},
  };
  for (const auto& c : cases) {
    const CubeLookup lookup = cubeLookup(c.direction * 3.0f);  // scale must not matter
    EXPECT_EQ(lookup.face, c.face);
    EXPECT_NEAR(lookup.st.x, c.s, 1e-6f);
    EXPECT_NEAR(lookup.st.y, c.t, 1e-6f);
  }
}

// Rendering a point with a face's view-projection must put it where sampling the cube map in
// the point's direction reads: NDC (x, y) = (2s - 1, 2t - 1) on the face cubeLookup selects.
TEST(CubeFaceMatrices, ProjectionAgreesWithLookupForRandomPoints) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> coord(-10.0f, 10.0f);
  const glm::vec3 center(1.5f, -2.0f, 0.25f);
  const glm::mat4 projection = cubeFaceProjection(0.1f, 40.0f);
  for (int i = 0; i < 2000; ++i) {
    const glm::vec3 p = center + glm::vec3(coord(rng), coord(rng), coord(rng));
    const CubeLookup lookup = cubeLookup(p - center);
    const glm::vec3 ndc = project(projection * cubeFaceView(lookup.face, center), p);
    EXPECT_NEAR(ndc.x, 2.0f * lookup.st.x - 1.0f, 1e-4f);
    EXPECT_NEAR(ndc.y, 2.0f * lookup.st.y - 1.0f, 1e-4f);
    EXPECT_GE(ndc.z, -1e-6f);
    EXPECT_LE(ndc.z, 1.0f + 1e-6f);
  }
}

TEST(CubeFaceMatrices, PointInFaceDirectionLandsOnExpectedTexel) {
  // A point 30% right and 20% up of the face center (in s, t) lands on texel
  // (0.65 * size, 0.6 * size) of that face, for every face.
  const int size = 256;
  const glm::vec3 center(0.0f);
  for (int face = 0; face < kCubeFaceCount; ++face) {
    const glm::mat4 view = cubeFaceView(static_cast<CubeFace>(face), center);
    // Invert the view to place a point at NDC (0.3, 0.2) on the face plane at distance 5.
    const glm::vec3 p = glm::vec3(glm::inverse(view) * glm::vec4(0.3f * 5, 0.2f * 5, -5, 1));
    const CubeLookup lookup = cubeLookup(p - center);
    EXPECT_EQ(static_cast<int>(lookup.face), face);
    EXPECT_EQ(static_cast<int>(lookup.st.x * size), static_cast<int>(0.65f * size));
    EXPECT_EQ(static_cast<int>(lookup.st.y * size), static_cast<int>(0.6f * size));
  }
}

TEST(CubeFaceMatrices, ViewsAreRigidAndLookDownTheMajorAxis) {
  const glm::vec3 axes[] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (int face = 0; face < kCubeFaceCount; ++face) {
    const glm::mat4 view = cubeFaceView(static_cast<CubeFace>(face), glm::vec3(0));
    EXPECT_NEAR(glm::determinant(glm::mat3(view)), 1.0f, 1e-6f);  // a rotation, no mirror
    const glm::vec3 forward = glm::vec3(view * glm::vec4(axes[face], 0.0f));
    EXPECT_NEAR(forward.z, -1.0f, 1e-6f);
  }
}

TEST(CubeDepth, ReversedDepthMapsNearToOneAndFarToZero) {
  const float near = 0.05f, far = 20.0f;
  EXPECT_NEAR(axisDistanceToCubeDepth(near, near, far), 1.0f, 1e-6f);
  EXPECT_NEAR(axisDistanceToCubeDepth(far, near, far), 0.0f, 1e-6f);
  for (float z : {0.05f, 0.3f, 1.0f, 7.5f, 19.9f}) {
    const float depth = axisDistanceToCubeDepth(z, near, far);
    EXPECT_NEAR(cubeDepthToAxisDistance(depth, near, far), z, z * 1e-5f);
    // The projection matrix produces the same depth as the scalar formula.
    const glm::vec3 ndc = project(cubeFaceProjection(near, far), glm::vec3(0.1f, 0.2f, -z));
    EXPECT_NEAR(ndc.z, depth, 1e-6f);
  }
}

TEST(Camera, ReversedPerspectiveMapsNearToOne) {
  const glm::mat4 p = reversedPerspective(glm::radians(60.0f), 1.5f, 0.1f, 100.0f);
  EXPECT_NEAR(project(p, {0, 0, -0.1f}).z, 1.0f, 1e-6f);
  EXPECT_NEAR(project(p, {0, 0, -100.0f}).z, 0.0f, 1e-6f);
  const glm::mat4 infinite = reversedPerspective(glm::radians(60.0f), 1.5f, 0.1f, 0.0f);
  EXPECT_NEAR(project(infinite, {0, 0, -0.1f}).z, 1.0f, 1e-6f);
  EXPECT_GT(project(infinite, {0, 0, -1e6f}).z, 0.0f);
  // Vertical fov: a point at the top edge of the field of view lands on NDC y = 1.
  const float y = std::tan(glm::radians(30.0f)) * 10.0f;
  EXPECT_NEAR(project(p, {0, y, -10.0f}).y, 1.0f, 1e-5f);
}

namespace {

Scene sceneWithBounds() {
  Scene scene;
  scene.path = "test.gltf";
  scene.bounds.extend(glm::vec3(-1, 0, -1));
  scene.bounds.extend(glm::vec3(1, 2, 1));
  return scene;
}

Camera gltfCamera(int index, const std::string& name, glm::vec3 position, float aspect) {
  Camera camera;
  camera.index = index;
  camera.name = name;
  camera.yfov = glm::radians(50.0f);
  camera.aspectRatio = aspect;
  camera.znear = 0.1f;
  camera.world = glm::translate(glm::mat4(1.0f), position);
  return camera;
}

}  // namespace

TEST(Camera, AutomaticFramingSeesTheWholeScene) {
  const Scene scene = sceneWithBounds();
  const ViewCamera camera = resolveCamera(scene, {});
  EXPECT_EQ(camera.width, 1280);
  EXPECT_EQ(camera.height, 720);
  const glm::mat4 viewProjection = camera.projection * camera.view;
  for (int corner = 0; corner < 8; ++corner) {
    const glm::vec3 p{(corner & 1) ? 1.0f : -1.0f, (corner & 2) ? 2.0f : 0.0f,
                      (corner & 4) ? 1.0f : -1.0f};
    const glm::vec3 ndc = project(viewProjection, p);
    EXPECT_LE(std::abs(ndc.x), 1.0f);
    EXPECT_LE(std::abs(ndc.y), 1.0f);
    EXPECT_GT(ndc.z, 0.0f);
    EXPECT_LE(ndc.z, 1.0f);
  }
}

TEST(Camera, FirstGltfCameraByDefaultAndSelectionByNameOrIndex) {
  Scene scene = sceneWithBounds();
  scene.cameras.push_back(gltfCamera(0, "front", {0, 1, 5}, 0.0f));
  scene.cameras.push_back(gltfCamera(1, "side", {5, 1, 0}, 0.0f));
  EXPECT_EQ(resolveCamera(scene, {}).eye, glm::vec3(0, 1, 5));
  CameraRequest byName;
  byName.select = "side";
  EXPECT_EQ(resolveCamera(scene, byName).eye, glm::vec3(5, 1, 0));
  CameraRequest byIndex;
  byIndex.select = "1";
  EXPECT_EQ(resolveCamera(scene, byIndex).eye, glm::vec3(5, 1, 0));
  CameraRequest unknown;
  unknown.select = "top";
  try {
    resolveCamera(scene, unknown);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--camera top: test.gltf has no such camera"),
              std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("1 \"side\""), std::string::npos) << e.what();
  }
}

TEST(Camera, SizeFollowsTheCameraAspectRatio) {
  Scene scene = sceneWithBounds();
  scene.cameras.push_back(gltfCamera(0, "square", {0, 1, 5}, 1.0f));
  ViewCamera camera = resolveCamera(scene, {});
  EXPECT_EQ(camera.width, 1280);
  EXPECT_EQ(camera.height, 1280);
  CameraRequest widthOnly;
  widthOnly.width = 300;
  camera = resolveCamera(scene, widthOnly);
  EXPECT_EQ(camera.height, 300);
  CameraRequest both;
  both.width = 320;
  both.height = 200;
  camera = resolveCamera(scene, both);
  EXPECT_EQ(camera.width, 320);
  EXPECT_EQ(camera.height, 200);
}

TEST(Camera, OverridesMoveAndAimTheCamera) {
  Scene scene = sceneWithBounds();
  scene.cameras.push_back(gltfCamera(0, "front", {0, 1, 5}, 0.0f));
  CameraRequest request;
  request.eye = glm::vec3(3, 3, 3);
  request.target = glm::vec3(0, 1, 0);
  const ViewCamera camera = resolveCamera(scene, request);
  EXPECT_EQ(camera.eye, glm::vec3(3, 3, 3));
  // The target projects to the image center.
  const glm::vec3 ndc = project(camera.projection * camera.view, {0, 1, 0});
  EXPECT_NEAR(ndc.x, 0.0f, 1e-5f);
  EXPECT_NEAR(ndc.y, 0.0f, 1e-5f);

  CameraRequest same;
  same.eye = glm::vec3(0, 1, 0);
  same.target = glm::vec3(0, 1, 0);
  EXPECT_THROW(resolveCamera(scene, same), InputError);
  CameraRequest badFov;
  badFov.fovDegrees = 180.0f;
  EXPECT_THROW(resolveCamera(scene, badFov), InputError);
}
