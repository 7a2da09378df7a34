// Translucent casters (issue 18): BLEND and KHR_materials_transmission surfaces let part of the
// light through, tinted by their color, and the renderer's transmittance maps agree with exact
// rays that multiply through every translucent surface they cross (README, "Translucent
// shadows"). Every value below is also computed by hand from the material.
#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <glm/gtc/matrix_transform.hpp>

#include "renderer/passes/lighting_pass.h"
#include "renderer/render/renderer.h"
#include "renderer/scene/gltf_loader.h"
#include "renderer/scene/translucency.h"
#include "renderer/verify/shadow_reference.h"
#include "renderer/verify/shadow_verification.h"
#include "renderer/view/camera.h"
#include "renderer/view/shadow_plan.h"
#include "scenes/builder/gltf_builder.h"
#include "tests/support/scene_objects.h"
#include "tests/support/shadow_checks.h"

namespace translucent_shadows_test {

using namespace omnishadow;

namespace {

Renderer& contextForThisProgram() {
  static Renderer renderer(ContextOptions{});
  return renderer;
}

Material glass(const glm::vec4& color, AlphaMode mode, float transmission) {
  Material m;
  m.baseColorFactor = color;
  m.alphaMode = mode;
  m.transmissionFactor = transmission;
  m.doubleSided = true;
  return m;
}

struct Pane {
  Material material;
  glm::vec3 center;
  float size = 2.0f;
  float scale = 1.0f;  // of the pane's node (a volume's thickness grows with it)
};

struct Staged {
  Scene scene;
  std::vector<Light> lights;
  ViewCamera camera;
};

// A point light and a spot light above the middle of an 8 x 8 floor, a sun slightly tilted;
// 256-texel maps.
std::vector<Light> overheadLights(bool translucent = true) {
  Light point;
  point.name = "point";
  point.position = {0.0f, 5.0f, 0.0f};
  point.intensity = 20.0f;
  Light spot = point;
  spot.name = "spot";
  spot.type = LightType::Spot;
  spot.position = {0.2f, 5.0f, -0.1f};
  spot.direction = {0.0f, -1.0f, 0.0f};
  spot.outerConeAngle = 0.8f;
  Light sun;
  sun.name = "sun";
  sun.type = LightType::Directional;
  sun.direction = glm::normalize(glm::vec3(0.15f, -1.0f, 0.1f));
  sun.intensity = 2.0f;
  std::vector<Light> lights = {point, spot, sun};
  for (Light& light : lights) {
    light.shadow.resolution = 256;
    light.shadow.translucent = translucent;
  }
  return lights;
}

// 128 x 96, looking down from `eye`.
ViewCamera cameraAbove(const Scene& scene, const glm::vec3& eye, const glm::vec3& target) {
  CameraRequest request;
  request.eye = eye;
  request.target = target;
  request.up = {0.0f, 1.0f, 0.0f};
  request.fovDegrees = 50.0f;
  request.width = 128;
  request.height = 96;
  return resolveCamera(scene, request);
}

// Horizontal panes over a white floor, seen from above (blended panes do not hide the floor
// in the AOVs), plus `extra` opaque boxes (center, half extent).
Staged paneScene(const std::vector<Pane>& panes,
                 const std::vector<std::pair<glm::vec3, float>>& boxes = {}) {
  Staged s;
  s.scene.materials.push_back(Material{});
  test::placeMesh(s.scene, builder::makePlane(8.0f), glm::mat4(1.0f), 0);
  for (const auto& [center, half] : boxes)
    test::placeMesh(s.scene, builder::makeBox(glm::vec3(half)),
                    glm::translate(glm::mat4(1.0f), center), 0);
  for (const Pane& pane : panes) {
    s.scene.materials.push_back(pane.material);
    test::placeMesh(s.scene, builder::makePlane(pane.size),
                    glm::scale(glm::translate(glm::mat4(1.0f), pane.center), glm::vec3(pane.scale)),
                    static_cast<int>(s.scene.materials.size()) - 1);
  }
  s.lights = overheadLights();
  s.camera = cameraAbove(s.scene, {0.0f, 7.0f, 2.5f}, {0.0f, 0.0f, 0.0f});
  return s;
}

Frame renderAovs(const Staged& s) {
  return test::renderAovs(contextForThisProgram(), s.scene, s.lights, s.camera);
}

ShadowVerification verifyAgainstRays(const Staged& s, const Frame& frame) {
  return test::verifyAgainstRays(s.scene, s.lights, frame, s.camera);
}

// Every light: interior agreement and false rates within the bar, and the interior RGB
// transmittance within kTransmittanceTolerance of the rays' at >= 99.5% of at least
// `minTinted` points.
void expectAgreementWithTheRays(const ShadowVerification& v, std::int64_t minChecked) {
  for (const LightVerification& light : v.lights) {
    SCOPED_TRACE(light.name);
    EXPECT_GT(light.interior.evaluated, 1000);
    EXPECT_GE(light.interior.agreementRate(), 0.999);
    EXPECT_LE(light.interior.falseShadowRate(), 0.0005);
    EXPECT_LE(light.interior.falseLightRate(), 0.0005);
    EXPECT_GE(light.transmittance.evaluated, minChecked);
    EXPECT_GE(light.transmittance.agreementRate(), 0.995);
  }
}

// What the AOVs say of the floor points whose rays find `expected` (within 1e-5) here and a
// tenth of a unit around: how many, and how many rendered within 0.02 per channel and with
// visibility = the RGB mean.
struct HandCheck {
  int points = 0, matching = 0;
};

HandCheck checkFloor(const Staged& s, const FloatImage& aovs, const Light& light,
                     const glm::vec3& expected) {
  const ShadowReference reference(s.scene);
  const int p = aovs.channelIndex("P.X"), a = aovs.channelIndex("A");
  const int t = aovs.channelIndex("transmittance." + light.name + ".R");
  const int vis = aovs.channelIndex("visibility." + light.name);
  EXPECT_GE(t, 0);
  HandCheck check;
  if (t < 0) return check;
  const glm::vec3 up(0.0f, 1.0f, 0.0f);
  for (int y = 0; y < aovs.height; ++y)
    for (int x = 0; x < aovs.width; ++x) {
      if (!(aovs.at(x, y, a) > 0.0f)) continue;
      const glm::vec3 P{aovs.at(x, y, p), aovs.at(x, y, p + 1), aovs.at(x, y, p + 2)};
      if (std::abs(P.y) > 1e-3f) continue;
      bool interior = true;
      for (const glm::vec3& shift : {glm::vec3(0), glm::vec3(0.1f, 0, 0), glm::vec3(-0.1f, 0, 0),
                                     glm::vec3(0, 0, 0.1f), glm::vec3(0, 0, -0.1f)}) {
        const glm::vec3 r = reference.transmittance(light, P + shift, up);
        interior =
            interior && glm::all(glm::lessThanEqual(glm::abs(r - expected), glm::vec3(1e-5f)));
      }
      if (!interior) continue;
      ++check.points;
      const glm::vec3 rendered{aovs.at(x, y, t), aovs.at(x, y, t + 1), aovs.at(x, y, t + 2)};
      const float mean = (rendered.r + rendered.g + rendered.b) / 3.0f;
      if (glm::all(glm::lessThanEqual(glm::abs(rendered - expected), glm::vec3(0.02f))) &&
          std::abs(aovs.at(x, y, vis) - mean) < 1e-5f)
        ++check.matching;
    }
  return check;
}

}  // namespace

SurfaceTexels texels(const glm::vec4& baseColor) {
  SurfaceTexels t;
  t.baseColor = baseColor;
  return t;
}

TEST(Translucency, SurfaceTransmittanceFollowsTheIssuesFormula) {
  // BLEND: 1 - alpha, whatever the color.
  EXPECT_EQ(surfaceTransmittance(glass({1, 0, 0, 1}, AlphaMode::Blend, 0),
                                 texels({0.2f, 0.4f, 0.6f, 0.25f})),
            glm::vec3(0.75f));
  // Transmission: transmission x base color.
  EXPECT_EQ(surfaceTransmittance(glass({1, 1, 1, 1}, AlphaMode::Opaque, 0.5f),
                                 texels({1.0f, 0.5f, 0.25f, 0.1f})),
            glm::vec3(0.5f, 0.25f, 0.125f));
  // Both: (1 - alpha) + alpha x transmission x base color.
  EXPECT_EQ(surfaceTransmittance(glass({1, 1, 1, 1}, AlphaMode::Blend, 0.5f),
                                 texels({1.0f, 0.5f, 0.25f, 0.5f})),
            glm::vec3(0.75f, 0.625f, 0.5625f));
  // MASK texels below the cutoff are holes.
  EXPECT_EQ(surfaceTransmittance(glass({1, 1, 1, 1}, AlphaMode::Mask, 0.5f),
                                 texels({1.0f, 0.0f, 0.0f, 0.4f})),
            glm::vec3(1.0f));
  EXPECT_TRUE(isTranslucentCaster(glass({1, 1, 1, 1}, AlphaMode::Opaque, 0.1f)));
  EXPECT_FALSE(isTranslucentCaster(glass({1, 1, 1, 0.1f}, AlphaMode::Mask, 0.0f)));
}

// A volume (KHR_materials_volume) that light crosses twice: Beer's law over half its
// thickness at each crossing, a thickness that grows with the node's scale; diffuse
// transmission adds (1 - transmission) x its fraction x its color. By hand.
Material volumeGlass() {
  Material m = glass({1, 1, 1, 1}, AlphaMode::Opaque, 1.0f);
  m.thicknessFactor = 0.4f;
  m.attenuationDistance = 0.5f;
  m.attenuationColor = {0.25f, 0.5f, 1.0f};
  return m;
}

Material diffuseLeaf() {
  Material m = glass({1, 0, 0, 1}, AlphaMode::Blend, 0.25f);
  m.diffuseTransmissionFactor = 0.8f;
  m.diffuseTransmissionColorFactor = {0.0f, 1.0f, 0.5f};
  return m;
}

TEST(Translucency, VolumesAttenuateAndDiffuseTransmissionAddsItsColor) {
  const SurfaceTexels white = texels({1, 1, 1, 1});
  // 0.25^(0.4 / (2 x 0.5)) = 0.25^0.4, 0.5^0.4; twice the scale, twice the exponent.
  const glm::vec3 once = surfaceTransmittance(volumeGlass(), white);
  EXPECT_NEAR(once.r, 0.574349f, 1e-5f);
  EXPECT_NEAR(once.g, 0.757858f, 1e-5f);
  EXPECT_EQ(once.b, 1.0f);
  const glm::vec3 scaled = surfaceTransmittance(volumeGlass(), white, 2.0f);
  EXPECT_NEAR(scaled.r, 0.329877f, 1e-5f);
  EXPECT_NEAR(scaled.g, 0.574349f, 1e-5f);
  // The thickness texture's G scales the thickness.
  SurfaceTexels thin = white;
  thin.thickness = 0.5f;
  EXPECT_NEAR(surfaceTransmittance(volumeGlass(), thin).r, 0.757858f, 1e-5f);
  // Not drawn as a volume (BLEND), not attenuated: as the lighting pass draws it.
  Material blended = volumeGlass();
  blended.alphaMode = AlphaMode::Blend;
  EXPECT_EQ(surfaceTransmittance(blended, white), glm::vec3(1.0f));
  // 0.25 x (1, 0, 0) + 0.75 x 0.8 x (0, 1, 0.5); its texture's A and color texture scale it.
  const SurfaceTexels red = texels({1, 0, 0, 1});
  EXPECT_EQ(surfaceTransmittance(diffuseLeaf(), red), glm::vec3(0.25f, 0.6f, 0.3f));
  SurfaceTexels textured = red;
  textured.diffuseTransmission = 0.5f;
  textured.diffuseTransmissionColor = {1.0f, 0.5f, 1.0f};
  EXPECT_EQ(surfaceTransmittance(diffuseLeaf(), textured), glm::vec3(0.25f, 0.15f, 0.15f));
  Material leafOnly;
  leafOnly.diffuseTransmissionFactor = 0.5f;
  EXPECT_TRUE(isTranslucentCaster(leafOnly));
  EXPECT_FLOAT_EQ(volumeScale(glm::scale(glm::mat4(1.0f), glm::vec3(1.0f, 2.0f, 4.0f))), 2.0f);
}

// The transmittance pass draws both as the rays find them. The volume pane is an opaque
// surface to the camera: it hangs high, near the lights, so that the floor it shades reaches
// past what it hides; the leaf is BLEND with alpha 1 (only what it lets through passes).
TEST(TranslucentShadows, VolumesAndDiffuseTransmissionTintAsTheRaysAndTheHandValueSay) {
  struct Case {
    const char* name;
    Pane pane;
    glm::vec3 hand;
  };
  const Case cases[] = {
      {"volume", {volumeGlass(), {0.0f, 3.5f, 0.0f}, 1.0f}, {0.574349f, 0.757858f, 1.0f}},
      {"scaled volume",
       {volumeGlass(), {0.0f, 3.5f, 0.0f}, 0.5f, 2.0f},
       {0.329877f, 0.574349f, 1.0f}},
      {"diffuse transmission", {diffuseLeaf(), {0.0f, 1.0f, 0.0f}}, {0.25f, 0.6f, 0.3f}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const Staged s = paneScene({c.pane});
    const Frame frame = renderAovs(s);
    int points = 0;
    for (const Light& light : s.lights) {
      SCOPED_TRACE(light.name);
      const HandCheck check = checkFloor(s, *frame.aovs, light, c.hand);
      EXPECT_EQ(check.matching, check.points);
      points += check.points;
    }
    EXPECT_GT(points, 300);
    expectAgreementWithTheRays(verifyAgainstRays(s, frame), 200);
  }
}

// Each pane's color and alpha from its own base color texture: a green and a red texel of alpha
// 0.4 under white factors, transmission 0.5: (1 - 0.4) + 0.4 x 0.5 x the texel's color.
TEST(TranslucentShadows, TexturedPanesTintAsTheirTexturesSay) {
  Staged s = paneScene({{glass({1, 1, 1, 1}, AlphaMode::Blend, 0.5f), {-1.6f, 1.0f, 0.0f}, 1.5f},
                        {glass({1, 1, 1, 1}, AlphaMode::Blend, 0.5f), {1.6f, 1.0f, 0.0f}, 1.5f}});
  for (const std::uint8_t red : {0, 255}) {
    Image texel;
    texel.width = texel.height = 1;
    texel.rgba = {red, static_cast<std::uint8_t>(255 - red), 0, 102};
    s.scene.images.push_back(texel);
    Texture texture;
    texture.image = static_cast<int>(s.scene.images.size()) - 1;
    s.scene.textures.push_back(texture);
    s.scene.materials[s.scene.textures.size()].baseColorTexture.texture = texture.image;
  }
  const Frame frame = renderAovs(s);
  const Light& point = s.lights[0];
  for (const glm::vec3 hand : {glm::vec3(0.6f, 0.8f, 0.6f), glm::vec3(0.8f, 0.6f, 0.6f)}) {
    const HandCheck check = checkFloor(s, *frame.aovs, point, hand);
    EXPECT_GT(check.points, 100) << hand.r;
    EXPECT_EQ(check.matching, check.points) << hand.r;
  }
}

// A colored pane (BLEND with transmission) 1 unit over the floor: the floor under it receives
// (1 - 0.8) + 0.8 x 0.5 x (1, 0.5, 0.2) = (0.6, 0.4, 0.28) of every light, as the rays find.
TEST(TranslucentShadows, ColoredPaneCastsATintedShadowThatMatchesTheRaysAndTheHandValue) {
  const Staged s =
      paneScene({{glass({1.0f, 0.5f, 0.2f, 0.8f}, AlphaMode::Blend, 0.5f), {0.0f, 1.0f, 0.0f}}});
  const Frame frame = renderAovs(s);
  const glm::vec3 hand(0.6f, 0.4f, 0.28f);
  for (const Light& light : s.lights) {
    SCOPED_TRACE(light.name);
    const HandCheck check = checkFloor(s, *frame.aovs, light, hand);
    EXPECT_GT(check.points, 300);
    EXPECT_EQ(check.matching, check.points);
  }
  expectAgreementWithTheRays(verifyAgainstRays(s, frame), 1000);
}

// Two overlapping panes: where both shade the floor, their transmittances multiply:
// 0.4 (BLEND alpha 0.6) x 0.8 x (0.25, 0.5, 1) (opaque-alpha BLEND with transmission 0.8).
TEST(TranslucentShadows, OverlappingPanesMultiply) {
  const Staged s =
      paneScene({{glass({1.0f, 1.0f, 1.0f, 0.6f}, AlphaMode::Blend, 0.0f), {-0.6f, 1.0f, 0.0f}},
                 {glass({0.25f, 0.5f, 1.0f, 1.0f}, AlphaMode::Blend, 0.8f), {0.6f, 1.6f, 0.0f}}});
  const Frame frame = renderAovs(s);
  const Light& point = s.lights[0];
  const HandCheck both = checkFloor(s, *frame.aovs, point, glm::vec3(0.08f, 0.16f, 0.32f));
  const HandCheck first = checkFloor(s, *frame.aovs, point, glm::vec3(0.4f));
  const HandCheck second = checkFloor(s, *frame.aovs, point, glm::vec3(0.2f, 0.4f, 0.8f));
  for (const HandCheck& check : {both, first, second}) {
    EXPECT_GT(check.points, 100);
    EXPECT_EQ(check.matching, check.points);
  }
  expectAgreementWithTheRays(verifyAgainstRays(s, frame), 1000);
}

// The transmittance pass clears only what the previous pass drew and what it draws itself
// (llvmpipe clears RGBA32F slowly): a pane that moved between two frames of one renderer must
// leave no tint behind where it was. The second frame's textures are the first's, from the
// renderer's pool.
TEST(TranslucentShadows, APaneThatMovedBetweenFramesLeavesNoTintWhereItWas) {
  const Material tinted = glass({0.2f, 0.9f, 0.4f, 0.7f}, AlphaMode::Blend, 0.0f);
  const Staged before = paneScene({{tinted, {-1.5f, 1.0f, -1.0f}, 1.2f}});
  const Staged after = paneScene({{tinted, {1.5f, 1.2f, 1.0f}, 1.2f}});
  renderAovs(before);
  const Frame frame = renderAovs(after);
  for (const Light& light : after.lights) {
    SCOPED_TRACE(light.name);
    // Under where the pane was, every channel is lit; under where it is, tinted by 0.3.
    const HandCheck old = checkFloor(before, *frame.aovs, light, glm::vec3(0.3f));
    EXPECT_GT(old.points, 50);
    EXPECT_EQ(old.matching, 0);
    const HandCheck now = checkFloor(after, *frame.aovs, light, glm::vec3(0.3f));
    EXPECT_GT(now.points, 50);
    EXPECT_EQ(now.matching, now.points);
  }
  expectAgreementWithTheRays(verifyAgainstRays(after, frame), 200);
}

// Renders of one scene keep its point and spot maps (the shadow cache) and their transmittance
// in the atlas. When a light before them in the atlas changes how many layers it needs, a
// reused map's transmittance moves and must be drawn again: the frame equals a fresh render.
TEST(TranslucentShadows, AReusedMapWhoseAtlasLayersMovedIsTintedAsAFreshRender) {
  const Staged s = paneScene(
      {{glass({0.2f, 0.9f, 0.4f, 0.7f}, AlphaMode::Blend, 0.0f), {0.3f, 1.0f, 0.2f}, 1.6f}});
  Renderer& renderer = contextForThisProgram();
  StageTimes times;
  const glm::vec3 ambient(0.03f);
  // The point light low and beside the pane reaches it through two cube faces, not one, so
  // the spot light's atlas layer moves.
  std::vector<Light> lowPoint = s.lights;
  lowPoint[0].position = {-1.2f, 1.05f, 0.2f};
  renderer.render(s.scene, s.lights, ambient, s.camera, {}, times);
  const Frame moved = renderer.render(s.scene, lowPoint, ambient, s.camera, {}, times);
  EXPECT_EQ(moved.shadowMapsReused, 1);  // the spot; the point moved, the sun follows the camera
  const Frame again = renderer.render(s.scene, lowPoint, ambient, s.camera, {}, times);
  EXPECT_EQ(again.shadowMapsReused, 2);
  const Staged other = paneScene({});
  renderer.render(other.scene, other.lights, ambient, other.camera, {}, times);
  const Frame fresh = renderer.render(s.scene, lowPoint, ambient, s.camera, {}, times);
  EXPECT_EQ(fresh.shadowMapsReused, 0);
  EXPECT_EQ(moved.beauty.pixels, fresh.beauty.pixels);
  EXPECT_EQ(again.beauty.pixels, fresh.beauty.pixels);
}

// An opaque box over a colored BLEND pane still blocks every channel on the floor below; the
// box's top, in front of the pane, and the top of an opaque-mode transmission pane (the glass
// itself) are not tinted.
TEST(TranslucentShadows, OpaqueCastersBlockFullyAndReceiversInFrontOfThePaneAreNotTinted) {
  const Staged s = paneScene(
      {{glass({0.2f, 0.9f, 0.4f, 1.0f}, AlphaMode::Opaque, 0.7f), {-1.2f, 1.0f, 0.0f}, 1.6f},
       {glass({0.2f, 0.9f, 0.4f, 0.5f}, AlphaMode::Blend, 1.0f), {1.0f, 1.0f, 0.0f}, 1.6f}},
      {{{0.8f, 2.5f, 0.0f}, 0.3f}});
  const Frame frame = renderAovs(s);
  const FloatImage& aovs = *frame.aovs;
  const ShadowReference reference(s.scene);
  const Light& point = s.lights[0];
  const int p = aovs.channelIndex("P.X"), a = aovs.channelIndex("A");
  const int t = aovs.channelIndex("transmittance.point.R");
  const int vis = aovs.channelIndex("visibility.point");
  ASSERT_GE(t, 0);
  // The rays' value where it is the same (to float rounding of the interpolated color) a tenth
  // of a unit around, else -1.
  const auto steadyReference = [&](const glm::vec3& P) {
    const glm::vec3 up(0.0f, 1.0f, 0.0f);
    const glm::vec3 here = reference.transmittance(point, P, up);
    for (const glm::vec3& shift : {glm::vec3(0.1f, 0, 0), glm::vec3(-0.1f, 0, 0),
                                   glm::vec3(0, 0, 0.1f), glm::vec3(0, 0, -0.1f)})
      if (glm::any(glm::greaterThan(glm::abs(reference.transmittance(point, P + shift, up) - here),
                                    glm::vec3(1e-5f))))
        return glm::vec3(-1.0f);
    return here;
  };
  int boxTop = 0, paneTop = 0, floorBlocked = 0, floorTinted = 0;
  for (int y = 0; y < aovs.height; ++y)
    for (int x = 0; x < aovs.width; ++x) {
      if (!(aovs.at(x, y, a) > 0.0f)) continue;
      const glm::vec3 P{aovs.at(x, y, p), aovs.at(x, y, p + 1), aovs.at(x, y, p + 2)};
      const glm::vec3 rgb{aovs.at(x, y, t), aovs.at(x, y, t + 1), aovs.at(x, y, t + 2)};
      const glm::vec3 expected = steadyReference(P);
      if (expected.x < 0.0f) continue;
      if (std::abs(P.y - 2.8f) < 1e-3f) {
        ++boxTop;
        EXPECT_EQ(expected, glm::vec3(1.0f));
        EXPECT_EQ(rgb, glm::vec3(1.0f)) << P.x << " " << P.z;
      }
      // The transmission pane's own top (the BLEND pane is not in the AOVs).
      if (std::abs(P.y - 1.0f) < 1e-3f) {
        ++paneTop;
        EXPECT_EQ(expected, glm::vec3(1.0f));
        EXPECT_EQ(rgb, glm::vec3(1.0f)) << P.x << " " << P.z;
      }
      // The floor in the box's shadow: the pane and the box in line, nothing gets through.
      if (std::abs(P.y) < 1e-3f && expected == glm::vec3(0.0f)) {
        ++floorBlocked;
        EXPECT_EQ(rgb, glm::vec3(0.0f)) << P.x << " " << P.z;
        EXPECT_EQ(aovs.at(x, y, vis), 0.0f);
      }
      // Beside it, under the BLEND pane alone: 0.5 + 0.5 x (0.2, 0.9, 0.4).
      if (std::abs(P.y) < 1e-3f &&
          glm::all(
              glm::lessThan(glm::abs(expected - glm::vec3(0.6f, 0.95f, 0.7f)), glm::vec3(1e-5f)))) {
        ++floorTinted;
        EXPECT_LT(glm::length(rgb - expected), 0.02f) << P.x << " " << P.z;
      }
    }
  EXPECT_GT(boxTop, 20);
  EXPECT_GT(paneTop, 150);
  EXPECT_GT(floorBlocked, 20);
  EXPECT_GT(floorTinted, 100);
  expectAgreementWithTheRays(verifyAgainstRays(s, frame), 500);
}

// "translucentShadows": false is the cut-out behaviour: a BLEND pane of alpha >= 0.5 blocks
// fully, one below lets everything through, transmission is ignored, and the AOVs have no
// transmittance channels. The rays follow the same rule.
TEST(TranslucentShadows, TranslucentShadowsOffRestoresCutOutShadows) {
  Staged s = paneScene(
      {{glass({1.0f, 0.5f, 0.2f, 0.6f}, AlphaMode::Blend, 0.5f), {-1.2f, 1.0f, 0.0f}, 1.6f},
       {glass({1.0f, 0.5f, 0.2f, 0.4f}, AlphaMode::Blend, 0.5f), {1.2f, 1.0f, 0.0f}, 1.6f}});
  s.lights = overheadLights(false);
  const Frame frame = renderAovs(s);
  const FloatImage& aovs = *frame.aovs;
  for (const Light& light : s.lights)
    EXPECT_EQ(aovs.channelIndex("transmittance." + light.name + ".R"), -1);
  const int p = aovs.channelIndex("P.X"), a = aovs.channelIndex("A");
  const int vis = aovs.channelIndex("visibility.point");
  int blocked = 0, open = 0;
  for (int y = 0; y < aovs.height; ++y)
    for (int x = 0; x < aovs.width; ++x) {
      if (!(aovs.at(x, y, a) > 0.0f)) continue;
      const glm::vec3 P{aovs.at(x, y, p), aovs.at(x, y, p + 1), aovs.at(x, y, p + 2)};
      if (std::abs(P.y) > 1e-3f || std::abs(P.z) > 0.6f) continue;
      // Shadows of the panes' centers (x = -+1.2 x 5/4 = -+1.5), away from their edges.
      if (std::abs(P.x + 1.5f) < 0.5f) {
        ++blocked;
        EXPECT_EQ(aovs.at(x, y, vis), 0.0f) << P.x;
      }
      if (std::abs(P.x - 1.5f) < 0.5f) {
        ++open;
        EXPECT_EQ(aovs.at(x, y, vis), 1.0f) << P.x;
      }
    }
  EXPECT_GT(blocked, 50);
  EXPECT_GT(open, 50);
  for (const LightVerification& light : verifyAgainstRays(s, frame).lights) {
    EXPECT_GE(light.interior.agreementRate(), 0.999) << light.name;
    EXPECT_EQ(light.transmittance.evaluated, 0) << light.name;
  }
}

// KHR_materials_transmission from a glTF file: a vertical opaque-mode pane of transmission
// 0.75 and base color (1, 0.5, 0.25) with a 1 x 2 transmission texture (R 255 where z < 0, 64
// where z > 0, nearest texels) lets 0.75 x (1, 0.5, 0.25) through to the floor on one side and
// 0.75 x 64/255 x (1, 0.5, 0.25) on the other.
TEST(TranslucentShadows, TransmissionFromAGltfFileTintsTheShadow) {
  builder::GltfBuilder b;
  builder::MaterialDesc floor;
  builder::PrimitiveOptions floorOptions;
  floorOptions.material = b.addMaterial(floor);
  b.addNode("floor", {}, b.addMesh(builder::makePlane(8.0f), floorOptions));
  builder::MaterialDesc pane;
  pane.baseColor = {1.0f, 0.5f, 0.25f, 1.0f};
  pane.doubleSided = true;
  builder::PrimitiveOptions paneOptions;
  paneOptions.material = b.addMaterial(pane);
  const int texture = b.addTexture(1, 2, {255, 0, 0, 255, 64, 0, 0, 255}, "transmission");
  tinygltf::Sampler nearest;
  nearest.magFilter = nearest.minFilter = TINYGLTF_TEXTURE_FILTER_NEAREST;
  b.model().samplers.push_back(nearest);
  b.model().textures[static_cast<std::size_t>(texture)].sampler =
      static_cast<int>(b.model().samplers.size()) - 1;
  tinygltf::Value::Object textureInfo = {{"index", tinygltf::Value(texture)}};
  tinygltf::Value::Object transmission = {{"transmissionFactor", tinygltf::Value(0.75)},
                                          {"transmissionTexture", tinygltf::Value(textureInfo)}};
  b.model()
      .materials[static_cast<std::size_t>(paneOptions.material)]
      .extensions["KHR_materials_transmission"] = tinygltf::Value(transmission);
  b.model().extensionsUsed.push_back("KHR_materials_transmission");
  builder::Transform wall;
  wall.translation = {0.0f, 1.2f, 0.0f};
  wall.rotation = glm::angleAxis(glm::radians(90.0f), glm::vec3(0.0f, 0.0f, 1.0f));
  b.addNode("pane", wall, b.addMesh(builder::makePlane(2.0f), paneOptions));
  const std::filesystem::path file =
      std::filesystem::path(::testing::TempDir()) / "translucent_transmission.gltf";
  b.write(file, builder::FileFormat::GltfEmbedded);

  Staged s;
  s.scene = loadGltf(file);
  ASSERT_TRUE(s.scene.warnings.empty()) << s.scene.warnings.front();
  Light point;
  point.name = "point";
  point.position = {-2.5f, 2.0f, 0.0f};
  point.intensity = 20.0f;
  point.shadow.resolution = 256;
  s.lights = {point};
  s.camera = cameraAbove(s.scene, {2.0f, 7.0f, 0.5f}, {2.0f, 0.0f, 0.0f});
  const Frame frame = renderAovs(s);
  const HandCheck full = checkFloor(s, *frame.aovs, point, glm::vec3(0.75f, 0.375f, 0.1875f));
  const HandCheck quarter =
      checkFloor(s, *frame.aovs, point, 0.75f * (64.0f / 255.0f) * glm::vec3(1.0f, 0.5f, 0.25f));
  for (const HandCheck& check : {full, quarter}) {
    EXPECT_GT(check.points, 150);
    EXPECT_EQ(check.matching, check.points);
  }
  expectAgreementWithTheRays(verifyAgainstRays(s, frame), 1000);
}

// The AOV pass has as many visibility targets as the frame's lights need
// (aovVisibilityLayout(): one per four scalar terms; with translucent shadows, up to four
// lights' scalar and RGB terms in one pass, more lights' RGB terms in passes of their own, six
// a pass). A light's channels are the same whatever the number of lights beside it: frames of 1
// to 9 and of 21 lights give the first and the last light, bit for bit, the visibility,
// transmittance, position, normal and distance it has alone.
TEST(TranslucentShadows, ALightsAovsAreTheSameWhateverTheLightsBesideIt) {
  for (const auto& [lights, outputs] :
       std::vector<std::pair<int, int>>{{0, 1}, {1, 1}, {4, 1}, {5, 2}, {20, 5}, {21, 5}}) {
    const AovVisibilityLayout layout = aovVisibilityLayout(lights, false);
    EXPECT_EQ(layout.outputs, outputs) << lights;
    EXPECT_EQ(layout.scalarPerPass, 4 * outputs) << lights;
    EXPECT_FALSE(layout.combined);
  }
  for (int lights = 1; lights <= 30; ++lights) {
    const AovVisibilityLayout layout = aovVisibilityLayout(lights, true);
    EXPECT_LE(layout.outputs, contract::kMaxVisibilityOutputs) << lights;
    EXPECT_EQ(layout.combined, lights <= kMaxCombinedLights) << lights;
    if (layout.combined) {
      EXPECT_GE(layout.scalarPerPass, lights);
      EXPECT_GE(4 * layout.outputs, layout.scalarPerPass + 3 * lights) << lights;
    } else {
      EXPECT_GE(layout.rgbPerPass, std::min(lights, 6)) << lights;
      EXPECT_GE(4 * layout.outputs, 3 * layout.rgbPerPass) << lights;
    }
  }
  Staged s = paneScene(
      {{glass({1.0f, 0.5f, 0.2f, 0.75f}, AlphaMode::Blend, 0.0f), {0.0f, 1.0f, 0.0f}, 4.0f}});
  s.camera.width = 48;
  s.camera.height = 36;
  const auto light = [](int i) {
    Light l;
    l.name = "l" + std::to_string(i);
    l.position = {0.15f * static_cast<float>(i % 7) - 0.45f, 5.0f,
                  0.1f * static_cast<float>(i / 7)};
    l.shadow.resolution = 64;
    l.shadow.translucent = true;
    return l;
  };
  // The channels of light `i` in a frame of `lights`, by name suffix.
  const auto channelsOf = [](const Frame& frame, int i) {
    const FloatImage& aovs = *frame.aovs;
    const std::string name = "l" + std::to_string(i);
    std::vector<float> values;
    for (const std::string& channel :
         std::vector<std::string>{"P.X", "P.Y", "P.Z", "N.X", "N.Y", "N.Z", "Z",
                                  "visibility." + name, "transmittance." + name + ".R",
                                  "transmittance." + name + ".G", "transmittance." + name + ".B"}) {
      const int c = aovs.channelIndex(channel);
      EXPECT_GE(c, 0) << channel;
      if (c < 0) return values;
      for (int y = 0; y < aovs.height; ++y)
        for (int x = 0; x < aovs.width; ++x) values.push_back(aovs.at(x, y, c));
    }
    return values;
  };
  const auto alone = [&](int i) {
    s.lights = {light(i)};
    return channelsOf(renderAovs(s), i);
  };
  const std::vector<float> first = alone(0);
  for (int count : {2, 3, 4, 5, 6, 7, 8, 9, 21}) {
    SCOPED_TRACE(count);
    s.lights.clear();
    for (int i = 0; i < count; ++i) s.lights.push_back(light(i));
    const Frame frame = renderAovs(s);
    EXPECT_TRUE(channelsOf(frame, 0) == first);
    EXPECT_TRUE(channelsOf(frame, count - 1) == alone(count - 1));
  }
}

// Eight lights take two passes of RGB terms (six lights each): every light's
// transmittance.<light>.R/G/B holds its own color. Lights 0-3 and 5-7 see the floor's middle
// through a BLEND pane (alpha 0.75: 0.25 in every channel), light 4 beside the pane sees it lit;
// light 6 has translucentShadows off and light 7 is vsm: cut-out shadows, no channels.
TEST(TranslucentShadows, ManyLightsEachGetTheirOwnTransmittanceChannels) {
  Staged s = paneScene(
      {{glass({1.0f, 0.5f, 0.2f, 0.75f}, AlphaMode::Blend, 0.0f), {0.0f, 1.0f, 0.0f}, 4.0f}});
  s.lights.clear();
  for (int i = 0; i < 8; ++i) {
    Light light;
    light.name = "l" + std::to_string(i);
    light.position = {0.1f * static_cast<float>(i) - 0.4f, 5.0f, 0.0f};
    if (i == 4) light.position = {6.0f, 1.5f, 0.0f};
    light.shadow.resolution = 64;
    light.shadow.translucent = i != 6;
    // Every filter in one frame: the lighting pass compiles them all with translucent shadows.
    const ShadowFilter filters[8] = {
        ShadowFilter::Pcf, ShadowFilter::PcfDisk, ShadowFilter::Hard, ShadowFilter::Poisson,
        ShadowFilter::Pcf, ShadowFilter::Pcss,    ShadowFilter::Pcf,  ShadowFilter::Vsm};
    light.shadow.filter = filters[i];
    light.shadow.radius = i == 5 ? 0.05f : 0.0f;
    s.lights.push_back(light);
  }
  const Frame frame = renderAovs(s);
  const FloatImage& aovs = *frame.aovs;
  // The covered pixel nearest to the floor's middle.
  const int p = aovs.channelIndex("P.X"), a = aovs.channelIndex("A");
  int bestX = 0, bestY = 0;
  float best = 1e30f;
  for (int y = 0; y < aovs.height; ++y)
    for (int x = 0; x < aovs.width; ++x) {
      if (!(aovs.at(x, y, a) > 0.0f)) continue;
      const float d =
          glm::length(glm::vec3(aovs.at(x, y, p), aovs.at(x, y, p + 1), aovs.at(x, y, p + 2)));
      if (d < best) best = d, bestX = x, bestY = y;
    }
  ASSERT_LT(best, 0.1f);
  for (int i = 0; i < 8; ++i) {
    SCOPED_TRACE(i);
    const std::string name = "l" + std::to_string(i);
    const int t = aovs.channelIndex("transmittance." + name + ".R");
    const float visibility = aovs.at(bestX, bestY, aovs.channelIndex("visibility." + name));
    if (i == 6 || i == 7) {  // cut-out shadows: off, and vsm
      EXPECT_EQ(t, -1);
      EXPECT_LT(visibility, 0.05f);
      continue;
    }
    ASSERT_GE(t, 0);
    const float expected = i == 4 ? 1.0f : 0.25f;
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(aovs.at(bestX, bestY, t + c), expected, 1e-5f);
    EXPECT_NEAR(visibility, expected, 1e-5f);
  }
}

}  // namespace translucent_shadows_test
