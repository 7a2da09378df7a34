// Cube map face conventions and camera math, against the GL specification's tables.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <random>

#include "renderer/core/errors.h"
#include "renderer/view/camera.h"
#include "renderer/view/cube_faces.h"
#include "renderer/view/light_clusters.h"
#include "renderer/view/shadow_views.h"

namespace view_math_test {

using namespace omnishadow;

namespace {

// A point through a view-projection matrix, to normalized device coordinates.
glm::vec3 project(const glm::mat4& viewProjection, const glm::vec3& p) {
  const glm::vec4 clip = viewProjection * glm::vec4(p, 1.0f);
  return glm::vec3(clip) / clip.w;
}

// An empty scene whose bounds reach from `low` to `high`.
Scene boundedScene(const glm::vec3& low, const glm::vec3& high) {
  Scene scene;
  scene.bounds.extend(low);
  scene.bounds.extend(high);
  return scene;
}

// The camera at `eye` aimed at the origin; `request` gives any other setting.
ViewCamera cameraAtOrigin(const Scene& scene, const glm::vec3& eye, CameraRequest request = {}) {
  request.eye = eye;
  request.target = glm::vec3(0, 0, 0);
  return resolveCamera(scene, request);
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

// The InputError resolveCamera() throws for `request`, or "" when it resolves.
std::string resolveError(const Scene& scene, const CameraRequest& request) {
  try {
    resolveCamera(scene, request);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
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
  const std::string message = resolveError(scene, unknown);
  EXPECT_NE(message.find("--camera top: test.gltf has no such camera"), std::string::npos)
      << message;
  EXPECT_NE(message.find("1 \"side\""), std::string::npos) << message;
}

TEST(Camera, ABrokenCameraIsRefusedOnlyWhenRenderedFrom) {
  // The loader accepts a file with a broken camera (with a warning); resolveCamera() refuses to
  // render from it, naming the camera, and the scene's other cameras still render.
  Scene scene = sceneWithBounds();
  scene.cameras.push_back(gltfCamera(0, "good", {0, 1, 5}, 0.0f));
  Camera broken = gltfCamera(1, "flat", {5, 1, 0}, 0.0f);
  broken.orthographic = true;
  broken.xmag = 1.0f;
  broken.ymag = 0.0f;
  broken.zfar = 10.0f;
  scene.cameras.push_back(broken);
  EXPECT_EQ(resolveCamera(scene, {}).eye, glm::vec3(0, 1, 5));
  CameraRequest request;
  request.select = "flat";
  EXPECT_EQ(resolveError(scene, request),
            "test.gltf: cameras[1]: orthographic ymag must be non-zero");
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

// Extreme camera numbers either give a view or an InputError naming the option given. The
// float length of a vector beyond about 1.8e19 overflows, which once made an --eye at 3e38 read
// as an --up parallel to the view, and an --fov of 1e-30 framed the scene from 1e32 radii.
TEST(Camera, ExtremeNumbersGiveAViewOrNameTheOption) {
  const Scene framed = sceneWithBounds();  // no camera: automatic framing
  Scene withCamera = sceneWithBounds();
  withCamera.cameras.push_back(gltfCamera(0, "front", {0, 1, 5}, 0.0f));
  // The camera's forward axis (world space) is minus the third row of the view's rotation.
  const auto forward = [](const glm::mat4& view) {
    return -glm::vec3(view[0][2], view[1][2], view[2][2]);
  };
  for (const Scene* scene : std::vector<const Scene*>{&framed, &withCamera}) {
    EXPECT_EQ(resolveError(*scene, {.fovDegrees = 1e-30f}),
              "--fov 1e-30: expected degrees from 0.001 to below 180");
    EXPECT_EQ(resolveError(*scene, {.fovDegrees = 180.0f}),
              "--fov 180: expected degrees from 0.001 to below 180");
    EXPECT_EQ(resolveError(*scene, {.fovDegrees = 0.001f}), "");
    EXPECT_EQ(resolveError(*scene, {.fovDegrees = 179.9999f}), "");
    EXPECT_EQ(resolveError(*scene, {.eye = glm::vec3(1, 2, 3), .target = glm::vec3(1, 2, 3)}),
              "--eye/--target: the eye and the target are the same point");
    EXPECT_EQ(resolveError(*scene, {.eye = glm::vec3(0, 5, 0),
                                    .target = glm::vec3(0, 0, 0),
                                    .up = glm::vec3(0, 1, 0)}),
              "--up: the up vector is parallel to the view direction");
    EXPECT_EQ(resolveError(*scene, {.eye = glm::vec3(-3e38f), .target = glm::vec3(3e38f)}),
              "--eye/--target: the eye is too far from the origin: the view matrix overflows "
              "float");
    // Far, but a view: it looks from the eye toward what it looked at.
    const ViewCamera far = resolveCamera(*scene, {.eye = glm::vec3(3e38f, 0, 0)});
    const glm::vec3 expected = scene == &framed ? glm::vec3(-1, 0, 0)   // the scene's center
                                                : glm::vec3(0, 0, -1);  // the camera's forward
    EXPECT_NEAR(glm::length(forward(far.view) - expected), 0.0f, 1e-6f);
  }
  // An --eye alone so far out that eye + forward == eye in float keeps the camera's direction.
  const ViewCamera corner = resolveCamera(withCamera, {.eye = glm::vec3(3e38f)});
  EXPECT_NEAR(glm::length(forward(corner.view) - glm::vec3(0, 0, -1)), 0.0f, 1e-6f);
  // Ordinary views are glm's float lookAt to the bit, as before.
  const ViewCamera plain =
      resolveCamera(framed, {.eye = glm::vec3(3, 2, 1), .target = glm::vec3(0.5f, 0.25f, 0)});
  EXPECT_EQ(plain.view,
            glm::lookAt(glm::vec3(3, 2, 1), glm::vec3(0.5f, 0.25f, 0), glm::vec3(0, 1, 0)));
}

TEST(Camera, EyeAndTargetWithoutUpLookLevel) {
  // A file camera rolled 30° about its view axis: an --eye/--target view does not keep the roll.
  Scene scene = sceneWithBounds();
  Camera rolled = gltfCamera(0, "rolled", {0, 1, 5}, 0.0f);
  rolled.world = rolled.world * glm::rotate(glm::mat4(1.0f), glm::radians(30.0f), {0, 0, 1});
  scene.cameras.push_back(rolled);
  CameraRequest request;
  request.eye = glm::vec3(4, 2, 4);
  request.target = glm::vec3(0, 1, 0);
  const glm::mat4 cameraToWorld = glm::inverse(resolveCamera(scene, request).view);
  EXPECT_NEAR(glm::vec3(cameraToWorld[0]).y, 0.0f, 1e-5f);  // the image's x axis is level
  EXPECT_GT(glm::vec3(cameraToWorld[1]).y, 0.0f);           // and its top points up
  // Straight down, +Y cannot be up: the top of the image faces -Z.
  request.eye = glm::vec3(0, 5, 0);
  request.target = glm::vec3(0, 0, 0);
  const glm::mat4 down = glm::inverse(resolveCamera(scene, request).view);
  EXPECT_NEAR(glm::vec3(down[1]).z, -1.0f, 1e-5f);
  // An explicit --up still rolls the view.
  request.eye = glm::vec3(4, 2, 4);
  request.up = glm::vec3(1, 0, 0);
  const glm::mat4 sideways = glm::inverse(resolveCamera(scene, request).view);
  EXPECT_GT(std::abs(glm::vec3(sideways[0]).y), 0.5f);
}

// ---------------------------------------------------------------------------------------------
// Spot and directional shadow projections (renderer/shadow_views.h)

TEST(SpotShadow, MapHoldsTheWholeOuterConeWithReversedDepth) {
  Light light;
  light.type = LightType::Spot;
  light.position = {1, 2, 3};
  light.direction = glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f));
  light.outerConeAngle = glm::radians(40.0f);
  const SpotShadowFrame frame = spotShadowFrame(light, 0.1f, 20.0f, 512);
  EXPECT_FALSE(frame.coneClipped);
  EXPECT_GT(frame.tanHalfFov, std::tan(light.outerConeAngle));
  // Points on the outer cone's surface, all around it, land inside the map.
  const glm::vec3 side = glm::normalize(glm::cross(light.direction, glm::vec3(0, 0, 1)));
  for (int i = 0; i < 32; ++i) {
    const glm::mat4 spin = glm::rotate(glm::mat4(1.0f), 6.2831853f * i / 32.0f, light.direction);
    const glm::vec3 axis = glm::vec3(spin * glm::vec4(side, 0.0f));
    const glm::vec3 onCone = glm::vec3(glm::rotate(glm::mat4(1.0f), light.outerConeAngle, axis) *
                                       glm::vec4(light.direction, 0));
    const glm::vec3 ndc = project(frame.viewProjection, light.position + 5.0f * onCone);
    EXPECT_LT(std::abs(ndc.x), 1.0f);
    EXPECT_LT(std::abs(ndc.y), 1.0f);
  }
  // Near maps to depth 1, far to 0 (reversed), along the axis.
  EXPECT_NEAR(project(frame.viewProjection, light.position + 0.1f * light.direction).z, 1.0f,
              1e-4f);
  EXPECT_NEAR(project(frame.viewProjection, light.position + 20.0f * light.direction).z, 0.0f,
              1e-4f);
}

TEST(SpotShadow, ConesWiderThanOneMapAreClippedAndSaySo) {
  Light light;
  light.type = LightType::Spot;
  light.outerConeAngle = glm::radians(89.0f);
  EXPECT_TRUE(spotShadowFrame(light, 0.1f, 10.0f, 256).coneClipped);
}

TEST(Cascades, PracticalSplitMixesLogarithmicAndLinear) {
  const std::vector<float> linear = cascadeSplits(1.0f, 101.0f, 4, 0.0f);
  EXPECT_NEAR(linear[0], 26.0f, 1e-3f);
  EXPECT_NEAR(linear[1], 51.0f, 1e-3f);
  const std::vector<float> logarithmic = cascadeSplits(1.0f, 10000.0f, 4, 1.0f);
  EXPECT_NEAR(logarithmic[0], 10.0f, 1e-2f);
  EXPECT_NEAR(logarithmic[2], 1000.0f, 1.0f);
  EXPECT_EQ(logarithmic[3], 10000.0f);
  const std::vector<float> mixed = cascadeSplits(1.0f, 10000.0f, 3, 0.5f);
  for (std::size_t i = 1; i < mixed.size(); ++i) EXPECT_GT(mixed[i], mixed[i - 1]);
}

TEST(Cascades, EachCascadeCoversItsSliceOfTheVisibleScene) {
  const Scene scene = boundedScene({-20, 0, -20}, {20, 5, 20});
  const ViewCamera camera = cameraAtOrigin(scene, {0, 3, 18}, {.width = 160, .height = 90});
  Light sun;
  sun.type = LightType::Directional;
  sun.direction = glm::normalize(glm::vec3(-0.4f, -1.0f, -0.3f));
  sun.shadow.cascades = 4;
  sun.shadow.resolution = 1024;
  const DirectionalShadowFrame frame = directionalShadowFrame(sun, camera, scene.bounds);
  ASSERT_EQ(frame.cascades.size(), 4u);
  // Random visible scene points: the cascade that their view depth selects holds them, with
  // depth inside [0, 1]; nearer cascades have smaller texels.
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  int checked = 0;
  for (int i = 0; i < 4000; ++i) {
    const glm::vec3 p =
        glm::mix(scene.bounds.min, scene.bounds.max, glm::vec3(u(rng), u(rng), u(rng)));
    const glm::vec3 ndcCamera = project(camera.projection * camera.view, p);
    if (std::abs(ndcCamera.x) > 1 || std::abs(ndcCamera.y) > 1 || ndcCamera.z <= 0) continue;
    const float viewDepth = -(camera.view * glm::vec4(p, 1.0f)).z;
    const auto c = std::find_if(frame.cascades.begin(), frame.cascades.end(),
                                [&](const Cascade& k) { return viewDepth <= k.viewDepthEnd; });
    ASSERT_NE(c, frame.cascades.end());
    const glm::vec3 ndc = project(c->viewProjection, p);
    EXPECT_LE(std::abs(ndc.x), 1.0f);
    EXPECT_LE(std::abs(ndc.y), 1.0f);
    EXPECT_GE(ndc.z, 0.0f);
    EXPECT_LE(ndc.z, 1.0f);
    ++checked;
  }
  EXPECT_GT(checked, 500);
  for (std::size_t i = 1; i < frame.cascades.size(); ++i)
    EXPECT_LT(frame.cascades[i - 1].texelSize, frame.cascades[i].texelSize);
  // Any scene point, visible or not, lies within the maps' depth range: casters outside the
  // camera's view still shadow what it sees.
  EXPECT_LE(frame.nearToLight, frame.farFromLight);
}

TEST(Cascades, ShadowDistanceEndsTheLastCascade) {
  const Scene scene = boundedScene({-50, 0, -50}, {50, 5, 50});
  const ViewCamera camera = cameraAtOrigin(scene, {0, 3, 45});
  Light sun;
  sun.type = LightType::Directional;
  sun.direction = glm::vec3(0, -1, 0);
  sun.shadow.cascades = 2;
  sun.shadow.distance = 30.0f;
  const DirectionalShadowFrame frame = directionalShadowFrame(sun, camera, scene.bounds);
  EXPECT_EQ(frame.cascades.back().viewDepthEnd, 30.0f);
}

// ---------------------------------------------------------------------------------------------
// Light clusters (renderer/light_clusters.h)

std::vector<std::uint32_t> clusterList(const LightClusters& clusters, std::size_t cluster) {
  const auto first = clusters.lights.begin() + clusters.ranges[2 * cluster];
  return std::vector<std::uint32_t>(first, first + clusters.ranges[2 * cluster + 1]);
}

ViewCamera topDownCamera() {
  return cameraAtOrigin(boundedScene({-10, 0, -10}, {10, 1, 10}), {0, 10, 0.001f},
                        {.fovDegrees = 90.0f, .width = 320, .height = 320});
}

// `count` point lights with ranges, scattered through and around topDownCamera()'s view.
std::vector<Light> randomRangedLights(std::mt19937& rng, int count) {
  std::uniform_real_distribution<float> u(-12.0f, 12.0f), h(-8.0f, 9.5f), r(0.3f, 3.0f);
  std::vector<Light> lights(static_cast<std::size_t>(count));
  for (Light& light : lights) {
    light.position = {u(rng), h(rng), u(rng)};
    light.range = r(rng);
  }
  return lights;
}

std::vector<const Light*> pointersTo(const std::vector<Light>& lights) {
  std::vector<const Light*> out;
  for (const Light& light : lights) out.push_back(&light);
  return out;
}

TEST(LightClusters, RangedLightsOnlyInTheClustersTheirSphereTouches) {
  const ViewCamera camera = topDownCamera();
  Light small, everywhere, behind, sun;
  small.position = {5, 0, 5};  // lower right quadrant of the picture seen from above
  small.range = 1.0f;
  everywhere.position = {0, 1, 0};
  behind.position = {0, 30, 0};  // above the camera, its range ends before the near plane
  behind.range = 5.0f;
  sun.type = LightType::Directional;
  const LightClusters clusters =
      buildLightClusters({&small, &everywhere, &behind, &sun}, camera, 11.0f, 16, 24);
  ASSERT_EQ(clusters.columns, 20);
  ASSERT_EQ(clusters.rows, 20);
  ASSERT_EQ(clusters.slices, 24);
  // No range and directional: listed once for everyone.
  ASSERT_EQ(clusters.globalCount, 2u);
  EXPECT_EQ(clusters.lights[0], 1u);
  EXPECT_EQ(clusters.lights[1], 3u);
  int smallClusters = 0;
  for (std::size_t c = 0; c < clusters.ranges.size() / 2; ++c) {
    const std::vector<std::uint32_t> list = clusterList(clusters, c);
    EXPECT_EQ(std::find(list.begin(), list.end(), 1u), list.end());
    EXPECT_EQ(std::find(list.begin(), list.end(), 2u), list.end());  // out of view
    if (std::find(list.begin(), list.end(), 0u) == list.end()) continue;
    ++smallClusters;
    // The sphere (radius 1 at 10 m, 90 degree view: 16 px per metre) covers pixels near
    // (240, 80) counted from the bottom left, at view depths 9..11 m.
    const int tile = static_cast<int>(c) % (clusters.columns * clusters.rows);
    const int slice = static_cast<int>(c) / (clusters.columns * clusters.rows);
    const int x = (tile % clusters.columns) * 16 + 8, y = (tile / clusters.columns) * 16 + 8;
    EXPECT_NEAR(x, 240, 40);
    EXPECT_NEAR(y, 80, 40);
    EXPECT_GE(slice, clusterSlice(clusters, 9.0f) - 1);
    EXPECT_LE(slice, clusterSlice(clusters, 11.0f) + 1);
  }
  EXPECT_GE(smallClusters, 4);
  EXPECT_LE(smallClusters, 25 * 3);
}

// Frames of one camera reuse the cluster boxes (ClusterBoxCache); a frame of another camera,
// or of another far depth, must not: each grid equals the one built without a cache.
TEST(LightClusters, CachedBoxesGiveTheClustersOfEachCamera) {
  std::mt19937 rng(9);
  const std::vector<Light> storage = randomRangedLights(rng, 200);
  const std::vector<const Light*> lights = pointersTo(storage);
  ViewCamera wide = topDownCamera();
  ViewCamera narrow = wide;
  narrow.projection = reversedPerspective(0.4f, 1.0f, 0.05f, 0.0f);
  ViewCamera ortho = wide;
  ortho.orthographic = true;
  ortho.projection = reversedOrthographic(12.0f, 12.0f, 0.01f, 30.0f);
  ClusterBoxCache cache;
  const std::pair<const ViewCamera*, float> frames[] = {
      {&wide, 20.0f}, {&wide, 20.0f},  {&narrow, 20.0f}, {&wide, 20.0f},
      {&wide, 8.0f},  {&ortho, 20.0f}, {&narrow, 20.0f}};
  for (const auto& [camera, far] : frames) {
    const LightClusters cached = buildLightClusters(lights, *camera, far, 16, 24, &cache);
    const LightClusters fresh = buildLightClusters(lights, *camera, far, 16, 24);
    EXPECT_EQ(cached.ranges, fresh.ranges);
    EXPECT_EQ(cached.lights, fresh.lights);
  }
}

// From 16 ranged lights on, the clusters' rows are listed on several threads, in blocks of
// rows dealt out in turn: each list must be what each light alone gives, in light order, with
// the lights reaching everywhere first. The second grid's 13 x 23 rows do not fill their last
// block, and its 21 columns are not the rows' count.
TEST(LightClusters, ManyLightsListEachClusterAsEachLightAloneDoes) {
  struct Grid {
    bool orthographic;
    int width, height, slices;
  };
  for (const Grid grid : {Grid{false, 320, 320, 24}, Grid{true, 320, 320, 24},
                          Grid{false, 328, 200, 23}, Grid{true, 328, 200, 23}}) {
    ViewCamera camera = topDownCamera();
    camera.width = grid.width;
    camera.height = grid.height;
    if (grid.orthographic) {
      camera.orthographic = true;
      camera.projection = reversedOrthographic(12.0f, 12.0f, 0.01f, 30.0f);
    }
    std::mt19937 rng(11);
    std::vector<Light> storage = randomRangedLights(rng, 301);
    storage[7].range = 0.0f;  // reaches everywhere
    const std::vector<const Light*> lights = pointersTo(storage);
    ClusterBoxCache cache;
    const LightClusters all = buildLightClusters(lights, camera, 20.0f, 16, grid.slices, &cache);
    ASSERT_EQ(all.columns, (grid.width + 15) / 16);
    const std::size_t count = all.ranges.size() / 2;
    ASSERT_EQ(count, static_cast<std::size_t>(all.columns * all.rows * grid.slices));
    std::vector<std::vector<std::uint32_t>> expected(count);
    for (std::size_t i = 0; i < storage.size(); ++i) {
      if (storage[i].range <= 0.0f) continue;
      const LightClusters alone =
          buildLightClusters({&storage[i]}, camera, 20.0f, 16, grid.slices, &cache);
      ASSERT_EQ(alone.ranges.size(), all.ranges.size());
      for (std::size_t c = 0; c < count; ++c)
        if (alone.ranges[2 * c + 1] != 0) expected[c].push_back(static_cast<std::uint32_t>(i));
    }
    ASSERT_EQ(all.globalCount, 1u);
    EXPECT_EQ(all.lights[0], 7u);
    std::size_t pairs = 0;
    for (std::size_t c = 0; c < count; ++c) {
      ASSERT_EQ(clusterList(all, c), expected[c]) << "cluster " << c;
      // Each list starts where the one before it ends: no gap, no overlap.
      ASSERT_EQ(all.ranges[2 * c], 1 + pairs) << "cluster " << c;
      pairs += expected[c].size();
    }
    EXPECT_GT(pairs, 1000u);
    EXPECT_EQ(all.lights.size(), 1 + pairs);
  }
}

TEST(LightClusters, EveryPointFindsEveryLightThatReachesItInItsCluster) {
  // Random ranged lights through a perspective and an orthographic view; random points in
  // view: a light whose sphere holds the point must be in the point's cluster, and most
  // clusters list far fewer lights than their screen tile would.
  for (const bool orthographic : {false, true}) {
    ViewCamera camera = topDownCamera();
    if (orthographic) {
      camera.orthographic = true;
      camera.projection = reversedOrthographic(12.0f, 12.0f, 0.01f, 30.0f);
    }
    std::mt19937 rng(5);
    const std::vector<Light> storage = randomRangedLights(rng, 300);
    const std::vector<const Light*> lights = pointersTo(storage);
    const LightClusters clusters = buildLightClusters(lights, camera, 20.0f, 16, 24);
    const glm::mat4 inverse = glm::inverse(camera.projection * camera.view);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    auto viewDepthOf = [&](const glm::vec3& p) { return -(camera.view * glm::vec4(p, 1.0f)).z; };
    int checked = 0, reached = 0;
    std::size_t listed = 0;
    for (int k = 0; k < 20000; ++k) {
      // A random point of a random pixel's ray, at a view depth in 0.05..19.5.
      const float px = unit(rng) * 320.0f, py = unit(rng) * 320.0f;
      const glm::vec2 ndc(px / 160.0f - 1.0f, py / 160.0f - 1.0f);
      const glm::vec4 h0 = inverse * glm::vec4(ndc, 1.0f, 1.0f);
      const glm::vec4 h1 = inverse * glm::vec4(ndc, 0.5f, 1.0f);
      const glm::vec3 a = glm::vec3(h0) / h0.w, b = glm::vec3(h1) / h1.w;
      const float depth = 0.05f + 19.45f * unit(rng);
      const float t = (depth - viewDepthOf(a)) / (viewDepthOf(b) - viewDepthOf(a));
      const glm::vec3 p = a + t * (b - a);
      const int tile = (static_cast<int>(py) / 16) * clusters.columns + static_cast<int>(px) / 16;
      const std::size_t cluster = static_cast<std::size_t>(clusterSlice(clusters, depth)) *
                                      clusters.columns * clusters.rows +
                                  static_cast<std::size_t>(tile);
      const std::vector<std::uint32_t> list = clusterList(clusters, cluster);
      listed += list.size();
      for (std::size_t i = 0; i < storage.size(); ++i) {
        if (glm::distance(storage[i].position, p) >= storage[i].range * 0.9999f) continue;
        ++reached;
        EXPECT_NE(std::find(list.begin(), list.end(), static_cast<std::uint32_t>(i)), list.end())
            << (orthographic ? "orthographic" : "perspective") << ": light " << i << " at pixel ("
            << px << ", " << py << "), depth " << depth;
      }
      ++checked;
    }
    EXPECT_GT(reached, 2000);
    // Lights reaching an average point: about 300 * 4/3 pi (r^3 averaged: 9.2) / (24 * 17.5 *
    // 24 m^3) = 1.1; the clusters' conservative bounds list a few more.
    EXPECT_LT(static_cast<double>(listed) / checked, 4.0)
        << (orthographic ? "orthographic" : "perspective");
  }
}

}  // namespace view_math_test
