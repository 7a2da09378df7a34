// Camera sets (orbit, hemisphere) and the exported camera conventions (OpenGL, OpenCV, EXR).
#include "renderer/view/camera_sets.h"

#include <gtest/gtest.h>

#include <cmath>
#include <glm/gtc/matrix_transform.hpp>

#include "renderer/view/camera_export.h"

namespace omnishadow::camera_sets_test {
namespace {

TEST(CameraSets, OrbitKeepsElevationAndDistanceAndSpreadsEvenly) {
  const glm::vec3 center(1, 2, 3), eye(1, 5, 7);  // 3 above, 4 in front
  const std::vector<CameraView> views = orbitViews(eye, center, 8);
  ASSERT_EQ(views.size(), 8u);
  EXPECT_NEAR(glm::length(views[0].eye - eye), 0.0f, 1e-5f);  // starts at the camera
  for (std::size_t k = 0; k < views.size(); ++k) {
    EXPECT_EQ(views[k].target, center);
    EXPECT_NEAR(views[k].eye.y, 5.0f, 1e-5f);
    EXPECT_NEAR(glm::length(views[k].eye - center), 5.0f, 1e-5f);
    // Neighbours 45° apart on the circle of radius 4: chord 2 * 4 * sin(22.5°).
    const glm::vec3 next = views[(k + 1) % views.size()].eye;
    EXPECT_NEAR(glm::length(next - views[k].eye), 8.0f * std::sin(glm::radians(22.5f)), 1e-4f);
  }
}

TEST(CameraSets, HemisphereViewsCoverTheUpperHalfEvenly) {
  const glm::vec3 center(0, 1, 0);
  const int n = 64;
  const std::vector<CameraView> views = hemisphereViews(center, 3.0f, n);
  ASSERT_EQ(views.size(), static_cast<std::size_t>(n));
  glm::vec3 mean(0.0f);
  int upperHalfOfHeights = 0;
  for (const CameraView& v : views) {
    EXPECT_EQ(v.target, center);
    EXPECT_NEAR(glm::length(v.eye - center), 3.0f, 1e-4f);
    EXPECT_GT(v.eye.y - center.y, 0.0f);
    mean += (v.eye - center) / 3.0f;
    if ((v.eye.y - center.y) / 3.0f > 0.5f) ++upperHalfOfHeights;
  }
  mean /= static_cast<float>(n);
  // Uniform over the hemisphere: the mean direction is (0, 1/2, 0), and half the views lie
  // above height 1/2 (equal heights hold equal areas).
  EXPECT_NEAR(mean.x, 0.0f, 0.03f);
  EXPECT_NEAR(mean.z, 0.0f, 0.03f);
  EXPECT_NEAR(mean.y, 0.5f, 0.01f);
  EXPECT_EQ(upperHalfOfHeights, n / 2);
  // No two views closer than a fair share of the area allows (2 pi / n per view).
  float closest = 1e9f;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < i; ++j)
      closest = std::min(closest, glm::length(views[i].eye - views[j].eye) / 3.0f);
  EXPECT_GT(closest, 0.5f * std::sqrt(2.0f * 3.14159f / n));
}

TEST(CameraExport, OpenCvMatricesReprojectToThePixelTheProjectionDrawsAt) {
  ViewCamera camera;
  camera.width = 200;
  camera.height = 100;
  camera.eye = glm::vec3(3, 2, 5);
  camera.view = glm::lookAt(camera.eye, glm::vec3(0, 0.5f, 0), glm::vec3(0, 1, 0));
  camera.projection = reversedPerspective(glm::radians(40.0f), 2.0f, 0.1f, 0.0f);
  const CameraExport e = exportCamera(camera);
  const glm::dvec4 point(0.3, 0.9, -0.4, 1.0);
  // Where GL draws it: NDC to window coordinates, rows counted from the top.
  const glm::dvec4 clip = e.projection * e.worldToCameraGl * point;
  const double u = (clip.x / clip.w + 1.0) * 0.5 * camera.width;
  const double v = (1.0 - clip.y / clip.w) * 0.5 * camera.height;
  // OpenCV: K [R | t] X.
  const glm::dvec4 x = e.worldToCameraCv * point;
  EXPECT_GT(x.z, 0.0);
  EXPECT_NEAR(e.fx * x.x / x.z + e.cx, u, 1e-3);
  EXPECT_NEAR(e.fy * x.y / x.z + e.cy, v, 1e-3);
  EXPECT_NEAR(e.fx, e.fy, 1e-3);  // square pixels
  EXPECT_NEAR(e.verticalFovDegrees, 40.0, 1e-4);
  // The inverses and the camera position.
  const glm::dvec4 origin = e.cameraToWorldCv * glm::dvec4(0, 0, 0, 1);
  EXPECT_NEAR(glm::length(glm::dvec3(origin) - glm::dvec3(camera.eye)), 0.0, 1e-5);
  // OpenEXR's camera space: +z is the viewing direction.
  const glm::dvec4 target = e.worldToCameraExr * glm::dvec4(0, 0.5, 0, 1);
  EXPECT_GT(target.z, 0.0);
  EXPECT_NEAR(target.x, 0.0, 1e-5);
}

}  // namespace
}  // namespace omnishadow::camera_sets_test
