// Material extensions as rendered: KHR_texture_transform in the lighting pass (the Khronos
// TextureTransformTest, texel by texel) and in the shadow pass's alpha test,
// KHR_materials_pbrSpecularGlossiness against its BRDF worked out by hand, and
// KHR_materials_sheen, KHR_materials_clearcoat and KHR_materials_transmission (see-through,
// thin-walled) against their specifications' formulas evaluated here. Small frames on whatever
// EGL gives (llvmpipe in CI).
#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <functional>
#include <glm/gtc/matrix_transform.hpp>
#include <numbers>
#include <string>
#include <vector>

#include "renderer/output/display_transform.h"
#include "renderer/passes/lighting_pass.h"
#include "renderer/passes/shader_contract.h"
#include "renderer/render/renderer.h"
#include "renderer/scene/gltf_loader.h"
#include "renderer/view/camera.h"
#include "renderer/view/sheen_albedo_table.h"
#include "renderer/view/sheen_brdf.h"
#include "scenes/builder/gltf_builder.h"
#include "tests/support/shared_renderer.h"
#include "tests/support/temp_folder.h"

namespace omnishadow::material_render_test {
namespace {

namespace fs = std::filesystem;
using namespace builder;
using Value = tinygltf::Value;
using test_support::lookFrom;
using test_support::sharedRenderer;

constexpr float kPi = std::numbers::pi_v<float>;

Frame render(const Scene& scene, const std::vector<Light>& lights, const ViewCamera& camera,
             DebugView view = DebugView::None) {
  return test_support::renderWithAovs(scene, lights, camera, {.debugView = view});
}

// A directional light named "sun" shining along `direction`, `lux` strong.
Light sunAlong(glm::vec3 direction, float lux) {
  Light sun;
  sun.name = "sun";
  sun.type = LightType::Directional;
  sun.direction = direction;
  sun.intensity = lux;
  return sun;
}

float srgbToLinear(std::uint8_t value) {
  const float c = static_cast<float>(value) / 255.0f;
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

glm::vec3 worldAt(const FloatImage& aovs, int x, int y) {
  const int p = aovs.channelIndex("P.X");
  return {aovs.at(x, y, p), aovs.at(x, y, p + 1), aovs.at(x, y, p + 2)};
}

// The affine map from a planar mesh's local (x, y) to its TEXCOORD_0, from its first triangle.
glm::mat3 uvFromPosition(const Mesh& mesh) {
  const glm::vec3 a = mesh.positions[mesh.indices[0]], b = mesh.positions[mesh.indices[1]],
                  c = mesh.positions[mesh.indices[2]];
  const glm::vec2 ua = mesh.uv0[mesh.indices[0]], ub = mesh.uv0[mesh.indices[1]],
                  uc = mesh.uv0[mesh.indices[2]];
  const glm::mat3 positions(glm::vec3(a.x, a.y, 1), glm::vec3(b.x, b.y, 1), glm::vec3(c.x, c.y, 1));
  const glm::mat3 uvs(glm::vec3(ua, 1), glm::vec3(ub, 1), glm::vec3(uc, 1));
  return uvs * glm::inverse(positions);
}

// The texel of `image` at `uv` with clamp-to-edge, when it and its 8 neighbours are equal (so
// that the filter cannot matter); false otherwise.
bool uniformTexel(const Image& image, glm::vec2 uv, glm::u8vec4& texel) {
  const auto clampTo = [](int v, int size) { return std::max(0, std::min(size - 1, v)); };
  const int x =
      clampTo(static_cast<int>(std::floor(uv.x * static_cast<float>(image.width))), image.width);
  const int y =
      clampTo(static_cast<int>(std::floor(uv.y * static_cast<float>(image.height))), image.height);
  const auto at = [&](int tx, int ty) {
    const std::size_t i = (static_cast<std::size_t>(clampTo(ty, image.height)) * image.width +
                           clampTo(tx, image.width)) *
                          4;
    return glm::u8vec4(image.rgba[i], image.rgba[i + 1], image.rgba[i + 2], image.rgba[i + 3]);
  };
  texel = at(x, y);
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx)
      if (at(x + dx, y + dy) != texel) return false;
  return true;
}

const fs::path kTextureTransformTest =
    fs::path(OMNISHADOW_SOURCE_DIR) /
    "scenes/khronos/TextureTransformTest/TextureTransformTest.gltf";

// Every pixel of the six test quads shows the texel the extension's transform picks (computed
// here from the pixel's world position, the quad's UVs and the material's transform), wherever
// that texel's neighbourhood is uniform. Pixels where the untransformed texel differs prove the
// check could fail.
TEST(TextureTransformRender, EveryQuadOfTheKhronosTestShowsTheTransformedTexels) {
  const Scene scene = loadGltf(kTextureTransformTest);
  const ViewCamera camera = lookFrom(scene, {0, 0, 4}, {0, 0, 0}, 384, 256, 50.0f);
  const Frame frame = render(scene, {}, camera, DebugView::Albedo);
  ASSERT_TRUE(frame.aovs);
  const int alpha = frame.aovs->channelIndex("A");
  std::vector<int> checked(scene.instances.size(), 0), discriminating(scene.instances.size(), 0);
  for (int y = 0; y < camera.height; ++y) {
    for (int x = 0; x < camera.width; ++x) {
      if (frame.aovs->at(x, y, alpha) < 1.0f) continue;
      const glm::vec3 world = worldAt(*frame.aovs, x, y);
      // The six quads lie in z = 0; the markers, 0.01 in front, use mipmapped textures.
      if (std::abs(world.z) > 1e-3f) continue;
      for (std::size_t i = 0; i < scene.instances.size(); ++i) {
        const MeshInstance& instance = scene.instances[i];
        const glm::vec3 local = glm::vec3(glm::inverse(instance.world) * glm::vec4(world, 1.0f));
        if (std::abs(local.z) > 1e-3f || std::abs(local.x) > 0.5f || std::abs(local.y) > 0.5f)
          continue;
        const Mesh& mesh = scene.meshes[static_cast<std::size_t>(instance.mesh)];
        const Material& material = scene.materials[static_cast<std::size_t>(mesh.material)];
        const TextureSlot& slot = material.baseColorTexture;
        const Image& image = scene.images[static_cast<std::size_t>(
            scene.textures[static_cast<std::size_t>(slot.texture)].image)];
        const glm::vec2 uv = glm::vec2(uvFromPosition(mesh) * glm::vec3(local.x, local.y, 1.0f));
        const glm::vec2 transformed = glm::vec2(slot.uvTransform * glm::vec3(uv, 1.0f));
        glm::u8vec4 texel, plain;
        if (!uniformTexel(image, transformed, texel)) continue;
        ++checked[i];
        if (!uniformTexel(image, uv, plain) || plain != texel) ++discriminating[i];
        for (int c = 0; c < 3; ++c) {
          EXPECT_NEAR(frame.beauty.at(x, y, c), srgbToLinear(texel[c]), 0.01f)
              << "quad \"" << material.name << "\", pixel " << x << "," << y << ", channel " << c;
        }
      }
    }
  }
  int quads = 0;
  for (std::size_t i = 0; i < scene.instances.size(); ++i) {
    if (checked[i] == 0) continue;  // a marker
    ++quads;
    EXPECT_GT(checked[i], 1000) << "instance " << i;
    EXPECT_GT(discriminating[i], 300) << "instance " << i;
  }
  EXPECT_EQ(quads, 6);
}

// The arrows of the Rotation, Scale and All quads point at their green "Correct" markers, not
// at the yellow "not supported" or red "wrong direction" ones: with the markers taken out of the
// scene, the arrow's black line (on its quad) comes closer to the centre of each green marker
// than to any other marker of the same quad, and within 0.2 (markers are 0.1 to 0.15 wide and
// may sit just past the quad's edge). Positions are world units read from the AOVs.
TEST(TextureTransformRender, ArrowsPointAtTheCorrectMarkers) {
  Scene scene = loadGltf(kTextureTransformTest);
  struct Marker {
    glm::vec3 center;
    std::string material;
    glm::vec3 quad{0.0f};   // centre of the quad it belongs to
    float distance = 1e9f;  // to the nearest arrow pixel on that quad
  };
  std::vector<Marker> markers;
  std::vector<MeshInstance> quads;
  for (const MeshInstance& instance : scene.instances) {
    const Mesh& mesh = scene.meshes[static_cast<std::size_t>(instance.mesh)];
    const std::string& name = scene.materials[static_cast<std::size_t>(mesh.material)].name;
    if (name == "Correct" || name == "NotSupported" || name == "Error")
      markers.push_back({glm::vec3(instance.world[3]), name});
    else
      quads.push_back(instance);
  }
  ASSERT_EQ(markers.size(), 6u);
  for (Marker& marker : markers) {
    float nearest = 1e9f;
    for (const MeshInstance& quad : quads) {
      const glm::vec3 center(quad.world[3]);
      if (glm::length(center - marker.center) < nearest) {
        nearest = glm::length(center - marker.center);
        marker.quad = center;
      }
    }
  }
  scene.instances = quads;
  const ViewCamera camera = lookFrom(scene, {0, 0, 4}, {0, 0, 0}, 384, 256, 50.0f);
  const Frame frame = render(scene, {}, camera, DebugView::Albedo);
  ASSERT_TRUE(frame.aovs);
  const int alpha = frame.aovs->channelIndex("A");
  for (int y = 0; y < camera.height; ++y) {
    for (int x = 0; x < camera.width; ++x) {
      if (frame.aovs->at(x, y, alpha) < 1.0f || frame.beauty.at(x, y, 0) > 0.05f) continue;
      const glm::vec3 p = worldAt(*frame.aovs, x, y);
      for (Marker& marker : markers) {
        if (std::abs(p.x - marker.quad.x) > 0.45f || std::abs(p.y - marker.quad.y) > 0.45f)
          continue;  // another quad, or this one's dark grey border
        marker.distance = std::min(marker.distance, glm::length(p - marker.center));
      }
    }
  }
  int correct = 0;
  for (const Marker& green : markers) {
    if (green.material != "Correct") continue;
    ++correct;
    EXPECT_LT(green.distance, 0.2f) << "quad at x " << green.quad.x;
    for (const Marker& other : markers) {
      if (other.material == "Correct" || other.quad != green.quad) continue;
      EXPECT_GT(other.distance, green.distance + 0.1f)
          << "quad at x " << green.quad.x << ": the arrow is nearer the " << other.material
          << " marker";
    }
  }
  EXPECT_EQ(correct, 3);
}

// A cut-out card whose alpha texture is opaque on its left half only (u < 0.5, x < 0), drawn
// through KHR_texture_transform scale (-1, 1) and offset (1, 0), a mirror in u: the camera
// above sees only the right half, and the sun, coming down at 45 degrees towards -x, casts only
// the right half's shadow, one unit to the left on the floor (under the card's empty left
// half), and none where the left half's would be.
TEST(TextureTransformRender, MaskedShadowsAndCoverageFollowTheTransform) {
  test_support::TempFolder folder("omnishadow-material-render");
  GltfBuilder builder;
  std::vector<std::uint8_t> rgba;
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x)
      rgba.insert(rgba.end(), {255, 255, 255, static_cast<std::uint8_t>(x < 2 ? 255 : 0)});
  MaterialDesc cutout;
  cutout.alphaMode = "MASK";
  cutout.doubleSided = true;
  cutout.baseColorTexture = builder.addTexture(4, 4, rgba, "left half");
  PrimitiveOptions options;
  options.material = builder.addMaterial(cutout);
  tinygltf::TextureInfo& info = builder.model()
                                    .materials[static_cast<std::size_t>(options.material)]
                                    .pbrMetallicRoughness.baseColorTexture;
  Value::Array scale = {Value(-1.0), Value(1.0)}, offset = {Value(1.0), Value(0.0)};
  info.extensions["KHR_texture_transform"] =
      Value(Value::Object{{"scale", Value(scale)}, {"offset", Value(offset)}});
  builder.model().samplers.push_back({});
  builder.model().samplers.back().magFilter = TINYGLTF_TEXTURE_FILTER_NEAREST;
  builder.model().samplers.back().minFilter = TINYGLTF_TEXTURE_FILTER_NEAREST;
  builder.model().textures[0].sampler = 0;
  // The quad spans x, z in [-1, 1] at height 1 (u runs along +x), the floor is at 0.
  builder::MeshData card = builder::makePlane(2.0f);
  builder.addNode("card", {{0, 1, 0}}, builder.addMesh(card, options));
  MaterialDesc floor;
  PrimitiveOptions floorOptions;
  floorOptions.material = builder.addMaterial(floor);
  builder.addNode("floor", {}, builder.addMesh(builder::makePlane(8.0f), floorOptions));
  const fs::path file = folder / "card.gltf";
  builder.write(file, FileFormat::GltfEmbedded);
  const Scene scene = loadGltf(file);

  Light sun = sunAlong(glm::normalize(glm::vec3(-1, -1, 0)), 2.0f);
  sun.shadow.resolution = 1024;
  sun.shadow.filter = ShadowFilter::Hard;
  const ViewCamera camera = lookFrom(scene, {0, 6, 0}, {0, 0, 0}, 128, 128, 60.0f, {0, 0, -1});
  const Frame frame = render(scene, {sun}, camera);
  ASSERT_TRUE(frame.aovs);
  const int visibility = frame.aovs->channelIndex("visibility.sun");
  int cardLeft = 0, cardRight = 0, underLeftHalf = 0, shadowedUnderLeftHalf = 0, farLeft = 0,
      shadowedFarLeft = 0;
  for (int y = 0; y < camera.height; ++y) {
    for (int x = 0; x < camera.width; ++x) {
      const glm::vec3 p = worldAt(*frame.aovs, x, y);
      if (std::abs(p.z) > 0.8f) continue;
      const bool shadowed = frame.aovs->at(x, y, visibility) < 0.5f;
      if (std::abs(p.y - 1.0f) < 1e-3f) {
        if (p.x > 0.2f && p.x < 0.8f) ++cardRight;
        if (p.x < -0.2f && p.x > -0.8f) ++cardLeft;
      } else if (std::abs(p.y) < 1e-3f) {
        if (p.x < -0.2f && p.x > -0.8f) {
          ++underLeftHalf;
          shadowedUnderLeftHalf += shadowed;
        }
        if (p.x < -1.2f && p.x > -1.8f) {
          ++farLeft;
          shadowedFarLeft += shadowed;
        }
      }
    }
  }
  EXPECT_GT(cardRight, 200);
  EXPECT_EQ(cardLeft, 0) << "the lighting pass drew the untransformed (left) half";
  EXPECT_GT(underLeftHalf, 200);
  EXPECT_EQ(shadowedUnderLeftHalf, underLeftHalf) << "the right half cast no full shadow";
  EXPECT_GT(farLeft, 200);
  EXPECT_EQ(shadowedFarLeft, 0) << "the shadow pass drew the untransformed (left) half";
}

// A normal texture seen through KHR_texture_transform turns the normals it stores with it: a
// plane whose uniform normal texture (tilted towards the texture's +X) is rotated or mirrored by
// the extension shades like the same plane with those UVs baked into TEXCOORD_0 (its tangents
// then generated from them), and unlike the plane without the transform.
TEST(TextureTransformRender, NormalTexturesTurnWithTheirTransform) {
  test_support::TempFolder folder("omnishadow-material-render");
  const auto shadingNormal = [&](const std::vector<glm::vec2>& uvs, const Value* transform) {
    GltfBuilder builder;
    MaterialDesc desc;
    desc.normalTexture = builder.addTexture(1, 1, {204, 128, 230, 255}, "tilted");  // (.6, 0, .8)
    PrimitiveOptions options;
    options.material = builder.addMaterial(desc);
    if (transform)
      builder.model().materials[0].normalTexture.extensions["KHR_texture_transform"] = *transform;
    builder::MeshData plane = builder::makePlane(2.0f);
    plane.uvs = uvs;
    builder.addNode("plane", {}, builder.addMesh(plane, options));
    const fs::path file = folder / "plane.gltf";
    builder.write(file, FileFormat::GltfEmbedded);
    const Scene scene = loadGltf(file);
    const ViewCamera camera = lookFrom(scene, {0, 3, 0}, {0, 0, 0}, 16, 16, 30.0f, {0, 0, -1});
    const Frame frame = render(scene, {}, camera);
    const int n = frame.aovs->channelIndex("N.X");
    return glm::vec3(frame.aovs->at(8, 8, n), frame.aovs->at(8, 8, n + 1),
                     frame.aovs->at(8, 8, n + 2));
  };
  const std::vector<glm::vec2> uvs = builder::makePlane(2.0f).uvs;
  const struct {
    glm::vec2 offset;
    float rotation;
    glm::vec2 scale;
  } cases[] = {{{0.0f, 0.0f}, 0.9f, {1.5f, 1.5f}},
               {{1.0f, 0.0f}, 0.0f, {-1.0f, 1.0f}},
               {{0.2f, 0.3f}, -2.0f, {1.0f, 1.0f}}};
  const glm::vec3 plain = shadingNormal(uvs, nullptr);
  for (const auto& c : cases) {
    const Value transform(Value::Object{
        {"offset", Value(Value::Array{Value(double{c.offset.x}), Value(double{c.offset.y})})},
        {"rotation", Value(double{c.rotation})},
        {"scale", Value(Value::Array{Value(double{c.scale.x}), Value(double{c.scale.y})})}});
    const glm::vec3 transformed = shadingNormal(uvs, &transform);
    // The same mapping as a matrix, baked into the vertices' UVs.
    const float co = std::cos(c.rotation), si = std::sin(c.rotation);
    std::vector<glm::vec2> baked;
    for (const glm::vec2 uv : uvs) {
      baked.emplace_back(c.scale.x * co * uv.x + c.scale.y * si * uv.y + c.offset.x,
                         -c.scale.x * si * uv.x + c.scale.y * co * uv.y + c.offset.y);
    }
    const glm::vec3 expected = shadingNormal(baked, nullptr);
    EXPECT_LT(glm::length(transformed - expected), 2e-3f)
        << "rotation " << c.rotation << ": (" << transformed.x << ", " << transformed.y << ", "
        << transformed.z << ") vs (" << expected.x << ", " << expected.y << ", " << expected.z
        << ")";
    EXPECT_GT(glm::length(expected - plain), 0.3f) << "rotation " << c.rotation;
  }
}

// A floor of a specular-glossiness material under a sun straight above, seen from straight
// above through a narrow lens (so V = L = N to within 1.5 degrees): the spec's BRDF gives
// diffuse (1 - F0) * diffuse * (1 - max(F0)) / pi * E and specular F0 * D * Vis * E with
// NdotH = 1: D = 1 / (pi alpha^2), Vis = 1 / 4, alpha = (1 - glossiness)^2.
TEST(SpecularGlossinessRender, MatchesTheExtensionsBrdfByHand) {
  test_support::TempFolder folder("omnishadow-material-render");
  GltfBuilder builder;
  PrimitiveOptions options;
  options.material = builder.addMaterial(MaterialDesc{});
  const glm::vec3 diffuse(0.6f, 0.4f, 0.2f), specular(0.5f, 0.25f, 0.125f);
  const float glossiness = 0.25f;  // roughness 0.75, alpha 0.5625
  builder.model().materials[0].extensions["KHR_materials_pbrSpecularGlossiness"] =
      Value(Value::Object{
          {"diffuseFactor", Value(Value::Array{Value(0.6), Value(0.4), Value(0.2), Value(1.0)})},
          {"specularFactor", Value(Value::Array{Value(0.5), Value(0.25), Value(0.125)})},
          {"glossinessFactor", Value(0.25)}});
  builder.addNode("floor", {}, builder.addMesh(builder::makePlane(4.0f), options));
  const fs::path file = folder / "floor.gltf";
  builder.write(file, FileFormat::GltfEmbedded);
  const Scene scene = loadGltf(file);
  ASSERT_TRUE(scene.materials[0].specularGlossiness);

  Light sun = sunAlong(glm::vec3(0, -1, 0), 3.0f);
  sun.shadow.enabled = false;
  const ViewCamera camera = lookFrom(scene, {0, 20, 0}, {0, 0, 0}, 32, 32, 3.0f, {0, 0, -1});
  const Frame frame = render(scene, {sun}, camera);
  const float alpha = (1.0f - glossiness) * (1.0f - glossiness);
  const float d = 1.0f / (kPi * alpha * alpha), vis = 0.25f;
  const float weight = 1.0f - 0.5f;  // 1 - max(specular)
  const glm::vec3 expected =
      (glm::vec3(1.0f) - specular) * weight * diffuse / kPi * 3.0f + specular * d * vis * 3.0f;
  for (const auto& [x, y] : {std::pair{16, 16}, std::pair{4, 4}, std::pair{27, 9}}) {
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(frame.beauty.at(x, y, c), expected[c], 0.01f * expected[c])
          << "pixel " << x << "," << y << " channel " << c;
    }
  }
}

// The lighting pass compiles a program per material variant (texture slots, specular-
// glossiness) and switches between them from draw to draw: three such materials in one frame,
// through the beauty pass and the AOV pass, each still shade by its own BRDF worked out by hand.
TEST(MaterialVariantRender, EachMaterialOfOneFrameKeepsItsOwnBrdf) {
  test_support::TempFolder folder("omnishadow-material-variants");
  GltfBuilder builder;
  MaterialDesc plain;
  plain.baseColor = {0.6f, 0.4f, 0.2f, 1.0f};
  plain.roughness = 0.5f;
  MaterialDesc textured = plain;
  textured.baseColor = glm::vec4(1.0f);
  textured.baseColorTexture = builder.addTexture(1, 1, {255, 128, 0, 255}, "orange");
  PrimitiveOptions options;
  const glm::vec3 at[3] = {{-3, 0, 0}, {0, 0, 0}, {3, 0, 0}};
  const int materials[3] = {builder.addMaterial(plain), builder.addMaterial(textured),
                            builder.addMaterial(MaterialDesc{})};
  builder.model().materials[2].extensions["KHR_materials_pbrSpecularGlossiness"] =
      Value(Value::Object{
          {"diffuseFactor", Value(Value::Array{Value(0.6), Value(0.4), Value(0.2), Value(1.0)})},
          {"specularFactor", Value(Value::Array{Value(0.5), Value(0.25), Value(0.125)})},
          {"glossinessFactor", Value(0.25)}});
  for (int i = 0; i < 3; ++i) {
    options.material = materials[i];
    builder.addNode("plane" + std::to_string(i), {at[i]},
                    builder.addMesh(builder::makePlane(2.0f), options));
  }
  const fs::path file = folder / "planes.gltf";
  builder.write(file, FileFormat::GltfEmbedded);
  const Scene scene = loadGltf(file);

  Light sun = sunAlong(glm::vec3(0, -1, 0), 3.0f);
  sun.shadow.enabled = false;
  // 9 m wide at the planes: their centers at pixels 16, 48 and 80. From far away, so that V is
  // within a degree of N on every plane.
  const ViewCamera camera = lookFrom(scene, {0, 200, 0}, {0, 0, 0}, 96, 32,
                                     2.0f * glm::degrees(std::atan(1.5f / 200.0f)), {0, 0, -1});
  // N = L = V: Fresnel is F0, the GGX lobe 1 / (pi alpha^2), the visibility term 1/4.
  const auto metallicRoughness = [](glm::vec3 base, float roughness) {
    const float alpha = roughness * roughness;
    return (1.0f - 0.04f) * base / kPi * 3.0f +
           glm::vec3(0.04f / (kPi * alpha * alpha) * 0.25f * 3.0f);
  };
  const glm::vec3 specular(0.5f, 0.25f, 0.125f), diffuse(0.6f, 0.4f, 0.2f);
  const float glossAlpha = 0.75f * 0.75f;
  const glm::vec3 expected[3] = {metallicRoughness(diffuse, 0.5f),
                                 metallicRoughness({1.0f, srgbToLinear(128), 0.0f}, 0.5f),
                                 (glm::vec3(1.0f) - specular) * 0.5f * diffuse / kPi * 3.0f +
                                     specular / (kPi * glossAlpha * glossAlpha) * 0.25f * 3.0f};
  for (const bool aovs : {false, true}) {
    StageTimes times;
    RenderSettings settings;
    settings.aovs = aovs;
    const Frame frame =
        sharedRenderer().render(scene, {sun}, glm::vec3(0.0f), camera, settings, times);
    for (int i = 0; i < 3; ++i)
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(frame.beauty.at(16 + 32 * i, 16, c), expected[i][c], 0.01f * expected[i][c])
            << "material " << i << " channel " << c << (aovs ? " (AOV pass)" : " (beauty pass)");
  }
}

// The floors of the ior and specular tests: three 2 m floors in a row along x (centres -3, 0
// and 3), each of the base color (0.6, 0.4, 0.2) and roughness 0.5 with `metallic[i]`, their
// glTF materials given to `extend` (which adds the extensions) before the file is written.
constexpr glm::vec3 kFloorBase(0.6f, 0.4f, 0.2f);
constexpr float kFloorAlpha = 0.25f;  // roughness 0.5

Scene floorsInARow(const fs::path& file, const std::array<float, 3>& metallic,
                   const std::function<void(GltfBuilder&)>& extend) {
  GltfBuilder builder;
  MaterialDesc material;
  material.baseColor = glm::vec4(kFloorBase, 1.0f);
  material.roughness = 0.5f;
  PrimitiveOptions options;
  for (int i = 0; i < 3; ++i) {
    material.metallic = metallic[static_cast<std::size_t>(i)];
    options.material = builder.addMaterial(material);
    builder.addNode("plane" + std::to_string(i),
                    {glm::vec3(3.0f * static_cast<float>(i - 1), 0, 0)},
                    builder.addMesh(builder::makePlane(2.0f), options));
  }
  extend(builder);
  builder.write(file, FileFormat::GltfEmbedded);
  Scene scene = loadGltf(file);
  EXPECT_TRUE(scene.warnings.empty()) << scene.warnings.front();
  return scene;
}

// floorsInARow() under a 3 lux sun straight above, seen from straight above through a narrow
// lens (N = L = V on every floor to within a degree): the floors' centres at pixels (16, 16),
// (48, 16) and (80, 16).
Frame renderFloorsFromAbove(const Scene& scene, Shading shading) {
  Light sun = sunAlong(glm::vec3(0, -1, 0), 3.0f);
  sun.shadow.enabled = false;
  const ViewCamera camera = lookFrom(scene, {0, 200, 0}, {0, 0, 0}, 96, 32,
                                     2.0f * glm::degrees(std::atan(1.5f / 200.0f)), {0, 0, -1});
  StageTimes times;
  RenderSettings settings;
  settings.shading = shading;
  return sharedRenderer().render(scene, {sun}, glm::vec3(0.0f), camera, settings, times);
}

// At N = L = V: the GGX lobe times its visibility, 1 / (pi alpha^2) x 1/4, and the normalized
// Blinn-Phong lobe (shininess 2 / alpha^2 - 2 at N.H = 1).
constexpr float kFloorGgxLobe = 1.0f / (kPi * kFloorAlpha * kFloorAlpha) * 0.25f;
constexpr float kFloorPhongShininess = 2.0f / (kFloorAlpha * kFloorAlpha) - 2.0f;
constexpr float kFloorPhongLobe = (kFloorPhongShininess + 8.0f) / (8.0f * kPi);

// KHR_materials_ior: floors of ior 1.5 (no extension), 1.33 and 2.42: each reflects its own F0
// = ((ior - 1) / (ior + 1))^2 through the GGX lobe, and the diffuse what Fresnel leaves, as
// worked out by hand. Also in the Phong shading, whose specular is F0 times its lobe.
TEST(IorRender, EachFloorReflectsItsOwnFresnel) {
  test_support::TempFolder folder("omnishadow-ior-render");
  const float iors[3] = {1.5f, 1.33f, 2.42f};
  const Scene scene = floorsInARow(folder / "planes.gltf", {0, 0, 0}, [&](GltfBuilder& builder) {
    for (int i = 1; i < 3; ++i)
      builder.model().materials[i].extensions["KHR_materials_ior"] =
          Value(Value::Object{{"ior", Value(static_cast<double>(iors[i]))}});
    builder.model().extensionsUsed = {"KHR_materials_ior"};
  });
  for (const Shading shading : {Shading::Pbr, Shading::Phong}) {
    const Frame frame = renderFloorsFromAbove(scene, shading);
    for (int i = 0; i < 3; ++i) {
      const float r = (iors[i] - 1.0f) / (iors[i] + 1.0f), f0 = r * r;
      const glm::vec3 expected =
          shading == Shading::Pbr
              ? (1.0f - f0) * kFloorBase / kPi * 3.0f + glm::vec3(f0 * kFloorGgxLobe * 3.0f)
              : kFloorBase / kPi * 3.0f + glm::vec3(f0 * kFloorPhongLobe * 3.0f);
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(frame.beauty.at(16 + 32 * i, 16, c), expected[c], 0.01f * expected[c])
            << "ior " << iors[i] << " channel " << c
            << (shading == Shading::Pbr ? " (PBR)" : " (Phong)");
    }
  }
}

// KHR_materials_specular's factors (with an ior of 1.33 from KHR_materials_ior) on a dielectric
// and on a half-metal floor (N = L = V, so the Fresnel terms are their normal-incidence values):
// the dielectric reflects f0 = min(F0(ior) x color, 1) x factor through the GGX lobe, its
// diffuse is weighted by 1 - max(f0), the metal reflects its base color; worked out by hand, in
// the PBR and the Phong shading. A third floor with the factors' defaults draws as the core
// material does.
TEST(SpecularRender, FactorsScaleTheDielectricFresnelAsTheSpecificationWrites) {
  test_support::TempFolder folder("omnishadow-specular-render");
  const Scene scene =
      floorsInARow(folder / "planes.gltf", {0.0f, 0.5f, 0.0f}, [](GltfBuilder& builder) {
        auto& materials = builder.model().materials;
        for (int i = 0; i < 2; ++i) {
          materials[i].extensions["KHR_materials_specular"] = Value(Value::Object{
              {"specularFactor", Value(0.5)},
              {"specularColorFactor", Value(Value::Array{Value(2.0), Value(1.0), Value(0.25)})}});
          materials[i].extensions["KHR_materials_ior"] = Value(Value::Object{{"ior", Value(1.33)}});
        }
        materials[2].extensions["KHR_materials_specular"] = Value(Value::Object{});
        builder.model().extensionsUsed = {"KHR_materials_specular", "KHR_materials_ior"};
      });
  const float r = 0.33f / 2.33f;
  const glm::vec3 f0 = glm::min(r * r * glm::vec3(2.0f, 1.0f, 0.25f), glm::vec3(1.0f)) * 0.5f;
  const glm::vec3 diffuse = kFloorBase / kPi * 3.0f;
  for (const Shading shading : {Shading::Pbr, Shading::Phong}) {
    const Frame frame = renderFloorsFromAbove(scene, shading);
    glm::vec3 expected[3];
    if (shading == Shading::Pbr) {
      const float diffuseWeight = 1.0f - std::max(f0.r, std::max(f0.g, f0.b));
      expected[0] = diffuseWeight * diffuse + f0 * kFloorGgxLobe * 3.0f;
      expected[1] =
          0.5f * diffuseWeight * diffuse + glm::mix(f0, kFloorBase, 0.5f) * kFloorGgxLobe * 3.0f;
      expected[2] = 0.96f * diffuse + glm::vec3(0.04f * kFloorGgxLobe * 3.0f);
    } else {  // Blinn-Phong: the metallic input is not used, the specular color is f0
      expected[0] = expected[1] = diffuse + f0 * kFloorPhongLobe * 3.0f;
      expected[2] = diffuse + glm::vec3(0.04f * kFloorPhongLobe * 3.0f);
    }
    for (int i = 0; i < 3; ++i)
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(frame.beauty.at(16 + 32 * i, 16, c), expected[i][c], 0.01f * expected[i][c])
            << "floor " << i << " channel " << c
            << (shading == Shading::Pbr ? " (PBR)" : " (Phong)");
  }
}

// Every wholly covered floor pixel of `frame` (its AOVs give each pixel's point) against
// `expected(V)`, within 1%; returns how many were checked and, through `changed`, how many
// differ from `other(V)` by more than 10% in some channel.
int expectFloorPixels(const Frame& frame, const FloatImage& aovs, glm::vec3 eye,
                      const std::function<glm::vec3(glm::vec3)>& expected,
                      const std::function<glm::vec3(glm::vec3)>& other, int& changed,
                      const std::string& what) {
  int checked = 0;
  changed = 0;
  for (int y = 1; y + 1 < frame.beauty.height; ++y)
    for (int x = 1; x + 1 < frame.beauty.width; ++x) {
      bool floor = true;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          floor = floor && frame.beauty.at(x + dx, y + dy, 3) == 1.0f &&
                  std::abs(worldAt(aovs, x + dx, y + dy).y) < 1e-3f;
      if (!floor) continue;
      const glm::vec3 V = glm::normalize(eye - worldAt(aovs, x, y));
      const glm::vec3 e = expected(V), o = other(V);
      bool differs = false;
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(frame.beauty.at(x, y, c), e[c], 0.01f * e[c] + 1e-4f)
            << what << ": pixel " << x << "," << y << " channel " << c;
        differs = differs || std::abs(e[c] - o[c]) > 0.1f * o[c];
      }
      changed += differs ? 1 : 0;
      ++checked;
    }
  return checked;
}

// A floor frame as the floor tests check it: rendered with AOVs (`aovs`), or as the beauty pass
// draws it; either way with the AOV frame whose points expectFloorPixels() reads.
std::pair<Frame, Frame> renderFloorFrame(const Scene& scene, const Light& sun, float ambient,
                                         const ViewCamera& camera, bool aovs) {
  RenderSettings settings;
  settings.aovs = true;
  StageTimes times;
  Frame withAovs =
      sharedRenderer().render(scene, {sun}, glm::vec3(ambient), camera, settings, times);
  if (aovs) return {withAovs, withAovs};
  settings.aovs = false;
  Frame beauty = sharedRenderer().render(scene, {sun}, glm::vec3(ambient), camera, settings, times);
  return {std::move(beauty), std::move(withAovs)};
}

// The sheen test's materials: a dielectric base, and its sheen (color zero: none).
struct SheenInputs {
  glm::vec3 base{0.5f, 0.3f, 0.2f};
  float roughness = 0.6f;
  glm::vec3 sheenColor{0.9f, 0.6f, 0.3f};
  float sheenRoughness = 0.5f;
};

Value sheenExtension(glm::vec3 color, float roughness) {
  return Value(Value::Object{
      {"sheenColorFactor", Value(Value::Array{Value(color.r), Value(color.g), Value(color.b)})},
      {"sheenRoughnessFactor", Value(roughness)}});
}

// Outgoing radiance of a lit point, from the glTF BRDF (Appendix B) and KHR_materials_sheen's
// implementation notes written out here: Lambert and GGX with Schlick's Fresnel for the base,
// the Charlie lobe for the sheen, the base scaled by min(1 - max3(sheen) E(N.V), 1 - max3(sheen)
// E(N.L)); the ambient (radiance arriving evenly) reflected by the base's albedo and by the
// sheen's E(N.V), the base's share scaled by E(N.V) alone.
glm::vec3 sheenRadiance(const SheenInputs& in, glm::vec3 N, glm::vec3 V, glm::vec3 L,
                        float radiance, float ambient) {
  const float NdotV = std::max(glm::dot(N, V), 1e-4f), NdotL = glm::dot(N, L);
  const float strength = std::max(in.sheenColor.r, std::max(in.sheenColor.g, in.sheenColor.b));
  const float albedoV = sheenAlbedo(NdotV, in.sheenRoughness);
  glm::vec3 out = ambient * (in.base * (1.0f - strength * albedoV) + in.sheenColor * albedoV);
  if (NdotL <= 0.0f) return out;
  const glm::vec3 H = glm::normalize(L + V);
  const float NdotH = std::max(glm::dot(N, H), 0.0f), VdotH = std::max(glm::dot(V, H), 0.0f);
  const float alpha = in.roughness * in.roughness, a2 = alpha * alpha;
  const float f = 0.04f + 0.96f * std::pow(1.0f - VdotH, 5.0f);
  const float d = a2 / (kPi * std::pow(NdotH * NdotH * (a2 - 1.0f) + 1.0f, 2.0f));
  const float vis = 0.5f / (NdotL * std::sqrt(NdotV * NdotV * (1.0f - a2) + a2) +
                            NdotV * std::sqrt(NdotL * NdotL * (1.0f - a2) + a2));
  const glm::vec3 base = (1.0f - f) * in.base / kPi + glm::vec3(f * d * vis);
  const double alphaG = std::max(in.sheenRoughness * in.sheenRoughness, kMinSheenAlpha);
  const float sheen = static_cast<float>(charlieDistribution(NdotH, alphaG) *
                                         charlieVisibility(NdotV, NdotL, alphaG));
  const float scaling =
      std::min(1.0f - strength * albedoV, 1.0f - strength * sheenAlbedo(NdotL, in.sheenRoughness));
  return out + (base * scaling + in.sheenColor * sheen) * radiance * NdotL;
}

// A floor with a sheen, seen at grazing angles under a low sun from behind the camera (where
// a velvet's sheen shows: the half vector near the surface), with an ambient: every pixel of the
// floor is the radiance the formulas above give for its own view direction, within 1%, in the
// beauty pass and in the AOV pass. Without the sheen the same pixels are darker by far more than
// that, so the check can fail.
TEST(SheenRender, MatchesTheExtensionsBrdfAtEveryPixel) {
  test_support::TempFolder folder("omnishadow-sheen-render");
  const SheenInputs in;
  GltfBuilder builder;
  MaterialDesc material;
  material.baseColor = glm::vec4(in.base, 1.0f);
  material.roughness = in.roughness;
  PrimitiveOptions options;
  options.material = builder.addMaterial(material);
  builder.model().materials[0].extensions["KHR_materials_sheen"] =
      sheenExtension(in.sheenColor, in.sheenRoughness);
  builder.model().extensionsUsed = {"KHR_materials_sheen"};
  builder.addNode("floor", {}, builder.addMesh(builder::makePlane(4.0f), options));
  const fs::path file = folder / "floor.gltf";
  builder.write(file, FileFormat::GltfEmbedded);
  const Scene scene = loadGltf(file);
  ASSERT_TRUE(scene.warnings.empty()) << scene.warnings.front();
  ASSERT_TRUE(hasSheen(scene.materials[0]));

  const glm::vec3 towardsSun = glm::normalize(glm::vec3(0.3f, 0.35f, 1.0f));
  Light sun = sunAlong(-towardsSun, 3.0f);
  sun.shadow.enabled = false;
  const float ambient = 0.2f;
  const glm::vec3 eye(0.0f, 1.5f, 4.5f);
  const ViewCamera camera = lookFrom(scene, eye, {0, 0, 0}, 48, 32, 30.0f);
  SheenInputs none = in;
  none.sheenColor = glm::vec3(0.0f);
  const glm::vec3 N(0, 1, 0);
  for (const bool aovs : {true, false}) {
    const auto [frame, withAovs] = renderFloorFrame(scene, sun, ambient, camera, aovs);
    int sheenShows = 0;
    const int checked = expectFloorPixels(
        frame, *withAovs.aovs, eye,
        [&](glm::vec3 V) { return sheenRadiance(in, N, V, towardsSun, 3.0f, ambient); },
        [&](glm::vec3 V) { return sheenRadiance(none, N, V, towardsSun, 3.0f, ambient); },
        sheenShows, aovs ? "AOV pass" : "beauty pass");
    EXPECT_GT(checked, 300);
    EXPECT_GT(sheenShows, checked / 2);
  }
}

// A floor of a dielectric material with `sheen` as its KHR_materials_sheen (none when null),
// `texel` its one texture's RGBA.
Scene sheenFloor(const fs::path& file, const Value* sheen, const std::vector<std::uint8_t>& texel) {
  GltfBuilder builder;
  const int texture = builder.addTexture(1, 1, texel, "sheen");
  MaterialDesc material;
  material.baseColor = {0.5f, 0.3f, 0.2f, 1.0f};
  material.roughness = 0.6f;
  PrimitiveOptions options;
  options.material = builder.addMaterial(material);
  if (sheen) {
    Value extension = *sheen;
    if (extension.Has("sheenColorTexture") || extension.Has("sheenRoughnessTexture"))
      for (const char* slot : {"sheenColorTexture", "sheenRoughnessTexture"})
        extension.Get<Value::Object>()[slot] = Value(Value::Object{{"index", Value(texture)}});
    builder.model().materials[0].extensions["KHR_materials_sheen"] = extension;
    builder.model().extensionsUsed = {"KHR_materials_sheen"};
  }
  builder.addNode("floor", {}, builder.addMesh(builder::makePlane(4.0f), options));
  builder.write(file, FileFormat::GltfEmbedded);
  Scene scene = loadGltf(file);
  EXPECT_TRUE(scene.warnings.empty()) << scene.warnings.front();
  return scene;
}

// A sheen texture holds the color in RGB (sRGB) and the roughness in A (linear), one image for
// both slots: a floor so textured draws as the floor whose factors are the products. A sheen
// color of zero draws exactly the material without the extension.
TEST(SheenRender, TextureChannelsMultiplyTheFactorsAndZeroColorIsNoSheen) {
  test_support::TempFolder folder("omnishadow-sheen-texture");
  const std::vector<std::uint8_t> texel = {200, 128, 64, 153};  // roughness x 0.6
  Value textured = sheenExtension({1.0f, 0.5f, 1.0f}, 0.8f);
  textured.Get<Value::Object>()["sheenColorTexture"] = Value(Value::Object{});
  const Value factors = sheenExtension(
      glm::vec3(srgbToLinear(200), 0.5f * srgbToLinear(128), srgbToLinear(64)), 0.8f * 0.6f);
  const Value zero = sheenExtension(glm::vec3(0.0f), 0.7f);
  const Value* extensions[4] = {&textured, &factors, &zero, nullptr};

  const glm::vec3 towardsSun = glm::normalize(glm::vec3(0.2f, 0.3f, 1.0f));
  Light sun = sunAlong(-towardsSun, 3.0f);
  sun.shadow.enabled = false;
  std::vector<Frame> frames;
  for (int i = 0; i < 4; ++i) {
    const Scene scene =
        sheenFloor(folder / ("floor" + std::to_string(i) + ".gltf"), extensions[i], texel);
    const ViewCamera camera = lookFrom(scene, {0, 1.5f, 4.5f}, {0, 0, 0}, 32, 32, 30.0f);
    frames.push_back(render(scene, {sun}, camera));
  }
  int floorPixels = 0;
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x) {
      if (frames[3].beauty.at(x, y, 3) < 1.0f) continue;  // not all floor
      for (int c = 0; c < 3; ++c) {
        const float fromFactors = frames[1].beauty.at(x, y, c);
        EXPECT_NEAR(frames[0].beauty.at(x, y, c), fromFactors, 0.01f * fromFactors + 1e-5f)
            << "pixel " << x << "," << y << " channel " << c;
        // Zero color against no extension: the same program, the same inputs, the same bits.
        EXPECT_EQ(frames[2].beauty.at(x, y, c), frames[3].beauty.at(x, y, c))
            << "pixel " << x << "," << y << " channel " << c;
      }
      if (frames[1].beauty.at(x, y, 0) > 1.1f * frames[3].beauty.at(x, y, 0)) ++floorPixels;
    }
  EXPECT_GT(floorPixels, 100);  // where the sheen shows: the texture's check could fail there
}

// Real data: the WhackAMole sample's body and teeth have a white sheen (roughness 0.4 and 0.7),
// its other materials none. Rendered as loaded and with the sheens' colors set to zero: every
// pixel of another opaque material is the same bits, and on the body the sheen is a grazing-angle
// effect: where the body turns away from the camera it gains far more light than where it faces
// the camera, which the base's albedo scaling leaves a little darker than without the sheen.
TEST(SheenRender, WhackAMoleSheenChangesItsMaterialsAloneAndShowsAtGrazingAngles) {
  const fs::path path =
      fs::path(OMNISHADOW_SOURCE_DIR) / "scenes/thirdparty/WhackAMole/WhackAMole.glb";
  const Scene scene = loadGltf(path);
  Scene plain = scene;
  int sheens = 0;
  for (Material& m : plain.materials) {
    sheens += hasSheen(m) ? 1 : 0;
    m.sheenColorFactor = glm::vec3(0.0f);
  }
  ASSERT_EQ(sheens, 2);
  Light key;
  key.name = "key";
  key.type = LightType::Point;
  key.position = {0.25f, 0.5f, 0.15f};
  key.intensity = 0.6f;
  key.shadow.near = 0.01f;
  key.shadow.far = 3.0f;
  const glm::vec3 eye(0.066f, 0.21f, -0.35f);
  const ViewCamera camera = lookFrom(scene, eye, {0, 0.02f, 0}, 160, 120, 20.0f);
  RenderSettings settings;
  settings.aovs = true;
  settings.layers.materialId = true;
  StageTimes times;
  const Frame with =
      sharedRenderer().render(scene, {key}, glm::vec3(0.02f), camera, settings, times);
  const Frame without =
      sharedRenderer().render(plain, {key}, glm::vec3(0.02f), camera, settings, times);
  const FloatImage& aovs = *with.aovs;
  const int materialChannel = aovs.channelIndex("materialId");
  const int normalChannel = aovs.channelIndex("N.X");
  ASSERT_GE(materialChannel, 0);
  int others = 0, facing = 0, grazing = 0;
  double facingRatio = 0.0, grazingRatio = 0.0;
  for (int y = 0; y < aovs.height; ++y)
    for (int x = 0; x < aovs.width; ++x) {
      const int material = static_cast<int>(aovs.at(x, y, materialChannel));
      if (material < 0) continue;
      const std::string& name = scene.materials[static_cast<std::size_t>(material)].name;
      if (name != "Body") {
        if (name == "Teeth" || name == "HillTransition") continue;  // a sheen; blended
        for (int c = 0; c < 3; ++c)
          EXPECT_EQ(with.beauty.at(x, y, c), without.beauty.at(x, y, c))
              << name << " pixel " << x << "," << y;
        ++others;
        continue;
      }
      const glm::vec3 N(aovs.at(x, y, normalChannel), aovs.at(x, y, normalChannel + 1),
                        aovs.at(x, y, normalChannel + 2));
      const glm::vec3 V = glm::normalize(eye - worldAt(aovs, x, y));
      const float NdotV = glm::dot(N, V);
      const double ratio = (with.beauty.at(x, y, 0) + with.beauty.at(x, y, 1) + 1e-6) /
                           (without.beauty.at(x, y, 0) + without.beauty.at(x, y, 1) + 1e-6);
      if (NdotV > 0.9f) {
        facingRatio += ratio;
        ++facing;
      } else if (NdotV < 0.3f) {
        grazingRatio += ratio;
        ++grazing;
      }
    }
  ASSERT_GT(facing, 50);
  ASSERT_GT(grazing, 50);
  EXPECT_GT(others, 5000);
  facingRatio /= facing;
  grazingRatio /= grazing;
  // Measured: 0.89 over 140 pixels facing the camera, 1.94 over 112 grazing ones.
  EXPECT_LT(facingRatio, 1.0);
  EXPECT_GT(grazingRatio, 1.5);
}

// The clearcoat tests' material: a dielectric base with an emission, and its layer.
struct ClearcoatInputs {
  glm::vec3 base{0.5f, 0.3f, 0.2f};
  float roughness = 0.6f;
  glm::vec3 emissive{0.05f, 0.02f, 0.0f};
  float clearcoat = 0.8f;
  float clearcoatRoughness = 0.3f;
};

// Appendix B's GGX distribution times its height-correlated visibility.
float ggxLobe(float NdotH, float NdotV, float NdotL, float alpha) {
  const float a2 = alpha * alpha;
  const float d = a2 / (kPi * std::pow(NdotH * NdotH * (a2 - 1.0f) + 1.0f, 2.0f));
  return d * 0.5f /
         (NdotL * std::sqrt(NdotV * NdotV * (1.0f - a2) + a2) +
          NdotV * std::sqrt(NdotL * NdotL * (1.0f - a2) + a2));
}

// Outgoing radiance of a lit point from the glTF BRDF (Appendix B) with KHR_materials_clearcoat
// as its implementation notes write it, here: the layer's weight clearcoat x Fresnel(0.04,
// |Nc.V|); the base (light, emission and ambient) keeps 1 - weight; the layer adds its GGX lobe
// for the light and reflects the ambient with its weight.
glm::vec3 clearcoatRadiance(const ClearcoatInputs& in, glm::vec3 N, glm::vec3 Nc, glm::vec3 V,
                            glm::vec3 L, float radiance, float ambient) {
  const float weight =
      in.clearcoat * (0.04f + 0.96f * std::pow(1.0f - std::abs(glm::dot(Nc, V)), 5.0f));
  glm::vec3 below = ambient * in.base + in.emissive;
  const float NdotV = std::max(glm::dot(N, V), 1e-4f), NdotL = glm::dot(N, L);
  const glm::vec3 H = glm::normalize(L + V);
  if (NdotL > 0.0f) {
    const float VdotH = std::max(glm::dot(V, H), 0.0f);
    const float f = 0.04f + 0.96f * std::pow(1.0f - VdotH, 5.0f);
    const float alpha = in.roughness * in.roughness;
    below += ((1.0f - f) * in.base / kPi +
              glm::vec3(f * ggxLobe(std::max(glm::dot(N, H), 0.0f), NdotV, NdotL, alpha))) *
             radiance * NdotL;
  }
  glm::vec3 out = below * (1.0f - weight) + glm::vec3(weight * ambient);
  const float NcL = glm::dot(Nc, L);
  if (NcL > 0.0f) {
    const float alpha = std::max(in.clearcoatRoughness * in.clearcoatRoughness, 1e-3f);
    out += glm::vec3(
        weight *
        ggxLobe(std::max(glm::dot(Nc, H), 0.0f), std::max(glm::dot(Nc, V), 1e-4f), NcL, alpha) *
        radiance * NcL);
  }
  return out;
}

// A 4 m floor of `material` with `extension` as its `name` extension (none when null), and a
// 1x1 texture of `texel` (RGBA, linear) the extension may name as texture 0.
Scene floorWith(const fs::path& file, const MaterialDesc& material, const char* name,
                const Value* extension, const std::vector<std::uint8_t>& texel) {
  GltfBuilder builder;
  builder.addTexture(1, 1, texel, "extension");
  PrimitiveOptions options;
  options.material = builder.addMaterial(material);
  if (extension) {
    builder.model().materials[0].extensions[name] = *extension;
    builder.model().extensionsUsed = {name};
  }
  builder.addNode("floor", {}, builder.addMesh(builder::makePlane(4.0f), options));
  builder.write(file, FileFormat::GltfEmbedded);
  Scene scene = loadGltf(file);
  EXPECT_TRUE(scene.warnings.empty()) << scene.warnings.front();
  return scene;
}

// A 4 m floor of the clearcoat tests' base material with `clearcoat` as its
// KHR_materials_clearcoat (none when null), and a texture of `texel` (RGBA, linear) that the
// extension's texture slots may name as texture 0.
Scene clearcoatFloor(const fs::path& file, const ClearcoatInputs& in, const Value* clearcoat,
                     const std::vector<std::uint8_t>& texel = {255, 255, 255, 255}) {
  MaterialDesc material;
  material.baseColor = glm::vec4(in.base, 1.0f);
  material.roughness = in.roughness;
  material.emissive = in.emissive;
  return floorWith(file, material, "KHR_materials_clearcoat", clearcoat, texel);
}

Value clearcoatExtension(float factor, float roughness) {
  return Value(Value::Object{{"clearcoatFactor", Value(factor)},
                             {"clearcoatRoughnessFactor", Value(roughness)}});
}

// A clearcoated floor seen at grazing angles with the sun behind it (where the layer's Fresnel
// and its mirror-like lobe show), with an ambient and an emission: every pixel is the radiance
// the formulas above give for its own view direction, within 1%, in the beauty and the AOV pass;
// most pixels differ from the uncoated floor's by more than 10%, so the check can fail.
TEST(ClearcoatRender, MatchesTheExtensionsLayeringAtEveryPixel) {
  test_support::TempFolder folder("omnishadow-clearcoat-render");
  const ClearcoatInputs in;
  const Value extension = clearcoatExtension(in.clearcoat, in.clearcoatRoughness);
  const Scene scene = clearcoatFloor(folder / "floor.gltf", in, &extension);
  ASSERT_TRUE(hasClearcoat(scene.materials[0]));
  const glm::vec3 towardsSun = glm::normalize(glm::vec3(0.1f, 0.35f, -1.0f));
  Light sun = sunAlong(-towardsSun, 3.0f);
  sun.shadow.enabled = false;
  const float ambient = 0.2f;
  const glm::vec3 eye(0.0f, 1.5f, 4.5f), N(0, 1, 0);
  const ViewCamera camera = lookFrom(scene, eye, {0, 0, 0}, 48, 32, 30.0f);
  ClearcoatInputs none = in;
  none.clearcoat = 0.0f;
  for (const bool aovs : {true, false}) {
    const auto [frame, withAovs] = renderFloorFrame(scene, sun, ambient, camera, aovs);
    int changed = 0;
    const int checked = expectFloorPixels(
        frame, *withAovs.aovs, eye,
        [&](glm::vec3 V) { return clearcoatRadiance(in, N, N, V, towardsSun, 3.0f, ambient); },
        [&](glm::vec3 V) { return clearcoatRadiance(none, N, N, V, towardsSun, 3.0f, ambient); },
        changed, aovs ? "AOV pass" : "beauty pass");
    EXPECT_GT(checked, 300);
    EXPECT_GT(changed, checked / 2);
  }
}

// The layer's textures: R of clearcoatTexture and G of clearcoatRoughnessTexture multiply the
// factors (one linear image in both slots draws as the products), a clearcoatNormalTexture tilts
// the layer alone (the formulas with the tilted normal for the layer and the flat one for the
// base, tangents generated from the floor's UVs), and a factor of zero draws exactly the
// material without the extension.
TEST(ClearcoatRender, TexturesMultiplyTheFactorsAndTheNormalTextureTiltsTheLayerAlone) {
  test_support::TempFolder folder("omnishadow-clearcoat-textures");
  const ClearcoatInputs in;
  const std::vector<std::uint8_t> texel = {204, 153, 0, 255};  // clearcoat x 0.8, roughness x 0.6
  Value textured = clearcoatExtension(1.0f, 0.5f);
  for (const char* slot : {"clearcoatTexture", "clearcoatRoughnessTexture"})
    textured.Get<Value::Object>()[slot] = Value(Value::Object{{"index", Value(0)}});
  const Value factors = clearcoatExtension(204.0f / 255.0f, 0.5f * 153.0f / 255.0f);
  // A normal texture tilted towards +u (the floor's +x): (0.3, 0, 1) normalized, as bytes.
  const std::vector<std::uint8_t> normalTexel = {166, 128, 246, 255};
  Value tilted = clearcoatExtension(in.clearcoat, in.clearcoatRoughness);
  tilted.Get<Value::Object>()["clearcoatNormalTexture"] = Value(Value::Object{{"index", Value(0)}});
  const Value zero = clearcoatExtension(0.0f, 0.7f);

  const glm::vec3 towardsSun = glm::normalize(glm::vec3(0.1f, 0.35f, -1.0f));
  Light sun = sunAlong(-towardsSun, 3.0f);
  sun.shadow.enabled = false;
  const float ambient = 0.2f;
  const glm::vec3 eye(0.0f, 1.5f, 4.5f), N(0, 1, 0);
  const auto renderFloor = [&](const std::string& name, const Value* extension,
                               const std::vector<std::uint8_t>& pixel) {
    const Scene scene = clearcoatFloor(folder / (name + ".gltf"), in, extension, pixel);
    const ViewCamera camera = lookFrom(scene, eye, {0, 0, 0}, 48, 32, 30.0f);
    return test_support::renderWithAovs(scene, {sun}, camera, {}, glm::vec3(ambient));
  };
  const Frame fromTextures = renderFloor("textured", &textured, texel);
  const Frame fromFactors = renderFloor("factors", &factors, texel);
  const Frame fromZero = renderFloor("zero", &zero, texel);
  const Frame plain = renderFloor("plain", nullptr, texel);
  int coated = 0;
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 48; ++x) {
      if (plain.beauty.at(x, y, 3) < 1.0f) continue;  // not all floor
      for (int c = 0; c < 3; ++c) {
        const float expected = fromFactors.beauty.at(x, y, c);
        EXPECT_NEAR(fromTextures.beauty.at(x, y, c), expected, 0.01f * expected + 1e-5f)
            << "pixel " << x << "," << y << " channel " << c;
        EXPECT_EQ(fromZero.beauty.at(x, y, c), plain.beauty.at(x, y, c))
            << "pixel " << x << "," << y << " channel " << c;
      }
      if (std::abs(fromFactors.beauty.at(x, y, 0) - plain.beauty.at(x, y, 0)) >
          0.1f * plain.beauty.at(x, y, 0))
        ++coated;
    }
  EXPECT_GT(coated, 100);  // where the layer shows: the texture check could fail there

  // The tilted layer, against the formulas with its normal as the shader decodes the texel.
  const Frame frame = renderFloor("tilted", &tilted, normalTexel);
  const glm::vec3 tangentNormal =
      glm::vec3(normalTexel[0], normalTexel[1], normalTexel[2]) / 255.0f * 2.0f - 1.0f;
  // Tangent +x (along u), bitangent -z (up the image: glTF's v runs down it), normal +y.
  const glm::vec3 Nc =
      glm::normalize(glm::vec3(tangentNormal.x, tangentNormal.z, -tangentNormal.y));
  int changed = 0;
  const int checked = expectFloorPixels(
      frame, *frame.aovs, eye,
      [&](glm::vec3 V) { return clearcoatRadiance(in, N, Nc, V, towardsSun, 3.0f, ambient); },
      [&](glm::vec3 V) { return clearcoatRadiance(in, N, N, V, towardsSun, 3.0f, ambient); },
      changed, "tilted layer");
  EXPECT_GT(checked, 300);
  EXPECT_GT(changed, 20);
}

// A frame whose shadow filters take most texture units (hard, pcf and vsm point lights in four
// groups, and a pcss spot light: five sampler families of four units) leaves too few after them
// for a material with many extension textures, which then draws those layers from their
// factors. Its shadows are the same there with a floor that has seven extension textures
// (clearcoat's three, specular's two, a sheen color and a roughness of its own) as with a plain
// one: no material texture is bound over a shadow map.
TEST(ClearcoatRender, AFrameWhoseShadowsTakeEveryUnitKeepsItsShadows) {
  test_support::TempFolder folder("omnishadow-clearcoat-units");
  const ClearcoatInputs in;
  Value textured = clearcoatExtension(1.0f, 0.5f);
  for (const char* slot :
       {"clearcoatTexture", "clearcoatRoughnessTexture", "clearcoatNormalTexture"})
    textured.Get<Value::Object>()[slot] = Value(Value::Object{{"index", Value(0)}});
  std::vector<Light> lights;
  const struct {
    ShadowFilter filter;
    int resolution;
  } rig[] = {{ShadowFilter::Hard, 64},
             {ShadowFilter::Pcf, 128},
             {ShadowFilter::Vsm, 64},
             {ShadowFilter::Pcf, 256}};
  for (std::size_t i = 0; i < std::size(rig); ++i) {
    Light point;
    point.name = "point" + std::to_string(i);
    point.type = LightType::Point;
    point.position = {-1.5f + static_cast<float>(i), 1.2f, 0.3f};
    point.intensity = 2.0f;
    point.shadow.filter = rig[i].filter;
    point.shadow.resolution = rig[i].resolution;
    lights.push_back(point);
  }
  Light spot;
  spot.name = "spot";
  spot.type = LightType::Spot;
  spot.position = {0.0f, 2.0f, 1.0f};
  spot.direction = glm::normalize(glm::vec3(0.0f, -1.0f, -0.3f));
  spot.intensity = 5.0f;
  spot.shadow.filter = ShadowFilter::Pcss;
  lights.push_back(spot);
  LightingFeatures features = lightingFeatures(lights, DebugView::None);
  features.shadowSlots = 4;
  // Too few units after the shadow arrays for the coated floor's seven extension textures.
  ASSERT_GT(shadowSamplerUnits(features).end + 7, contract::kTextureUnits);

  std::vector<Frame> frames;
  for (const Value* extension :
       {static_cast<const Value*>(&textured), static_cast<const Value*>(nullptr)}) {
    GltfBuilder builder;
    builder.addTexture(1, 1, {200, 100, 250, 255}, "clearcoat");
    const int other = builder.addTexture(1, 1, {50, 150, 100, 60}, "other");
    MaterialDesc material;
    material.baseColor = glm::vec4(in.base, 1.0f);
    PrimitiveOptions options;
    options.material = builder.addMaterial(material);
    if (extension) {
      // Every extension texture: the clearcoat's three, the specular's two and a sheen
      // roughness of another image than its color's.
      auto& extensions = builder.model().materials[0].extensions;
      extensions["KHR_materials_clearcoat"] = *extension;
      const auto info = [](int index) { return Value(Value::Object{{"index", Value(index)}}); };
      extensions["KHR_materials_specular"] =
          Value(Value::Object{{"specularTexture", info(other)}, {"specularColorTexture", info(0)}});
      Value sheen = sheenExtension({0.5f, 0.5f, 0.5f}, 0.5f);
      sheen.Get<Value::Object>()["sheenColorTexture"] = info(0);
      sheen.Get<Value::Object>()["sheenRoughnessTexture"] = info(other);
      extensions["KHR_materials_sheen"] = sheen;
      builder.model().extensionsUsed = {"KHR_materials_clearcoat", "KHR_materials_specular",
                                        "KHR_materials_sheen"};
    }
    builder.addNode("floor", {}, builder.addMesh(builder::makePlane(4.0f), options));
    builder.addNode("box", {glm::vec3(0.0f, 0.3f, 0.0f)},
                    builder.addMesh(builder::makeBox(glm::vec3(0.3f))));
    const fs::path file = folder / (extension ? "coated.gltf" : "plain.gltf");
    builder.write(file, FileFormat::GltfEmbedded);
    const Scene scene = loadGltf(file);
    frames.push_back(
        render(scene, lights, lookFrom(scene, {0, 3.5f, 3.5f}, {0, 0, 0}, 48, 32, 50.0f)));
  }
  const FloatImage& coated = *frames[0].aovs;
  const FloatImage& plain = *frames[1].aovs;
  int shadowed = 0;
  for (const Light& light : lights) {
    const int channel = plain.channelIndex("visibility." + light.name);
    ASSERT_GE(channel, 0) << light.name;
    for (int y = 0; y < 32; ++y)
      for (int x = 0; x < 48; ++x) {
        EXPECT_EQ(coated.at(x, y, channel), plain.at(x, y, channel))
            << light.name << " at " << x << "," << y;
        shadowed += plain.at(x, y, channel) < 0.5f ? 1 : 0;
      }
  }
  EXPECT_GT(shadowed, 20);  // the box shadows the floor: the check could fail
}

// KHR_materials_specular's textures: A of specularTexture and RGB (sRGB) of
// specularColorTexture multiply the factors, so a floor so textured draws as the floor whose
// factors are the products (N = L = V, in the PBR and the Phong shading); both differ from the
// floor without the extension by more than the tolerance, so the check can fail.
TEST(SpecularRender, TexturesMultiplyTheFactors) {
  test_support::TempFolder folder("omnishadow-specular-textures");
  const std::vector<std::uint8_t> texel = {255, 128, 64, 128};
  const Scene scene = floorsInARow(folder / "planes.gltf", {0, 0, 0}, [&](GltfBuilder& builder) {
    const int texture = builder.addTexture(1, 1, texel, "specular");
    const auto info = [&] { return Value(Value::Object{{"index", Value(texture)}}); };
    auto& materials = builder.model().materials;
    materials[0].extensions["KHR_materials_specular"] = Value(Value::Object{
        {"specularFactor", Value(0.8)},
        {"specularColorFactor", Value(Value::Array{Value(4.0), Value(2.0), Value(1.0)})},
        {"specularTexture", info()},
        {"specularColorTexture", info()}});
    const double weight = 0.8 * 128.0 / 255.0;
    materials[1].extensions["KHR_materials_specular"] = Value(Value::Object{
        {"specularFactor", Value(weight)},
        {"specularColorFactor",
         Value(Value::Array{Value(4.0 * srgbToLinear(255)), Value(2.0 * srgbToLinear(128)),
                            Value(1.0 * srgbToLinear(64))})}});
    builder.model().extensionsUsed = {"KHR_materials_specular"};
  });
  for (const Shading shading : {Shading::Pbr, Shading::Phong}) {
    const Frame frame = renderFloorsFromAbove(scene, shading);
    for (int c = 0; c < 3; ++c) {
      const float fromFactors = frame.beauty.at(48, 16, c), plain = frame.beauty.at(80, 16, c);
      EXPECT_NEAR(frame.beauty.at(16, 16, c), fromFactors, 0.01f * fromFactors)
          << "channel " << c << (shading == Shading::Pbr ? " (PBR)" : " (Phong)");
      EXPECT_GT(std::abs(fromFactors - plain), 0.03f * plain)
          << "channel " << c << (shading == Shading::Pbr ? " (PBR)" : " (Phong)");
    }
  }
}

// A sheen roughness texture of another image than the sheen color's is read through a unit of
// its own: a floor so textured draws as the floor whose factors are the products.
TEST(SheenRender, ARoughnessTextureOfAnotherImageMultipliesItsFactor) {
  test_support::TempFolder folder("omnishadow-sheen-two-images");
  const glm::vec3 towardsSun = glm::normalize(glm::vec3(0.2f, 0.3f, 1.0f));
  Light sun = sunAlong(-towardsSun, 3.0f);
  sun.shadow.enabled = false;
  std::vector<Frame> frames;
  // Textured; the products as factors; the roughness texture left out (what not reading it draws).
  for (const int kind : {0, 1, 2}) {
    const bool textured = kind != 1;
    GltfBuilder builder;
    const int color = builder.addTexture(1, 1, {255, 255, 255, 255}, "color");
    const int roughness = builder.addTexture(1, 1, {0, 0, 0, 51}, "roughness");  // x 0.2
    MaterialDesc material;
    material.baseColor = {0.5f, 0.3f, 0.2f, 1.0f};
    material.roughness = 0.6f;
    PrimitiveOptions options;
    options.material = builder.addMaterial(material);
    Value sheen = sheenExtension({0.9f, 0.6f, 0.3f}, textured ? 1.0f : 0.2f);
    if (textured) {
      sheen.Get<Value::Object>()["sheenColorTexture"] =
          Value(Value::Object{{"index", Value(color)}});
      if (kind == 0)
        sheen.Get<Value::Object>()["sheenRoughnessTexture"] =
            Value(Value::Object{{"index", Value(roughness)}});
    }
    builder.model().materials[0].extensions["KHR_materials_sheen"] = sheen;
    builder.model().extensionsUsed = {"KHR_materials_sheen"};
    builder.addNode("floor", {}, builder.addMesh(builder::makePlane(4.0f), options));
    const fs::path file = folder / ("floor" + std::to_string(kind) + ".gltf");
    builder.write(file, FileFormat::GltfEmbedded);
    const Scene scene = loadGltf(file);
    ASSERT_TRUE(scene.warnings.empty()) << scene.warnings.front();
    frames.push_back(
        render(scene, {sun}, lookFrom(scene, {0, 1.5f, 4.5f}, {0, 0, 0}, 32, 32, 30.0f)));
  }
  int floorPixels = 0, readShows = 0;
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x) {
      if (frames[1].beauty.at(x, y, 3) < 1.0f) continue;
      ++floorPixels;
      for (int c = 0; c < 3; ++c) {
        const float expected = frames[1].beauty.at(x, y, c);
        EXPECT_NEAR(frames[0].beauty.at(x, y, c), expected, 0.01f * expected + 1e-5f)
            << "pixel " << x << "," << y << " channel " << c;
      }
      if (std::abs(frames[2].beauty.at(x, y, 0) - frames[1].beauty.at(x, y, 0)) >
          0.03f * frames[1].beauty.at(x, y, 0))
        ++readShows;
    }
  EXPECT_GT(floorPixels, 100);
  EXPECT_GT(readShows, floorPixels / 4);  // where not reading the texture would show
}

// KHR_materials_transmission, drawn see-through (thin-walled). The tests' glass: a 4 m pane at
// y = 0 of `in`, over a 12 m floor at y = -1 of `floorColor` (none when its alpha is 0), both
// single-sided and facing up; `extend` changes the file before it is written.
struct GlassInputs {
  glm::vec3 base{0.9f, 0.7f, 0.5f};
  float roughness = 0.5f;
  float transmission = 1.0f;
  float ior = 1.5f;
};

Scene glassOverFloor(const fs::path& file, const GlassInputs& in, glm::vec4 floorColor,
                     const std::function<void(GltfBuilder&)>& extend = {}) {
  GltfBuilder builder;
  MaterialDesc glass;
  glass.baseColor = glm::vec4(in.base, 1.0f);
  glass.roughness = in.roughness;
  PrimitiveOptions options;
  options.material = builder.addMaterial(glass);
  Value::Object transmission{{"transmissionFactor", Value(in.transmission)}};
  builder.model().materials[0].extensions["KHR_materials_transmission"] =
      Value(std::move(transmission));
  builder.model().extensionsUsed = {"KHR_materials_transmission"};
  if (in.ior != 1.5f) {
    builder.model().materials[0].extensions["KHR_materials_ior"] =
        Value(Value::Object{{"ior", Value(in.ior)}});
    builder.model().extensionsUsed.push_back("KHR_materials_ior");
  }
  builder.addNode("glass", {}, builder.addMesh(builder::makePlane(4.0f), options));
  if (floorColor.a > 0.0f) {
    MaterialDesc floor;
    floor.baseColor = floorColor;
    floor.roughness = 1.0f;
    options.material = builder.addMaterial(floor);
    builder.addNode("floor", {glm::vec3(0.0f, -1.0f, 0.0f)},
                    builder.addMesh(builder::makePlane(12.0f), options));
  }
  if (extend) extend(builder);
  builder.write(file, FileFormat::GltfEmbedded);
  Scene scene = loadGltf(file);
  EXPECT_TRUE(scene.warnings.empty()) << scene.warnings.front();
  return scene;
}

// Schlick's Fresnel of F0 0.04 (ior 1.5) at cos `c`.
float fresnel004(float c) {
  return 0.04f + 0.96f * std::pow(1.0f - std::clamp(c, 0.0f, 1.0f), 5.0f);
}

// A sun below a clear-ish glass pane seen from above, across it (nothing but a black floor
// behind): every pixel is the light the specification's thin-walled BTDF lets through towards
// the camera (a GGX lobe of (roughness x clamp(2 ior - 2, 0, 1))^2 around the straight line
// through the pane), times transmission x base color x what Fresnel towards the camera leaves,
// within 1%, in the beauty and the AOV pass; with a transmission of 0 the pane is black there.
TEST(TransmissionRender, ALightBehindThePaneShinesThroughItAsTheBtdfSays) {
  test_support::TempFolder folder("omnishadow-transmission-btdf");
  const GlassInputs in;
  const Scene scene = glassOverFloor(folder / "glass.gltf", in, glm::vec4(0, 0, 0, 1));
  ASSERT_TRUE(hasTransmission(scene.materials[0]));
  const glm::vec3 towardsSun = glm::normalize(glm::vec3(-0.1f, -0.35f, -1.0f));
  Light sun = sunAlong(-towardsSun, 3.0f);
  sun.shadow.enabled = false;
  const glm::vec3 eye(0.0f, 1.5f, 4.5f), N(0, 1, 0);
  const ViewCamera camera = lookFrom(scene, eye, {0, 0, 0}, 48, 32, 30.0f);
  const auto through = [&](glm::vec3 V, float transmission) {
    const float NdotL = glm::dot(N, towardsSun);
    const glm::vec3 mirrored = towardsSun - 2.0f * NdotL * N;
    const float alpha = in.roughness * in.roughness;
    const float lobe = ggxLobe(std::max(glm::dot(N, glm::normalize(mirrored + V)), 0.0f),
                               std::max(glm::dot(N, V), 1e-4f), -NdotL, alpha);
    return transmission * (1.0f - fresnel004(glm::dot(N, V))) * in.base * lobe * -NdotL * 3.0f;
  };
  for (const bool aovs : {true, false}) {
    const auto [frame, withAovs] = renderFloorFrame(scene, sun, 0.0f, camera, aovs);
    int changed = 0;
    const int checked = expectFloorPixels(
        frame, *withAovs.aovs, eye, [&](glm::vec3 V) { return through(V, 1.0f); },
        [&](glm::vec3 V) { return through(V, 0.0f); }, changed, aovs ? "AOV pass" : "beauty pass");
    EXPECT_GT(checked, 300);
    EXPECT_GT(changed, checked / 2);
  }
}

// glassOverFloor seen straight down from 100 m, 0.4 m of the pane across 16 x 16 pixels: the
// sun to one side (no shadows), so that the pane's own highlight misses the camera.
struct StraightDown {
  glm::vec3 floorColor{0.2f, 0.5f, 0.3f};
  glm::vec3 towardsSun = glm::normalize(glm::vec3(0.5f, 1.0f, 0.0f));
  float ambient = 0.1f;

  Frame frame(const Scene& scene, const RenderSettings& settings = {}) const {
    Light sun = sunAlong(-towardsSun, 3.0f);
    sun.shadow.enabled = false;
    const glm::vec3 eye(0.0f, 100.0f, 0.0f);
    const ViewCamera camera = lookFrom(scene, eye, {0, 0, 0}, 16, 16,
                                       2.0f * glm::degrees(std::atan(0.2f / eye.y)), {0, 0, -1});
    StageTimes times;
    return sharedRenderer().render(scene, {sun}, glm::vec3(ambient), camera, settings, times);
  }
  // The floor alone, at the middle pixel (the pane's node left without its mesh).
  glm::vec3 floorPixel(const fs::path& folder) const {
    const Frame bare =
        frame(glassOverFloor(folder / "bare.gltf", GlassInputs{}, glm::vec4(floorColor, 1),
                             [](GltfBuilder& b) { b.model().nodes[0].mesh = -1; }));
    return {bare.beauty.at(8, 8, 0), bare.beauty.at(8, 8, 1), bare.beauty.at(8, 8, 2)};
  }
};

// The floor behind a pane, seen straight down through it: a clear pane shows the floor's pixel
// times transmission x base color x (1 - Fresnel); half the transmission shows half of that over
// half the pane's own diffuse; an opaque pane's pixel is its diffuse alone. Where nothing lies
// behind the pane, its coverage is 1 minus the fraction of the background it lets through.
TEST(TransmissionRender, ThePaneShowsTheFloorBehindItTintedAndCoversWhatItLetsThrough) {
  test_support::TempFolder folder("omnishadow-transmission-floor");
  const StraightDown view;
  const glm::vec3 floorColor = view.floorColor, towardsSun = view.towardsSun;
  const float ambient = view.ambient;
  GlassInputs clear;
  clear.roughness = 0.0f;
  const glm::vec3 floorPixel = view.floorPixel(folder.path());
  ASSERT_GT(floorPixel.g, 0.1f);
  const float NdotL = towardsSun.y;
  const float VdotH = glm::dot(glm::vec3(0, 1, 0), glm::normalize(towardsSun + glm::vec3(0, 1, 0)));
  for (const float transmission : {1.0f, 0.5f, 0.0f}) {
    GlassInputs in;
    in.roughness = 0.0f;
    in.transmission = transmission;
    const Frame frame = view.frame(glassOverFloor(
        folder / ("t" + std::to_string(transmission) + ".gltf"), in, glm::vec4(floorColor, 1)));
    const glm::vec3 diffuse =
        (1.0f - fresnel004(VdotH)) * in.base / kPi * 3.0f * NdotL + ambient * in.base;
    const glm::vec3 expected = (1.0f - transmission) * diffuse +
                               transmission * (1.0f - fresnel004(1.0f)) * in.base * floorPixel;
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(frame.beauty.at(8, 8, c), expected[c], 0.01f * expected[c])
          << "transmission " << transmission << " channel " << c;
    EXPECT_EQ(frame.beauty.at(8, 8, 3), 1.0f);
  }
  // Nothing behind: the pane covers 1 - transmission x (1 - F0) x mean(base color) of the pixel,
  // and its color holds no background.
  const Frame alone = view.frame(glassOverFloor(folder / "alone.gltf", clear, glm::vec4(0.0f)));
  const float letThrough =
      (1.0f - fresnel004(1.0f)) * (clear.base.r + clear.base.g + clear.base.b) / 3.0f;
  EXPECT_NEAR(alone.beauty.at(8, 8, 3), 1.0f - letThrough, 1e-3f);
  // The lighting pass cannot encode such a frame itself: it is drawn in float, which the caller
  // gets (FloatBeautyEncoding::Caller) or which is encoded after (the default), to the same bytes.
  const Scene behind = glassOverFloor(folder / "encoded.gltf", clear, glm::vec4(floorColor, 1));
  RenderSettings toCaller;
  toCaller.srgb8Exposure = 0.0f;
  toCaller.floatBeautyEncoding = FloatBeautyEncoding::Caller;
  const Frame linear = view.frame(behind, toCaller);
  EXPECT_FALSE(linear.srgb8.has_value());
  ASSERT_FALSE(linear.beauty.pixels.empty());
  RenderSettings srgb8;
  srgb8.srgb8Exposure = 0.0f;
  const Frame encoded = view.frame(behind, srgb8);
  ASSERT_TRUE(encoded.srgb8.has_value());
  EXPECT_TRUE(encoded.beauty.pixels.empty());
  EXPECT_EQ(encoded.srgb8->rgb, toSrgb8(linear.beauty, 0.0f));
}

// The floor seen straight down through two clear walls of glass (the scene `extend` makes of
// glassOverFloor's): (1 - F0)^2 x base^2 x the floor's pixel, within 1%. One wall alone would
// show (1 - F0) x base x the floor's pixel.
void expectTheFloorThroughTwoWalls(const std::string& name,
                                   const std::function<void(GltfBuilder&)>& extend) {
  test_support::TempFolder folder("omnishadow-transmission-" + name);
  const StraightDown view;
  GlassInputs clear;
  clear.roughness = 0.0f;
  const glm::vec3 floorPixel = view.floorPixel(folder.path());
  const Frame frame = view.frame(
      glassOverFloor(folder / (name + ".gltf"), clear, glm::vec4(view.floorColor, 1), extend));
  const glm::vec3 once = (1.0f - fresnel004(1.0f)) * clear.base;
  const glm::vec3 expected = once * once * floorPixel;
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(frame.beauty.at(8, 8, c), expected[c], 0.01f * expected[c]) << "channel " << c;
}

// Two clear panes, one half a metre over the other: the far pane is drawn first, over a copy of
// the floor, and the near one over a copy that holds it.
TEST(TransmissionRender, ClearPanesOneBehindTheOtherShowEachOther) {
  expectTheFloorThroughTwoWalls("stacked", [](GltfBuilder& b) {
    b.addNode("far glass", {glm::vec3(0.0f, -0.5f, 0.0f)}, b.model().nodes[0].mesh);
  });
}

// A thin-walled, double-sided glass box: its back faces are drawn first, the beauty copied,
// then its front faces, so that its top shows its bottom (a flat double-sided pane has one side
// to show).
TEST(TransmissionRender, AThinWalledBoxShowsItsFarSideThroughItsNearSide) {
  expectTheFloorThroughTwoWalls("box", [](GltfBuilder& b) {
    tinygltf::Model& model = b.model();
    model.materials[0].doubleSided = true;
    PrimitiveOptions options;
    options.material = 0;
    model.nodes[0].mesh = b.addMesh(builder::makeBox(glm::vec3(2.0f, 0.2f, 2.0f)), options);
    model.nodes[0].translation = {0.0, -0.5, 0.0};
  });
}

// Roughness blurs what shows through: across the seam of a red and a green floor, a rough pane's
// pixels near the seam mix both colors where a clear pane's stay one; with an ior of 1 the
// specification takes the roughness away, and the pane shows the seam sharp again.
TEST(TransmissionRender, RoughnessBlursWhatShowsThroughUnlessTheIorIsOne) {
  test_support::TempFolder folder("omnishadow-transmission-blur");
  // Tilted 35 degrees along the picture's short side, so that a clear pane's mirror image of
  // the sun lies outside the picture.
  Light sun = sunAlong(glm::normalize(glm::vec3(0.0f, -1.0f, 0.7f)), 3.0f);
  sun.shadow.enabled = false;
  const auto seamPixels = [&](const GlassInputs& in, const std::string& name) {
    const Scene scene =
        glassOverFloor(folder / (name + ".gltf"), in, glm::vec4(0.8f, 0, 0, 1), [](GltfBuilder& b) {
          MaterialDesc green;
          green.baseColor = glm::vec4(0, 0.8f, 0, 1);
          green.roughness = 1.0f;
          PrimitiveOptions options;
          options.material = b.addMaterial(green);
          b.addNode("green", {glm::vec3(3.0f, -0.999f, 0.0f)},
                    b.addMesh(builder::makePlane(6.0f), options));
        });
    const ViewCamera camera = lookFrom(scene, {0, 10, 0}, {0, 0, 0}, 64, 16, 20.0f, {0, 0, -1});
    StageTimes times;
    const Frame frame =
        sharedRenderer().render(scene, {sun}, glm::vec3(0.0f), camera, RenderSettings{}, times);
    int mixed = 0;  // pixels where both red and green show
    for (int x = 0; x < 64; ++x)
      if (frame.beauty.at(x, 8, 0) > 0.02f && frame.beauty.at(x, 8, 1) > 0.02f) ++mixed;
    return mixed;
  };
  GlassInputs rough;
  rough.roughness = 1.0f;
  GlassInputs clear = rough;
  clear.roughness = 0.0f;
  GlassInputs airy = rough;
  airy.ior = 1.0f;
  EXPECT_LE(seamPixels(clear, "clear"), 1);
  EXPECT_GE(seamPixels(rough, "rough"), 6);
  EXPECT_LE(seamPixels(airy, "airy"), 1);
}

// The pane is a surface for everything but its color: the AOVs give its point and normal, the
// ids its object; the Phong shading draws it as its base material (opaque); and a frame is the
// same bits every time it is drawn.
TEST(TransmissionRender, AovsAndIdsSeeThePaneAndPhongDrawsItOpaque) {
  test_support::TempFolder folder("omnishadow-transmission-aovs");
  GlassInputs in;
  const Scene scene = glassOverFloor(folder / "glass.gltf", in, glm::vec4(0.2f, 0.5f, 0.3f, 1));
  Light sun = sunAlong(glm::normalize(glm::vec3(-0.5f, -1.0f, 0.0f)), 3.0f);
  const ViewCamera camera = lookFrom(scene, {0, 5, 0}, {0, 0, 0}, 16, 16, 20.0f, {0, 0, -1});
  RenderSettings settings;
  settings.objectIds = true;
  const Frame frame = render(scene, {sun}, camera);
  ASSERT_TRUE(frame.aovs.has_value());
  EXPECT_NEAR(worldAt(*frame.aovs, 8, 8).y, 0.0f, 1e-4f);
  const Frame again = render(scene, {sun}, camera);
  EXPECT_EQ(frame.beauty.pixels, again.beauty.pixels);
  EXPECT_EQ(frame.aovs->pixels, again.aovs->pixels);
  StageTimes times;
  const Frame ids = sharedRenderer().render(scene, {sun}, glm::vec3(0.0f), camera, settings, times);
  ASSERT_TRUE(ids.objectIds.has_value());
  EXPECT_EQ(ids.objectIds->at(8, 8, 0), 0.0f);  // the pane, draw 0
  // Phong: the pane as if it had no extension (unshadowed: the two panes cast different
  // shadows, translucent and opaque).
  sun.shadow.enabled = false;
  settings = {};
  settings.shading = Shading::Phong;
  const Frame phong =
      sharedRenderer().render(scene, {sun}, glm::vec3(0.0f), camera, settings, times);
  const Scene plain =
      glassOverFloor(folder / "plain.gltf", in, glm::vec4(0.2f, 0.5f, 0.3f, 1), [](GltfBuilder& b) {
        b.model().materials[0].extensions.clear();
        b.model().extensionsUsed.clear();
      });
  const Frame plainPhong =
      sharedRenderer().render(plain, {sun}, glm::vec3(0.0f), camera, settings, times);
  EXPECT_EQ(phong.beauty.pixels, plainPhong.beauty.pixels);
}

// KHR_materials_volume on the pane of glassOverFloor(): thickness `thickness` (in the mesh's
// units), attenuation `distance` and `color`.
void addVolume(GltfBuilder& b, float thickness, float distance, glm::vec3 color) {
  b.model().materials[0].extensions["KHR_materials_volume"] = Value(Value::Object{
      {"thicknessFactor", Value(thickness)},
      {"attenuationDistance", Value(distance)},
      {"attenuationColor", Value(Value::Array{Value(color.r), Value(color.g), Value(color.b)})}});
  b.model().extensionsUsed.push_back("KHR_materials_volume");
}

// Straight down through a volume, the view ray does not bend, and what shows through loses
// attenuationColor^(thickness x the mesh's scale along the ray / attenuationDistance) (Beer's
// law, the mesh's thickness in its own units: the pane's node is scaled 3x along y); a
// thickness of 0 is the thin wall, bit for bit.
TEST(VolumeRender, WhatShowsThroughIsAttenuatedByBeersLawOverTheScaledThickness) {
  test_support::TempFolder folder("omnishadow-volume-attenuation");
  const glm::vec3 floorColor(0.2f, 0.5f, 0.3f), color(0.5f, 0.8f, 0.9f);
  Light sun = sunAlong(glm::normalize(glm::vec3(-0.5f, -1.0f, 0.0f)), 3.0f);
  sun.shadow.enabled = false;
  const glm::vec3 eye(0.0f, 100.0f, 0.0f);
  const auto frameOf = [&](const Scene& scene) {
    const ViewCamera camera = lookFrom(scene, eye, {0, 0, 0}, 16, 16,
                                       2.0f * glm::degrees(std::atan(0.2f / eye.y)), {0, 0, -1});
    StageTimes times;
    return sharedRenderer().render(scene, {sun}, glm::vec3(0.0f), camera, RenderSettings{}, times);
  };
  GlassInputs in;
  in.roughness = 0.0f;
  const auto scaled = [](GltfBuilder& b) { b.model().nodes[0].scale = {1.0, 3.0, 1.0}; };
  const Frame thin =
      frameOf(glassOverFloor(folder / "thin.gltf", in, glm::vec4(floorColor, 1), scaled));
  const Frame volume = frameOf(
      glassOverFloor(folder / "volume.gltf", in, glm::vec4(floorColor, 1), [&](GltfBuilder& b) {
        scaled(b);
        addVolume(b, 0.5f, 2.0f, color);
      }));
  for (int c = 0; c < 3; ++c) {
    const float expected = thin.beauty.at(8, 8, c) * std::pow(color[c], 0.5f * 3.0f / 2.0f);
    EXPECT_NEAR(volume.beauty.at(8, 8, c), expected, 0.01f * expected) << "channel " << c;
  }
  const Frame zero = frameOf(
      glassOverFloor(folder / "zero.gltf", in, glm::vec4(floorColor, 1), [&](GltfBuilder& b) {
        scaled(b);
        addVolume(b, 0.0f, 2.0f, color);
      }));
  EXPECT_EQ(zero.beauty.pixels, thin.beauty.pixels);
}

// The seam tests' slab: the glass pane of glassOverFloor() (clear, white) with a volume of
// `thickness`, over a floor of `near` for z < 0 and a 6 m plane of `far` for z > 0 just above it;
// `extend` adds to the file. Seen from kSeamEye in a 16x64 frame (seamCamera()).
constexpr glm::vec3 kSeamEye(0.0f, 3.0f, 3.0f);

Scene seamSlab(const fs::path& file, float thickness, glm::vec3 near, glm::vec3 far,
               const std::function<void(GltfBuilder&)>& extend = {}) {
  GlassInputs in;
  in.roughness = 0.0f;
  in.base = glm::vec3(1.0f);
  return glassOverFloor(file, in, glm::vec4(near, 1.0f), [&](GltfBuilder& b) {
    addVolume(b, thickness, 1000.0f, glm::vec3(1.0f));
    MaterialDesc material;
    material.baseColor = glm::vec4(far, 1.0f);
    material.roughness = 1.0f;
    PrimitiveOptions options;
    options.material = b.addMaterial(material);
    b.addNode("far", {glm::vec3(0.0f, -0.999f, 3.0f)},
              b.addMesh(builder::makePlane(6.0f), options));
    if (extend) extend(b);
  });
}

ViewCamera seamCamera(const Scene& scene) {
  return lookFrom(scene, kSeamEye, {0, 0, 0}, 16, 64, 50.0f);
}

// Whether the floor seen from kSeamEye through `through` (down to y = -1) lies past the seam.
bool pastTheSeam(glm::vec3 through) {
  const glm::vec3 d = through - kSeamEye;
  return (kSeamEye + d * ((-1.0f - kSeamEye.y) / d.y)).z > 0.0f;
}

// For each row of the frame's middle column whose view ray meets the pane away from its edges,
// `visit(row, ray direction, point on the pane)`.
void forEachPaneRow(const ViewCamera& camera,
                    const std::function<void(int, glm::vec3, glm::vec3)>& visit) {
  const glm::mat4 toWorld = glm::inverse(camera.projection * camera.view);
  for (int y = 0; y < camera.height; ++y) {
    const glm::vec2 ndc(1.0f / 16.0f, 1.0f - (static_cast<float>(y) + 0.5f) / 32.0f);
    const glm::vec4 far = toWorld * glm::vec4(ndc, 0.5f, 1.0f);
    const glm::vec3 dir = glm::normalize(glm::vec3(far) / far.w - kSeamEye);
    const glm::vec3 P = kSeamEye + dir * (-kSeamEye.y / dir.y);  // on the pane, y = 0
    if (dir.y >= 0.0f || std::abs(P.x) > 1.9f || std::abs(P.z) > 1.9f) continue;
    visit(y, dir, P);
  }
}

// Whether `exit` projects inside the frame, away from its edge (reads there are clamped).
bool readsInside(const ViewCamera& camera, glm::vec3 exit) {
  const glm::vec4 clip = camera.projection * camera.view * glm::vec4(exit, 1.0f);
  return std::abs(clip.y / clip.w) < 0.95f;
}

Frame renderSeam(const Scene& scene) {
  Light sun = sunAlong(glm::vec3(0, -1, 0), 3.0f);
  sun.shadow.enabled = false;
  StageTimes times;
  return sharedRenderer().render(scene, {sun}, glm::vec3(0.0f), seamCamera(scene), RenderSettings{},
                                 times);
}

// Seen at an angle, a volume shows the floor where the refracted view ray leaves it: across a
// red and a green floor, the seam seen through a 1 m thick pane (ior 1.5) lies on the rows the
// exit points predict (each row's pixel takes the floor the camera sees through the exit
// point's projection), not where a thin wall shows it; at most one row differs, at the seam.
TEST(VolumeRender, TheSeamBehindAThickPaneShiftsAsTheRefractedRaySays) {
  test_support::TempFolder folder("omnishadow-volume-refraction");
  const Scene scene =
      seamSlab(folder / "slab.gltf", 1.0f, glm::vec3(0.8f, 0, 0), glm::vec3(0, 0.8f, 0));
  ASSERT_TRUE(hasVolume(scene.materials[0]));
  const Frame frame = renderSeam(scene);
  const ViewCamera camera = seamCamera(scene);
  int mismatches = 0, checked = 0, thinDiffers = 0;
  forEachPaneRow(camera, [&](int y, glm::vec3 dir, glm::vec3 P) {
    const glm::vec3 exit = P + glm::refract(dir, glm::vec3(0, 1, 0), 1.0f / 1.5f);
    if (!readsInside(camera, exit)) return;
    const bool predicted = pastTheSeam(exit);
    const bool green = frame.beauty.at(8, y, 1) > frame.beauty.at(8, y, 0);
    mismatches += green != predicted ? 1 : 0;
    thinDiffers += pastTheSeam(P) != predicted ? 1 : 0;
    ++checked;
  });
  EXPECT_GT(checked, 20);
  EXPECT_LE(mismatches, 1);
  EXPECT_GE(thinDiffers, 3);
}

// KHR_materials_dispersion through a 2 m slab over a black and a white floor: red, green and
// blue each show the seam on the rows their own exit points predict (iors 1.25, 1.5 and 1.75 at
// a dispersion of 20: half the spread, 0.5 x 0.025 x 20, below and above), so that the channels
// part near the seam; at most one row differs per channel.
TEST(VolumeRender, DispersionPartsTheChannelsWhereTheirRaysLeave) {
  test_support::TempFolder folder("omnishadow-volume-dispersion");
  const Scene scene =
      seamSlab(folder / "prism.gltf", 2.0f, glm::vec3(0.0f), glm::vec3(0.8f), [](GltfBuilder& b) {
        b.model().materials[0].extensions["KHR_materials_dispersion"] =
            Value(Value::Object{{"dispersion", Value(20.0)}});
        b.model().extensionsUsed.push_back("KHR_materials_dispersion");
      });
  ASSERT_TRUE(hasDispersion(scene.materials[0]));
  const Frame frame = renderSeam(scene);
  const ViewCamera camera = seamCamera(scene);
  const float iors[3] = {1.25f, 1.5f, 1.75f};
  int mismatches[3] = {0, 0, 0}, checked = 0, parted = 0;
  forEachPaneRow(camera, [&](int y, glm::vec3 dir, glm::vec3 P) {
    bool predicted[3];
    for (int c = 0; c < 3; ++c) {
      const glm::vec3 exit = P + 2.0f * glm::refract(dir, glm::vec3(0, 1, 0), 1.0f / iors[c]);
      if (!readsInside(camera, exit)) return;
      predicted[c] = pastTheSeam(exit);
    }
    for (int c = 0; c < 3; ++c)
      mismatches[c] += (frame.beauty.at(8, y, c) > 0.1f) != predicted[c] ? 1 : 0;
    parted += predicted[0] != predicted[2] ? 1 : 0;
    ++checked;
  });
  EXPECT_GT(checked, 20);
  for (int c = 0; c < 3; ++c) EXPECT_LE(mismatches[c], 1) << "channel " << c;
  EXPECT_GE(parted, 4);
}

// KHR_materials_anisotropy. The tests' floor: a 4 m plane (u along +x, v along +z: generated
// tangents +x) of a rough metal, whose every pixel is specular.
struct AnisotropyInputs {
  glm::vec3 base{0.9f, 0.6f, 0.3f};
  float roughness = 0.3f;
  float metallic = 1.0f;
  float strength = 0.8f;
};

// Outgoing radiance of the floor's point for a sun along -L: the glTF BRDF with the
// specification's anisotropic lobe, alpha mix(roughness^2, 1, strength^2) along T and
// roughness^2 along B = N x T, plus the ambient.
glm::vec3 anisotropicRadiance(const AnisotropyInputs& in, glm::vec3 T, glm::vec3 V, glm::vec3 L,
                              float radiance, float ambient) {
  const glm::vec3 N(0, 1, 0);
  glm::vec3 out = ambient * in.base;
  const float NdotL = glm::dot(N, L);
  if (NdotL <= 0.0f) return out;
  const glm::vec3 B = glm::normalize(glm::cross(N, T));
  const glm::vec3 H = glm::normalize(L + V);
  const float NdotV = std::max(glm::dot(N, V), 1e-4f), NdotH = std::max(glm::dot(N, H), 0.0f);
  const float VdotH = std::max(glm::dot(V, H), 0.0f);
  const float alpha = in.roughness * in.roughness;
  const float at = alpha + (1.0f - alpha) * in.strength * in.strength, ab = alpha;
  const float a2 = at * ab;
  const glm::vec3 f(ab * glm::dot(T, H), at * glm::dot(B, H), a2 * NdotH);
  const float w2 = a2 / glm::dot(f, f);
  const float d = a2 * w2 * w2 / kPi;
  const float v =
      0.5f / (NdotL * glm::length(glm::vec3(at * glm::dot(T, V), ab * glm::dot(B, V), NdotV)) +
              NdotV * glm::length(glm::vec3(at * glm::dot(T, L), ab * glm::dot(B, L), NdotL)));
  const glm::vec3 f0 = glm::mix(glm::vec3(0.04f), in.base, in.metallic);
  const glm::vec3 F = f0 + (1.0f - f0) * std::pow(1.0f - VdotH, 5.0f);
  out += ((1.0f - F) * (1.0f - in.metallic) * in.base / kPi + F * d * v) * radiance * NdotL;
  return out;
}

// The anisotropy tests' floor with `anisotropy` as its KHR_materials_anisotropy, and a 1x1
// linear texture of `texel` the extension may name as texture 0 (floorWith()).
Scene anisotropicFloor(const fs::path& file, const AnisotropyInputs& in, const Value& anisotropy,
                       const std::vector<std::uint8_t>& texel) {
  MaterialDesc material;
  material.baseColor = glm::vec4(in.base, 1.0f);
  material.roughness = in.roughness;
  material.metallic = in.metallic;
  return floorWith(file, material, "KHR_materials_anisotropy", &anisotropy, texel);
}

// Every floor pixel against anisotropicRadiance() for its own view direction, within 1%, in
// the beauty and the AOV pass: the direction the tangent (rotation 0), turned a quarter by the
// rotation, or read from the texture (RG about (0.5, 1): the bitangent's way, B about 0.5
// halving the strength). Most pixels differ from the round lobe's by more than 10%, so the checks
// can fail.
TEST(AnisotropyRender, MatchesTheSpecificationsLobeAtEveryPixel) {
  test_support::TempFolder folder("omnishadow-anisotropy-render");
  const glm::vec3 towardsSun = glm::normalize(glm::vec3(0.3f, 0.5f, -1.0f));
  Light sun = sunAlong(-towardsSun, 3.0f);
  sun.shadow.enabled = false;
  const float ambient = 0.05f;
  const glm::vec3 eye(0.0f, 1.5f, 4.5f);
  const AnisotropyInputs in;
  AnisotropyInputs round = in;
  round.strength = 0.0f;
  // The texel below: B 128/255 of the strength, RG (128, 255) a direction a fifth of a degree
  // off the bitangent's: -z, against the way v grows, as glTF's tangent space has it (a normal
  // texture's green points there too).
  AnisotropyInputs half = in;
  half.strength = in.strength * 128.0f / 255.0f;
  const glm::vec3 alongU(1, 0, 0), alongV(0, 0, 1);
  const glm::vec3 texelDirection = glm::normalize(glm::vec3(2.0f * 128.0f / 255.0f - 1.0f, 0, -1));
  const struct {
    const char* name;
    Value extension;
    std::vector<std::uint8_t> texel;
    AnisotropyInputs expected;
    glm::vec3 direction;
  } cases[] = {
      {"tangent",
       Value(Value::Object{{"anisotropyStrength", Value(in.strength)}}),
       {255, 128, 255, 255},
       in,
       alongU},
      {"rotated",
       Value(Value::Object{{"anisotropyStrength", Value(in.strength)},
                           {"anisotropyRotation", Value(kPi / 2.0)}}),
       {255, 128, 255, 255},
       in,
       alongV},
      {"texture",
       Value(Value::Object{{"anisotropyStrength", Value(in.strength)},
                           {"anisotropyTexture", Value(Value::Object{{"index", Value(0)}})}}),
       {128, 255, 128, 255},
       half,
       texelDirection},
  };
  for (const auto& c : cases) {
    const Scene scene =
        anisotropicFloor(folder / (std::string(c.name) + ".gltf"), in, c.extension, c.texel);
    ASSERT_TRUE(hasAnisotropy(scene.materials[0]));
    const ViewCamera camera = lookFrom(scene, eye, {0, 0, 0}, 48, 32, 30.0f);
    for (const bool aovs : {true, false}) {
      const auto [frame, withAovs] = renderFloorFrame(scene, sun, ambient, camera, aovs);
      int changed = 0;
      const int checked = expectFloorPixels(
          frame, *withAovs.aovs, eye,
          [&](glm::vec3 V) {
            return anisotropicRadiance(c.expected, c.direction, V, towardsSun, 3.0f, ambient);
          },
          [&](glm::vec3 V) {
            return anisotropicRadiance(round, alongU, V, towardsSun, 3.0f, ambient);
          },
          changed, std::string(c.name) + (aovs ? " (AOV pass)" : " (beauty pass)"));
      EXPECT_GT(checked, 300) << c.name;
      EXPECT_GT(changed, checked / 2) << c.name;
    }
  }
}

// KHR_materials_iridescence's film Fresnel, as its specification's implementation notes write
// it (with the Khronos sample viewer's limit at a thickness of 0), evaluated here in double.
glm::dvec3 iridescentFresnel(double filmIor, glm::dvec3 baseF0, double thickness,
                             double cosTheta1) {
  const double pi = std::numbers::pi;
  const auto smooth = [](double x) {
    const double t = std::clamp(x / 0.03, 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
  };
  const double ior = 1.0 + (filmIor - 1.0) * smooth(thickness);
  const double cosTheta2Sq = 1.0 - (1.0 / (ior * ior)) * (1.0 - cosTheta1 * cosTheta1);
  if (cosTheta2Sq < 0.0) return glm::dvec3(1.0);
  const double cosTheta2 = std::sqrt(cosTheta2Sq);
  const auto schlick = [](double f0, double c) {
    return f0 + (1.0 - f0) * std::pow(std::clamp(1.0 - c, 0.0, 1.0), 5.0);
  };
  const double r0 = (ior - 1.0) / (ior + 1.0);
  const double R12 = schlick(r0 * r0, cosTheta1), T121 = 1.0 - R12;
  const double phi21 = pi - (ior < 1.0 ? pi : 0.0);
  const glm::dmat3 xyzToRec709(3.2404542, -0.9692660, 0.0556434, -1.5371385, 1.8760108, -0.2040259,
                               -0.4985314, 0.0415560, 1.0572252);
  glm::dvec3 I(0.0), Cm(0.0), r123(0.0), phi(0.0);
  glm::dvec3 R23(0.0), Rs(0.0);
  for (int c = 0; c < 3; ++c) {
    const double s = std::sqrt(std::clamp(baseF0[c], 0.0, 0.9999));
    const double baseIor = (1.0 + s) / (1.0 - s);
    const double r1 = (baseIor - ior) / (baseIor + ior);
    R23[c] = schlick(r1 * r1, cosTheta2);
    phi[c] = phi21 + (baseIor < ior ? pi : 0.0);
    const double R123 = std::clamp(R12 * R23[c], 1e-5, 0.9999);
    r123[c] = std::sqrt(R123);
    Rs[c] = T121 * T121 * R23[c] / (1.0 - R123);
    I[c] = R12 + Rs[c];
    Cm[c] = Rs[c] - T121;
  }
  const double opd = 2.0 * ior * thickness * cosTheta2;
  for (int m = 1; m <= 2; ++m) {
    Cm *= r123;
    const double phase = 2.0 * pi * m * opd * 1.0e-9;
    const glm::dvec3 val(5.4856e-13, 4.4201e-13, 5.2481e-13);
    const glm::dvec3 pos(1.6810e+06, 1.7953e+06, 2.2084e+06);
    const glm::dvec3 var(4.3278e+09, 9.3046e+09, 6.6121e+09);
    glm::dvec3 xyz;
    for (int c = 0; c < 3; ++c)
      xyz[c] = val[c] * std::sqrt(2.0 * pi * var[c]) * std::cos(pos[c] * phase + m * phi[c]) *
               std::exp(-phase * phase * var[c]);
    xyz.x += 9.7470e-14 * std::sqrt(2.0 * pi * 4.5282e+09) *
             std::cos(2.2399e+06 * phase + m * phi[0]) * std::exp(-4.5282e+09 * phase * phase);
    xyz /= 1.0685e-7;
    I += Cm * 2.0 * (xyzToRec709 * xyz);
  }
  return glm::max(I, glm::dvec3(0.0));
}

// The iridescence tests' floor: a dielectric or a metal under a film of strength `strength`,
// index 1.3 and `thickness` nm (its maximum, with no thickness texture).
struct FilmInputs {
  glm::vec3 base{0.5f, 0.3f, 0.2f};
  float roughness = 0.4f;
  float metallic = 0.0f;
  float strength = 0.8f;
  float thickness = 400.0f;
};

// The floor's radiance as the specification layers the film: the dielectric keeps
// mix(fresnel_mix(diffuse, specular), rgb_mix(diffuse, specular, film), strength), the metal's
// Fresnel mixes towards the film's; the film's Fresnel at N.V, the base's at V.H.
glm::vec3 filmRadiance(const FilmInputs& in, glm::vec3 V, glm::vec3 L, float radiance,
                       float ambient) {
  const glm::vec3 N(0, 1, 0);
  glm::vec3 out = ambient * in.base;
  const float NdotL = glm::dot(N, L);
  if (NdotL <= 0.0f) return out;
  const glm::vec3 H = glm::normalize(L + V);
  const float NdotV = std::max(glm::dot(N, V), 1e-4f), NdotH = std::max(glm::dot(N, H), 0.0f);
  const float VdotH = std::max(glm::dot(V, H), 0.0f);
  const double cosView = std::clamp(static_cast<double>(glm::dot(N, V)), 0.0, 1.0);
  const glm::vec3 filmDielectric =
      glm::vec3(iridescentFresnel(1.3, glm::dvec3(0.04), in.thickness, cosView));
  const glm::vec3 filmMetal =
      glm::vec3(iridescentFresnel(1.3, glm::dvec3(in.base), in.thickness, cosView));
  const float x5 = std::pow(1.0f - VdotH, 5.0f);
  const float fd = 0.04f + 0.96f * x5;
  const glm::vec3 fm = in.base + (1.0f - in.base) * x5;
  const glm::vec3 dielectric = glm::mix(glm::vec3(fd), filmDielectric, in.strength);
  const glm::vec3 metal = glm::mix(fm, filmMetal, in.strength);
  const float filmMax = std::max(filmDielectric.r, std::max(filmDielectric.g, filmDielectric.b));
  const float diffuseWeight =
      (1.0f - in.metallic) * ((1.0f - fd) * (1.0f - in.strength) + (1.0f - filmMax) * in.strength);
  const float lobe = ggxLobe(NdotH, NdotV, NdotL, in.roughness * in.roughness);
  out += (diffuseWeight * in.base / kPi + glm::mix(dielectric, metal, in.metallic) * lobe) *
         radiance * NdotL;
  return out;
}

// A floor with a film, dielectric, metal and half metal, seen over a range of angles (the film's
// color changes with them): every pixel is filmRadiance() for its own view direction within 1%, in
// the beauty and the AOV pass; most differ from the floor without the film by more than 10%.
TEST(IridescenceRender, MatchesTheSpecificationsThinFilmAtEveryPixel) {
  test_support::TempFolder folder("omnishadow-iridescence-render");
  const glm::vec3 towardsSun = glm::normalize(glm::vec3(0.1f, 0.6f, -1.0f));
  Light sun = sunAlong(-towardsSun, 3.0f);
  sun.shadow.enabled = false;
  const float ambient = 0.05f;
  const glm::vec3 eye(0.0f, 1.5f, 4.5f);
  // Metallic 0 and 1 take the film over one base alone (a variant of their own); 0.5 both.
  for (const float metallic : {0.0f, 1.0f, 0.5f}) {
    FilmInputs in;
    in.metallic = metallic;
    FilmInputs none = in;
    none.strength = 0.0f;
    MaterialDesc material;
    material.baseColor = glm::vec4(in.base, 1.0f);
    material.roughness = in.roughness;
    material.metallic = in.metallic;
    const Value film(Value::Object{{"iridescenceFactor", Value(in.strength)},
                                   {"iridescenceThicknessMaximum", Value(in.thickness)}});
    const Scene scene =
        floorWith(folder / ("film" + std::to_string(static_cast<int>(10 * metallic)) + ".gltf"),
                  material, "KHR_materials_iridescence", &film, {255, 255, 255, 255});
    ASSERT_TRUE(hasIridescence(scene.materials[0]));
    const ViewCamera camera = lookFrom(scene, eye, {0, 0, 0}, 48, 32, 30.0f);
    for (const bool aovs : {true, false}) {
      const auto [frame, withAovs] = renderFloorFrame(scene, sun, ambient, camera, aovs);
      int changed = 0;
      const int checked = expectFloorPixels(
          frame, *withAovs.aovs, eye,
          [&](glm::vec3 V) { return filmRadiance(in, V, towardsSun, 3.0f, ambient); },
          [&](glm::vec3 V) { return filmRadiance(none, V, towardsSun, 3.0f, ambient); }, changed,
          "metallic " + std::to_string(metallic) + (aovs ? " (AOV pass)" : " (beauty pass)"));
      EXPECT_GT(checked, 300);
      EXPECT_GT(changed, checked / 2) << "metallic " << metallic;
    }
  }
}

// KHR_materials_diffuse_transmission on a dielectric floor lit by a sun above or below it,
// with an ambient: the light behind shines through as Lambert of the color, weighted by the
// fraction and what Fresnel towards the camera leaves; the light in front keeps 1 - the
// fraction of its diffuse; the ambient mixes the base color towards the color by the fraction.
struct LeafInputs {
  glm::vec3 base{0.3f, 0.6f, 0.2f};
  float roughness = 0.7f;
  float fraction = 0.6f;
  glm::vec3 color{0.9f, 0.8f, 0.1f};
};

glm::vec3 leafRadiance(const LeafInputs& in, glm::vec3 V, glm::vec3 L, float radiance,
                       float ambient) {
  const glm::vec3 N(0, 1, 0);
  glm::vec3 out = ambient * glm::mix(in.base, in.color, in.fraction);
  const float NdotL = glm::dot(N, L), NdotV = std::max(glm::dot(N, V), 1e-4f);
  if (NdotL < 0.0f)
    return out +
           in.fraction * (1.0f - fresnel004(glm::dot(N, V))) * in.color / kPi * radiance * -NdotL;
  const glm::vec3 H = glm::normalize(L + V);
  const float f = fresnel004(std::max(glm::dot(V, H), 0.0f));
  const float lobe =
      ggxLobe(std::max(glm::dot(N, H), 0.0f), NdotV, NdotL, in.roughness * in.roughness);
  return out + ((1.0f - in.fraction) * (1.0f - f) * in.base / kPi + glm::vec3(f * lobe)) *
                   radiance * NdotL;
}

// Every floor pixel against leafRadiance() for its own view direction, within 1%, in the
// beauty and the AOV pass, with the sun below the floor and above it; most pixels differ from
// the floor without the extension by more than 10%, so the checks can fail.
TEST(DiffuseTransmissionRender, LightsBehindShineThroughAsTheSpecificationMixesIt) {
  test_support::TempFolder folder("omnishadow-diffuse-transmission");
  const LeafInputs in;
  LeafInputs none = in;
  none.fraction = 0.0f;
  MaterialDesc material;
  material.baseColor = glm::vec4(in.base, 1.0f);
  material.roughness = in.roughness;
  const Value extension(Value::Object{
      {"diffuseTransmissionFactor", Value(in.fraction)},
      {"diffuseTransmissionColorFactor",
       Value(Value::Array{Value(in.color.r), Value(in.color.g), Value(in.color.b)})}});
  const Scene scene =
      floorWith(folder / "leaf.gltf", material, "KHR_materials_diffuse_transmission", &extension,
                {255, 255, 255, 255});
  ASSERT_TRUE(hasDiffuseTransmission(scene.materials[0]));
  const float ambient = 0.1f;
  const glm::vec3 eye(0.0f, 1.5f, 4.5f);
  const ViewCamera camera = lookFrom(scene, eye, {0, 0, 0}, 48, 32, 30.0f);
  for (const glm::vec3 towardsSun : {glm::normalize(glm::vec3(0.2f, -0.8f, -0.5f)),
                                     glm::normalize(glm::vec3(0.2f, 0.8f, -0.5f))}) {
    Light sun = sunAlong(-towardsSun, 3.0f);
    sun.shadow.enabled = false;
    for (const bool aovs : {true, false}) {
      const auto [frame, withAovs] = renderFloorFrame(scene, sun, ambient, camera, aovs);
      int changed = 0;
      const int checked = expectFloorPixels(
          frame, *withAovs.aovs, eye,
          [&](glm::vec3 V) { return leafRadiance(in, V, towardsSun, 3.0f, ambient); },
          [&](glm::vec3 V) { return leafRadiance(none, V, towardsSun, 3.0f, ambient); }, changed,
          std::string(towardsSun.y < 0.0f ? "sun below" : "sun above") +
              (aovs ? " (AOV pass)" : " (beauty pass)"));
      EXPECT_GT(checked, 300);
      EXPECT_GT(changed, checked / 2);
    }
  }
}

}  // namespace
}  // namespace omnishadow::material_render_test
