// Rendering facts checked through the AOVs: shadows land where geometry says they must, points
// that see the light are lit, cube map faces are where the GL convention puts them.
// Runs on whatever EGL gives (llvmpipe in CI); sizes are small to keep it quick.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <glm/gtc/matrix_transform.hpp>
#include <limits>
#include <memory>
#include <random>
#include <tuple>

#include "renderer/core/errors.h"
#include "renderer/gl/software_rasterizer.h"
#include "renderer/passes/lighting_pass.h"
#include "renderer/passes/shader_contract.h"
#include "renderer/passes/shadow_textures.h"
#include "renderer/render/renderer.h"
#include "renderer/scene/gltf_loader.h"
#include "renderer/scene/srgb_transfer.h"
#include "renderer/verify/shadow_verification.h"
#include "renderer/view/camera.h"
#include "renderer/view/cube_faces.h"
#include "renderer/view/shadow_plan.h"
#include "scenes/builder/gltf_builder.h"
#include "tests/support/render_heap.h"
#include "tests/support/scene_objects.h"
#include "tests/support/segment_occlusion.h"
#include "tests/support/shared_renderer.h"

namespace render_test {

using namespace omnishadow;

namespace {

using test_support::lookFrom;
using test_support::segmentBlocked;
using test_support::sharedRenderer;
using test_support::WorldTriangle;

int addMaterial(Scene& scene, glm::vec4 color, bool doubleSided = false) {
  Material m;
  m.baseColorFactor = color;
  m.metallicFactor = 0.0f;
  m.roughnessFactor = 1.0f;
  m.doubleSided = doubleSided;
  scene.materials.push_back(m);
  return static_cast<int>(scene.materials.size()) - 1;
}

void addObject(Scene& scene, const builder::MeshData& data, const glm::mat4& world, int material) {
  test::placeMesh(scene, data, world, material);
}

glm::mat4 translate(glm::vec3 t) {
  return glm::translate(glm::mat4(1.0f), t);
}

Light pointLight(const std::string& name, glm::vec3 position, ShadowFilter filter,
                 int resolution = 512) {
  Light light;
  light.name = name;
  light.position = position;
  light.intensity = 10.0f;
  light.shadow.resolution = resolution;
  light.shadow.filter = filter;
  return light;
}

// The pixel (column, row from the top) where a world point appears.
glm::ivec2 project(const ViewCamera& camera, glm::vec3 p) {
  const glm::vec4 clip = camera.projection * camera.view * glm::vec4(p, 1.0f);
  const glm::vec2 ndc = glm::vec2(clip) / clip.w;
  return {static_cast<int>((ndc.x * 0.5f + 0.5f) * static_cast<float>(camera.width)),
          static_cast<int>((0.5f - ndc.y * 0.5f) * static_cast<float>(camera.height))};
}

Frame renderAovs(const Scene& scene, const std::vector<Light>& lights, const ViewCamera& camera,
                 Shading shading = Shading::Pbr) {
  return test_support::renderWithAovs(scene, lights, camera, {.shading = shading},
                                      glm::vec3(0.03f));
}

struct AovPixel {
  glm::vec3 position, normal;
  float coverage;
  float visibility;
};

AovPixel pixelAt(const FloatImage& aovs, int x, int y, const std::string& light) {
  const int p = aovs.channelIndex("P.X");
  const int n = aovs.channelIndex("N.X");
  const int v = aovs.channelIndex("visibility." + light);
  return {{aovs.at(x, y, p), aovs.at(x, y, p + 1), aovs.at(x, y, p + 2)},
          {aovs.at(x, y, n), aovs.at(x, y, n + 1), aovs.at(x, y, n + 2)},
          aovs.at(x, y, aovs.channelIndex("A")),
          aovs.at(x, y, v)};
}

// Slab test: does the segment from `from` to `to` pass through the box?
// A lone box, 0.4 m a side, centred at `at`: a caster whose bounding sphere (radius
// 0.2 sqrt(3)) covers only part of a shadow view.
Scene loneBoxAt(glm::vec3 at) {
  Scene scene;
  addObject(scene, builder::makeBox({0.2f, 0.2f, 0.2f}), translate(at),
            addMaterial(scene, glm::vec4(0.8f)));
  return scene;
}

bool segmentHitsBox(glm::vec3 from, glm::vec3 to, glm::vec3 boxMin, glm::vec3 boxMax) {
  const glm::vec3 d = to - from;
  float t0 = 0.0f, t1 = 1.0f;
  for (int i = 0; i < 3; ++i) {
    if (std::abs(d[i]) < 1e-9f) {
      if (from[i] < boxMin[i] || from[i] > boxMax[i]) return false;
      continue;
    }
    float a = (boxMin[i] - from[i]) / d[i];
    float b = (boxMax[i] - from[i]) / d[i];
    if (a > b) std::swap(a, b);
    t0 = std::max(t0, a);
    t1 = std::min(t1, b);
    if (t0 > t1) return false;
  }
  return true;
}

}  // namespace

// A sphere of radius r at height h above a plane, the light at height H right above it: the
// shadow on the plane is a disc of radius H * tan(asin(r / (H - h))) around the origin for
// point and spot lights, and of radius r for a directional light shining straight down.
struct DiscCase {
  LightType type;
  ShadowFilter filter;
};

class SphereAbovePlane : public ::testing::TestWithParam<DiscCase> {};

TEST_P(SphereAbovePlane, CastsADiscShapedShadowExactlyWhereGeometrySays) {
  const float r = 0.5f, h = 1.5f, H = 4.0f;
  const LightType type = GetParam().type;
  const float discRadius =
      type == LightType::Directional ? r : H * std::tan(std::asin(r / (H - h)));
  Scene scene;
  const int white = addMaterial(scene, glm::vec4(0.8f, 0.8f, 0.8f, 1.0f));
  addObject(scene, builder::makePlane(8.0f), glm::mat4(1.0f), white);
  addObject(scene, builder::makeSphere(r, 64, 32), translate({0, h, 0}), white);
  Light light = pointLight("lamp", {0, H, 0}, GetParam().filter, 1024);
  light.type = type;
  light.direction = {0, -1, 0};
  light.outerConeAngle = glm::radians(60.0f);
  if (type == LightType::Directional) light.intensity = 2.0f;
  const ViewCamera camera = lookFrom(scene, {0, 7, 4}, {0, 0, 0}, 320, 240, 50.0f);
  const Frame frame = renderAovs(scene, {light}, camera);
  ASSERT_TRUE(frame.aovs);

  // Filters blur the edge over a few texels. A texel on the plane near the disc's edge spans
  // about 2 * H / resolution for the point light's cube (seen from straight above), 2 * H *
  // tan(60 deg) / resolution for the spot map and the plane's width / resolution for the sun.
  const float texel = (type == LightType::Point  ? 2.0f * H
                       : type == LightType::Spot ? 2.0f * H * std::tan(glm::radians(61.0f))
                                                 : 8.0f) /
                      1024.0f * 1.2f;
  const ShadowFilter filter = GetParam().filter;
  const float margin = (filter == ShadowFilter::PcfDisk                               ? 6.0f
                        : filter == ShadowFilter::Hard || filter == ShadowFilter::Pcf ? 2.0f
                                                                                      : 4.0f) *
                       texel;
  int inside = 0, outside = 0;
  for (int y = 0; y < camera.height; ++y) {
    for (int x = 0; x < camera.width; ++x) {
      const AovPixel px = pixelAt(*frame.aovs, x, y, "lamp");
      if (px.coverage < 1.0f || std::abs(px.position.y) > 1e-3f) continue;  // not the plane
      const float rho = glm::length(glm::vec2(px.position.x, px.position.z));
      if (type == LightType::Spot && rho > H * std::tan(glm::radians(59.0f))) continue;
      if (rho < discRadius - margin) {
        ++inside;
        EXPECT_LT(px.visibility, 0.01f) << "lit inside the shadow at rho " << rho;
      } else if (rho > discRadius + margin) {
        ++outside;
        EXPECT_GT(px.visibility, 0.99f) << "shadowed outside the disc at rho " << rho;
      }
    }
  }
  EXPECT_GT(inside, type == LightType::Directional ? 200 : 500);
  EXPECT_GT(outside, 5000);
}

std::vector<DiscCase> allLightsAndFilters() {
  std::vector<DiscCase> cases;
  for (const LightType type : {LightType::Point, LightType::Spot, LightType::Directional})
    for (const ShadowFilter filter : {ShadowFilter::Hard, ShadowFilter::Pcf, ShadowFilter::PcfDisk,
                                      ShadowFilter::Poisson, ShadowFilter::Pcss, ShadowFilter::Vsm})
      cases.push_back({type, filter});
  return cases;
}

INSTANTIATE_TEST_SUITE_P(LightsAndFilters, SphereAbovePlane,
                         ::testing::ValuesIn(allLightsAndFilters()),
                         [](const ::testing::TestParamInfo<DiscCase>& param) {
                           std::string name = std::string(toString(param.param.type)) + "_" +
                                              toString(param.param.filter);
                           for (char& c : name)
                             if (c == '-') c = '_';
                           return name;
                         });

// A shadow edge that crosses from the light's -Y cube face onto its +X face (the floor at
// y = -1 changes face at x = 1): with seamless filtering the shadow has no lit seam and no
// gap along the face boundary, for the filters whose taps cross it.
class CubeFaceSeam : public ::testing::TestWithParam<ShadowFilter> {};

TEST_P(CubeFaceSeam, ShadowEdgeCrossesTheFaceBoundaryWithoutSeamOrGap) {
  Scene scene;
  const int white = addMaterial(scene, glm::vec4(0.8f));
  addObject(scene, builder::makePlane(8.0f), translate({0, -1, 0}), white);
  const glm::vec3 boxMin(0.3f, -0.55f, -1.0f), boxMax(1.2f, -0.45f, 0.3f);
  addObject(scene, builder::makeBox((boxMax - boxMin) * 0.5f), translate((boxMin + boxMax) * 0.5f),
            white);
  const Light light = pointLight("lamp", {0, 0, 0}, GetParam(), 512);
  const ViewCamera camera =
      lookFrom(scene, {1.0f, 2.0f, 1.4f}, {1.0f, -1.0f, 0.5f}, 240, 240, 40.0f);
  const Frame frame = renderAovs(scene, {light}, camera);
  // The shadow's edge on the floor is the box's top edge z = 0.3 at y = -0.45 seen from the
  // light: z = 0.3 / 0.45. Two texels there are about 0.01 m; the disk filter spans more.
  const float edge = 0.3f / 0.45f;
  const float margin = GetParam() == ShadowFilter::PcfDisk ? 0.06f : 0.03f;
  int shadowed = 0, lit = 0;
  for (int y = 0; y < camera.height; ++y) {
    for (int x = 0; x < camera.width; ++x) {
      const AovPixel px = pixelAt(*frame.aovs, x, y, "lamp");
      if (px.coverage < 1.0f || std::abs(px.position.y + 1.0f) > 1e-3f) continue;
      if (std::abs(px.position.x - 1.0f) > 0.12f) continue;  // the band around the face edge
      if (std::abs(px.position.z - edge) < margin) continue;
      const bool blocked = segmentHitsBox(px.position, light.position, boxMin, boxMax);
      if (blocked) {
        ++shadowed;
        EXPECT_LT(px.visibility, 0.01f) << "lit seam at " << px.position.x << ", " << px.position.z;
      } else {
        ++lit;
        EXPECT_GT(px.visibility, 0.99f) << "gap at " << px.position.x << ", " << px.position.z;
      }
    }
  }
  EXPECT_GT(shadowed, 300);
  EXPECT_GT(lit, 300);
}

INSTANTIATE_TEST_SUITE_P(Filters, CubeFaceSeam,
                         ::testing::Values(ShadowFilter::Pcf, ShadowFilter::PcfDisk,
                                           ShadowFilter::Poisson, ShadowFilter::Vsm),
                         [](const ::testing::TestParamInfo<ShadowFilter>& param) {
                           std::string name = toString(param.param);
                           for (char& c : name)
                             if (c == '-') c = '_';
                           return name;
                         });

TEST(Shadows, PointsThatSeeTheLightAreLitEverywhereOnTheSphere) {
  // No self-shadowing (acne) on a curved surface: every point of the sphere whose normal faces
  // the light by more than a grazing angle is fully lit.
  Scene scene;
  const int white = addMaterial(scene, glm::vec4(0.8f));
  addObject(scene, builder::makeSphere(1.0f, 96, 48), glm::mat4(1.0f), white);
  const glm::vec3 lightPosition(2.0f, 3.0f, 1.5f);
  const Light light = pointLight("lamp", lightPosition, ShadowFilter::Pcf);
  const ViewCamera camera = lookFrom(scene, {3, 2, 4}, {0, 0, 0}, 256, 256, 45.0f);
  const Frame frame = renderAovs(scene, {light}, camera);
  int checked = 0;
  for (int y = 0; y < camera.height; ++y) {
    for (int x = 0; x < camera.width; ++x) {
      const AovPixel px = pixelAt(*frame.aovs, x, y, "lamp");
      if (px.coverage < 1.0f) continue;
      const glm::vec3 L = glm::normalize(lightPosition - px.position);
      const float NdotL = glm::dot(glm::normalize(px.position), L);  // sphere normal
      if (NdotL > 0.1f) {
        ++checked;
        EXPECT_GT(px.visibility, 0.999f) << "acne at " << x << "," << y << " N.L " << NdotL;
      } else if (NdotL < -0.3f) {  // near the terminator the bias may leak light
        EXPECT_LT(px.visibility, 0.01f) << "back of the sphere lit at " << x << "," << y;
      }
    }
  }
  EXPECT_GT(checked, 3000);
}

// Six boxes around a light inside a closed room, each off-center in its face so that a flipped
// or rotated face would move its shadow. From the light's own position, looking along each axis,
// every wall point must be shadowed exactly when the segment to the light crosses a box.
TEST(Shadows, ShadowsOnAllSixCubeFacesMatchRayCasting) {
  Scene scene;
  const int wall = addMaterial(scene, glm::vec4(0.7f), true);
  const int boxMaterial = addMaterial(scene, glm::vec4(0.3f, 0.4f, 0.8f, 1.0f));
  // The room: an inward-visible double-sided box from -5 to 5.
  addObject(scene, builder::makeBox({5, 5, 5}), glm::mat4(1.0f), wall);
  const glm::vec3 light(0.2f, -0.1f, 0.3f);
  const glm::vec3 axes[] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  struct Box {
    glm::vec3 min, max;
  };
  std::vector<Box> boxes;
  for (int i = 0; i < 6; ++i) {
    const glm::vec3 a = axes[i];
    // Perpendicular offsets differ per face (distance and direction) to break symmetries.
    const glm::vec3 u = glm::abs(a.x) > 0 ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
    const glm::vec3 v = glm::cross(a, u);
    const glm::vec3 center = light + a * (1.5f + 0.3f * i) + u * 0.6f + v * (0.25f + 0.05f * i);
    const glm::vec3 half(0.35f, 0.25f, 0.3f);
    boxes.push_back({center - half, center + half});
    addObject(scene, builder::makeBox(half), translate(center), boxMaterial);
  }
  const Light lamp = pointLight("lamp", light, ShadowFilter::Hard, 512);

  for (int face = 0; face < 6; ++face) {
    const glm::vec3 a = axes[face];
    const glm::vec3 up = std::abs(a.y) > 0 ? glm::vec3(0, 0, 1) : glm::vec3(0, 1, 0);
    // Seen from beside the light (from the light itself every shadow hides behind its caster),
    // from the first candidate position that is not inside a box.
    const glm::vec3 side = glm::abs(a.x) > 0 ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
    const glm::vec3 other = glm::cross(a, side);
    glm::vec3 eye = light;
    for (const glm::vec3 offset : {-side * 1.6f - other * 1.1f, side * 1.6f + other * 1.1f,
                                   -side * 1.6f + other * 1.1f, side * 1.6f - other * 1.1f}) {
      const glm::vec3 candidate = light + offset - a * 0.5f;
      bool inside = false;
      for (const Box& b : boxes)
        inside |= glm::all(glm::greaterThan(candidate, b.min - 0.2f)) &&
                  glm::all(glm::lessThan(candidate, b.max + 0.2f));
      if (!inside) {
        eye = candidate;
        break;
      }
    }
    ASSERT_NE(eye, light);
    const ViewCamera camera = lookFrom(scene, eye, eye + a, 160, 160, 100.0f, up);
    const Frame frame = renderAovs(scene, {lamp}, camera);
    int shadowed = 0, lit = 0;
    for (int y = 0; y < camera.height; ++y) {
      for (int x = 0; x < camera.width; ++x) {
        const AovPixel px = pixelAt(*frame.aovs, x, y, "lamp");
        if (px.coverage < 1.0f) continue;
        const bool onWall = glm::any(glm::greaterThan(glm::abs(px.position), glm::vec3(4.999f)));
        if (!onWall) continue;
        // Two texels of tolerance at the silhouettes, measured at the boxes' distance.
        const float margin = 0.05f;
        bool surelyHit = false, maybeHit = false;
        for (const Box& b : boxes) {
          surelyHit |= segmentHitsBox(light, px.position, b.min + margin, b.max - margin);
          maybeHit |= segmentHitsBox(light, px.position, b.min - margin, b.max + margin);
        }
        if (surelyHit) {
          ++shadowed;
          EXPECT_LT(px.visibility, 0.01f)
              << "face " << kCubeFaceNames[face] << " pixel " << x << "," << y;
        } else if (!maybeHit) {
          ++lit;
          EXPECT_GT(px.visibility, 0.99f)
              << "face " << kCubeFaceNames[face] << " pixel " << x << "," << y;
        }
      }
    }
    EXPECT_GT(shadowed, 80) << "face " << kCubeFaceNames[face];
    EXPECT_GT(lit, 2000) << "face " << kCubeFaceNames[face];
  }
}

// The --shadow-pass strategies draw the same triangles with the same matrices, so every texel
// of every face must be identical: objects straddling faces, cut-out casters, mirrored and
// culled ones, and three lights in one cube map array.
TEST(ShadowMap, AllShadowPassStrategiesWriteIdenticalTexels) {
  Scene scene;
  const int grey = addMaterial(scene, glm::vec4(0.5f));
  const int twoSided = addMaterial(scene, glm::vec4(0.7f), true);
  addObject(scene, builder::makePlane(10.0f), glm::mat4(1.0f), grey);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-3.0f, 3.0f);
  for (int i = 0; i < 40; ++i) {
    glm::mat4 world = translate({u(rng), 0.5f + 0.3f * std::abs(u(rng)), u(rng)});
    if (i % 5 == 0) world = glm::scale(world, glm::vec3(-1, 1, 1));  // mirrored
    addObject(scene, i % 2 ? builder::makeSphere(0.3f, 16, 8) : builder::makeBox(glm::vec3(0.3f)),
              world, i % 3 ? grey : twoSided);
  }
  // Instances of one mesh too large to copy for each (GpuScene's world-space caster stream):
  // these draws are transformed per vertex, the others are not.
  addObject(scene, builder::makeSphere(0.2f, 96, 48), translate({-1, 1.5f, -1}), grey);
  for (int i = 0; i < 16; ++i) {
    const glm::mat4 world = translate({u(rng), 1.2f + 0.1f * std::abs(u(rng)), u(rng)});
    scene.instances.push_back({static_cast<int>(scene.meshes.size()) - 1, world, -1, {}, {}});
    scene.bounds.extend(scene.meshes.back().bounds.transformed(world));
  }
  // Alpha-tested casters: one that casts (alpha above the cutoff), one that casts nothing.
  for (const float alpha : {0.8f, 0.2f}) {
    const int cutOut = addMaterial(scene, glm::vec4(0.6f, 0.6f, 0.6f, alpha));
    scene.materials[static_cast<std::size_t>(cutOut)].alphaMode = AlphaMode::Mask;
    addObject(scene, builder::makeBox(glm::vec3(0.35f)), translate({u(rng), 0.9f, u(rng)}), cutOut);
  }
  std::vector<Light> lights = {pointLight("a", {0, 2, 0}, ShadowFilter::Pcf, 128),
                               pointLight("b", {1.5f, 1, -1}, ShadowFilter::Pcf, 128),
                               pointLight("c", {-2, 0.8f, 2}, ShadowFilter::Pcf, 128)};
  // All three in one batch of `batched` (one clear for the whole texture), then in three
  // (each light's layers cleared on their own).
  std::vector<Light> culled = lights;
  culled[1].shadow.cullFace = CullFace::Front;
  culled[2].shadow.cullFace = CullFace::Back;
  for (const std::vector<Light>* set : {&lights, &culled}) {
    const auto six = sharedRenderer().renderShadowDistances(scene, *set, ShadowPassStrategy::Six);
    for (const ShadowPassStrategy other :
         {ShadowPassStrategy::Geometry, ShadowPassStrategy::Instanced,
          ShadowPassStrategy::Batched}) {
      const auto maps = sharedRenderer().renderShadowDistances(scene, *set, other);
      ASSERT_EQ(maps.size(), six.size());
      for (std::size_t l = 0; l < maps.size(); ++l) {
        for (int face = 0; face < kCubeFaceCount; ++face) {
          const std::vector<float>& a = six[l].faces[face];
          const std::vector<float>& b = maps[l].faces[face];
          ASSERT_EQ(a.size(), b.size());
          int differing = 0;
          for (std::size_t i = 0; i < a.size(); ++i)
            if (std::memcmp(&a[i], &b[i], sizeof(float)) != 0) ++differing;
          EXPECT_EQ(differing, 0) << toString(other) << ", light " << l << ", face "
                                  << kCubeFaceNames[face] << (set == &culled ? ", culled" : "");
        }
      }
    }
  }
}

int differingTexels(const CubeDistances& a, const CubeDistances& b) {
  int differing = 0;
  for (int face = 0; face < kCubeFaceCount; ++face) {
    EXPECT_EQ(a.faces[face].size(), b.faces[face].size());
    for (std::size_t i = 0; i < std::min(a.faces[face].size(), b.faces[face].size()); ++i)
      if (std::memcmp(&a.faces[face][i], &b.faces[face][i], sizeof(float)) != 0) ++differing;
  }
  return differing;
}

TEST(ShadowMap, SkippingTheBackFacesOfClosedCastersChangesNoTexel) {
  // The shadow pass skips the back faces of closed solids that a light sees from outside
  // (renderer/mesh_topology.h). The same scene with every mesh opened up (one triangle drawn
  // twice: not closed any more, same pixels) draws all faces; the maps must not differ. The
  // lights: one inside a closed box (its walls are back faces from there), one whose near plane
  // cuts into a box, and lights out in the open.
  Scene closed, open;
  for (Scene* scene : {&closed, &open}) {
    const int grey = addMaterial(*scene, glm::vec4(0.5f));
    const int twoSided = addMaterial(*scene, glm::vec4(0.7f), true);
    auto add = [&](builder::MeshData mesh, const glm::mat4& world, int material) {
      if (scene == &open)
        mesh.indices.insert(mesh.indices.end(), mesh.indices.begin(), mesh.indices.begin() + 3);
      addObject(*scene, mesh, world, material);
    };
    add(builder::makeBox(glm::vec3(5.0f, 0.1f, 5.0f)), translate({0, -0.1f, 0}), grey);
    add(builder::makeBox(glm::vec3(0.6f)), translate({2.5f, 0.8f, 2.5f}), grey);  // holds "c"
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-3.5f, 3.5f);
    for (int i = 0; i < 30; ++i) {
      glm::mat4 world = translate({u(rng), 0.4f + 0.2f * std::abs(u(rng)), u(rng)});
      if (i % 4 == 0) world = glm::scale(world, glm::vec3(1, 1, -1));  // mirrored
      const builder::MeshData mesh = i % 3 == 0   ? builder::makeBox(glm::vec3(0.25f))
                                     : i % 3 == 1 ? builder::makeSphere(0.3f, 16, 8)
                                                  : builder::makeCylinder(0.2f, 0.6f, 12);
      add(mesh, world, i % 5 == 0 ? twoSided : grey);
    }
    // "b" is just outside this box's bounding sphere, but its near plane cuts the box open.
    add(builder::makeBox(glm::vec3(0.5f)), translate({-1.0f, 1.0f, 0.0f}), grey);
  }
  std::vector<Light> lights = {pointLight("a", {0, 2.5f, 0}, ShadowFilter::Pcf, 128),
                               pointLight("b", {-0.48f, 1.52f, 0.52f}, ShadowFilter::Pcf, 128),
                               pointLight("c", {2.5f, 0.8f, 2.5f}, ShadowFilter::Pcf, 128),
                               pointLight("d", {-3, 0.3f, 3}, ShadowFilter::Pcf, 128)};
  lights[1].shadow.near = 0.3f;
  for (const ShadowPassStrategy strategy :
       {ShadowPassStrategy::Six, ShadowPassStrategy::Geometry}) {
    const auto skipped = sharedRenderer().renderShadowDistances(closed, lights, strategy);
    const auto drawn = sharedRenderer().renderShadowDistances(open, lights, strategy);
    ASSERT_EQ(skipped.size(), lights.size());
    ASSERT_EQ(drawn.size(), lights.size());
    for (std::size_t l = 0; l < lights.size(); ++l)
      EXPECT_EQ(differingTexels(skipped[l], drawn[l]), 0)
          << toString(strategy) << ", light " << lights[l].name;
  }
}

// On llvmpipe the renderer counts a new depth-only shadow texture as cleared without clearing
// it (ShadowTexturePool's madeZeroed): the driver fills the storage of every texture it makes
// with zeros, the cleared depth. Checked on a texture made where one full of depths was just
// deleted, with malloc set as `render` sets it (test_support::RenderHeap), so that the heap
// hands back those very bytes; moments (VSM) still clear.
TEST(ShadowMap, NewShadowTexturesOfLlvmpipeHoldTheClearedDepth) {
  if (!gl::isLlvmpipe(sharedRenderer().glDescription()))
    GTEST_SKIP() << "the renderer relies on this on llvmpipe only";
  const test_support::RenderHeap heap;
  const int n = 256;
  const ShadowGroupPlan cube{{ShadowLayout::Cube, n, DepthFormat::Float32, false}, 12};
  const std::size_t texels = static_cast<std::size_t>(n) * n * 12;
  for (int round = 0; round < 2; ++round) {
    {
      ShadowTexturePool unknown;
      ShadowGroupTextures full = unknown.take(cube);
      const float depth = 0.75f;
      glClearTexImage(full.depth.get(), 0, GL_DEPTH_COMPONENT, GL_FLOAT, &depth);
      glFinish();
    }
    ShadowTexturePool zeroed(true);
    ShadowGroupTextures fresh = zeroed.take(cube);
    for (const TexelRect& written : fresh.written) EXPECT_TRUE(written.empty());
    std::vector<float> depths(texels, -1.0f);
    glGetTextureImage(fresh.depth.get(), 0, GL_DEPTH_COMPONENT, GL_FLOAT,
                      static_cast<GLsizei>(texels * sizeof(float)), depths.data());
    ASSERT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
    EXPECT_EQ(std::count(depths.begin(), depths.end(), kClearedDepth),
              static_cast<std::ptrdiff_t>(texels));
    ShadowGroupPlan vsm = cube;
    vsm.key.moments = true;
    const ShadowGroupTextures moments = zeroed.take(vsm);
    for (const TexelRect& written : moments.written)
      EXPECT_TRUE(written.x0 == 0 && written.y0 == 0 && written.x1 == n && written.y1 == n);
  }
}

TEST(ShadowMap, EachFaceHoldsTheDistancesOfItsOwnDirection) {
  // One box on each axis at a different distance, off-center; the read-back map must hold
  // each box's distance at the texel cubeLookup gives for its direction, and not at the
  // mirrored texels (which a flipped face would show).
  Scene scene;
  const int grey = addMaterial(scene, glm::vec4(0.5f));
  const glm::vec3 axes[] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  std::vector<glm::vec3> targets;
  for (int i = 0; i < 6; ++i) {
    const glm::vec3 a = axes[i];
    const glm::vec3 u = glm::abs(a.x) > 0 ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
    const glm::vec3 v = glm::cross(a, u);
    const float distance = 1.0f + 0.5f * i;
    const glm::vec3 center = a * (distance + 0.1f) + (u * 0.45f + v * 0.2f) * distance;
    addObject(scene, builder::makeBox(glm::vec3(0.1f * distance)), translate(center), grey);
    targets.push_back(center - a * (0.1f * distance));  // the box face towards the light
  }
  Light lamp = pointLight("lamp", glm::vec3(0.0f), ShadowFilter::Hard, 256);
  lamp.shadow.far = 20.0f;
  const std::vector<CubeDistances> maps = sharedRenderer().renderShadowDistances(scene, {lamp});
  ASSERT_EQ(maps.size(), 1u);
  const CubeDistances& map = maps[0];
  for (int i = 0; i < 6; ++i) {
    const CubeLookup hit = cubeLookup(targets[i]);
    ASSERT_EQ(static_cast<int>(hit.face), i);
    const int column = static_cast<int>(hit.st.x * map.resolution);
    const int row = static_cast<int>(hit.st.y * map.resolution);
    EXPECT_NEAR(map.at(hit.face, column, row), glm::length(targets[i]),
                0.01f * glm::length(targets[i]))
        << "face " << kCubeFaceNames[i];
    EXPECT_TRUE(std::isinf(map.at(hit.face, map.resolution - 1 - column, row)))
        << "face " << kCubeFaceNames[i] << " mirrored in s";
    EXPECT_TRUE(std::isinf(map.at(hit.face, column, map.resolution - 1 - row)))
        << "face " << kCubeFaceNames[i] << " mirrored in t";
  }
}

TEST(Lighting, PointLightFollowsInverseSquareInCandela) {
  // A white Lambertian plane straight under a 10 cd light at 2 m: illuminance 2.5 lux, so the
  // diffuse radiance is albedo / pi * 2.5 (a dielectric's Fresnel takes ~4% off).
  Scene scene;
  const int white = addMaterial(scene, glm::vec4(1.0f));
  addObject(scene, builder::makePlane(4.0f), glm::mat4(1.0f), white);
  Light light = pointLight("lamp", {0, 2, 0}, ShadowFilter::Pcf);
  const ViewCamera camera = lookFrom(scene, {0, 3, 0.001f}, {0, 0, 0}, 65, 65, 20.0f);
  StageTimes times;
  const Frame frame = sharedRenderer().render(scene, {light}, glm::vec3(0.0f), camera, {}, times);
  const float expected = 1.0f / 3.14159265f * 10.0f / 4.0f;
  const float center = frame.beauty.at(32, 32, 0);
  EXPECT_NEAR(center, expected, expected * 0.06f);
  EXPECT_LE(center, expected);

  // With a range, KHR_lights_punctual's window leaves nothing beyond it.
  light.range = 1.9f;
  const Frame ranged = sharedRenderer().render(scene, {light}, glm::vec3(0.0f), camera, {}, times);
  EXPECT_EQ(ranged.beauty.at(32, 32, 0), 0.0f);
}

TEST(Lighting, SpotConeAndDirectionalLight) {
  Scene scene;
  const int white = addMaterial(scene, glm::vec4(1.0f));
  addObject(scene, builder::makePlane(8.0f), glm::mat4(1.0f), white);
  const ViewCamera camera = lookFrom(scene, {0, 6, 0.001f}, {0, 0, 0}, 101, 101, 60.0f);
  const Light spot{.name = "spot",
                   .type = LightType::Spot,
                   .position = {0, 2, 0},
                   .direction = {0, -1, 0},
                   .intensity = 10.0f,
                   .innerConeAngle = 0.2f,
                   .outerConeAngle = 0.4f};  // radius tan(0.4) * 2 = 0.85 m on the floor
  StageTimes times;
  const Frame lit = sharedRenderer().render(scene, {spot}, glm::vec3(0.0f), camera, {}, times);
  EXPECT_GT(lit.beauty.at(50, 50, 0), 0.5f);  // under the spot
  // 2 m off-center is far outside the cone: black.
  const float pixelsPerMetre = 50.0f / (6.0f * std::tan(glm::radians(30.0f)));
  EXPECT_EQ(lit.beauty.at(50 + static_cast<int>(2.0f * pixelsPerMetre), 50, 0), 0.0f);

  Light sun;
  sun.name = "sun";
  sun.type = LightType::Directional;
  sun.direction = glm::normalize(glm::vec3(0, -1, -1));  // 45 degrees: N.L = 0.707
  sun.intensity = 2.0f;                                  // lux
  const Frame day = sharedRenderer().render(scene, {sun}, glm::vec3(0.0f), camera, {}, times);
  const float expected = 1.0f / 3.14159265f * 2.0f * 0.70710678f;
  EXPECT_NEAR(day.beauty.at(50, 50, 0), expected, expected * 0.08f);
}

TEST(Shadows, AlphaMaskCastsCutOutShadows) {
  // A horizontal screen with a 4x4 checker of holes over the floor, the light right above:
  // under each opaque cell the floor is in shadow, under each hole it is lit.
  Scene scene;
  const int floor = addMaterial(scene, glm::vec4(0.8f));
  addObject(scene, builder::makePlane(10.0f), glm::mat4(1.0f), floor);
  const int size = 64;
  Image image;
  image.width = image.height = size;
  image.rgba.resize(size * size * 4);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      std::uint8_t* p = &image.rgba[(y * size + x) * 4];
      p[0] = p[1] = p[2] = 200;
      p[3] = ((x / 16 + y / 16) % 2 == 0) ? 255 : 0;
    }
  scene.images.push_back(image);
  Texture texture;
  texture.image = 0;
  texture.sampler.minFilter = 0x2600;  // nearest: crisp holes
  texture.sampler.magFilter = 0x2600;
  scene.textures.push_back(texture);
  Material screen;
  screen.alphaMode = AlphaMode::Mask;
  screen.doubleSided = true;
  screen.baseColorTexture.texture = 0;
  scene.materials.push_back(screen);
  const float screenHeight = 1.0f, H = 3.0f;
  addObject(scene, builder::makePlane(2.0f), translate({0, screenHeight, 0}),
            static_cast<int>(scene.materials.size()) - 1);

  const Light light = pointLight("lamp", {0, H, 0}, ShadowFilter::Hard, 1024);
  const ViewCamera camera = lookFrom(scene, {0, 8, 2.5f}, {0, 0, 0}, 200, 200, 40.0f);
  const Frame frame = renderAovs(scene, {light}, camera);
  int shadowed = 0, lit = 0;
  for (int y = 0; y < camera.height; ++y) {
    for (int x = 0; x < camera.width; ++x) {
      const AovPixel px = pixelAt(*frame.aovs, x, y, "lamp");
      if (px.coverage < 1.0f || std::abs(px.position.y) > 1e-3f) continue;
      // Where the ray to the light crosses the screen, in the screen's UV space.
      const glm::vec3 onScreen =
          px.position + (glm::vec3(0, H, 0) - px.position) * (screenHeight / H);
      const glm::vec2 uv = (glm::vec2(onScreen.x, onScreen.z) + 1.0f) * 0.5f;
      if (uv.x <= 0.0f || uv.x >= 1.0f || uv.y <= 0.0f || uv.y >= 1.0f) continue;
      const glm::vec2 cell = uv * 4.0f;
      const glm::vec2 inCell = cell - glm::floor(cell);
      if (glm::any(glm::lessThan(inCell, glm::vec2(0.15f))) ||
          glm::any(glm::greaterThan(inCell, glm::vec2(0.85f))))
        continue;  // near a cell edge
      // Plane UVs: u along +x, v along +z (builder::makePlane); row 0 of the image is v = 0.
      const int cx = static_cast<int>(cell.x), cy = static_cast<int>(cell.y);
      const bool opaque = (cx + cy) % 2 == 0;
      if (opaque) {
        ++shadowed;
        EXPECT_LT(px.visibility, 0.01f) << "under an opaque cell at " << x << "," << y;
      } else {
        ++lit;
        EXPECT_GT(px.visibility, 0.99f) << "under a hole at " << x << "," << y;
      }
    }
  }
  EXPECT_GT(shadowed, 300);
  EXPECT_GT(lit, 300);
}

TEST(Shading, PhongUsesTheSameShadowTermsAsPbr) {
  Scene scene;
  const int white = addMaterial(scene, glm::vec4(0.8f));
  addObject(scene, builder::makePlane(8.0f), glm::mat4(1.0f), white);
  addObject(scene, builder::makeSphere(0.5f, 32, 16), translate({0, 1.5f, 0}), white);
  const std::vector<Light> lights = {pointLight("a", {0, 4, 0}, ShadowFilter::Pcf),
                                     pointLight("b", {1.5f, 3, 1}, ShadowFilter::PcfDisk)};
  const ViewCamera camera = lookFrom(scene, {0, 7, 4}, {0, 0, 0}, 96, 72);
  const Frame pbr = renderAovs(scene, lights, camera, Shading::Pbr);
  const Frame phong = renderAovs(scene, lights, camera, Shading::Phong);
  for (const char* name : {"visibility.a", "visibility.b"}) {
    const int c = pbr.aovs->channelIndex(name);
    ASSERT_GE(c, 0);
    ASSERT_EQ(phong.aovs->channelIndex(name), c);
    for (int y = 0; y < camera.height; ++y)
      for (int x = 0; x < camera.width; ++x)
        ASSERT_EQ(pbr.aovs->at(x, y, c), phong.aovs->at(x, y, c));
  }
  // The beauty differs (different BRDF), but shadowed floor stays dark in both.
  EXPECT_NE(pbr.beauty.pixels, phong.beauty.pixels);
}

TEST(Aovs, ChannelsAndManyLightsAcrossSeveralPasses) {
  // More lights than one pass reports visibility for: every light still gets its channel.
  Scene scene;
  const int white = addMaterial(scene, glm::vec4(0.8f));
  addObject(scene, builder::makePlane(8.0f), glm::mat4(1.0f), white);
  addObject(scene, builder::makeBox({0.5f, 0.5f, 0.5f}), translate({0, 0.5f, 0}), white);
  std::vector<Light> lights;
  constexpr int kShadowedLights = 16;
  for (int i = 0; i < 26; ++i) {
    const float angle = 6.2831853f * static_cast<float>(i) / 26.0f;
    Light light = pointLight("l" + std::to_string(i),
                             {3 * std::cos(angle), 1.0f + 0.1f * i, 3 * std::sin(angle)},
                             ShadowFilter::Pcf, 64);
    light.shadow.enabled = i < kShadowedLights;
    lights.push_back(light);
  }
  const ViewCamera camera = lookFrom(scene, {0, 6, 6}, {0, 0, 0}, 64, 48);
  const Frame frame = renderAovs(scene, lights, camera);
  const FloatImage& aovs = *frame.aovs;
  const std::vector<std::string> fixed = {"R",   "G",   "B",   "A",   "P.X", "P.Y",
                                          "P.Z", "N.X", "N.Y", "N.Z", "Z"};
  for (std::size_t i = 0; i < fixed.size(); ++i) EXPECT_EQ(aovs.channels[i], fixed[i]);
  ASSERT_EQ(aovs.channels.size(), fixed.size() + lights.size());
  // Shadowed lights leave some floor in shadow behind the box; unshadowed ones never do.
  for (int i = 0; i < 26; ++i) {
    const int c = aovs.channelIndex("visibility.l" + std::to_string(i));
    float minimum = 1.0f;
    for (int y = 0; y < camera.height; ++y)
      for (int x = 0; x < camera.width; ++x) minimum = std::min(minimum, aovs.at(x, y, c));
    if (i < kShadowedLights)
      EXPECT_LT(minimum, 0.01f) << "light " << i;
    else
      EXPECT_EQ(minimum, 1.0f) << "light " << i;
  }
  // Camera distance and normals are consistent with the geometry.
  const AovPixel center = pixelAt(aovs, 32, 24, "l0");
  const float z = aovs.at(32, 24, aovs.channelIndex("Z"));
  EXPECT_NEAR(z, glm::length(center.position - camera.eye), 1e-3f);
  EXPECT_NEAR(glm::length(center.normal), 1.0f, 1e-3f);
  EXPECT_GT(glm::dot(center.normal, camera.eye - center.position), 0.0f);
}

// 300 shadowed point lights in a ring around a post: each light's shadow of the post falls on
// the floor opposite it, so every visibility channel has shadow exactly there.
TEST(Shadows, HundredsOfShadowedPointLightsInOneFrame) {
  Scene scene;
  const int white = addMaterial(scene, glm::vec4(0.8f));
  addObject(scene, builder::makePlane(12.0f), glm::mat4(1.0f), white);
  addObject(scene, builder::makeBox({0.2f, 1.0f, 0.2f}), translate({0, 1.0f, 0}), white);
  std::vector<Light> lights;
  constexpr int kLights = 300;
  for (int i = 0; i < kLights; ++i) {
    const float angle = 6.2831853f * static_cast<float>(i) / kLights;
    Light light =
        pointLight("l" + std::to_string(i), {2 * std::cos(angle), 1.5f, 2 * std::sin(angle)},
                   ShadowFilter::Hard, 32);
    light.intensity = 0.05f;
    lights.push_back(light);
  }
  const ViewCamera camera = lookFrom(scene, {0, 9, 0.01f}, {0, 0, 0}, 96, 96);
  const Frame frame = renderAovs(scene, lights, camera);
  const FloatImage& aovs = *frame.aovs;
  for (int i = 0; i < kLights; i += 7) {
    const float angle = 6.2831853f * static_cast<float>(i) / kLights;
    // Behind the post seen from the light, on the floor: shadowed; beside the light: lit.
    const glm::vec3 behind{-0.6f * std::cos(angle), 0.0f, -0.6f * std::sin(angle)};
    const glm::vec3 beside{1.0f * std::cos(angle), 0.0f, 1.0f * std::sin(angle)};
    const int c = aovs.channelIndex("visibility.l" + std::to_string(i));
    const glm::ivec2 b = project(camera, behind), l = project(camera, beside);
    EXPECT_EQ(aovs.at(b.x, b.y, c), 0.0f) << "light " << i;
    EXPECT_EQ(aovs.at(l.x, l.y, c), 1.0f) << "light " << i;
  }
}

// A thousand unshadowed lights with ranges over a floor: the light-count debug view shows, per
// pixel, how many lights reach it; screen tiles must not drop any (nor add any).
TEST(Lighting, AThousandRangedLightsReachExactlyThePixelsInTheirRange) {
  Scene scene;
  addObject(scene, builder::makePlane(20.0f), glm::mat4(1.0f), addMaterial(scene, glm::vec4(0.8f)));
  std::vector<Light> lights;
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-9.0f, 9.0f);
  for (int i = 0; i < 1000; ++i) {
    Light light =
        pointLight("l" + std::to_string(i), {u(rng), 0.3f, u(rng)}, ShadowFilter::Pcf, 16);
    light.shadow.enabled = false;
    light.range = 0.8f;
    light.intensity = 1.0f;
    lights.push_back(light);
  }
  const ViewCamera camera = lookFrom(scene, {0, 14, 0.01f}, {0, 0, 0}, 128, 128, 70.0f);
  StageTimes times;
  RenderSettings settings;
  settings.aovs = true;
  const Frame frame =
      sharedRenderer().render(scene, lights, glm::vec3(0.0f), camera, settings, times);
  settings.aovs = false;
  settings.debugView = DebugView::LightCount;
  const Frame count =
      sharedRenderer().render(scene, lights, glm::vec3(0.0f), camera, settings, times);
  int checked = 0, reached = 0;
  for (int y = 0; y < camera.height; y += 3) {
    for (int x = 0; x < camera.width; x += 3) {
      const AovPixel px = pixelAt(*frame.aovs, x, y, "l0");
      if (px.coverage < 1.0f) continue;
      int expected = 0;
      bool borderline = false;
      for (const Light& light : lights) {
        const float d = glm::length(light.position - px.position);
        borderline |= std::abs(d - light.range) < 1e-3f;
        expected += d < light.range ? 1 : 0;
      }
      if (borderline) continue;
      EXPECT_EQ(std::lround(count.beauty.at(x, y, 0) * 1000.0f), expected) << x << "," << y;
      reached += expected > 0 ? 1 : 0;
      ++checked;
    }
  }
  EXPECT_GT(checked, 1000);
  EXPECT_GT(reached, 300);
}

// Shadow maps are cleared only where they may hold something: where the last pass drew and
// where this pass's casters may draw. A lone box (its bounding sphere covers part of one face)
// that moves between two renders of one renderer, whose maps come back from its pool, leaves
// no depth where it was, in a point light's cube face and in a spot light's map: every depth
// the second render's maps hold is as far as the box is now.
TEST(Shadows, ACasterThatMovedBetweenRendersLeavesNoDepthWhereItWas) {
  Light lamp = pointLight("lamp", {0, 0, 0}, ShadowFilter::Hard, 128);
  Light spot = pointLight("spot", {0, 0, 0}, ShadowFilter::Hard, 128);
  spot.type = LightType::Spot;
  spot.direction = {0, -1, 0};
  spot.outerConeAngle = 0.7f;
  const glm::vec3 was{0.3f, -1.5f, 0.2f}, is{-0.5f, -3.0f, -0.4f};  // both below: face -Y
  RenderSettings settings;
  settings.readShadowMaps = true;
  StageTimes times;
  const Scene before = loneBoxAt(was), after = loneBoxAt(is);
  const ViewCamera camera = lookFrom(after, {0, 2, 4}, {0, -2, 0}, 32, 24);
  const Frame first =
      sharedRenderer().render(before, {lamp, spot}, glm::vec3(0.0f), camera, settings, times);
  const Frame frame =
      sharedRenderer().render(after, {lamp, spot}, glm::vec3(0.0f), camera, settings, times);
  // No part of the moved box is nearer than its center's depth less its bounding radius.
  const float radius = 0.2f * std::sqrt(3.0f);
  const auto depths = [](const Frame& f) {
    std::vector<float> all = f.planarShadowMaps.at(0).distances;
    for (const std::vector<float>& face : f.shadowMaps.at(0).distances.faces)
      all.insert(all.end(), face.begin(), face.end());
    return all;
  };
  const auto countBelow = [](const std::vector<float>& values, float limit) {
    return std::count_if(values.begin(), values.end(), [&](float v) { return v < limit; });
  };
  // The first render drew the box where it was, the second only where it is.
  EXPECT_GT(countBelow(depths(first), glm::length(was) + radius), 100);
  EXPECT_EQ(countBelow(depths(frame), -is.y - radius), 0);
  EXPECT_GT(countBelow(depths(frame), glm::length(is) + radius), 100);
}

// Renderer::prepare() clears the shadow maps it makes ready, so that the render which takes
// them need not: maps that come back from the pool holding an earlier render's depths hold none
// of them after it. (A resolution no other test uses keeps the pool's other maps out of it.)
TEST(Shadows, PreparedMapsHoldNoDepthOfAnEarlierRender) {
  const std::vector<Light> lamp = {pointLight("lamp", {0, 0, 0}, ShadowFilter::Hard, 136)};
  const glm::vec3 was{0.3f, -1.5f, 0.2f}, is{-0.5f, -3.0f, -0.4f};  // both below: face -Y
  const float radius = 0.2f * std::sqrt(3.0f);
  const auto countBelow = [](const CubeDistances& cube, float limit) {
    long n = 0;
    for (const std::vector<float>& face : cube.faces)
      n += std::count_if(face.begin(), face.end(), [&](float v) { return v < limit; });
    return n;
  };
  Renderer& renderer = sharedRenderer();
  const std::vector<CubeDistances> first = renderer.renderShadowDistances(loneBoxAt(was), lamp);
  EXPECT_GT(countBelow(first.at(0), glm::length(was) + radius), 100);
  EXPECT_GT(renderer.prepare(lamp, 32, 24, RenderSettings{}, 64.0), 0.0);
  const std::vector<CubeDistances> second = renderer.renderShadowDistances(loneBoxAt(is), lamp);
  EXPECT_EQ(countBelow(second.at(0), -is.y - radius), 0);
  EXPECT_GT(countBelow(second.at(0), glm::length(is) + radius), 100);
}

// A render draws the same picture whether the renderer was prepared for it or not; prepare()
// keeps to its budget, and passes over what render() refuses. Two scenes take turns, so that each
// render misses the shadow cache and takes its maps from the pool: the prepared ones when there
// are.
TEST(Shadows, PreparingChangesNoPixelAndRefusesNothing) {
  const auto sceneWithBoxAt = [](glm::vec3 at) {
    Scene scene;
    const int white = addMaterial(scene, glm::vec4(0.8f));
    addObject(scene, builder::makePlane(8.0f), glm::mat4(1.0f), white);
    addObject(scene, builder::makeBox({0.5f, 0.5f, 0.5f}), translate(at), white);
    return scene;
  };
  const Scene a = sceneWithBoxAt({0, 0.5f, 0}), b = sceneWithBoxAt({1.0f, 0.5f, -1.0f});
  Light spot = pointLight("spot", {1.5f, 3.0f, 1.0f}, ShadowFilter::Pcf, 200);
  spot.type = LightType::Spot;
  spot.direction = glm::normalize(glm::vec3(-1.5f, -3.0f, -1.0f));
  spot.outerConeAngle = 0.7f;
  const std::vector<Light> lights = {
      pointLight("lamp", {-1.5f, 2.0f, 1.0f}, ShadowFilter::Vsm, 200), spot};
  const ViewCamera camera = lookFrom(a, {3, 4, 5}, {0, 0, 0}, 80, 60);
  RenderSettings settings;
  StageTimes times;
  Renderer& renderer = sharedRenderer();
  const auto draw = [&](const Scene& scene) {
    return renderer.render(scene, lights, glm::vec3(0.02f), camera, settings, times).beauty.pixels;
  };
  const FloatPixels plainA = draw(a), plainB = draw(b);
  // A 200^2 cube map and spot map, depth and moments, and an 80x60 beauty target.
  const double bytes = renderer.prepare(lights, camera.width, camera.height, settings, 64.0);
  EXPECT_GT(bytes, 6.0 * 200 * 200 * 4);
  EXPECT_EQ(draw(a), plainA);
  // Other lights, another size.
  EXPECT_GT(renderer.prepare({lights.front()}, 40, 30, settings, 64.0), 0.0);
  EXPECT_EQ(draw(b), plainB);
  // Where the lighting pass may encode an 8-bit beauty, the float targets are prepared too (the
  // scene decides which it takes), and either frame is the one drawn without preparing.
  RenderSettings encoded = settings;
  encoded.srgb8Exposure = 0.0f;
  const auto encode = [&](const Scene& scene) {
    return renderer.render(scene, lights, glm::vec3(0.02f), camera, encoded, times).srgb8->rgb;
  };
  const std::vector<std::uint8_t> encodedA = encode(a);
  EXPECT_EQ(renderer.prepare(lights, camera.width, camera.height, encoded, 64.0) - bytes,
            80.0 * 60.0 * (4 + 4));  // RGBA8UI and depth
  EXPECT_EQ(encode(a), encodedA);
  renderer.prepare(lights, camera.width, camera.height, encoded, 64.0);
  EXPECT_EQ(draw(b), plainB);

  // Above the budget nothing is prepared, nor below the minimum (where a caller's memory
  // warm-up holds the frame's pages); what render() refuses is neither prepared nor thrown.
  const double mebibytes = bytes / (1024.0 * 1024.0);
  EXPECT_EQ(renderer.prepare(lights, camera.width, camera.height, settings, 0.999 * mebibytes),
            0.0);
  EXPECT_EQ(
      renderer.prepare(lights, camera.width, camera.height, settings, 64.0, 1.001 * mebibytes),
      0.0);
  EXPECT_EQ(
      renderer.prepare(lights, camera.width, camera.height, settings, 64.0, 0.999 * mebibytes),
      bytes);
  std::vector<Light> huge = lights;
  huge.front().shadow.resolution = renderer.limits().maxCubeMapSize * 2;
  EXPECT_EQ(renderer.prepare(huge, camera.width, camera.height, settings, 64.0), 0.0);
  EXPECT_THROW(renderer.render(a, huge, glm::vec3(0.02f), camera, settings, times), InputError);
  RenderSettings tight = settings;
  tight.maxShadowMemoryMiB = 0.01;
  EXPECT_EQ(renderer.prepare(lights, camera.width, camera.height, tight, 64.0), 0.0);
  EXPECT_THROW(renderer.render(a, lights, glm::vec3(0.02f), camera, tight, times), InputError);
}

// The lighting pass reads its lights from uniform blocks, or from storage buffers past what the
// blocks hold, and loops over every light, or over a cluster's lights once some light has a
// range. Dark extra lights switch each path on without adding light: every path draws the
// picture of the same three shadowed lights (point, spot, directional).
TEST(Lighting, EveryWayOfReadingTheLightsDrawsTheSamePicture) {
  Scene scene;
  const int white = addMaterial(scene, glm::vec4(0.8f));
  addObject(scene, builder::makePlane(8.0f), glm::mat4(1.0f), white);
  addObject(scene, builder::makeBox({0.5f, 0.5f, 0.5f}), translate({0, 0.5f, 0}), white);
  Light spot = pointLight("spot", {1.5f, 3.0f, 1.0f}, ShadowFilter::PcfDisk, 256);
  spot.type = LightType::Spot;
  spot.direction = glm::normalize(glm::vec3(-1.5f, -3.0f, -1.0f));
  spot.outerConeAngle = 0.7f;
  Light sun = pointLight("sun", {0, 0, 0}, ShadowFilter::Pcf, 256);
  sun.type = LightType::Directional;
  sun.direction = glm::normalize(glm::vec3(1.0f, -2.0f, 0.5f));
  sun.intensity = 1.0f;
  const std::vector<Light> lit = {pointLight("lamp", {-1.5f, 2.0f, 1.0f}, ShadowFilter::Pcf, 256),
                                  spot, sun};
  const auto withDark = [&](int count, bool ranged) {
    std::vector<Light> lights = lit;
    for (int i = 0; i < count; ++i) {
      Light dark = pointLight("dark" + std::to_string(i), {0.1f * i, 1.5f, 0}, ShadowFilter::Pcf);
      dark.shadow.enabled = false;
      dark.intensity = 0.0f;
      dark.range = ranged ? 3.0f : 0.0f;
      lights.push_back(dark);
    }
    return lights;
  };
  const ViewCamera camera = lookFrom(scene, {3, 4, 5}, {0, 0, 0}, 96, 72);
  StageTimes times;
  const auto draw = [&](const std::vector<Light>& lights) {
    return sharedRenderer().render(scene, lights, glm::vec3(0.02f), camera, {}, times).beauty;
  };
  const FloatImage reference = draw(lit);
  float brightest = 0.0f;
  for (const float v : reference.pixels) brightest = std::max(brightest, v);
  ASSERT_GT(brightest, 0.1f);
  const int manyLights = contract::kMaxUniformLights;  // with `lit`: past the uniform block
  for (const auto& [count, ranged, path] :
       {std::tuple{1, true, "uniform blocks, clusters"},
        std::tuple{manyLights, false, "storage buffers, every light"},
        std::tuple{manyLights, true, "storage buffers, clusters"}}) {
    const FloatImage picture = draw(withDark(count, ranged));
    ASSERT_EQ(picture.pixels.size(), reference.pixels.size());
    float largest = 0.0f;
    for (std::size_t i = 0; i < picture.pixels.size(); ++i)
      largest = std::max(largest, std::abs(picture.pixels[i] - reference.pixels[i]));
    EXPECT_LE(largest, 1e-5f * brightest) << path;
  }
}

// A box on a plane, both white: the scene of the lighting-variant tests below.
Scene boxOnAPlane() {
  Scene scene;
  const int white = addMaterial(scene, glm::vec4(0.8f));
  addObject(scene, builder::makePlane(8.0f), glm::mat4(1.0f), white);
  addObject(scene, builder::makeBox({0.5f, 0.5f, 0.5f}), translate({0, 0.5f, 0}), white);
  return scene;
}

// The lighting pass is compiled without the spot cone and the directional case when the frame
// has no such light: a frame of point lights draws the same either way.
TEST(Lighting, PointLightsDrawTheSameWithOrWithoutTheOtherTypesCompiledIn) {
  const Scene scene = boxOnAPlane();
  const Light lamp = pointLight("lamp", {-1.5f, 2.0f, 1.0f}, ShadowFilter::Pcf, 256);
  Light spot = pointLight("spot", {1.5f, 3.0f, 1.0f}, ShadowFilter::Pcf);
  spot.type = LightType::Spot;
  spot.direction = glm::vec3(0, -1, 0);
  Light sun = pointLight("sun", {0, 0, 0}, ShadowFilter::Pcf);
  sun.type = LightType::Directional;
  sun.direction = glm::vec3(0, -1, 0);
  for (Light* dark : {&spot, &sun}) {
    dark->intensity = 0.0f;
    dark->shadow.enabled = false;
  }

  const LightingFeatures points = lightingFeatures({lamp}, DebugView::None);
  EXPECT_FALSE(points.spotLights);
  EXPECT_FALSE(points.directionalLights);
  const LightingFeatures all = lightingFeatures({lamp, spot, sun}, DebugView::None);
  EXPECT_TRUE(all.spotLights);
  EXPECT_TRUE(all.directionalLights);

  const ViewCamera camera = lookFrom(scene, {3, 4, 5}, {0, 0, 0}, 96, 72);
  StageTimes times;
  const auto draw = [&](const std::vector<Light>& lights) {
    return sharedRenderer().render(scene, lights, glm::vec3(0.02f), camera, {}, times).beauty;
  };
  const FloatImage lean = draw({lamp});
  const FloatImage full = draw({lamp, spot, sun});
  ASSERT_EQ(lean.pixels.size(), full.pixels.size());
  float brightest = 0.0f, largest = 0.0f;
  for (std::size_t i = 0; i < lean.pixels.size(); ++i) {
    brightest = std::max(brightest, full.pixels[i]);
    largest = std::max(largest, std::abs(lean.pixels[i] - full.pixels[i]));
  }
  ASSERT_GT(brightest, 0.1f);
  EXPECT_LE(largest, 1e-6f * brightest);
}

// The lighting pass's shadow sampler arrays are sized to the frame's shadow groups (one slot:
// a constant index). A shadowed light draws the same picture whichever slot its group takes and
// however many the arrays have: alone (one slot), after two dark point lights whose maps have
// other resolutions (its group in the third cube slot), and beside dark spot and directional
// lights with maps of their own (a cube slot and two planar ones: the arrays of both layouts
// get two slots, since llvmpipe also indexes a cube array with a planar slot).
TEST(Lighting, AShadowedLightDrawsTheSameWhicheverSamplerSlotItsGroupTakes) {
  const Scene scene = boxOnAPlane();
  const Light lamp = pointLight("lamp", {-1.5f, 2.0f, 1.0f}, ShadowFilter::Pcf, 256);
  Light small = pointLight("small", {1.5f, 2.0f, -1.0f}, ShadowFilter::Pcf, 128);
  Light smaller = pointLight("smaller", {0.0f, 3.0f, 2.0f}, ShadowFilter::Pcf, 64);
  Light spot = pointLight("spot", {1.5f, 3.0f, 1.0f}, ShadowFilter::Vsm, 128);
  spot.type = LightType::Spot;
  spot.direction = glm::vec3(0, -1, 0);
  Light sun = pointLight("sun", {0, 0, 0}, ShadowFilter::Pcf, 128);
  sun.type = LightType::Directional;
  sun.direction = glm::vec3(0.3f, -1, 0.2f);
  for (Light* dark : {&small, &smaller, &spot, &sun}) dark->intensity = 0.0f;

  ShadowAtlasPlan atlas;
  atlas.groups = {{{ShadowLayout::Cube, 256}, 6},
                  {{ShadowLayout::Planar, 128}, 1},
                  {{ShadowLayout::Planar, 64}, 1}};
  LightingFeatures features;
  setShadowSlots(atlas, features);
  EXPECT_EQ(features.shadowSlots, 2);
  setShadowSlots({}, features);
  EXPECT_EQ(features.shadowSlots, 0);

  const ViewCamera camera = lookFrom(scene, {3, 4, 5}, {0, 0, 0}, 96, 72);
  StageTimes times;
  const auto draw = [&](const std::vector<Light>& lights) {
    return sharedRenderer().render(scene, lights, glm::vec3(0.02f), camera, {}, times).beauty;
  };
  const FloatImage alone = draw({lamp});
  float brightest = 0.0f;
  for (float v : alone.pixels) brightest = std::max(brightest, v);
  ASSERT_GT(brightest, 0.1f);
  const std::vector<std::vector<Light>> frames = {
      {small, smaller, lamp}, {lamp, spot, sun}, {spot, small, sun, lamp}};
  for (const std::vector<Light>& lights : frames) {
    const FloatImage image = draw(lights);
    ASSERT_EQ(image.pixels.size(), alone.pixels.size());
    float largest = 0.0f;
    for (std::size_t i = 0; i < alone.pixels.size(); ++i)
      largest = std::max(largest, std::abs(alone.pixels[i] - image.pixels[i]));
    EXPECT_LE(largest, 1e-6f * brightest)
        << lights.size() << " lights, the first " << lights[0].name;
  }
}

// A white sphere over a white plane, and a spot light shining at it from above one side.
Scene sphereOverPlane() {
  Scene scene;
  const int white = addMaterial(scene, glm::vec4(0.8f));
  addObject(scene, builder::makePlane(8.0f), glm::mat4(1.0f), white);
  addObject(scene, builder::makeSphere(0.5f, 24, 12), translate({0, 1, 0}), white);
  return scene;
}

Light sideSpot() {
  Light spot = pointLight("spot", {1, 3, 0}, ShadowFilter::Pcf, 256);
  spot.type = LightType::Spot;
  spot.direction = glm::normalize(glm::vec3(-1, -3, 0));
  spot.outerConeAngle = 0.8f;
  return spot;
}

// Batch jobs that render one scene from several cameras keep the point and spot maps of the
// previous render; directional maps follow the camera and are rendered again. The reused maps
// give the same images as freshly rendered ones.
TEST(Shadows, StaticShadowMapsAreReusedForTheSameSceneAndLights) {
  Scene scene = sphereOverPlane();
  const int white = 0;  // sphereOverPlane()'s material
  const Light spot = sideSpot();
  Light sun = pointLight("sun", {0, 0, 0}, ShadowFilter::Pcf, 256);
  sun.type = LightType::Directional;
  sun.direction = glm::normalize(glm::vec3(0.3f, -1, 0.2f));
  sun.intensity = 1.0f;
  const std::vector<Light> lights = {pointLight("lamp", {0, 3, 0}, ShadowFilter::Pcf, 128), spot,
                                     sun};
  Scene other = scene;
  addObject(other, builder::makeBox(glm::vec3(0.3f)), translate({2, 0.3f, 2}), white);
  const ViewCamera first = lookFrom(scene, {0, 6, 4}, {0, 0, 0}, 64, 48);
  const ViewCamera second = lookFrom(scene, {4, 5, 0}, {0, 0, 0}, 64, 48);
  StageTimes times;
  Renderer& renderer = sharedRenderer();
  const Frame a = renderer.render(scene, lights, glm::vec3(0.03f), first, {}, times);
  const Frame reused = renderer.render(scene, lights, glm::vec3(0.03f), second, {}, times);
  EXPECT_EQ(reused.shadowMapsReused, 2);    // lamp and spot
  EXPECT_EQ(reused.shadowMapsRendered, 1);  // the sun
  const Frame changed = renderer.render(other, lights, glm::vec3(0.03f), second, {}, times);
  EXPECT_EQ(changed.shadowMapsReused, 0);  // another scene: everything rendered
  Light moved = lights[0];
  moved.position.x += 0.1f;
  const Frame movedLight =
      renderer.render(other, {moved, lights[1], lights[2]}, glm::vec3(0.03f), second, {}, times);
  EXPECT_EQ(movedLight.shadowMapsReused, 1);  // the spot only
  renderer.render(other, lights, glm::vec3(0.03f), second, {}, times);
  const Frame fresh = renderer.render(scene, lights, glm::vec3(0.03f), second, {}, times);
  EXPECT_EQ(fresh.shadowMapsReused, 0);
  EXPECT_EQ(fresh.beauty.pixels, reused.beauty.pixels);
}

// A cut-out caster's texture shapes its shadow, and the renderer hashes its pixels once per
// scene revision (as it takes meshes and textures): a texture changed in place under the same
// revision is taken as the one it hashed, and the shadow map is kept; with revision 0 or a new
// one the change is seen and the map rendered again.
TEST(Shadows, ACutOutCastersPixelsAreHashedOncePerSceneRevision) {
  Scene scene = sphereOverPlane();
  Image image;
  image.width = image.height = 4;
  image.rgba.assign(4 * 4 * 4, 255);
  scene.images.push_back(image);
  scene.textures.push_back(Texture{0, {}});
  const int cutOut = addMaterial(scene, glm::vec4(0.8f));
  scene.materials[static_cast<std::size_t>(cutOut)].alphaMode = AlphaMode::Mask;
  scene.materials[static_cast<std::size_t>(cutOut)].baseColorTexture.texture = 0;
  scene.meshes[1].material = cutOut;  // the sphere
  scene.revision = newSceneRevision();
  const std::vector<Light> lights = {pointLight("lamp", {0, 3, 0}, ShadowFilter::Pcf, 128)};
  const ViewCamera camera = lookFrom(scene, {0, 6, 4}, {0, 0, 0}, 64, 48);
  StageTimes times;
  Renderer& renderer = sharedRenderer();
  renderer.render(scene, lights, glm::vec3(0.03f), camera, {}, times);
  EXPECT_EQ(renderer.render(scene, lights, glm::vec3(0.03f), camera, {}, times).shadowMapsReused,
            1);
  for (std::size_t texel = 3; texel < scene.images[0].rgba.size(); texel += 4)
    scene.images[0].rgba[texel] = 0;  // the whole sphere cut out: it casts no shadow now
  EXPECT_EQ(renderer.render(scene, lights, glm::vec3(0.03f), camera, {}, times).shadowMapsReused,
            1);
  scene.revision = 0;
  EXPECT_EQ(renderer.render(scene, lights, glm::vec3(0.03f), camera, {}, times).shadowMapsReused,
            0);
  scene.revision = newSceneRevision();
  renderer.render(scene, lights, glm::vec3(0.03f), camera, {}, times);
  scene.images[0].rgba.assign(scene.images[0].rgba.size(), 255);
  scene.revision = newSceneRevision();
  EXPECT_EQ(renderer.render(scene, lights, glm::vec3(0.03f), camera, {}, times).shadowMapsReused,
            0);
}

namespace {

// 60 boxes and spheres on a floor under 40 point lights with 32^2 maps and ranges of 3 m, placed
// by `seed`: enough lights that their CPU work is spread over threads.
std::pair<Scene, std::vector<Light>> manyLightsOnBlocks(unsigned seed) {
  Scene scene;
  const int grey = addMaterial(scene, glm::vec4(0.6f));
  addObject(scene, builder::makePlane(12.0f), glm::mat4(1.0f), grey);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-5.0f, 5.0f);
  for (int i = 0; i < 60; ++i)
    addObject(scene, i % 2 ? builder::makeSphere(0.25f, 12, 6) : builder::makeBox(glm::vec3(0.25f)),
              translate({u(rng), 0.4f, u(rng)}), grey);
  std::vector<Light> lights;
  for (int i = 0; i < 40; ++i) {
    Light light =
        pointLight("l" + std::to_string(i), {u(rng), 1.2f, u(rng)}, ShadowFilter::Pcf, 32);
    light.range = 3.0f;
    lights.push_back(light);
  }
  return {std::move(scene), std::move(lights)};
}

}  // namespace

// From 16 lights on, the batched pass finds each light's draws on several threads: the maps
// are still six's, texel for texel.
TEST(ShadowMap, TheBatchedPassOfManyLightsWritesSixsTexels) {
  const auto [scene, lights] = manyLightsOnBlocks(11);
  const auto six = sharedRenderer().renderShadowDistances(scene, lights, ShadowPassStrategy::Six);
  const auto batched =
      sharedRenderer().renderShadowDistances(scene, lights, ShadowPassStrategy::Batched);
  ASSERT_EQ(batched.size(), six.size());
  for (std::size_t l = 0; l < six.size(); ++l)
    EXPECT_EQ(differingTexels(six[l], batched[l]), 0) << "light " << l;
}

// One GL context drawing 16 maps or more (a GPU's frame) works out the lights' culling and
// draw lists ahead, on several threads: each light's map is the one it gets drawn among fewer
// lights, whose work is done between their GL calls.
TEST(ShadowMap, ManyLightsPlannedAheadInOneContextWriteTheirOwnTexels) {
  const auto [scene, lights] = manyLightsOnBlocks(5);
  for (const ShadowPassStrategy strategy :
       {ShadowPassStrategy::Six, ShadowPassStrategy::Instanced}) {
    const auto together = sharedRenderer().renderShadowDistances(scene, lights, strategy, false);
    ASSERT_EQ(together.size(), lights.size());
    for (std::size_t first = 0; first < lights.size(); first += 10) {
      const std::vector<Light> few(lights.begin() + static_cast<std::ptrdiff_t>(first),
                                   lights.begin() + static_cast<std::ptrdiff_t>(first + 10));
      const auto alone = sharedRenderer().renderShadowDistances(scene, few, strategy, false);
      ASSERT_EQ(alone.size(), few.size());
      for (std::size_t l = 0; l < few.size(); ++l)
        EXPECT_EQ(differingTexels(together[first + l], alone[l]), 0) << "light " << first + l;
    }
  }
}

// The batched pass across frames: maps of lights that did not move are kept in the texture it
// draws the others into, other textures' lights (vsm, a spot) are drawn one by one, and every
// frame is the one the default pass draws.
TEST(ShadowMap, TheBatchedPassDrawsWhatSixDrawsAcrossFramesAndLightKinds) {
  Scene scene;
  const int grey = addMaterial(scene, glm::vec4(0.6f));
  addObject(scene, builder::makePlane(8.0f), glm::mat4(1.0f), grey);
  for (int i = 0; i < 9; ++i)
    addObject(scene, i % 2 ? builder::makeSphere(0.3f, 16, 8) : builder::makeBox(glm::vec3(0.3f)),
              translate({-1.5f + 1.5f * static_cast<float>(i % 3), 0.5f,
                         -1.5f + 1.5f * static_cast<float>(i / 3)}),
              grey);
  std::vector<Light> lights;
  for (int i = 0; i < 4; ++i)
    lights.push_back(pointLight("p" + std::to_string(i),
                                {-2.0f + 1.3f * static_cast<float>(i), 2.0f, 0.7f},
                                ShadowFilter::Pcf, 128));
  lights[3].shadow.cullFace = CullFace::Back;  // a batch of its own in the same texture
  Light vsm = pointLight("vsm", {0.5f, 2.5f, -1.0f}, ShadowFilter::Vsm, 128);
  lights.push_back(vsm);
  lights.push_back(sideSpot());
  for (Light& light : lights) light.intensity = 3.0f;
  Scene other = scene;
  addObject(other, builder::makeBox(glm::vec3(0.4f)), translate({0.7f, 0.4f, 1.1f}), grey);
  std::vector<Light> moved = lights;
  moved[1].position.x += 0.3f;
  // Last, the first scene again with the four point lights in one batch: the whole texture is
  // cleared at once, and the box of the scene before must not stay in it.
  std::vector<Light> oneBatch = moved;
  oneBatch[3].shadow.cullFace = CullFace::None;
  const ViewCamera camera = lookFrom(scene, {0, 6, 5}, {0, 0, 0}, 96, 72);

  const auto sequence = [&](ShadowPassStrategy strategy) {
    RenderSettings settings;
    settings.shadowPass = strategy;
    StageTimes times;
    Renderer& renderer = sharedRenderer();
    renderer.render(other, {}, glm::vec3(0.03f), camera, settings, times);  // nothing to reuse
    std::vector<Frame> frames;
    for (const auto& [s, l] :
         {std::pair{&scene, &lights}, std::pair{&scene, &moved}, std::pair{&other, &moved},
          std::pair{&other, &moved}, std::pair{&scene, &oneBatch}})
      frames.push_back(renderer.render(*s, *l, glm::vec3(0.03f), camera, settings, times));
    return frames;
  };
  const std::vector<Frame> six = sequence(ShadowPassStrategy::Six);
  const std::vector<Frame> batched = sequence(ShadowPassStrategy::Batched);
  // The second frame keeps five maps, the fourth all six; the fifth draws the four point
  // lights' maps in one batch (and the vsm and spot maps again: the scene changed).
  EXPECT_EQ(batched[1].shadowMapsReused, 5);
  EXPECT_EQ(batched[3].shadowMapsReused, 6);
  for (std::size_t f = 0; f < six.size(); ++f) {
    EXPECT_EQ(batched[f].shadowMapsRendered, six[f].shadowMapsRendered) << f;
    EXPECT_EQ(batched[f].flatCastersLeftOut, six[f].flatCastersLeftOut) << f;
    EXPECT_EQ(batched[f].beauty.pixels, six[f].beauty.pixels) << "frame " << f;
  }
}

// Masks without a picture (`batch --no-png --masks`) draw the ids alone: no shadow map, no
// beauty. Their ids are those of a lit frame, and the next lit frame still finds the maps the
// last lit one left.
TEST(Shadows, ObjectIdsWithoutTheBeautyDrawNoShadowMapsAndKeepTheCache) {
  const Scene scene = sphereOverPlane();
  const Light spot = sideSpot();
  const std::vector<Light> lights = {pointLight("lamp", {0, 3, 0}, ShadowFilter::Pcf, 128), spot};
  const ViewCamera camera = lookFrom(scene, {0, 6, 4}, {0, 0, 0}, 64, 48);
  Renderer& renderer = sharedRenderer();
  auto stageNames = [](const StageTimes& times) {
    std::vector<std::string> names;
    for (const auto& stage : times.stages()) names.push_back(stage.first);
    return names;
  };
  auto has = [](const std::vector<std::string>& names, const char* name) {
    return std::find(names.begin(), names.end(), name) != names.end();
  };
  RenderSettings lit;
  requestObjectIds(lit);
  RenderSettings idsOnly = lit;
  idsOnly.beauty = false;
  StageTimes litTimes, idTimes, againTimes;
  const Frame a = renderer.render(scene, lights, glm::vec3(0.03f), camera, lit, litTimes);
  const Frame ids = renderer.render(scene, lights, glm::vec3(0.03f), camera, idsOnly, idTimes);
  const Frame again = renderer.render(scene, lights, glm::vec3(0.03f), camera, lit, againTimes);
  ASSERT_TRUE(a.objectIds && ids.objectIds);
  EXPECT_EQ(ids.objectIds->pixels, a.objectIds->pixels);
  EXPECT_TRUE(ids.beauty.pixels.empty());
  EXPECT_FALSE(ids.srgb8);
  EXPECT_EQ(ids.shadowMapsRendered + ids.shadowMapsReused, 0);
  EXPECT_TRUE(has(stageNames(litTimes), "shadow maps"));
  EXPECT_FALSE(has(stageNames(idTimes), "shadow maps"));
  EXPECT_FALSE(has(stageNames(idTimes), "lighting"));
  EXPECT_TRUE(has(stageNames(idTimes), "layers"));
  EXPECT_EQ(again.shadowMapsReused, 2);
  EXPECT_EQ(again.srgb8.has_value(), a.srgb8.has_value());
  EXPECT_EQ(again.beauty.pixels, a.beauty.pixels);

  // What needs the lit frame draws it, with or without a beauty asked for.
  for (auto ask : {+[](RenderSettings& s) { s.readShadowMaps = true; },
                   +[](RenderSettings& s) { s.lightViewSize = 16; },
                   +[](RenderSettings& s) { s.debugView = DebugView::Shadow; },
                   +[](RenderSettings& s) { s.objectIds = false; }}) {
    RenderSettings settings = idsOnly;
    ask(settings);
    StageTimes times;
    const Frame frame = renderer.render(scene, lights, glm::vec3(0.03f), camera, settings, times);
    EXPECT_EQ(frame.beauty.width, camera.width);
    EXPECT_TRUE(has(stageNames(times), "lighting"));
  }
}

// A frame with masks writes the ids beside its beauty, 8-bit or float, in the same draws: they
// must be the id pass's (masked cut-outs and overlaps included), and the pictures those of
// frames without masks.
TEST(Shadows, ObjectIdsBesideTheBeautyAreTheIdPasss) {
  Scene scene = sphereOverPlane();
  const int kept = addMaterial(scene, glm::vec4(0.9f, 0.2f, 0.2f, 0.8f));
  const int cut = addMaterial(scene, glm::vec4(0.2f, 0.9f, 0.2f, 0.3f));
  for (const int material : {kept, cut}) {
    scene.materials[static_cast<std::size_t>(material)].alphaMode = AlphaMode::Mask;
    scene.materials[static_cast<std::size_t>(material)].alphaCutoff = 0.5f;
  }
  addObject(scene, builder::makeBox(glm::vec3(0.4f)), translate({0.6f, 0.8f, 0.6f}), kept);
  addObject(scene, builder::makeBox(glm::vec3(0.5f)), translate({-0.5f, 1.0f, 0.5f}), cut);
  addObject(scene, builder::makeSphere(0.3f, 16, 8), translate({0.3f, 1.2f, 0.3f}), 0);
  const std::vector<Light> lights = {pointLight("lamp", {0, 3, 1}, ShadowFilter::Pcf, 128)};
  const ViewCamera camera = lookFrom(scene, {1, 4, 4}, {0, 0.8f, 0}, 96, 64);
  Renderer& renderer = sharedRenderer();
  auto render = [&](bool masks, bool picture, bool srgb8, StageTimes& times) {
    RenderSettings settings;
    if (masks) requestObjectIds(settings);
    settings.beauty = picture;
    if (srgb8) settings.srgb8Exposure = 0.0f;
    return renderer.render(scene, lights, glm::vec3(0.03f), camera, settings, times);
  };
  auto layers = [](const StageTimes& times) {
    return std::count_if(times.stages().begin(), times.stages().end(),
                         [](const auto& stage) { return stage.first == "layers"; });
  };
  StageTimes idTimes, times;
  const Frame idPass = render(true, false, false, idTimes);  // masks alone: the id pass
  ASSERT_TRUE(idPass.objectIds);
  EXPECT_EQ(layers(idTimes), 1);
  // Plain frames before and after: the renderer keeps its targets between frames of one size,
  // and the frame with masks needs one more attachment than the frame before it.
  for (const bool srgb8 : {true, false}) {
    StageTimes besideTimes;
    const Frame plain = render(false, true, srgb8, times);
    const Frame beside = render(true, true, srgb8, besideTimes);
    const Frame plainAgain = render(false, true, srgb8, times);
    EXPECT_FALSE(plain.objectIds);
    ASSERT_TRUE(beside.objectIds) << srgb8;
    EXPECT_EQ(beside.objectIds->pixels, idPass.objectIds->pixels) << srgb8;
    EXPECT_EQ(layers(besideTimes), 0) << srgb8;  // no pass of their own
    ASSERT_EQ(beside.srgb8.has_value(), srgb8);
    if (srgb8) {
      EXPECT_EQ(beside.srgb8->rgb, plain.srgb8->rgb);  // the ids do not move a byte
      EXPECT_EQ(plainAgain.srgb8->rgb, plain.srgb8->rgb);
    } else {
      EXPECT_EQ(beside.beauty.pixels, plain.beauty.pixels);
      EXPECT_EQ(plainAgain.beauty.pixels, plain.beauty.pixels);
    }
  }
  // The objects are all there: the cut-away box has no pixel, the others do.
  std::vector<int> pixels(scene.instances.size(), 0);
  for (const float id : idPass.objectIds->pixels)
    if (id >= 0) ++pixels[static_cast<std::size_t>(id)];
  EXPECT_GT(pixels[0], 0);
  EXPECT_GT(pixels[1], 0);
  EXPECT_GT(pixels[2], 0);
  EXPECT_EQ(pixels[3], 0);
  EXPECT_GT(pixels[4], 0);
}

TEST(Shadows, MoreShadowTexturesThanTheShaderSamplesIsAnInputError) {
  Scene scene;
  addObject(scene, builder::makePlane(2.0f), glm::mat4(1.0f), addMaterial(scene, glm::vec4(1.0f)));
  std::vector<Light> lights;
  // Five distinct resolutions need five cube map arrays; the shader samples four.
  for (int i = 0; i < 5; ++i)
    lights.push_back(pointLight("l" + std::to_string(i), {0, 1, 0}, ShadowFilter::Pcf, 16 + i));
  const ViewCamera camera = lookFrom(scene, {0, 3, 1}, {0, 0, 0}, 16, 16);
  StageTimes times;
  try {
    sharedRenderer().render(scene, lights, glm::vec3(0.0f), camera, {}, times);
    FAIL() << "expected an InputError";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("use fewer distinct shadow resolutions"),
              std::string::npos)
        << error.what();
  }
}

// ---------------------------------------------------------------------------------------------
// A real model made by others: the Cornell box with Suzanne (scenes/thirdparty). The visibility
// the renderer used must agree with exact ray casting against the model's own triangles.

namespace {

std::vector<WorldTriangle> worldTriangles(const Scene& scene) {
  std::vector<WorldTriangle> triangles;
  for (const MeshInstance& instance : scene.instances) {
    const Mesh& mesh = scene.meshes[instance.mesh];
    auto world = [&](std::uint32_t i) {
      return glm::vec3(instance.world * glm::vec4(mesh.positions[i], 1.0f));
    };
    for (std::size_t i = 0; i + 2 < mesh.indices.size(); i += 3)
      triangles.push_back(
          {world(mesh.indices[i]), world(mesh.indices[i + 1]), world(mesh.indices[i + 2])});
  }
  return triangles;
}

}  // namespace

TEST(Shadows, CornellBoxVisibilityAgreesWithRayCasting) {
  const Scene scene = loadGltf(std::string(OMNISHADOW_SOURCE_DIR) +
                               "/scenes/thirdparty/CornellBoxSuzanne/cornell-box.glb");
  const std::vector<WorldTriangle> triangles = worldTriangles(scene);
  const glm::vec3 lightPosition(0.15f, 0.55f, 0.35f);
  const int resolution = 1024;
  const Light light = pointLight("lamp", lightPosition, ShadowFilter::Hard, resolution);
  const ViewCamera camera =
      lookFrom(scene, {0.0f, 0.0f, 3.6f}, {0.0f, 0.0f, 0.0f}, 160, 160, 40.0f);
  const Frame frame = renderAovs(scene, {light}, camera);

  int agree = 0, disagree = 0, shadowed = 0, skippedEdges = 0;
  for (int y = 0; y + 1 < camera.height; ++y) {
    for (int x = 0; x + 1 < camera.width; ++x) {
      const AovPixel px = pixelAt(*frame.aovs, x, y, "lamp");
      const AovPixel right = pixelAt(*frame.aovs, x + 1, y, "lamp");
      const AovPixel below = pixelAt(*frame.aovs, x, y + 1, "lamp");
      if (px.coverage < 1.0f || right.coverage < 1.0f || below.coverage < 1.0f) continue;
      // The geometric normal from neighbouring positions: this model's shading normals are
      // smoothed across the room's corners. Pixels whose neighbours lie on another surface are
      // skipped.
      const glm::vec3 dx = right.position - px.position, dy = below.position - px.position;
      if (glm::length(dx) > 0.05f || glm::length(dy) > 0.05f) continue;
      glm::vec3 normal = glm::normalize(glm::cross(dx, dy));
      if (glm::dot(normal, camera.eye - px.position) < 0.0f) normal = -normal;
      const glm::vec3 toLight = lightPosition - px.position;
      const float distance = glm::length(toLight);
      if (glm::dot(normal, toLight / distance) < 0.2f) continue;  // grazing or facing away
      // Points within a few shadow-map texels of a shadow edge may go either way.
      const float texel = 2.0f * distance / static_cast<float>(resolution);
      const glm::vec3 t1 = glm::normalize(dx), t2 = glm::normalize(glm::cross(normal, t1));
      const glm::vec3 origin = px.position + normal * 1e-3f;
      const bool blocked = segmentBlocked(triangles, origin, lightPosition);
      bool edge = false;
      for (const glm::vec3 offset : {t1, -t1, t2, -t2})
        edge |= segmentBlocked(triangles, origin + offset * 3.0f * texel, lightPosition) != blocked;
      if (edge) {
        ++skippedEdges;
        continue;
      }
      const bool rendererLit = px.visibility > 0.5f;
      (rendererLit == !blocked ? agree : disagree)++;
      shadowed += blocked ? 1 : 0;
    }
  }
  std::printf(
      "cornell box: %d pixels agree with ray casting, %d disagree (%d shadowed), %d near "
      "shadow edges skipped\n",
      agree, disagree, shadowed, skippedEdges);
  EXPECT_GT(shadowed, 200);
  EXPECT_GT(agree, 5000);
  EXPECT_LE(disagree, agree / 1000)
      << "agree " << agree << ", edges skipped " << skippedEdges << ", shadowed " << shadowed;
}

// ---------------------------------------------------------------------------------------------
// Material and camera features as they reach the frame.

namespace {

// A floor plane seen from straight above, 32x32 pixels, lit from above.
ViewCamera topView(const Scene& scene) {
  return lookFrom(scene, {0, 4, 0.0001f}, {0, 0, 0}, 32, 32, 30.0f, {0, 0, -1});
}

Light lampAbove() {
  return pointLight("lamp", {0, 3, 0}, ShadowFilter::Pcf, 64);
}

}  // namespace

TEST(Materials, NormalMapTiltsTheShadingNormal) {
  // A constant tangent-space normal (0.6, 0, 0.8), i.e. tilted towards the tangent (+U = +X on
  // builder::makePlane), must come out as world normal (0.6, 0.8, 0) in the AOV.
  Scene scene;
  Image image;
  image.width = image.height = 4;
  const std::uint8_t nx = static_cast<std::uint8_t>(std::lround((0.6f * 0.5f + 0.5f) * 255.0f));
  const std::uint8_t nz = static_cast<std::uint8_t>(std::lround((0.8f * 0.5f + 0.5f) * 255.0f));
  for (int i = 0; i < 16; ++i) image.rgba.insert(image.rgba.end(), {nx, 128, nz, 255});
  scene.images.push_back(image);
  scene.textures.push_back({0, {}});
  const int material = addMaterial(scene, glm::vec4(0.8f));
  scene.materials[material].normalTexture.texture = 0;
  addObject(scene, builder::makePlane(4.0f), glm::mat4(1.0f), material);
  Mesh& mesh = scene.meshes.back();
  mesh.tangents.assign(mesh.positions.size(), glm::vec4(1, 0, 0, 1));
  const Frame frame = renderAovs(scene, {lampAbove()}, topView(scene));
  const AovPixel px = pixelAt(*frame.aovs, 16, 16, "lamp");
  EXPECT_NEAR(px.normal.x, 0.6f, 0.02f);
  EXPECT_NEAR(px.normal.y, 0.8f, 0.02f);
  EXPECT_NEAR(px.normal.z, 0.0f, 0.02f);
}

TEST(Materials, SingleSidedFacesAreCulledDoubleSidedAreNot) {
  // Seen from below, a single-sided floor is invisible; a double-sided one is drawn with its
  // normal facing the camera.
  for (const bool doubleSided : {false, true}) {
    Scene scene;
    addObject(scene, builder::makePlane(4.0f), glm::mat4(1.0f),
              addMaterial(scene, glm::vec4(0.8f), doubleSided));
    const ViewCamera below = lookFrom(scene, {0, -4, 0.0001f}, {0, 0, 0}, 32, 32, 30.0f, {0, 0, 1});
    const Frame frame = renderAovs(scene, {lampAbove()}, below);
    const AovPixel px = pixelAt(*frame.aovs, 16, 16, "lamp");
    EXPECT_EQ(px.coverage, doubleSided ? 1.0f : 0.0f);
    if (doubleSided) {
      EXPECT_NEAR(px.normal.y, -1.0f, 1e-4f);
    }
  }
}

TEST(Materials, MirroredInstancesKeepTheirOutsideFaces) {
  // A box scaled by -1 on X: its winding flips, and culling must follow, or the camera would
  // see the inside faces.
  Scene scene;
  addObject(scene, builder::makeBox(glm::vec3(1.0f)), glm::scale(glm::mat4(1.0f), {-1, 1, 1}),
            addMaterial(scene, glm::vec4(0.8f)));
  const Frame frame = renderAovs(scene, {lampAbove()}, topView(scene));
  const AovPixel px = pixelAt(*frame.aovs, 16, 16, "lamp");
  EXPECT_EQ(px.coverage, 1.0f);
  EXPECT_NEAR(px.position.y, 1.0f, 1e-3f);  // the top face, not the bottom one
}

TEST(Materials, BlendedSurfacesMixOverTheOpaqueOnesAndKeepTheirAovs) {
  Scene scene;
  addObject(scene, builder::makePlane(4.0f), glm::mat4(1.0f), addMaterial(scene, glm::vec4(1.0f)));
  const int glass = addMaterial(scene, glm::vec4(0.0f, 0.0f, 0.0f, 0.5f), true);
  scene.materials[glass].alphaMode = AlphaMode::Blend;
  addObject(scene, builder::makePlane(1.0f), translate({0, 1, 0}), glass);
  Light lamp = lampAbove();
  lamp.shadow.enabled = false;  // compare the floor's brightness alone
  const ViewCamera camera = topView(scene);
  const Frame frame = renderAovs(scene, {lamp}, camera);
  const FloatImage& aovs = *frame.aovs;
  // Under the black half-transparent square the floor is half as bright as beside it (the
  // square's own specular reflection aside), P still describes the floor, and A is 1.
  const float under = frame.beauty.at(16, 16, 1);
  const float beside = frame.beauty.at(2, 16, 1);
  EXPECT_GT(under, 0.0f);
  EXPECT_LT(under, beside * 0.6f);
  EXPECT_NEAR(pixelAt(aovs, 16, 16, "lamp").position.y, 0.0f, 1e-3f);
  EXPECT_EQ(frame.beauty.at(16, 16, 3), 1.0f);
}

TEST(Cameras, OrthographicCameraOfASampleModel) {
  // Cameras.gltf (scenes/thirdparty) has a perspective and an orthographic camera; the
  // orthographic one keeps parallel lines parallel: the square's pixel footprint does not
  // depend on distance, so both cameras see it, and the ortho image is fully predictable.
  const Scene scene =
      loadGltf(std::string(OMNISHADOW_SOURCE_DIR) + "/scenes/thirdparty/Cameras/Cameras.gltf");
  ASSERT_EQ(scene.cameras.size(), 2u);
  for (const Camera& gltfCamera : scene.cameras) {
    CameraRequest request;
    request.select = std::to_string(gltfCamera.index);
    request.width = 64;
    request.height = 64;
    const ViewCamera camera = resolveCamera(scene, request);
    EXPECT_EQ(camera.orthographic, gltfCamera.orthographic);
    const Frame frame = renderAovs(scene, {lampAbove()}, camera);
    float coverage = 0.0f;
    for (int y = 0; y < 64; ++y)
      for (int x = 0; x < 64; ++x) coverage += frame.beauty.at(x, y, 3);
    EXPECT_GT(coverage, 64.0f) << "camera " << gltfCamera.index << " sees the model";
  }
}

// ---------------------------------------------------------------------------------------------
// Debugging outputs: shadow map dumps, light views, debug views, AOV layers.

namespace {

// Six boxes of different colors, one on each axis around a point light at the origin, at
// different distances, inside nothing else.
Scene sixColoredBoxes(std::vector<glm::vec3>& colors, std::vector<float>& distances) {
  Scene scene;
  const glm::vec3 axes[] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  colors = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 0}, {0, 1, 1}, {1, 0, 1}};
  for (int i = 0; i < 6; ++i) {
    const float distance = 1.0f + 0.25f * static_cast<float>(i);
    distances.push_back(distance);
    // A large box whose face towards the light lies at `distance` and covers the face center.
    addObject(scene, builder::makeBox(glm::vec3(0.4f)), translate(axes[i] * (distance + 0.4f)),
              addMaterial(scene, glm::vec4(colors[i], 1.0f)));
  }
  return scene;
}

}  // namespace

TEST(DebugOutputs, LightViewsAndDumpsShowEachAxisOnItsOwnFace) {
  std::vector<glm::vec3> colors;
  std::vector<float> distances;
  const Scene scene = sixColoredBoxes(colors, distances);
  Light light = pointLight("lamp", glm::vec3(0.0f), ShadowFilter::Pcf, 64);
  RenderSettings settings;
  settings.readShadowMaps = true;
  settings.lightViewSize = 32;
  StageTimes times;
  const ViewCamera camera = lookFrom(scene, {4, 3, 5}, {0, 0, 0}, 16, 16);
  const Frame frame =
      sharedRenderer().render(scene, {light}, glm::vec3(0.0f), camera, settings, times);
  ASSERT_EQ(frame.lightViews.size(), 6u);
  ASSERT_EQ(frame.shadowMaps.size(), 1u);
  const CubeDistances& map = frame.shadowMaps[0].distances;
  for (int face = 0; face < 6; ++face) {
    SCOPED_TRACE(kCubeFaceNames[face]);
    const LightView& view = frame.lightViews[face];
    EXPECT_EQ(static_cast<int>(view.face), face);
    EXPECT_EQ(view.light, "lamp");
    // The face's center pixel shows that axis' box: the brightest channels are its color's.
    const glm::vec3 center(view.beauty.at(16, 16, 0), view.beauty.at(16, 16, 1),
                           view.beauty.at(16, 16, 2));
    ASSERT_GT(glm::length(center), 0.0f);
    const glm::vec3 hue = center / std::max(center.x, std::max(center.y, center.z));
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(hue[c], colors[face][c], 0.05f);
    // The dump holds that box's distance at the face center.
    EXPECT_NEAR(map.at(static_cast<CubeFace>(face), 32, 32), distances[face],
                distances[face] * 0.01f);
  }
}

TEST(DebugOutputs, DumpedDistancesAreWhatTheLightingCompared) {
  // For every receiver pixel: if the dump's distance in its direction is clearly shorter than
  // the receiver's own distance, the lighting found it shadowed, and vice versa.
  Scene scene;
  const int white = addMaterial(scene, glm::vec4(0.8f));
  addObject(scene, builder::makePlane(8.0f), glm::mat4(1.0f), white);
  addObject(scene, builder::makeSphere(0.5f, 32, 16), translate({0.3f, 1.2f, -0.2f}), white);
  const glm::vec3 lightPosition(0, 3, 0);
  Light light = pointLight("lamp", lightPosition, ShadowFilter::Hard, 256);
  // No normal offset: the lookup then stays on the ray through the receiver; a larger slope
  // bias instead keeps the grazing floor free of acne.
  light.shadow.normalBias = 0.0f;
  light.shadow.slopeBias = 10.0f;
  RenderSettings settings;
  settings.aovs = true;
  settings.readShadowMaps = true;
  StageTimes times;
  const ViewCamera camera = lookFrom(scene, {0, 6, 4}, {0, 0, 0}, 96, 72);
  const Frame frame =
      sharedRenderer().render(scene, {light}, glm::vec3(0.0f), camera, settings, times);
  const CubeDistances& map = frame.shadowMaps.at(0).distances;
  int shadowed = 0, lit = 0;
  for (int y = 0; y < camera.height; ++y) {
    for (int x = 0; x < camera.width; ++x) {
      const AovPixel px = pixelAt(*frame.aovs, x, y, "lamp");
      if (px.coverage < 1.0f || std::abs(px.position.y) > 1e-3f) continue;  // the floor only
      const glm::vec3 d = px.position - lightPosition;
      const CubeLookup hit = cubeLookup(d);
      const int column = std::min(static_cast<int>(hit.st.x * 256), 255);
      const int row = std::min(static_cast<int>(hit.st.y * 256), 255);
      const float stored = map.at(hit.face, column, row);
      const float receiver = glm::length(d);
      if (stored < receiver * 0.9f) {
        ++shadowed;
        EXPECT_EQ(px.visibility, 0.0f) << x << "," << y;
      } else if (stored > receiver * 0.98f) {
        ++lit;
        EXPECT_EQ(px.visibility, 1.0f) << x << "," << y;
      }
    }
  }
  EXPECT_GT(shadowed, 100);
  EXPECT_GT(lit, 1000);
}

TEST(DebugOutputs, PerLightLayersSumToTheBeauty) {
  Scene scene;
  const int red = addMaterial(scene, glm::vec4(0.9f, 0.2f, 0.1f, 1.0f));
  scene.materials[red].metallicFactor = 0.3f;
  scene.materials[red].roughnessFactor = 0.4f;
  addObject(scene, builder::makePlane(6.0f), glm::mat4(1.0f), addMaterial(scene, glm::vec4(0.7f)));
  addObject(scene, builder::makeSphere(0.6f, 32, 16), translate({0, 0.6f, 0}), red);
  const std::vector<Light> lights = {pointLight("a", {1.5f, 2.5f, 1}, ShadowFilter::Pcf, 128),
                                     pointLight("b", {-2, 1.5f, 0.5f}, ShadowFilter::PcfDisk, 128)};
  RenderSettings settings;
  settings.aovs = true;
  settings.layers = {true, true, true, true, true, true, true};
  StageTimes times;
  const ViewCamera camera = lookFrom(scene, {0, 3, 4}, {0, 0.3f, 0}, 64, 48);
  const Frame frame =
      sharedRenderer().render(scene, lights, glm::vec3(0.0f), camera, settings, times);
  const FloatImage& aovs = *frame.aovs;
  EXPECT_EQ(aovs.channels, aovChannels(lights, settings.layers));
  for (const char* name : {"albedo.R", "roughness", "metallic", "objectId", "materialId",
                           "diffuse.a.R", "specular.b.B"})
    EXPECT_GE(aovs.channelIndex(name), 0) << name;
  float maxError = 0.0f;
  for (int y = 0; y < camera.height; ++y) {
    for (int x = 0; x < camera.width; ++x) {
      for (int c = 0; c < 3; ++c) {
        const char* rgb[] = {"R", "G", "B"};
        float sum = 0.0f;
        for (const char* light : {"a", "b"})
          for (const char* part : {"diffuse", "specular"})
            sum += aovs.at(x, y, aovs.channelIndex(std::string(part) + "." + light + "." + rgb[c]));
        maxError = std::max(maxError, std::abs(sum - aovs.at(x, y, c)));
      }
    }
  }
  EXPECT_LT(maxError, 1e-4f);  // no ambient, no emission: the lights are all there is
  // The sphere at the center: its material's values and ids.
  const int centerX = 32, centerY = 24;
  EXPECT_NEAR(aovs.at(centerX, centerY, aovs.channelIndex("albedo.R")), 0.9f, 1e-5f);
  EXPECT_NEAR(aovs.at(centerX, centerY, aovs.channelIndex("roughness")), 0.4f, 1e-5f);
  EXPECT_NEAR(aovs.at(centerX, centerY, aovs.channelIndex("metallic")), 0.3f, 1e-5f);
  EXPECT_EQ(aovs.at(centerX, centerY, aovs.channelIndex("objectId")), 1.0f);
  EXPECT_EQ(aovs.at(centerX, centerY, aovs.channelIndex("materialId")), static_cast<float>(red));
  EXPECT_EQ(aovs.at(0, 0, aovs.channelIndex("objectId")), -1.0f);  // background
}

TEST(DebugOutputs, DebugViewsShowWhatTheySay) {
  Scene scene;
  const int green = addMaterial(scene, glm::vec4(0.1f, 0.6f, 0.2f, 1.0f));
  addObject(scene, builder::makePlane(8.0f), glm::mat4(1.0f), green);
  addObject(scene, builder::makeSphere(0.5f, 32, 16), translate({0, 1.5f, 0}), green);
  std::vector<Light> lights = {pointLight("lamp", {0, 4, 0}, ShadowFilter::Hard, 256),
                               pointLight("side", {3, 1, 0}, ShadowFilter::Hard, 256)};
  lights[1].range = 2.0f;  // reaches only part of the floor
  const ViewCamera camera = lookFrom(scene, {0, 7, 3}, {0, 0, 0}, 64, 48);
  auto render = [&](DebugView view) {
    RenderSettings settings;
    settings.aovs = true;
    settings.debugView = view;
    StageTimes times;
    return sharedRenderer().render(scene, lights, glm::vec3(0.0f), camera, settings, times);
  };
  const Frame normals = render(DebugView::Normals);
  const Frame albedo = render(DebugView::Albedo);
  const Frame shadow = render(DebugView::Shadow);
  const Frame depth = render(DebugView::Depth);
  const Frame count = render(DebugView::LightCount);
  int floorPixels = 0;
  for (int y = 0; y < camera.height; ++y) {
    for (int x = 0; x < camera.width; ++x) {
      const AovPixel px = pixelAt(*normals.aovs, x, y, "lamp");
      if (px.coverage < 1.0f || std::abs(px.position.y) > 1e-3f) continue;
      ++floorPixels;
      EXPECT_NEAR(normals.beauty.at(x, y, 1), 1.0f, 1e-4f);  // N = +Y -> (0.5, 1, 0.5)
      EXPECT_NEAR(normals.beauty.at(x, y, 0), 0.5f, 1e-4f);
      EXPECT_NEAR(albedo.beauty.at(x, y, 1), 0.6f, 1e-5f);
      const float lampVisibility = px.visibility;
      const float sideVisibility = pixelAt(*normals.aovs, x, y, "side").visibility;
      // The shadow view averages the shadowed lights that reach the point.
      const float sideDistance = glm::length(px.position - lights[1].position);
      if (std::abs(sideDistance - 2.0f) < 0.05f) continue;  // at the range's edge
      const bool sideReaches = sideDistance < 2.0f;
      EXPECT_NEAR(shadow.beauty.at(x, y, 0),
                  sideReaches ? 0.5f * (lampVisibility + sideVisibility) : lampVisibility, 1e-5f);
      // Depth view: the lamp's stored distance over far; on lit floor that is the floor's own
      // distance to the lamp.
      if (lampVisibility == 1.0f) {
        const float far = effectiveShadowFar(lights[0], scene.bounds);
        const float expected = glm::length(px.position - lights[0].position) / far;
        EXPECT_NEAR(depth.beauty.at(x, y, 0), expected, expected * 0.02f);
      }
      // Light count over the two lights: the side light contributes only within its range.
      const float expectedCount = (static_cast<float>(lampVisibility > 0.0f) +
                                   static_cast<float>(sideReaches && sideVisibility > 0.0f)) /
                                  2.0f;
      EXPECT_NEAR(count.beauty.at(x, y, 0), expectedCount, 1e-5f) << x << "," << y;
    }
  }
  EXPECT_GT(floorPixels, 1000);
}

TEST(Lighting, ACameraAtTheLightSeesNoInvalidValues) {
  // Regression: with the eye exactly at the light, V == L and Fresnel's pow(1 - V.H, 5) got a
  // slightly negative base, which is undefined in GLSL (black speckles).
  Scene scene;
  addObject(scene, builder::makePlane(8.0f), glm::mat4(1.0f), addMaterial(scene, glm::vec4(0.8f)));
  const Light light = pointLight("lamp", {0, 2, 0}, ShadowFilter::Pcf, 128);
  const ViewCamera camera = lookFrom(scene, {0, 2, 0}, {0, 0, 0.001f}, 64, 64, 90.0f, {0, 0, -1});
  StageTimes times;
  const Frame frame = sharedRenderer().render(scene, {light}, glm::vec3(0.0f), camera, {}, times);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      ASSERT_TRUE(std::isfinite(frame.beauty.at(x, y, 0))) << x << "," << y;
      ASSERT_GT(frame.beauty.at(x, y, 0), 0.0f) << x << "," << y;
    }
}

namespace {

// Resident memory of this process in KiB (llvmpipe's "GPU" memory is process memory).
long residentKiB() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind("VmRSS:", 0) == 0) return std::stol(line.substr(6));
  return -1;
}

}  // namespace

TEST(Batch, ManyScenesInOneContextDoNotGrowMemory) {
  // What batch mode does: one renderer, scene after scene. After a warm-up, 1000 more renders
  // of scenes with their own textures and shadow maps must not keep memory growing.
  auto makeScene = [](int i) {
    Scene scene;
    Image image;
    image.width = image.height = 8 + i % 3;
    image.rgba.assign(static_cast<std::size_t>(image.width * image.height) * 4,
                      static_cast<std::uint8_t>(i));
    scene.images.push_back(image);
    scene.textures.push_back({0, {}});
    const int material = addMaterial(scene, glm::vec4(0.8f));
    scene.materials[material].baseColorTexture.texture = 0;
    addObject(scene, builder::makePlane(4.0f), glm::mat4(1.0f), material);
    addObject(scene, builder::makeBox(glm::vec3(0.3f + 0.01f * static_cast<float>(i % 7))),
              translate({0, 0.5f, 0}), material);
    return scene;
  };
  const std::vector<Light> lights = {pointLight("a", {0, 2, 0}, ShadowFilter::Pcf, 16),
                                     pointLight("b", {1, 2, 1}, ShadowFilter::Hard, 32)};
  auto renderOne = [&](int i) {
    const Scene scene = makeScene(i);
    const ViewCamera camera = lookFrom(scene, {0, 3, 3}, {0, 0, 0}, 16 + i % 5, 16);
    StageTimes times;
    RenderSettings settings;
    settings.aovs = i % 2 == 0;
    sharedRenderer().render(scene, lights, glm::vec3(0.03f), camera, settings, times);
  };
  for (int i = 0; i < 100; ++i) renderOne(i);
  const long before = residentKiB();
  for (int i = 100; i < 1100; ++i) renderOne(i);
  const long after = residentKiB();
  ASSERT_GT(before, 0);
  std::printf("resident memory: %ld KiB after 100 renders, %ld KiB after 1100\n", before, after);
  EXPECT_LT(after - before, 8 * 1024) << "grew by " << (after - before) << " KiB";
}

TEST(Materials, TexturesLargerThanTheGlLimitAreDownscaledWithAWarning) {
  // One row wider than any GL allows (llvmpipe and NVIDIA: 16384 or 32768): cheap in memory.
  const int maxSize = sharedRenderer().limits().maxTextureSize;
  Scene scene;
  Image image;
  image.name = "wide";
  image.width = maxSize + 2;
  image.height = 1;
  image.rgba.assign(static_cast<std::size_t>(image.width) * 4, 200);
  scene.images.push_back(image);
  scene.textures.push_back({0, {}});
  const int material = addMaterial(scene, glm::vec4(1.0f));
  scene.materials[material].baseColorTexture.texture = 0;
  addObject(scene, builder::makePlane(4.0f), glm::mat4(1.0f), material);
  const ViewCamera camera = lookFrom(scene, {0, 4, 0.001f}, {0, 0, 0}, 16, 16);
  StageTimes times;
  const Frame frame =
      sharedRenderer().render(scene, {lampAbove()}, glm::vec3(0.0f), camera, {}, times);
  ASSERT_EQ(frame.warnings.size(), 1u);
  EXPECT_NE(frame.warnings[0].find("exceeds this GL's maximum texture size"), std::string::npos)
      << frame.warnings[0];
  EXPECT_GT(frame.beauty.at(8, 8, 0), 0.0f);

  // The same image as sRGB base color and linear occlusion: two textures, so their mipmap
  // chains are made on the upload's queue (renderer/scene/mipmap_queue.h) from the two halved
  // copies, which must live until the queue is done with them (AddressSanitizer checks that).
  scene.materials[material].occlusionTexture.texture = 0;
  const Frame both =
      sharedRenderer().render(scene, {lampAbove()}, glm::vec3(0.0f), camera, {}, times);
  ASSERT_EQ(both.warnings.size(), 2u);
  for (const std::string& warning : both.warnings)
    EXPECT_NE(warning.find("exceeds this GL's maximum texture size"), std::string::npos) << warning;
  EXPECT_GT(both.beauty.at(8, 8, 0), 0.0f);
}

TEST(Materials, EachOfManyTexturesGetsItsOwnMipmapLevels) {
  // Seven uniform textures, more than the upload keeps waiting for their levels at once
  // (gpu_scene.cpp: the chains are made on a queue and put in later), on seven planes seen from
  // far away, so that their smallest levels are what is sampled. Each must look like a plain
  // material of its color: a texture left without levels samples black, one given another's
  // levels another color.
  constexpr int kTextures = 7;
  Scene textured, plain;
  for (int i = 0; i < kTextures; ++i) {
    const std::uint8_t code[3] = {static_cast<std::uint8_t>(40 + 30 * i),
                                  static_cast<std::uint8_t>(220 - 25 * i),
                                  static_cast<std::uint8_t>(90 + 17 * i)};
    Image image;
    image.name = "uniform" + std::to_string(i);
    image.width = 64;
    image.height = 32;
    for (int t = 0; t < image.width * image.height; ++t)
      image.rgba.insert(image.rgba.end(), {code[0], code[1], code[2], 255});
    textured.images.push_back(image);
    textured.textures.push_back({i, {}});
    const glm::mat4 place = translate({4.5f * static_cast<float>(i - kTextures / 2), 0, 0});
    const int material = addMaterial(textured, glm::vec4(1.0f));
    textured.materials[material].baseColorTexture.texture = i;
    addObject(textured, builder::makePlane(4.0f), place, material);
    const glm::vec4 color(srgbDecode(code[0]), srgbDecode(code[1]), srgbDecode(code[2]), 1.0f);
    addObject(plain, builder::makePlane(4.0f), place, addMaterial(plain, color));
  }
  const ViewCamera camera = lookFrom(textured, {0, 60, 0.01f}, {0, 0, 0}, 64, 16, 30.0f);
  const Light light = pointLight("lamp", {0, 20, 0}, ShadowFilter::Pcf, 64);
  StageTimes times;
  const Frame a = sharedRenderer().render(textured, {light}, glm::vec3(0.1f), camera, {}, times);
  const Frame b = sharedRenderer().render(plain, {light}, glm::vec3(0.1f), camera, {}, times);
  ASSERT_EQ(a.beauty.pixels.size(), b.beauty.pixels.size());
  float largest = 0.0f, difference = 0.0f;
  for (std::size_t i = 0; i < a.beauty.pixels.size(); ++i) {
    largest = std::max(largest, b.beauty.pixels[i]);
    difference = std::max(difference, std::abs(a.beauty.pixels[i] - b.beauty.pixels[i]));
  }
  EXPECT_GT(largest, 0.05f) << "the planes are lit and in view";
  EXPECT_LT(difference, 1e-3f * largest);
}

// ---------------------------------------------------------------------------------------------
// Shadow quality against exact ray casting (the code behind `omnishadow verify`), with the
// default bias settings: issue 3's bar for every light type and filter.

namespace {

struct QualityCase {
  LightType type;
  ShadowFilter filter;
};

Light qualityLight(LightType type, ShadowFilter filter) {
  Light light = pointLight("light", {0.6f, 3.0f, 0.9f}, filter, 1024);
  light.type = type;
  if (type == LightType::Spot) {
    light.position = {2.5f, 4.0f, 2.0f};
    light.direction = glm::normalize(-light.position);
    light.outerConeAngle = 0.7f;
    light.intensity = 40.0f;
  }
  if (type == LightType::Directional) {
    light.direction = glm::normalize(glm::vec3(-0.4f, -1.0f, -0.3f));
    light.intensity = 2.0f;
    light.shadow.cascades = 2;
  }
  if (filter == ShadowFilter::Pcss)
    light.shadow.radius = type == LightType::Directional ? 0.01f : 0.05f;
  return light;
}

// Interior rates of one light on one scene, seen from one camera.
LightVerification verifyOne(const Scene& scene, const Light& light, const ViewCamera& camera) {
  const Frame frame = renderAovs(scene, {light}, camera);
  const ShadowReference reference(scene);
  const std::vector<LightToVerify> lights = {{light, effectiveShadowFar(light, scene.bounds)}};
  return verifyShadows(reference, scene.bounds, lights, *frame.aovs, camera, {}).lights.at(0);
}

void expectIssueThreeBar(const LightVerification& v) {
  std::printf(
      "%s: interior %lld, agreement %.4f%%, false shadow %lld, false light %lld; "
      "edge %lld, agreement %.2f%%\n",
      ::testing::UnitTest::GetInstance()->current_test_info()->name(),
      static_cast<long long>(v.interior.evaluated), 100.0 * v.interior.agreementRate(),
      static_cast<long long>(v.interior.falseShadow), static_cast<long long>(v.interior.falseLight),
      static_cast<long long>(v.edge.evaluated), 100.0 * v.edge.agreementRate());
  EXPECT_GT(v.interior.evaluated, 5000);
  EXPECT_GE(v.interior.agreementRate(), 0.999);
  EXPECT_LE(v.interior.falseShadowRate(), 0.0005) << v.interior.falseShadow << " points";
  EXPECT_LE(v.interior.falseLightRate(), 0.0005) << v.interior.falseLight << " points";
}

class ShadowQuality : public ::testing::TestWithParam<QualityCase> {};

// A floor with a sphere, a box, a 2 cm thin wall touching the floor and a tilted slab.
TEST_P(ShadowQuality, AgreesWithRayCastingWithDefaultBias) {
  Scene scene;
  const int white = addMaterial(scene, glm::vec4(0.8f));
  addObject(scene, builder::makePlane(10.0f), glm::mat4(1.0f), white);
  addObject(scene, builder::makeSphere(0.5f, 48, 24), translate({-1.0f, 0.8f, 0.0f}), white);
  addObject(scene, builder::makeBox(glm::vec3(0.4f)), translate({1.0f, 0.4f, -0.5f}), white);
  addObject(scene, builder::makeBox({0.6f, 0.5f, 0.01f}), translate({0.0f, 0.5f, 1.2f}), white);
  addObject(scene, builder::makeBox({0.5f, 0.05f, 0.5f}),
            glm::rotate(translate({0.5f, 1.2f, -1.5f}), 0.5f, glm::vec3(1, 0, 0)), white);
  const Light light = qualityLight(GetParam().type, GetParam().filter);
  const ViewCamera camera = lookFrom(scene, {3.5f, 4.5f, 5.0f}, {0, 0, 0}, 200, 150);
  expectIssueThreeBar(verifyOne(scene, light, camera));
}

// A large plane lit 80 degrees from its normal: no acne.
TEST_P(ShadowQuality, NoAcneOnAPlaneLitAtEightyDegrees) {
  Scene scene;
  addObject(scene, builder::makePlane(20.0f), glm::mat4(1.0f), addMaterial(scene, glm::vec4(0.8f)));
  addObject(scene, builder::makeBox(glm::vec3(0.3f)), translate({0, 0.3f, 0}),
            addMaterial(scene, glm::vec4(0.8f)));
  Light light = qualityLight(GetParam().type, GetParam().filter);
  const glm::vec3 toLight =
      glm::vec3(std::sin(glm::radians(80.0f)), std::cos(glm::radians(80.0f)), 0);
  light.position = 6.0f * toLight;
  light.direction = -toLight;
  light.range = 0.0f;
  const ViewCamera camera = lookFrom(scene, {-3.0f, 6.0f, 6.0f}, {0, 0, 0}, 200, 150);
  const LightVerification v = verifyOne(scene, light, camera);
  EXPECT_GT(v.interior.evaluated, 5000);
  EXPECT_LE(v.interior.falseShadowRate(), 0.0005) << v.interior.falseShadow << " points";
}

std::vector<QualityCase> qualityCases() {
  std::vector<QualityCase> cases;
  for (const LightType type : {LightType::Point, LightType::Spot, LightType::Directional})
    for (const ShadowFilter filter : {ShadowFilter::Hard, ShadowFilter::Pcf, ShadowFilter::PcfDisk,
                                      ShadowFilter::Poisson, ShadowFilter::Pcss, ShadowFilter::Vsm})
      cases.push_back({type, filter});
  return cases;
}

INSTANTIATE_TEST_SUITE_P(LightsAndFilters, ShadowQuality, ::testing::ValuesIn(qualityCases()),
                         [](const ::testing::TestParamInfo<QualityCase>& param) {
                           std::string name = std::string(toString(param.param.type)) + "_" +
                                              toString(param.param.filter);
                           for (char& c : name)
                             if (c == '-') c = '_';
                           return name;
                         });

// The beauty pass keeps its targets for the next frame of the same size, and the readback turns
// the rows around in the driver's copy where it can (GL_MESA_pack_invert): a frame after one of
// another size is the same frame again, top row first (sky above a floor seen from above it).
TEST(Readback, AFrameAfterOneOfAnotherSizeIsTheSameTopRowFirst) {
  Scene scene;
  const int white = addMaterial(scene, glm::vec4(0.8f));
  addObject(scene, builder::makePlane(40.0f), glm::mat4(1.0f), white);
  addObject(scene, builder::makeSphere(0.5f, 24, 12), translate({0, 0.5f, 0}), white);
  const Light light = pointLight("lamp", {1.0f, 3.0f, 1.0f}, ShadowFilter::Pcf, 128);
  const ViewCamera wide = lookFrom(scene, {0, 1.5f, 4}, {0, 0.8f, 0}, 48, 32, 60.0f);
  const ViewCamera tall = lookFrom(scene, {0, 1.5f, 4}, {0, 0.8f, 0}, 24, 40, 60.0f);
  const auto beauty = [&](const ViewCamera& camera) {
    StageTimes times;
    return sharedRenderer()
        .render(scene, {light}, glm::vec3(0.03f), camera, RenderSettings{}, times)
        .beauty;
  };
  const FloatImage first = beauty(wide);
  const FloatImage between = beauty(tall);
  const FloatImage again = beauty(wide);
  EXPECT_EQ(between.width, 24);
  EXPECT_EQ(between.height, 40);
  ASSERT_EQ(again.width, 48);
  ASSERT_EQ(again.height, 32);
  EXPECT_EQ(first.pixels, again.pixels);
  for (int x = 0; x < 48; ++x) {
    EXPECT_EQ(again.at(x, 0, 3), 0.0f) << "sky at the top, column " << x;
    EXPECT_EQ(again.at(x, 31, 3), 1.0f) << "floor at the bottom, column " << x;
  }
}

// Renderer::frameBytes, which the CLI's memory warm-up faults in ahead of a render: the shadow
// maps, and the beauty's targets with what the beauty is read back into, 8-bit where the scene
// lets the lighting pass encode it, float where blended surfaces need it; 0 for a frame that
// render() refuses.
TEST(Renderer, FrameBytesCountTheShadowMapsAndTheBeautyTheSceneTakes) {
  const Scene opaque =
      loadGltf(std::string(OMNISHADOW_SOURCE_DIR) + "/scenes/thirdparty/Box/Box.glb");
  Scene blended = opaque;
  for (Material& material : blended.materials) material.alphaMode = AlphaMode::Blend;
  const std::vector<Light> lights = {pointLight("key", {1.5f, 2.0f, 2.0f}, ShadowFilter::Pcf, 256)};
  const ViewCamera camera = lookFrom(opaque, {1.2f, 1.0f, 1.6f}, {0, 0, 0}, 320, 240);
  RenderSettings settings;
  settings.srgb8Exposure = 0.0f;
  const double maps = 6.0 * 256 * 256 * 4;  // one cube map of 32-bit depths
  const double pixels = 320.0 * 240.0;
  const double bytes8 = sharedRenderer().frameBytes(opaque, lights, camera, settings);
  EXPECT_GE(bytes8, maps + pixels * (4 + 4 + 3));  // RGBA8UI codes, depth, RGB read back
  EXPECT_LE(bytes8, maps * 1.5 + pixels * 16);
  const double bytesFloat = sharedRenderer().frameBytes(blended, lights, camera, settings);
  EXPECT_GE(bytesFloat - bytes8, pixels * (16 + 16 - 4 - 3));  // RGBA32F, and read back as such
  settings.antialiasing = 3;                                   // not 1, 4, 8 or 16
  EXPECT_EQ(sharedRenderer().frameBytes(opaque, lights, camera, settings), 0.0);
}

}  // namespace

}  // namespace render_test
