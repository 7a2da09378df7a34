// Environment lighting (EnvironmentLight) checked against what the light arriving from every
// direction must give: a white furnace, a sky over a black ground, a mirror's reflection, the
// background, and the errors of a bad image.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <glm/gtc/matrix_transform.hpp>
#include <string>
#include <vector>

#include "renderer/core/errors.h"
#include "renderer/output/image_writer.h"
#include "renderer/render/renderer.h"
#include "renderer/scene/srgb_transfer.h"
#include "renderer/view/environment_map.h"
#include "scenes/builder/gltf_builder.h"
#include "tests/support/scene_objects.h"
#include "tests/support/shared_renderer.h"
#include "tests/support/temp_folder.h"

namespace omnishadow::environment_render_test {
namespace {

namespace fs = std::filesystem;
using test_support::lookFrom;
using test_support::sharedRenderer;
using test_support::TempFolder;

constexpr float kPi = 3.14159265358979f;

// An equirectangular OpenEXR picture, each texel's radiance from its direction's (u, v).
fs::path writePanorama(const fs::path& path, int width, int height,
                       const std::function<glm::vec3(float u, float v)>& radiance) {
  FloatImage image;
  image.width = width;
  image.height = height;
  image.channels = {"R", "G", "B"};
  image.pixels.resize(static_cast<std::size_t>(width) * height * 3);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const glm::vec3 value = radiance((x + 0.5f) / width, (y + 0.5f) / height);
      for (int c = 0; c < 3; ++c) image.at(x, y, c) = value[c];
    }
  writeExr(path, image, ExrPixelType::Float);
  return path;
}

Material surface(glm::vec3 base, float metallic, float roughness) {
  Material m;
  m.baseColorFactor = glm::vec4(base, 1.0f);
  m.metallicFactor = metallic;
  m.roughnessFactor = roughness;
  m.doubleSided = true;
  return m;
}

Frame render(const Scene& scene, const Ambience& ambience, const ViewCamera& camera,
             RenderSettings settings = {}) {
  StageTimes times;
  return sharedRenderer().render(scene, {}, ambience, camera, settings, times);
}

Ambience withEnvironment(const EnvironmentLight& environment) {
  Ambience ambience(glm::vec3(0.0f));
  ambience.environment = environment;
  return ambience;
}

glm::vec3 pixel(const Frame& frame, int x, int y) {
  return {frame.beauty.at(x, y, 0), frame.beauty.at(x, y, 1), frame.beauty.at(x, y, 2)};
}

// A plane of 2 x 2 facing `normal` at the origin (makePlane faces +Y).
Scene planeFacing(const Material& material, glm::vec3 normal) {
  Scene scene;
  scene.materials.push_back(material);
  const glm::vec3 up(0, 1, 0);
  glm::mat4 world(1.0f);
  if (glm::length(glm::cross(up, normal)) > 1e-6f)
    world = glm::rotate(world, std::acos(glm::dot(up, normal)), glm::cross(up, normal));
  else if (normal.y < 0.0f)
    world = glm::rotate(world, kPi, glm::vec3(1, 0, 0));
  test::placeMesh(scene, builder::makePlane(2.0f), world, 0);
  return scene;
}

// The middle of a 32 x 32 picture of a plane facing `normal`, seen straight on from 3 units.
glm::vec3 middleOfPlane(const Material& material, glm::vec3 normal, const Ambience& ambience) {
  const Scene scene = planeFacing(material, normal);
  const glm::vec3 up = std::abs(normal.y) > 0.5f ? glm::vec3(0, 0, -1) : glm::vec3(0, 1, 0);
  const ViewCamera camera = lookFrom(scene, 3.0f * normal, {0, 0, 0}, 32, 32, 20.0f, up);
  const Frame frame = render(scene, ambience, camera);
  EXPECT_EQ(frame.beauty.at(16, 16, 3), 1.0f);
  return pixel(frame, 16, 16);
}

// A white surface in a uniform environment reflects exactly the radiance that arrives, whatever
// its roughness: what its specular lobe does not reflect, its diffuse does (the white furnace).
// A white mirror metal reflects it all too; a rough one only what single scattering keeps.
TEST(EnvironmentRender, AWhiteSurfaceInAUniformEnvironmentReflectsItsRadiance) {
  EnvironmentLight uniform;
  uniform.color = {0.5f, 0.6f, 0.7f};
  uniform.intensity = 2.0f;
  const glm::vec3 radiance = uniform.color * uniform.intensity;
  for (const float roughness : {0.0f, 0.3f, 0.7f, 1.0f}) {
    SCOPED_TRACE("roughness " + std::to_string(roughness));
    Scene scene;
    scene.materials.push_back(surface(glm::vec3(1.0f), 0.0f, roughness));
    test::placeMesh(scene, builder::makeSphere(1.0f, 48, 24), glm::mat4(1.0f), 0);
    const ViewCamera camera = lookFrom(scene, {0, 0, 4}, {0, 0, 0}, 48, 48, 35.0f);
    const Frame frame = render(scene, withEnvironment(uniform), camera);
    int covered = 0;
    for (int y = 0; y < 48; ++y)
      for (int x = 0; x < 48; ++x) {
        if (frame.beauty.at(x, y, 3) < 1.0f) continue;
        ++covered;
        for (int c = 0; c < 3; ++c)
          ASSERT_NEAR(frame.beauty.at(x, y, c), radiance[c], 2e-3f * radiance[c])
              << "pixel " << x << ", " << y << " channel " << c;
      }
    EXPECT_GT(covered, 600);
  }
  // The metal, seen face on (the split-sum table's A + B is 1 without roughness).
  const glm::vec3 mirror =
      middleOfPlane(surface(glm::vec3(1.0f), 1.0f, 0.0f), {0, 0, 1}, withEnvironment(uniform));
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(mirror[c], radiance[c], 0.02f * radiance[c]);
  const glm::vec3 rough =
      middleOfPlane(surface(glm::vec3(1.0f), 1.0f, 1.0f), {0, 0, 1}, withEnvironment(uniform));
  // GGX at roughness 1 seen face on reflects 0.307 of it (the integral of D Vis n.l over the
  // hemisphere, by uniform sampling); the table's last row lies at roughness 31.5 / 32.
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(rough[c] / radiance[c], 0.31f, 0.025f);
}

// The split-sum table as the shader reads it: bilinear between texel centres at (i + 0.5) /
// size, clamped at the edges (environment_textures.cpp makes the table 32 x 32).
glm::vec2 tableAt(float NdotV, float roughness) {
  static const SpecularBrdfTable table = specularBrdfTable(32);
  const auto texel = [&](int i, int j) {
    const std::size_t k = (static_cast<std::size_t>(j) * table.size + i) * 2;
    return glm::vec2(table.scaleBias[k], table.scaleBias[k + 1]);
  };
  const auto axis = [&](float t, int& i0, int& i1, float& f) {
    const float x = std::clamp(t * table.size - 0.5f, 0.0f, table.size - 1.0f);
    i0 = static_cast<int>(std::floor(x));
    i1 = std::min(i0 + 1, table.size - 1);
    f = x - static_cast<float>(i0);
  };
  int x0, x1, y0, y1;
  float fx, fy;
  axis(NdotV, x0, x1, fx);
  axis(roughness, y0, y1, fy);
  return glm::mix(glm::mix(texel(x0, y0), texel(x1, y0), fx),
                  glm::mix(texel(x0, y1), texel(x1, y1), fx), fy);
}

// Radiance beyond a half float's range (65504) keeps its value: a sun is 1e5 and more (the
// textures are floats; half floats, scaled, measured no faster on llvmpipe).
TEST(EnvironmentRender, RadianceBeyondAHalfsRangeKeepsItsValue) {
  TempFolder folder("omnishadow-environment-bright");
  EnvironmentLight light;
  light.image = writePanorama(folder / "bright.exr", 32, 16,
                              [](float, float) { return glm::vec3(2.0e5f, 1.0e5f, 3.0f); });
  const glm::vec3 mirror =
      middleOfPlane(surface(glm::vec3(1.0f), 1.0f, 0.0f), {0, 0, 1}, withEnvironment(light));
  const glm::vec3 matte =
      middleOfPlane(surface(glm::vec3(1.0f), 0.0f, 1.0f), {0, 0, 1}, withEnvironment(light));
  const glm::vec3 expected(2.0e5f, 1.0e5f, 3.0f);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(mirror[c], expected[c], 0.02f * expected[c]) << c;
    EXPECT_NEAR(matte[c], expected[c], 2e-3f * expected[c]) << c;
  }
}

// Each material layer in a uniform environment, seen face on (N = V), against its formula by
// hand: the same weights as for a light, with each lobe's albedo F0 A + F90 B from the table.
// Several are white furnaces (what a layer takes from below it gives back).
TEST(EnvironmentRender, EachMaterialLayerReflectsAUniformEnvironmentAsItsFormulaSays) {
  EnvironmentLight uniform;  // radiance 1 from everywhere
  const glm::vec3 grey(0.5f);
  struct Case {
    const char* name;
    Material material;
    glm::vec3 expected;
    bool background = false;
  };
  std::vector<Case> cases;
  {
    Material m = surface(grey, 0.0f, 1.0f);
    m.specularGlossiness = true;
    m.specularFactor = glm::vec3(0.2f, 0.3f, 0.4f);
    m.glossinessFactor = 0.6f;
    const glm::vec2 ab = tableAt(1.0f, 0.4f);
    cases.push_back({"specular-glossiness", m, m.specularFactor * ab.x + ab.y + grey * 0.6f});
  }
  {
    Material m = surface(grey, 0.0f, 0.5f);
    m.specularWeight = 0.5f;
    m.specularColorFactor = glm::vec3(1.0f, 2.0f, 4.0f);
    const glm::vec2 ab = tableAt(1.0f, 0.5f);
    const glm::vec3 dielectric =
        glm::min(0.04f * m.specularColorFactor, glm::vec3(1.0f)) * 0.5f * ab.x + 0.5f * ab.y;
    const float kept = 1.0f - std::max({dielectric.r, dielectric.g, dielectric.b});
    cases.push_back({"KHR_materials_specular", m, dielectric + grey * kept});
  }
  {
    Material m = surface(grey, 0.5f, 0.3f);  // half metal: the two lobes mixed
    const glm::vec2 ab = tableAt(1.0f, 0.3f);
    const glm::vec3 dielectric(0.04f * ab.x + ab.y), metal = grey * ab.x + ab.y;
    const glm::vec3 kept = glm::vec3(0.5f * (1.0f - dielectric.r));
    cases.push_back({"half metal", m, glm::mix(dielectric, metal, 0.5f) + grey * kept});
  }
  {
    Material m = surface(glm::vec3(1.0f), 0.0f, 0.7f);  // the base alone is a furnace: 1
    m.clearcoatFactor = 1.0f;
    m.clearcoatRoughnessFactor = 0.4f;
    const glm::vec2 ab = tableAt(1.0f, 0.4f);
    cases.push_back({"clearcoat", m, glm::vec3(1.0f - 0.04f + 0.04f * ab.x + ab.y)});
  }
  {
    Material m = surface(glm::vec3(1.0f), 0.0f, 0.7f);
    // A grey sheen takes max(color) E(N.V) from the base and gives color E(N.V) back.
    m.sheenColorFactor = glm::vec3(0.6f);
    m.sheenRoughnessFactor = 0.5f;
    cases.push_back({"sheen (a white furnace)", m, glm::vec3(1.0f)});
  }
  {
    // A clear pane before the environment shown as the background: the light it lets through
    // (1 - F0 face on) and what its lobe reflects (F0 A + B) make the radiance again.
    Material m = surface(glm::vec3(1.0f), 0.0f, 0.0f);
    m.transmissionFactor = 1.0f;
    const glm::vec2 ab = tableAt(1.0f, 0.0f);
    cases.push_back({"transmission", m, glm::vec3(0.96f + 0.04f * ab.x + ab.y), true});
  }
  {
    Material m = surface(glm::vec3(1.0f), 0.0f, 0.6f);
    m.diffuseTransmissionFactor = 1.0f;
    m.diffuseTransmissionColorFactor = glm::vec3(0.25f, 0.5f, 1.0f);
    const glm::vec2 ab = tableAt(1.0f, 0.6f);
    cases.push_back({"diffuse transmission", m,
                     glm::vec3(0.04f * ab.x + ab.y) + 0.96f * m.diffuseTransmissionColorFactor});
  }
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    uniform.background = c.background;
    const glm::vec3 seen = middleOfPlane(c.material, {0, 0, 1}, withEnvironment(uniform));
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(seen[i], c.expected[i], 0.01f * c.expected[i]) << i;
  }
  // Blinn-Phong diffuses the irradiance and reflects F0 of the prefiltered image.
  uniform.background = false;
  const Scene plane = planeFacing(surface(grey, 0.0f, 0.5f), {0, 0, 1});
  RenderSettings phong;
  phong.shading = Shading::Phong;
  const Frame phongFrame = render(plane, withEnvironment(uniform),
                                  lookFrom(plane, {0, 0, 3}, {0, 0, 0}, 32, 32, 20.0f), phong);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(phongFrame.beauty.at(16, 16, i), 0.54f, 0.0054f) << i;
}

// A sky of radiance L above the horizon and nothing below: a floor receives the whole sky (E /
// pi = L), a ceiling nothing, a wall half of it (its diffuse sees half the sky, its rough lobe
// looks at the horizon).
TEST(EnvironmentRender, ASkyLightsFloorsFullyWallsByHalfAndCeilingsNot) {
  TempFolder folder("omnishadow-environment-sky");
  const glm::vec3 sky(0.8f, 0.9f, 1.0f);
  EnvironmentLight light;
  light.image = writePanorama(folder / "sky.exr", 128, 64,
                              [&](float, float v) { return v < 0.5f ? sky : glm::vec3(0.0f); });
  light.origin = "lights.json";
  const Ambience ambience = withEnvironment(light);
  const Material white = surface(glm::vec3(1.0f), 0.0f, 1.0f);
  const glm::vec3 floor = middleOfPlane(white, {0, 1, 0}, ambience);
  const glm::vec3 ceiling = middleOfPlane(white, {0, -1, 0}, ambience);
  const glm::vec3 wall = middleOfPlane(white, {0, 0, 1}, ambience);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(floor[c], sky[c], 0.02f * sky[c]) << "channel " << c;
    EXPECT_LT(ceiling[c], 0.01f * sky[c]) << "channel " << c;
    EXPECT_NEAR(wall[c], 0.5f * sky[c], 0.05f * sky[c]) << "channel " << c;
  }
  // A grey floor: the dielectric's lobe reflects F0 A + B of the sky, the diffuse the grey of
  // the rest: between the grey and white.
  const glm::vec3 grey = middleOfPlane(surface(glm::vec3(0.25f), 0.0f, 0.5f), {0, 1, 0}, ambience);
  EXPECT_GT(grey.g, 0.25f * sky.g);
  EXPECT_LT(grey.g, 0.35f * sky.g);
}

// A mirror reflects the environment in the direction the law of reflection gives: red to +X,
// green to -X; a half turn of the environment swaps them.
TEST(EnvironmentRender, AMirrorReflectsTheDirectionItFacesAndTheRotationTurnsIt) {
  TempFolder folder("omnishadow-environment-mirror");
  EnvironmentLight light;
  // The middle column looks along -Z, the right half (u > 0.5) towards +X.
  light.image = writePanorama(folder / "halves.exr", 64, 32, [](float u, float) {
    return u > 0.5f ? glm::vec3(1.0f, 0.0f, 0.0f) : glm::vec3(0.0f, 1.0f, 0.0f);
  });
  const Material mirror = surface(glm::vec3(1.0f), 1.0f, 0.0f);
  const glm::vec3 east = middleOfPlane(mirror, {1, 0, 0}, withEnvironment(light));
  const glm::vec3 west = middleOfPlane(mirror, {-1, 0, 0}, withEnvironment(light));
  EXPECT_GT(east.r, 0.95f);
  EXPECT_LT(east.g, 0.02f);
  EXPECT_GT(west.g, 0.95f);
  EXPECT_LT(west.r, 0.02f);
  light.rotation = kPi;
  const glm::vec3 turned = middleOfPlane(mirror, {1, 0, 0}, withEnvironment(light));
  EXPECT_GT(turned.g, 0.95f);
  EXPECT_LT(turned.r, 0.02f);
  // A quarter turn counterclockwise seen from above brings what lay to +X round to -Z.
  light.rotation = kPi / 2.0f;
  const glm::vec3 quarter = middleOfPlane(mirror, {0, 0, -1}, withEnvironment(light));
  EXPECT_GT(quarter.r, 0.95f);
}

// With `background`, each pixel no surface covers shows the environment along its view ray and
// is opaque; without, it stays empty. The 8-bit beauty encodes the same values.
TEST(EnvironmentRender, TheBackgroundShowsTheEnvironmentAlongEachViewRay) {
  TempFolder folder("omnishadow-environment-background");
  EnvironmentLight light;
  light.image = writePanorama(folder / "ramp.exr", 64, 32,
                              [](float u, float v) { return glm::vec3(u, v, 0.25f); });
  light.background = true;
  Scene scene;
  scene.materials.push_back(surface(glm::vec3(1.0f), 0.0f, 1.0f));
  test::placeMesh(scene, builder::makeSphere(0.2f, 16, 8),
                  glm::translate(glm::mat4(1.0f), {3.0f, 0.0f, -5.0f}), 0);
  // Looking down -Z: the middle of the picture is (u, v) = (0.5, 0.5).
  const ViewCamera camera = lookFrom(scene, {0, 0, 0}, {0, 0, -1}, 33, 33, 30.0f);
  const Frame frame = render(scene, withEnvironment(light), camera);
  const glm::vec3 middle = pixel(frame, 16, 16);
  EXPECT_NEAR(middle.r, 0.5f, 0.01f);
  EXPECT_NEAR(middle.g, 0.5f, 0.01f);
  EXPECT_NEAR(middle.b, 0.25f, 1e-4f);
  // Left of the middle the rays turn towards -X, where u is smaller; rows grow downwards (the
  // picture's first row is its top) as v does.
  EXPECT_LT(pixel(frame, 2, 16).r, middle.r - 0.02f);
  for (int y = 0; y < 33; ++y)
    for (int x = 0; x < 33; ++x) ASSERT_EQ(frame.beauty.at(x, y, 3), 1.0f);

  // The debug views keep an empty background (a normals view shows only surfaces).
  RenderSettings normals;
  normals.debugView = DebugView::Normals;
  EXPECT_EQ(render(scene, withEnvironment(light), camera, normals).beauty.at(16, 16, 3), 0.0f);

  light.background = false;
  const Frame empty = render(scene, withEnvironment(light), camera);
  EXPECT_EQ(empty.beauty.at(16, 16, 3), 0.0f);
  EXPECT_EQ(pixel(empty, 16, 16), glm::vec3(0.0f));

  light.background = true;
  RenderSettings bytes;
  bytes.srgb8Exposure = 0.0f;
  const Frame encoded = render(scene, withEnvironment(light), camera, bytes);
  ASSERT_TRUE(encoded.srgb8);
  for (const auto& [x, y] : {std::pair{16, 16}, std::pair{2, 16}, std::pair{30, 5}})
    for (int c = 0; c < 3; ++c)
      EXPECT_EQ(encoded.srgb8->rgb[(static_cast<std::size_t>(y) * 33 + x) * 3 + c],
                srgb8(frame.beauty.at(x, y, c)))
          << x << ", " << y << " channel " << c;
}

// The background shows the picture sharper than the lighting's 1024 texels (a stripe of 2 of a
// 2048-wide panorama, straight ahead through a narrow view, keeps its value), and filtered
// where texels are smaller than pixels (columns alternating 0 and 1 through a wide view show
// their mean, not a moire).
TEST(EnvironmentRender, TheBackgroundKeepsDetailAndFiltersWhatPixelsCannotShow) {
  TempFolder folder("omnishadow-environment-background-detail");
  Scene scene;
  scene.materials.push_back(surface(glm::vec3(1.0f), 0.0f, 1.0f));
  test::placeMesh(scene, builder::makeSphere(0.2f, 16, 8),
                  glm::translate(glm::mat4(1.0f), {0.0f, 0.0f, 5.0f}), 0);  // behind the camera
  EnvironmentLight stripe;
  stripe.background = true;
  stripe.image = writePanorama(folder / "stripe.exr", 2048, 1024, [](float u, float) {
    return std::abs(u - 0.5f) < 1.0f / 2048.0f ? glm::vec3(1.0f) : glm::vec3(0.0f);
  });
  const ViewCamera narrow = lookFrom(scene, {0, 0, 0}, {0, 0, -1}, 64, 16, 0.5f);
  const Frame sharp = render(scene, withEnvironment(stripe), narrow);
  EXPECT_NEAR(sharp.beauty.at(32, 8, 0), 1.0f, 0.02f);
  EXPECT_LT(sharp.beauty.at(2, 8, 0), 0.01f);

  EnvironmentLight columns = stripe;
  columns.image = writePanorama(folder / "columns.exr", 2048, 1024, [](float u, float) {
    return static_cast<int>(u * 2048.0f) % 2 == 0 ? glm::vec3(1.0f) : glm::vec3(0.0f);
  });
  const ViewCamera wide = lookFrom(scene, {0, 0, 0}, {0, 0, -1}, 32, 32, 90.0f);
  const Frame filtered = render(scene, withEnvironment(columns), wide);
  for (int y = 4; y < 28; y += 4)
    for (int x = 0; x < 32; ++x)
      ASSERT_NEAR(filtered.beauty.at(x, y, 0), 0.5f, 0.05f) << x << ", " << y;
}

// With `sun`, the panorama's sun leaves the image and lights the scene as a shadowed
// directional light: the frame is the one drawn with the sunless sky and that light given by
// hand (the sun's texels' radiance above the sky times their solid angles, towards their mean
// direction), and the floor under a box lies in its shadow. Without `sun`, no shadow.
TEST(EnvironmentRender, TheSunOfAPanoramaCastsShadowsAsADirectionalLight) {
  TempFolder folder("omnishadow-environment-sun");
  constexpr int kWidth = 256, kHeight = 128;
  // Low enough that the box's shadow falls beside it as the camera above sees it.
  const glm::vec3 towardsSun = glm::normalize(glm::vec3(0.8f, 1.0f, 0.3f));
  const glm::vec2 sunUv = equirectCoordinates(towardsSun);
  const int sx = static_cast<int>(sunUv.x * kWidth), sy = static_cast<int>(sunUv.y * kHeight);
  const glm::vec3 sky(0.3f, 0.35f, 0.4f), sunRadiance(3000.0f, 2800.0f, 2500.0f);
  const auto inSun = [&](float u, float v) {
    const int x = static_cast<int>(u * kWidth), y = static_cast<int>(v * kHeight);
    return std::abs(x - sx) <= 1 && std::abs(y - sy) <= 1;
  };
  EnvironmentLight withSun;
  withSun.image = writePanorama(folder / "sun.exr", kWidth, kHeight, [&](float u, float v) {
    return inSun(u, v) ? sky + sunRadiance : sky;
  });
  withSun.sun = true;
  EnvironmentLight skyOnly;
  skyOnly.image =
      writePanorama(folder / "sky.exr", kWidth, kHeight, [&](float, float) { return sky; });
  // The light by hand.
  glm::dvec3 irradiance(0.0), direction(0.0);
  for (int y = sy - 1; y <= sy + 1; ++y)
    for (int x = sx - 1; x <= sx + 1; ++x) {
      const double a = y * kPi / kHeight, b = (y + 1) * kPi / kHeight;
      const double solidAngle = (2.0 * kPi / kWidth) * (std::cos(a) - std::cos(b));
      irradiance += glm::dvec3(sunRadiance) * solidAngle;
      direction +=
          glm::dvec3(equirectDirection({(x + 0.5f) / kWidth, (y + 0.5f) / kHeight})) * solidAngle;
    }
  Light sun;
  sun.name = "sun";
  sun.type = LightType::Directional;
  sun.direction = -glm::vec3(glm::normalize(direction));
  const float brightest = static_cast<float>(std::max({irradiance.r, irradiance.g, irradiance.b}));
  sun.color = glm::vec3(irradiance) / brightest;
  sun.intensity = brightest;

  Scene scene;
  scene.materials.push_back(surface(glm::vec3(0.8f), 0.0f, 1.0f));
  test::placeMesh(scene, builder::makePlane(4.0f), glm::mat4(1.0f), 0);
  const glm::vec3 boxCentre(0.0f, 0.6f, 0.0f);
  test::placeMesh(scene, builder::makeBox(glm::vec3(0.25f)),
                  glm::translate(glm::mat4(1.0f), boxCentre), 0);
  const ViewCamera camera = lookFrom(scene, {0, 5, 0}, {0, 0, 0}, 64, 64, 40.0f, {0, 0, -1});
  StageTimes times;
  const Frame extracted = render(scene, withEnvironment(withSun), camera);
  const Frame byHand =
      sharedRenderer().render(scene, {sun}, withEnvironment(skyOnly), camera, {}, times);
  for (std::size_t i = 0; i < extracted.beauty.pixels.size(); ++i)
    ASSERT_NEAR(extracted.beauty.pixels[i], byHand.beauty.pixels[i],
                1e-3f * std::max(1.0f, byHand.beauty.pixels[i]))
        << "value " << i;

  // Where the box's shadow falls, and a floor point well away from it.
  const auto pixelOf = [&](const glm::vec3& p) {
    const glm::vec4 clip = camera.projection * camera.view * glm::vec4(p, 1.0f);
    const glm::vec2 ndc = glm::vec2(clip) / clip.w;
    return glm::ivec2(static_cast<int>((ndc.x * 0.5f + 0.5f) * 64.0f),
                      static_cast<int>((0.5f - ndc.y * 0.5f) * 64.0f));
  };
  const glm::vec3 shadowed = boxCentre - towardsSun * (boxCentre.y / towardsSun.y);
  const glm::ivec2 dark = pixelOf(shadowed), lit = pixelOf({1.2f, 0.0f, 1.2f});
  const float litValue = extracted.beauty.at(lit.x, lit.y, 1);
  const float darkValue = extracted.beauty.at(dark.x, dark.y, 1);
  // Lambert's 0.8 / pi of the sun's irradiance on the floor, at its cosine.
  const float sunShare = 0.8f / kPi * static_cast<float>(irradiance.g) * towardsSun.y;
  EXPECT_NEAR(litValue - darkValue, sunShare, 0.05f * sunShare);
  withSun.sun = false;
  const Frame unshadowed = render(scene, withEnvironment(withSun), camera);
  EXPECT_NEAR(unshadowed.beauty.at(dark.x, dark.y, 1), unshadowed.beauty.at(lit.x, lit.y, 1),
              0.02f * unshadowed.beauty.at(lit.x, lit.y, 1));
}

// Two frames with one environment are byte-identical; a new image at the same path is read
// again (a renderer keeps the last environment's textures while the file is unchanged).
TEST(EnvironmentRender, FramesRepeatAndAChangedImageIsReadAgain) {
  TempFolder folder("omnishadow-environment-cache");
  EnvironmentLight light;
  light.image =
      writePanorama(folder / "sky.exr", 32, 16, [](float, float) { return glm::vec3(1.0f); });
  const Material white = surface(glm::vec3(1.0f), 0.0f, 0.6f);
  const Scene scene = planeFacing(white, {0, 1, 0});
  const ViewCamera camera = lookFrom(scene, {0, 3, 0}, {0, 0, 0}, 24, 24, 20.0f, {0, 0, -1});
  const Frame a = render(scene, withEnvironment(light), camera);
  const Frame b = render(scene, withEnvironment(light), camera);
  EXPECT_EQ(a.beauty.pixels, b.beauty.pixels);
  EXPECT_NEAR(a.beauty.at(12, 12, 0), 1.0f, 2e-3f);
  writePanorama(light.image, 64, 32, [](float, float) { return glm::vec3(3.0f); });
  const Frame brighter = render(scene, withEnvironment(light), camera);
  EXPECT_NEAR(brighter.beauty.at(12, 12, 0), 3.0f, 6e-3f);
  // Prepared ahead, as the CLI does while a scene loads: the same frame.
  writePanorama(light.image, 16, 8, [](float, float) { return glm::vec3(2.0f); });
  sharedRenderer().prepareEnvironment(light);
  const Frame prepared = render(scene, withEnvironment(light), camera);
  EXPECT_NEAR(prepared.beauty.at(12, 12, 0), 2.0f, 4e-3f);
}

// An image that cannot be read, or holds a value that is not finite, is an input error naming
// the lights file, the field and the image.
TEST(EnvironmentRender, ABadImageIsAnInputErrorNamingTheFieldAndTheFile) {
  TempFolder folder("omnishadow-environment-errors");
  const Scene scene = planeFacing(surface(glm::vec3(1.0f), 0.0f, 1.0f), {0, 1, 0});
  const ViewCamera camera = lookFrom(scene, {0, 3, 0}, {0, 0, 0}, 8, 8, 20.0f, {0, 0, -1});
  const auto messageOf = [&](const EnvironmentLight& light) -> std::string {
    try {
      render(scene, withEnvironment(light), camera);
    } catch (const InputError& error) {
      return error.what();
    }
    return "(no error)";
  };
  EnvironmentLight missing;
  missing.image = folder / "missing.exr";
  missing.origin = "rig.json";
  const std::string noFile = messageOf(missing);
  EXPECT_TRUE(noFile.starts_with("rig.json: environment.image: " + missing.image.string()))
      << noFile;
  EXPECT_EQ(noFile.find('\n'), std::string::npos);

  EnvironmentLight infinite;
  infinite.origin = "rig.json";
  infinite.image = writePanorama(folder / "inf.exr", 8, 4, [](float u, float v) {
    return u > 0.5f && v > 0.5f ? glm::vec3(INFINITY) : glm::vec3(1.0f);
  });
  const std::string notFinite = messageOf(infinite);
  EXPECT_EQ(notFinite, "rig.json: environment.image: " + infinite.image.string() +
                           ": pixel (4, 2) is not finite");
  EnvironmentLight huge = infinite;
  huge.image = writePanorama(folder / "huge.exr", 8, 4, [](float u, float) {
    return u < 0.2f ? glm::vec3(3e38f) : glm::vec3(1.0f);
  });
  EXPECT_EQ(messageOf(huge),
            "rig.json: environment.image: " + huge.image.string() + ": pixel (0, 0) is above 1e20");
  EnvironmentLight tall = infinite;
  tall.image =
      writePanorama(folder / "tall.exr", 4, 40000, [](float, float) { return glm::vec3(1.0f); });
  EXPECT_EQ(messageOf(tall),
            "rig.json: environment.image: " + tall.image.string() +
                ": 4x40000 is not an equirectangular panorama (twice as wide as high)");
  // Prepared ahead (while a scene loads), a bad image is left for the render to report.
  EXPECT_NO_THROW(sharedRenderer().prepareEnvironment(infinite));
  EXPECT_TRUE(messageOf(infinite).ends_with("is not finite")) << messageOf(infinite);
  // The renderer is still good for the next frame.
  EXPECT_EQ(messageOf(EnvironmentLight{}), "(no error)");
}

}  // namespace
}  // namespace omnishadow::environment_render_test
