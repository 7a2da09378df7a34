// The exact shadow reference and `omnishadow verify`: the alpha filter and the texel size on
// hand-made scenes, the classification and statistics on hand-made AOV pixels, then the real
// command on a model made by others and on built scenes, with good and absurd bias, and its
// errors. Renders are small (160x120): llvmpipe is slow and CI has two cores.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "renderer/output/image_writer.h"
#include "renderer/verify/embree_api.h"
#include "renderer/verify/shadow_reference.h"
#include "renderer/verify/shadow_verification.h"
#include "scenes/builder/gltf_builder.h"
#include "tests/support/run_binary.h"
#include "tests/support/temp_folder.h"

namespace omnishadow::verify_test {
namespace {

namespace fs = std::filesystem;
using test_support::filesIn;
using test_support::RunResult;
using test_support::TempFolder;

// ---------------------------------------------------------------------------------------------
// Hand-made scenes

int addMaterial(Scene& scene, AlphaMode mode = AlphaMode::Opaque, int texture = -1) {
  Material m;
  m.alphaMode = mode;
  m.baseColorTexture.texture = texture;
  scene.materials.push_back(m);
  return static_cast<int>(scene.materials.size()) - 1;
}

// A square in the plane y = height from (x0, z0) to (x1, z1); uv (0, 0) at (x0, z0) and
// (uvScale, uvScale) at (x1, z1).
Mesh square(float height, float x0, float z0, float x1, float z1, int material,
            float uvScale = 1.0f) {
  Mesh mesh;
  mesh.positions = {{x0, height, z0}, {x1, height, z0}, {x0, height, z1}, {x1, height, z1}};
  mesh.normals.assign(4, {0.0f, 1.0f, 0.0f});
  mesh.uv0 = {{0.0f, 0.0f}, {uvScale, 0.0f}, {0.0f, uvScale}, {uvScale, uvScale}};
  mesh.indices = {0, 2, 1, 1, 2, 3};
  mesh.material = material;
  for (const glm::vec3& p : mesh.positions) mesh.bounds.extend(p);
  return mesh;
}

void add(Scene& scene, const Mesh& mesh) {
  scene.meshes.push_back(mesh);
  scene.instances.push_back(
      {static_cast<int>(scene.meshes.size()) - 1, glm::mat4(1.0f), -1, {}, {}});
  scene.bounds.extend(mesh.bounds);
}

// 2x2 texels; the top-left one (u, v < 0.5) is transparent.
int addHoleTexture(Scene& scene) {
  Image image;
  image.width = image.height = 2;
  image.rgba = {255, 255, 255, 0, 255, 255, 255, 255, 255, 255, 255, 255, 255, 255, 255, 255};
  scene.images.push_back(image);
  Texture texture;
  texture.image = 0;
  scene.textures.push_back(texture);
  return static_cast<int>(scene.textures.size()) - 1;
}

Light sun() {
  Light light;
  light.name = "sun";
  light.type = LightType::Directional;
  light.direction = {0.0f, -1.0f, 0.0f};
  return light;
}

Light lamp(glm::vec3 position) {
  Light light;
  light.name = "lamp";
  light.position = position;
  light.shadow.resolution = 512;
  return light;
}

// A floor with a cut-out quad above it.
Scene cutoutScene(AlphaMode mode, float uvScale = 1.0f) {
  Scene scene;
  add(scene, square(0.0f, -4.0f, -4.0f, 4.0f, 4.0f, addMaterial(scene)));
  add(scene, square(1.0f, -1.0f, -1.0f, 1.0f, 1.0f, addMaterial(scene, mode, addHoleTexture(scene)),
                    uvScale));
  return scene;
}

constexpr glm::vec3 kUp{0.0f, 1.0f, 0.0f};

// Embree is loaded by the first exact reference, not before: in a fresh process (the test
// program re-run for this test alone), since another test may have loaded it already.
TEST(EmbreeApiDeathTest, TheFirstReferenceLoadsEmbree) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(
      {
        if (embreeLoaded()) std::exit(1);
        const ShadowReference reference{Scene{}};
        std::exit(embreeLoaded() ? 0 : 2);
      },
      ::testing::ExitedWithCode(0), "");
}

// Where Embree cannot be loaded, or a library of that name lacks its functions, the message
// names the library, and says which package brings it.
TEST(EmbreeApi, SaysWhichLibraryCannotBeLoadedOrLacksAFunction) {
  const EmbreeLoad missing = loadEmbree("libomnishadow-no-such-library.so.1");
  EXPECT_EQ(
      missing.error.rfind("Embree (libomnishadow-no-such-library.so.1) cannot be loaded: ", 0), 0u)
      << missing.error;
  EXPECT_NE(missing.error.find("; on Debian: apt install libembree3-3"), std::string::npos);
  EXPECT_EQ(missing.api.newDevice, nullptr);
  EXPECT_EQ(loadEmbree("libm.so.6").error, "Embree (libm.so.6) lacks a function omnishadow calls");
  const EmbreeApi& api = embreeApi();  // the one the build found
  EXPECT_NE(api.newDevice, nullptr);
  EXPECT_NE(api.occluded1, nullptr);
  EXPECT_TRUE(embreeLoaded());
}

TEST(ShadowReference, CutOutQuadCastsLightThroughItsHole) {
  const Scene scene = cutoutScene(AlphaMode::Mask);
  const ShadowReference reference(scene);
  EXPECT_EQ(reference.visibility(sun(), {-0.5f, 0.0f, -0.5f}, kUp), 1.0f);  // under the hole
  EXPECT_EQ(reference.visibility(sun(), {0.5f, 0.0f, -0.5f}, kUp), 0.0f);
  EXPECT_EQ(reference.visibility(sun(), {0.5f, 0.0f, 0.5f}, kUp), 0.0f);
  EXPECT_EQ(reference.visibility(sun(), {2.0f, 0.0f, 2.0f}, kUp), 1.0f);  // beside the quad
  // A point light's ray through the hole, at a slant.
  EXPECT_EQ(reference.visibility(lamp({-0.5f, 3.0f, -0.5f}), {-0.5f, 0.0f, -0.5f}, kUp), 1.0f);
  EXPECT_EQ(reference.visibility(lamp({-0.5f, 3.0f, -0.5f}), {1.0f, 0.0f, 1.0f}, kUp), 0.0f);
}

// Lights with "translucentShadows": false (cut-out shadows).
TEST(ShadowReference, BlendedSurfacesCastWhereAtLeastHalfOpaque) {
  Scene scene = cutoutScene(AlphaMode::Blend);
  Light cutOut = sun();
  cutOut.shadow.translucent = false;
  EXPECT_EQ(ShadowReference(scene).visibility(cutOut, {-0.5f, 0.0f, -0.5f}, kUp), 1.0f);
  EXPECT_EQ(ShadowReference(scene).visibility(cutOut, {0.5f, 0.0f, 0.5f}, kUp), 0.0f);
  scene.materials[1].baseColorFactor.a = 0.4f;  // below 0.5 everywhere
  EXPECT_EQ(ShadowReference(scene).visibility(cutOut, {0.5f, 0.0f, 0.5f}, kUp), 1.0f);
  // Vertex colors count too.
  scene.materials[1].baseColorFactor.a = 1.0f;
  scene.meshes[1].colors.assign(4, glm::vec4(1.0f, 1.0f, 1.0f, 0.3f));
  EXPECT_EQ(ShadowReference(scene).visibility(cutOut, {0.5f, 0.0f, 0.5f}, kUp), 1.0f);
}

// Translucent shadows (the default): the ray goes on through every translucent surface,
// multiplying by what each lets through, and stops at an opaque one.
TEST(ShadowReference, TranslucentShadowRaysMultiplyThroughEveryCrossing) {
  Scene scene = cutoutScene(AlphaMode::Blend);
  // The hole's texel (alpha 0) lets everything through, the others (alpha 1) nothing.
  EXPECT_EQ(ShadowReference(scene).transmittance(sun(), {-0.5f, 0.0f, -0.5f}, kUp),
            glm::vec3(1.0f));
  EXPECT_EQ(ShadowReference(scene).transmittance(sun(), {0.5f, 0.0f, 0.5f}, kUp), glm::vec3(0.0f));
  // Alpha 0.4 and COLOR_0 alpha 0.5: 1 - 0.2; COLOR_0's color does not tint BLEND alone.
  scene.materials[1].baseColorFactor.a = 0.4f;
  scene.meshes[1].colors.assign(4, glm::vec4(1.0f, 0.0f, 1.0f, 0.5f));
  EXPECT_NEAR(ShadowReference(scene).visibility(sun(), {0.5f, 0.0f, 0.5f}, kUp), 0.8f, 1e-6f);
  // With transmission 0.5: (1 - 0.2) + 0.2 x 0.5 x (1, 0, 1).
  scene.materials[1].transmissionFactor = 0.5f;
  const glm::vec3 once = ShadowReference(scene).transmittance(sun(), {0.5f, 0.0f, 0.5f}, kUp);
  EXPECT_NEAR(once.r, 0.9f, 1e-6f);
  EXPECT_NEAR(once.g, 0.8f, 1e-6f);
  EXPECT_NEAR(once.b, 0.9f, 1e-6f);
  // A second copy of the quad higher up: both crossings count.
  Mesh copy = scene.meshes[1];
  scene.meshes.push_back(copy);
  glm::mat4 up(1.0f);
  up[3] = glm::vec4(0.0f, 1.0f, 0.0f, 1.0f);
  scene.instances.push_back({static_cast<int>(scene.meshes.size()) - 1, up, -1, {}, {}});
  const glm::vec3 twice = ShadowReference(scene).transmittance(sun(), {0.5f, 0.0f, 0.5f}, kUp);
  EXPECT_NEAR(twice.r, 0.81f, 1e-6f);
  EXPECT_NEAR(twice.g, 0.64f, 1e-6f);
  // An opaque quad above both blocks everything.
  scene.materials[0].baseColorFactor = glm::vec4(1.0f);
  Mesh roof = scene.meshes[0];
  scene.meshes.push_back(roof);
  up[3] = glm::vec4(0.0f, 3.0f, 0.0f, 1.0f);
  scene.instances.push_back({static_cast<int>(scene.meshes.size()) - 1, up, -1, {}, {}});
  EXPECT_EQ(ShadowReference(scene).transmittance(sun(), {0.5f, 0.0f, 0.5f}, kUp), glm::vec3(0.0f));
}

TEST(ShadowReference, OpaqueMaterialsIgnoreAlpha) {
  const Scene scene = cutoutScene(AlphaMode::Opaque);
  EXPECT_EQ(ShadowReference(scene).visibility(sun(), {-0.5f, 0.0f, -0.5f}, kUp), 0.0f);
}

TEST(ShadowReference, TextureWrapModesRepeatTheHole) {
  // uv 0..2: with REPEAT the hole appears in every quarter of each 1x1 texture tile.
  Scene scene = cutoutScene(AlphaMode::Mask, 2.0f);
  const glm::vec3 secondTileHole{0.25f, 0.0f, 0.25f};  // uv (1.25, 1.25)
  EXPECT_EQ(ShadowReference(scene).visibility(sun(), secondTileHole, kUp), 1.0f);
  scene.textures[0].sampler.wrapS = scene.textures[0].sampler.wrapT = 0x812F;  // clamp to edge
  EXPECT_EQ(ShadowReference(scene).visibility(sun(), secondTileHole, kUp), 0.0f);
  // Mirrored: uv 1.25 reads texel 1 - 0.25 -> the opaque side; 1.75 mirrors to the hole.
  scene.textures[0].sampler.wrapS = scene.textures[0].sampler.wrapT = 0x8370;
  EXPECT_EQ(ShadowReference(scene).visibility(sun(), secondTileHole, kUp), 0.0f);
  EXPECT_EQ(ShadowReference(scene).visibility(sun(), {0.75f, 0.0f, 0.75f}, kUp), 1.0f);
}

TEST(ShadowReference, LightWithARadiusGivesPenumbraFractions) {
  // An opaque half-plane x < 0 at y = 1; a disk light of radius 0.5 at (0, 2, 0). Straight
  // below the edge half the disk is hidden.
  Scene scene;
  add(scene, square(1.0f, -4.0f, -4.0f, 0.0f, 4.0f, addMaterial(scene)));
  Light light = lamp({0.0f, 2.0f, 0.0f});
  light.shadow.radius = 0.5f;
  const ShadowReference reference(scene);
  EXPECT_NEAR(reference.visibility(light, {0.0f, 0.0f, 0.0f}, kUp), 0.5f, 0.07f);
  EXPECT_EQ(reference.visibility(light, {-2.0f, 0.0f, 0.0f}, kUp), 0.0f);
  EXPECT_EQ(reference.visibility(light, {2.0f, 0.0f, 0.0f}, kUp), 1.0f);
  // The same rays every time.
  EXPECT_EQ(reference.visibility(light, {0.1f, 0.0f, 0.0f}, kUp),
            reference.visibility(light, {0.1f, 0.0f, 0.0f}, kUp));
  // A sun of angular radius 0.2 rad: the penumbra under an edge 1 above is about
  // 2 tan(0.2) wide.
  Light wide = sun();
  wide.shadow.radius = 0.2f;
  EXPECT_NEAR(reference.visibility(wide, {0.0f, 0.0f, 0.0f}, kUp), 0.5f, 0.07f);
  EXPECT_EQ(reference.visibility(wide, {0.3f, 0.0f, 0.0f}, kUp), 1.0f);
  EXPECT_EQ(reference.visibility(wide, {-0.3f, 0.0f, 0.0f}, kUp), 0.0f);
}

TEST(ShadowReference, EpsilonFollowsTheSceneScale) {
  const Scene scene = cutoutScene(AlphaMode::Mask);
  EXPECT_NEAR(ShadowReference(scene).epsilon(), 1e-4f * std::sqrt(8.0f * 8.0f * 2.0f + 1.0f),
              1e-7f);
}

// ---------------------------------------------------------------------------------------------
// Texel size and edge band

TEST(ShadowVerification, TexelWorldSizePerLightType) {
  Light point = lamp({1.0f, 2.0f, 3.0f});
  point.shadow.resolution = 512;
  EXPECT_FLOAT_EQ(shadowTexelWorldSize(point, {3.0f, 1.0f, 3.5f}, {}), 2.0f * 2.0f / 512.0f);
  Light spot = point;
  spot.type = LightType::Spot;
  spot.outerConeAngle = 0.7853981633974483f;
  spot.shadow.resolution = 256;
  EXPECT_NEAR(shadowTexelWorldSize(spot, {1.0f, 2.0f, 7.0f}, {}), 2.0f * 4.0f / 256.0f, 1e-6f);
  Bounds bounds;
  bounds.extend({-1.0f, -1.0f, -2.0f});
  bounds.extend({1.0f, 1.0f, 2.0f});
  Light directional = sun();
  directional.shadow.resolution = 100;
  EXPECT_NEAR(shadowTexelWorldSize(directional, {}, bounds), 4.0f / 100.0f, 1e-6f);
  directional.direction = {0.0f, 0.0f, -1.0f};
  EXPECT_NEAR(shadowTexelWorldSize(directional, {}, bounds), 2.0f / 100.0f, 1e-6f);
}

TEST(ShadowVerification, EdgeBandAddsTheFilterReach) {
  Light light = lamp({0.0f, 0.0f, 0.0f});
  light.shadow.resolution = 100;
  const glm::vec3 p{0.0f, 0.0f, 5.0f};  // one texel = 0.1
  light.shadow.filter = ShadowFilter::Hard;
  EXPECT_NEAR(edgeBandWidth(light, p, 10.0f, 20.0f, {}, 3.0f), 0.3f, 1e-6f);
  light.shadow.filter = ShadowFilter::Pcf;
  EXPECT_NEAR(edgeBandWidth(light, p, 10.0f, 20.0f, {}, 3.0f), 0.4f, 1e-6f);
  light.shadow.filter = ShadowFilter::PcfDisk;
  light.shadow.filterRadius = 2.0f;  // x (1 + 10 / 20)
  EXPECT_NEAR(edgeBandWidth(light, p, 10.0f, 20.0f, {}, 3.0f), 0.6f, 1e-6f);
  light.shadow.filter = ShadowFilter::Poisson;
  EXPECT_NEAR(edgeBandWidth(light, p, 10.0f, 20.0f, {}, 3.0f), 0.5f, 1e-6f);
  light.shadow.filter = ShadowFilter::Pcss;
  light.shadow.radius = 0.25f;
  EXPECT_NEAR(edgeBandWidth(light, p, 10.0f, 20.0f, {}, 3.0f), 0.55f, 1e-6f);
}

// ---------------------------------------------------------------------------------------------
// Classification and statistics on hand-made AOV pixels

struct Pixel {
  bool covered = true;
  glm::vec3 position{0.0f};
  glm::vec3 normal{0.0f, 1.0f, 0.0f};
  std::vector<float> visibility = {};  // per light
};

FloatImage makeAovs(const std::vector<Pixel>& row, const std::vector<std::string>& lights,
                    const glm::vec3& eye) {
  FloatImage aovs;
  aovs.width = static_cast<int>(row.size());
  aovs.height = 1;
  aovs.channels = {"R", "G", "B", "A", "P.X", "P.Y", "P.Z", "N.X", "N.Y", "N.Z", "Z"};
  for (const std::string& light : lights) aovs.channels.push_back("visibility." + light);
  for (const Pixel& p : row) {
    std::vector<float> v = {0.5f, 0.5f, 0.5f, p.covered ? 1.0f : 0.0f};
    const glm::vec3 position = p.covered ? p.position : glm::vec3(0.0f);
    const glm::vec3 normal = p.covered ? p.normal : glm::vec3(0.0f);
    v.insert(v.end(), {position.x, position.y, position.z, normal.x, normal.y, normal.z,
                       p.covered ? glm::length(p.position - eye) : 0.0f});
    for (std::size_t i = 0; i < lights.size(); ++i)
      v.push_back(i < p.visibility.size() ? p.visibility[i] : 1.0f);
    aovs.pixels.insert(aovs.pixels.end(), v.begin(), v.end());
  }
  return aovs;
}

// A 10x10 floor and an opaque 2x2 square 1 above its center; the lamp 3 above the center
// throws the square's shadow on the floor out to |x|, |z| = 1.5.
struct SyntheticCase {
  Scene scene;
  ViewCamera camera;
  std::vector<LightToVerify> lights;

  SyntheticCase() {
    add(scene, square(0.0f, -5.0f, -5.0f, 5.0f, 5.0f, addMaterial(scene)));
    add(scene, square(1.0f, -1.0f, -1.0f, 1.0f, 1.0f, addMaterial(scene)));
    camera.eye = {0.0f, 6.0f, 2.0f};
    Light key = lamp({0.0f, 3.0f, 0.0f});
    Light ranged = lamp({0.0f, 3.0f, 0.0f});
    ranged.name = "ranged";
    ranged.range = 3.05f;  // reaches the floor only right under the lamp
    Light fill = lamp({0.0f, 3.0f, 0.0f});
    fill.name = "fill";
    fill.shadow.enabled = false;
    lights = {{key, 50.0f}, {ranged, 50.0f}, {fill, 50.0f}};
  }
};

TEST(ShadowVerification, ClassifiesAndCountsPerLight) {
  SyntheticCase c;
  const std::vector<Pixel> row = {
      {.covered = false},
      {.position = {0.0f, 0.0f, 0.0f}, .visibility = {0.0f, 0.0f}},     // in shadow, agreed
      {.position = {0.2f, 0.0f, 0.0f}, .visibility = {1.0f, 1.0f}},     // in shadow, lit: leak
      {.position = {3.0f, 0.0f, 3.0f}, .visibility = {0.2f, 1.0f}},     // lit, shadowed: acne
      {.position = {3.0f, 0.0f, -3.0f}, .visibility = {0.9f, 1.0f}},    // lit, agreed
      {.position = {1.5f, 0.0f, 0.0f}, .visibility = {1.0f, 1.0f}},     // on the shadow edge
      {.position = {3.0f, 0.0f, 0.0f}, .normal = {0.0f, -1.0f, 0.0f}},  // facing away
      {.position = {100.0f, 0.0f, 0.0f}},                               // N.L = 0.03: grazing
      {.position = {60.0f, 0.0f, 0.0f}, .normal = glm::normalize(glm::vec3(-60.0f, 3.0f, 0.0f))},
  };
  const FloatImage aovs = makeAovs(row, {"lamp", "ranged", "fill"}, c.camera.eye);
  const ShadowReference reference(c.scene);
  VerifySettings settings;
  settings.threads = 1;
  const ShadowVerification v =
      verifyShadows(reference, c.scene.bounds, c.lights, aovs, c.camera, settings);
  ASSERT_EQ(v.lights.size(), 3u);
  const LightVerification& key = v.lights[0];
  ASSERT_EQ(key.points.size(), row.size());
  EXPECT_EQ(key.points[0].verdict, Verdict::Background);
  EXPECT_EQ(key.points[1].verdict, Verdict::Agree);
  EXPECT_FALSE(key.points[1].edge);
  EXPECT_EQ(key.points[1].reference, 0.0f);
  EXPECT_EQ(key.points[2].verdict, Verdict::FalseLight);
  EXPECT_FALSE(key.points[2].edge);
  EXPECT_EQ(key.points[3].verdict, Verdict::FalseShadow);
  EXPECT_FALSE(key.points[3].edge);
  EXPECT_EQ(key.points[4].verdict, Verdict::Agree);
  EXPECT_TRUE(key.points[5].edge);
  EXPECT_EQ(key.points[6].verdict, Verdict::FacingAway);
  EXPECT_EQ(key.points[7].verdict, Verdict::Grazing);
  EXPECT_EQ(key.points[8].verdict, Verdict::BeyondShadowFar);

  EXPECT_EQ(key.skipped.background, 1);
  EXPECT_EQ(key.skipped.facingAway, 1);
  EXPECT_EQ(key.skipped.grazing, 1);
  EXPECT_EQ(key.skipped.beyondShadowFar, 1);
  EXPECT_EQ(key.interior.evaluated, 4);
  EXPECT_EQ(key.interior.agree, 2);
  EXPECT_EQ(key.interior.falseShadow, 1);
  EXPECT_EQ(key.interior.falseLight, 1);
  EXPECT_DOUBLE_EQ(key.interior.agreementRate(), 0.5);
  EXPECT_DOUBLE_EQ(key.interior.falseLightRate(), 0.25);
  EXPECT_EQ(key.edge.evaluated, 1);
  EXPECT_DOUBLE_EQ(worstInteriorErrorRate(key), 0.25);

  // Only the points under the lamp are reached; (0.2, 0, 0) is shadowed but the
  // renderer lit it.
  const LightVerification& ranged = v.lights[1];
  EXPECT_EQ(ranged.skipped.outOfRange, 6);
  EXPECT_EQ(ranged.interior.evaluated + ranged.edge.evaluated, 2);
  EXPECT_EQ(ranged.points[2].verdict, Verdict::FalseLight);

  const LightVerification& fill = v.lights[2];
  EXPECT_FALSE(fill.shadowed);
  EXPECT_TRUE(fill.points.empty());
  EXPECT_EQ(fill.interior.evaluated, 0);
  EXPECT_DOUBLE_EQ(worstInteriorErrorRate(fill), 0.0);
}

// Two squares 1 above the floor with a 2 cm gap between them: the lamp 3 above lights a strip
// |x| < 0.015 of the floor through it. A point 3 mm beside the strip is within the hard
// filter's band (3 texels, 0.035) of its edge, but a shift of the whole band steps over the
// strip into shadow again: only the points along the shift find it.
TEST(ShadowVerification, ALitGapNarrowerThanTheBandMakesItsNeighboursEdgePoints) {
  Scene scene;
  add(scene, square(0.0f, -5.0f, -5.0f, 5.0f, 5.0f, addMaterial(scene)));
  add(scene, square(1.0f, -1.0f, -1.0f, -0.01f, 1.0f, addMaterial(scene)));
  add(scene, square(1.0f, 0.01f, -1.0f, 1.0f, 1.0f, addMaterial(scene)));
  Light light = lamp({0.0f, 3.0f, 0.0f});
  light.shadow.filter = ShadowFilter::Hard;
  ViewCamera camera;
  camera.eye = {0.0f, 6.0f, 2.0f};
  const std::vector<Pixel> row = {
      {.position = {0.018f, 0.0f, 0.0f}, .visibility = {0.0f}},  // beside the strip
      {.position = {0.0f, 0.0f, 0.0f}, .visibility = {1.0f}},    // in it
      {.position = {0.3f, 0.0f, 0.0f}, .visibility = {0.0f}},    // far from it
  };
  const FloatImage aovs = makeAovs(row, {"lamp"}, camera.eye);
  const ShadowReference reference(scene);
  const ShadowVerification v =
      verifyShadows(reference, scene.bounds, {{light, 50.0f}}, aovs, camera, VerifySettings{});
  const std::vector<PointVerdict>& points = v.lights.at(0).points;
  EXPECT_EQ(points[0].reference, 0.0f);
  EXPECT_EQ(points[0].verdict, Verdict::Agree);
  EXPECT_TRUE(points[0].edge);
  EXPECT_EQ(points[1].reference, 1.0f);
  EXPECT_TRUE(points[1].edge);
  EXPECT_EQ(points[2].verdict, Verdict::Agree);
  EXPECT_FALSE(points[2].edge);
}

// KHR_materials_unlit surfaces are lit by nothing, so the lighting gives them no shadow term
// and their visibility AOV stays 1: an unlit floor in a shadow is skipped, not false light.
TEST(ShadowVerification, UnlitSurfacesAreSkippedNotCountedAsFalseLight) {
  SyntheticCase c;
  c.scene.materials[0].unlit = true;  // the floor; the square above it stays lit
  const std::vector<Pixel> row = {
      {.position = {0.0f, 0.0f, 0.0f}, .visibility = {1.0f}},  // the floor in the square's shadow
      {.position = {0.0f, 1.0f, 0.0f}, .visibility = {1.0f}},  // on the square
  };
  const FloatImage aovs = makeAovs(row, {"lamp"}, c.camera.eye);
  const ShadowReference reference(c.scene);
  const ShadowVerification v =
      verifyShadows(reference, c.scene.bounds, {c.lights[0]}, aovs, c.camera, VerifySettings{});
  const LightVerification& lamp = v.lights.at(0);
  EXPECT_EQ(lamp.points[0].verdict, Verdict::Unlit);
  EXPECT_EQ(lamp.skipped.unlit, 1);
  EXPECT_EQ(lamp.points[1].verdict, Verdict::Agree);
  EXPECT_EQ(lamp.interior.evaluated + lamp.edge.evaluated, 1);
  EXPECT_EQ(lamp.interior.falseLight + lamp.edge.falseLight, 0);
}

TEST(ShadowVerification, SpotConeAndDirectionalDistanceAreSkipped) {
  SyntheticCase c;
  Light spot = lamp({0.0f, 3.0f, 0.0f});
  spot.name = "spot";
  spot.type = LightType::Spot;
  spot.direction = {0.0f, -1.0f, 0.0f};
  spot.outerConeAngle = 0.5f;  // reaches |x| < 3 tan(0.5) = 1.64 on the floor
  Light directional = sun();
  directional.shadow.distance = 5.0f;  // shadows within 5 of the camera
  c.lights = {{spot, 50.0f}, {directional, 0.0f}};
  const std::vector<Pixel> row = {
      {.position = {0.0f, 0.0f, 0.0f}, .visibility = {0.0f, 0.0f}},
      {.position = {3.0f, 0.0f, 0.0f}, .visibility = {1.0f, 1.0f}},
  };
  const FloatImage aovs = makeAovs(row, {"spot", "sun"}, c.camera.eye);
  const ShadowVerification v =
      verifyShadows(ShadowReference(c.scene), c.scene.bounds, c.lights, aovs, c.camera, {});
  EXPECT_EQ(v.lights[0].points[0].verdict, Verdict::Agree);
  EXPECT_EQ(v.lights[0].points[1].verdict, Verdict::OutsideCone);
  // Distances from the camera: 6.3 and 7.0, both beyond 5.
  EXPECT_EQ(v.lights[1].skipped.beyondShadowFar, 2);
}

TEST(ShadowVerification, ResultsDoNotDependOnThreads) {
  SyntheticCase c;
  std::vector<Pixel> pixels;
  for (int y = 0; y < 24; ++y)
    for (int x = 0; x < 24; ++x) {
      const glm::vec3 p{(x - 12) * 0.2f, 0.0f, (y - 12) * 0.2f};
      pixels.push_back({.position = p, .visibility = {(x + y) % 3 ? 1.0f : 0.0f, 1.0f}});
    }
  FloatImage aovs = makeAovs(pixels, {"lamp", "ranged", "fill"}, c.camera.eye);
  aovs.width = aovs.height = 24;
  const ShadowReference reference(c.scene);
  VerifySettings one, many;
  one.threads = 1;
  many.threads = 5;
  const ShadowVerification a =
      verifyShadows(reference, c.scene.bounds, c.lights, aovs, c.camera, one);
  const ShadowVerification b =
      verifyShadows(reference, c.scene.bounds, c.lights, aovs, c.camera, many);
  for (std::size_t l = 0; l < a.lights.size(); ++l)
    for (std::size_t i = 0; i < a.lights[l].points.size(); ++i) {
      EXPECT_EQ(a.lights[l].points[i].verdict, b.lights[l].points[i].verdict);
      EXPECT_EQ(a.lights[l].points[i].edge, b.lights[l].points[i].edge);
    }
  EXPECT_GT(a.lights[0].interior.falseLight, 0);
  EXPECT_GT(a.lights[0].interior.falseShadow, 0);
}

TEST(ShadowVerification, ErrorImageColoursTheDisagreements) {
  SyntheticCase c;
  const std::vector<Pixel> row = {
      {.covered = false},
      {.position = {0.0f, 0.0f, 0.0f}, .visibility = {0.0f, 0.0f}},
      {.position = {0.2f, 0.0f, 0.0f}, .visibility = {1.0f, 0.0f}},  // false light
      {.position = {3.0f, 0.0f, 3.0f}, .visibility = {0.0f, 1.0f}},  // false shadow
  };
  const FloatImage aovs = makeAovs(row, {"lamp", "ranged", "fill"}, c.camera.eye);
  const ShadowVerification v =
      verifyShadows(ShadowReference(c.scene), c.scene.bounds, c.lights, aovs, c.camera, {});
  const std::vector<std::uint8_t> rgb = errorImage(v, aovs, c.camera);
  ASSERT_EQ(rgb.size(), 12u);
  EXPECT_EQ(rgb[0] + rgb[1] + rgb[2], 0);                           // background: black
  EXPECT_TRUE(rgb[3] == rgb[4] && rgb[4] == rgb[5] && rgb[3] > 0);  // agreement: grey
  EXPECT_GT(rgb[8], 200);                                           // false light: blue
  EXPECT_LT(rgb[6], 60);
  EXPECT_GT(rgb[9], 200);  // false shadow: red
  EXPECT_LT(rgb[11], 60);
}

// ---------------------------------------------------------------------------------------------
// omnishadow verify, end to end

class VerifyCommand : public ::testing::Test {
 protected:
  RunResult verify(std::vector<std::string> args) {
    args.insert(args.begin(), "verify");
    test_support::RunOptions options;
    options.workingDirectory = out_;
    return test_support::runOmnishadow(args, options);
  }

  fs::path writeText(const std::string& name, const std::string& text) {
    std::ofstream(folder_ / name) << text;
    return folder_ / name;
  }

  // A plane, a sphere above it and a box standing on it; the lamp casts both shadows.
  fs::path sphereScene() {
    builder::GltfBuilder b;
    const int grey = b.addMaterial({.name = "grey", .roughness = 0.8f});
    b.addNode("floor", {}, b.addMesh(builder::makePlane(8.0f), {.material = grey}));
    b.addNode("sphere", {.translation = {0.0f, 1.2f, 0.0f}},
              b.addMesh(builder::makeSphere(0.6f, 48, 24), {.material = grey}));
    b.addNode("box", {.translation = {1.4f, 0.4f, -0.6f}},
              b.addMesh(builder::makeBox(glm::vec3(0.4f)), {.material = grey}));
    const fs::path path = folder_ / "sphere.gltf";
    b.write(path, builder::FileFormat::GltfEmbedded);
    return path;
  }

  std::string lightsJson(const std::string& shadow) {
    return R"({"lights": [
      {"name": "lamp", "position": [-0.6, 3.5, 0.8], "intensity": 30, "shadow": )" +
           shadow + R"(},
      {"name": "fill", "position": [2, 4, 3], "intensity": 5, "shadow": false}]})";
  }

  std::vector<std::string> sphereView() {
    return {"--eye", "0,3.5,5", "--target", "0,0.5,0", "--width", "160", "--height", "120"};
  }

  static nlohmann::json parse(const RunResult& run) {
    try {
      return nlohmann::json::parse(run.out);
    } catch (const std::exception& e) {
      ADD_FAILURE() << e.what() << "\n" << run.out << run.err;
      return {};
    }
  }

  static int lines(const std::string& text) {
    return static_cast<int>(std::count(text.begin(), text.end(), '\n'));
  }

  TempFolder folder_{"omnishadow-verify"};
  fs::path out_ = [this] {
    fs::create_directory(folder_ / "out");
    return folder_ / "out";
  }();
};

// Embree (with TBB) is loaded when rays are cast, not by every process: a render maps neither
// (LD_DEBUG=files names every library the loader opens), and `verify` maps both.
TEST_F(VerifyCommand, OnlyVerifyLoadsEmbree) {
  const fs::path scene = sphereScene();
  const fs::path lights = writeText("sphere.lights.json", lightsJson("{\"resolution\": 64}"));
  test_support::RunOptions options;
  options.workingDirectory = out_;
  options.environment = {"LD_DEBUG=files"};
  std::vector<std::string> render = {"render",        scene.string(), "-l",
                                     lights.string(), "-o",           (out_ / "r.png").string()};
  const std::vector<std::string> view = sphereView();
  render.insert(render.end(), view.begin(), view.end());
  const RunResult rendered = test_support::runOmnishadow(render, options);
  ASSERT_EQ(rendered.status, 0) << rendered.err;
  EXPECT_NE(rendered.err.find("libEGL"), std::string::npos) << "LD_DEBUG gave no list";
  EXPECT_EQ(rendered.err.find("libembree3"), std::string::npos);
  EXPECT_EQ(rendered.err.find("libtbb"), std::string::npos);

  std::vector<std::string> verified = {"verify", scene.string(), "-l", lights.string()};
  verified.insert(verified.end(), view.begin(), view.end());
  const RunResult checked = test_support::runOmnishadow(verified, options);
  ASSERT_EQ(checked.status, 0) << checked.out << checked.err.substr(0, 2000);
  EXPECT_NE(checked.err.find("libembree3"), std::string::npos);
  EXPECT_NE(checked.err.find("libtbb"), std::string::npos);
}

TEST_F(VerifyCommand, CornellBoxAgreesWithTheRays) {
  const fs::path lights =
      writeText("cornell.lights.json",
                R"({"lights": [{"name": "lamp", "position": [0.15, 0.55, 0.35], "intensity": 2,
                      "shadow": {"resolution": 1024}}]})");
  std::vector<std::string> args = {
      std::string(OMNISHADOW_SOURCE_DIR) + "/scenes/thirdparty/CornellBoxSuzanne/cornell-box.glb",
      "-l",
      lights.string(),
      "--eye",
      "0,0,3.6",
      "--target",
      "0,0,0",
      "--fov",
      "40",
      "--width",
      "160",
      "--height",
      "120",
      "--json",
      "--max-error",
      "0.001"};
  const RunResult run = verify(args);
  ASSERT_EQ(run.status, 0) << run.out << run.err;
  const nlohmann::json report = parse(run);
  const nlohmann::json& lamp = report["lights"][0];
  EXPECT_EQ(lamp["name"], "lamp");
  EXPECT_GT(lamp["interior"]["evaluated"].get<int>(), 8000);
  EXPECT_GE(lamp["interior"]["agreementRate"].get<double>(), 0.999) << run.out;
  EXPECT_GT(lamp["skipped"]["facingAway"].get<int>() + lamp["skipped"]["grazing"].get<int>(), 0);
  EXPECT_TRUE(report["pass"].get<bool>());
}

// With ambient_occlusion in the lights file, its layer is compared with rays too: inside the
// Cornell box most of the occlusion the rays find is in the picture.
TEST_F(VerifyCommand, ReportsTheAmbientOcclusionAgainstTheRays) {
  const std::string box =
      std::string(OMNISHADOW_SOURCE_DIR) + "/scenes/thirdparty/CornellBoxSuzanne/cornell-box.glb";
  const std::vector<std::string> view = {"--eye", "0,0,3.6", "--target", "0,0,0",    "--fov",
                                         "40",    "--width", "160",      "--height", "120"};
  const fs::path occluded =
      writeText("occluded.json",
                R"({"ambient": [0.2, 0.2, 0.2], "ambient_occlusion": {"radius": 0.3},
          "lights": [{"name": "lamp", "position": [0.15, 0.55, 0.35], "intensity": 2}]})");
  std::vector<std::string> args = {box, "-l", occluded.string(), "--json"};
  args.insert(args.end(), view.begin(), view.end());
  const RunResult run = verify(args);
  ASSERT_EQ(run.status, 0) << run.out << run.err;
  const nlohmann::json occlusion = parse(run)["ambientOcclusion"];
  ASSERT_TRUE(occlusion.is_object()) << run.out;
  EXPECT_NEAR(occlusion["radius"].get<double>(), 0.3, 1e-6);
  EXPECT_EQ(occlusion["rays"], 64);
  EXPECT_GT(occlusion["evaluated"].get<int>(), 15000);
  EXPECT_EQ(occlusion["textured"], 0);
  EXPECT_LT(occlusion["meanAbsoluteError"].get<double>(), 0.05);
  EXPECT_GT(occlusion["occluded"].get<int>(), 2000);
  EXPECT_LT(occlusion["occludedMeanAbsoluteError"].get<double>(),
            0.5 * occlusion["occludedMeanHidden"].get<double>());

  std::vector<std::string> textArgs = {box, "-l", occluded.string()};
  textArgs.insert(textArgs.end(), view.begin(), view.end());
  const RunResult text = verify(textArgs);
  ASSERT_EQ(text.status, 0) << text.err;
  EXPECT_NE(text.out.find("ambient occlusion  radius 0.3, 64 rays per point meeting a surface "
                          "within 0.27\n"),
            std::string::npos)
      << text.out;

  const fs::path plain =
      writeText("plain.json", R"({"lights": [{"name": "lamp", "position": [0.15, 0.55, 0.35]}]})");
  std::vector<std::string> without = {box, "-l", plain.string(), "--json"};
  without.insert(without.end(), view.begin(), view.end());
  const RunResult none = verify(without);
  ASSERT_EQ(none.status, 0) << none.err;
  EXPECT_TRUE(parse(none)["ambientOcclusion"].is_null());
}

TEST_F(VerifyCommand, SphereAbovePlaneAgreesAndWritesTheErrorImage) {
  const fs::path lights = writeText("lights.json", lightsJson(R"({"resolution": 1024})"));
  std::vector<std::string> args = {
      sphereScene().string(), "-l",          lights.string(), "--error-image",
      "errors/verify.png",    "--max-error", "0.001"};
  for (const std::string& a : sphereView()) args.push_back(a);
  const RunResult text = verify(args);
  ASSERT_EQ(text.status, 0) << text.out << text.err;
  EXPECT_NE(text.out.find("light \"lamp\"  point  pcf  1024 texels"), std::string::npos)
      << text.out;
  EXPECT_NE(text.out.find("light \"fill\"  point  not shadowed"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("result     PASS"), std::string::npos) << text.out;
  const FloatImage image = readImage(out_ / "errors/verify.png");
  EXPECT_EQ(image.width, 160);
  EXPECT_EQ(image.height, 120);

  args.push_back("--json");
  const RunResult json = verify(args);
  ASSERT_EQ(json.status, 0) << json.err;
  const nlohmann::json report = parse(json);
  const nlohmann::json& lamp = report["lights"][0];
  EXPECT_GE(lamp["interior"]["agreementRate"].get<double>(), 0.999) << json.out;
  EXPECT_GT(lamp["interior"]["evaluated"].get<int>(), 10000);
  EXPECT_GT(lamp["edge"]["evaluated"].get<int>(), 100);
  EXPECT_GT(lamp["skipped"]["background"].get<int>(), 0);
  EXPECT_FALSE(report["lights"][1]["shadowed"].get<bool>());
  EXPECT_TRUE(report["lights"][1]["interior"].is_null());
  EXPECT_EQ(report["errorImage"], "errors/verify.png");
  // Same inputs, same report.
  EXPECT_EQ(verify(args).out, json.out);
}

TEST_F(VerifyCommand, AbsurdBiasLeaksLightAndFailsTheBound) {
  const fs::path lights =
      writeText("lights.json", lightsJson(R"({"resolution": 1024, "bias": 5})"));
  std::vector<std::string> args = {
      sphereScene().string(), "-l",   lights.string(), "--light", "lamp", "--json",
      "--max-error",          "0.001"};
  for (const std::string& a : sphereView()) args.push_back(a);
  const RunResult run = verify(args);
  EXPECT_EQ(run.status, 1) << run.out << run.err;
  const nlohmann::json report = parse(run);
  ASSERT_EQ(report["lights"].size(), 1u);  // --light
  const nlohmann::json& lamp = report["lights"][0];
  EXPECT_GT(lamp["interior"]["falseLightRate"].get<double>(), 0.01) << run.out;
  EXPECT_LT(lamp["interior"]["falseShadowRate"].get<double>(), 0.001) << run.out;
  EXPECT_FALSE(lamp["pass"].get<bool>());
  EXPECT_FALSE(report["pass"].get<bool>());
}

TEST_F(VerifyCommand, ErrorsExitWithStatus2OneLineAndNoFile) {
  const fs::path scene = sphereScene();
  const fs::path lights = writeText("lights.json", lightsJson("true"));
  writeText("a-file", "not a folder");
  struct Case {
    std::vector<std::string> args;
    std::string message;
  };
  // Each names an error image that must not appear.
  const std::vector<Case> cases = {
      {{"--light", "nope", "--error-image", "e.png"}, "--light nope: no such light"},
      {{"--max-error", "abc", "--error-image", "e.png"}, "--max-error abc: expected a fraction"},
      {{"--max-error", "2", "--error-image", "e.png"}, "--max-error 2: expected a fraction"},
      {{"--error-image", "e.jpg"}, "e.jpg: expected a .png name"},
      {{"--error-image", (folder_ / "a-file" / "e.png").string()}, "--error-image: cannot write"},
      {{"--source-samples", "10", "--error-image", "e.png"},
       "--source-samples 10: expected a square number"},
  };
  for (const Case& c : cases) {
    std::vector<std::string> args = {scene.string(), "-l", lights.string()};
    args.insert(args.end(), c.args.begin(), c.args.end());
    for (const std::string& a : sphereView()) args.push_back(a);
    const RunResult run = verify(args);
    EXPECT_EQ(run.status, 2) << c.message << "\n" << run.err;
    EXPECT_EQ(lines(run.err), 1) << run.err;
    EXPECT_NE(run.err.find(c.message), std::string::npos) << run.err;
    EXPECT_TRUE(filesIn(out_).empty()) << c.message;
  }
}

}  // namespace
}  // namespace omnishadow::verify_test
