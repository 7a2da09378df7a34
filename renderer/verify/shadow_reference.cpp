#include "renderer/verify/shadow_reference.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "renderer/core/errors.h"
#include "renderer/scene/translucency.h"
#include "renderer/verify/embree_api.h"

namespace omnishadow {
namespace {

// Geometry mask bits: shadow rays see every caster, camera rays only what the AOVs show.
constexpr unsigned kCastsShadow = 1u;
constexpr unsigned kInAovs = 2u;

constexpr int kGlClampToEdge = 0x812F;
constexpr int kGlMirroredRepeat = 0x8370;

// One channel (or RGB) of a texture at the nearest texel, with KHR_texture_transform applied to
// the per-vertex UVs (which an affine map allows); width 0 = no texture.
struct TexelMap {
  std::vector<glm::vec2> uv;
  int width = 0, height = 0, channels = 1;
  std::vector<float> values;  // `channels` per texel, row 0 = top
  int wrapS = 0, wrapT = 0;
};

// What the alpha filter needs of one cut-out instance, copied so that the reference does not
// depend on the Scene's lifetime.
struct Cutout {
  std::vector<std::uint32_t> indices;  // 3 per triangle, in Embree's primitive order
  std::vector<float> vertexAlpha;      // baseColorFactor.a * COLOR_0.a
  std::vector<glm::vec2> uv;           // the base color texture's set; empty = no texture
  int width = 0, height = 0;
  std::vector<std::uint8_t> texelAlpha;  // row 0 = top = v 0, as GL samples glTF images
  int wrapS = 0, wrapT = 0;
  float cutoff = 0.5f;
  // Translucent casters (translucency.h): what a shadow ray crossing them keeps of the light.
  bool translucent = false;
  Material material;
  std::vector<glm::vec3> vertexColor;  // baseColorFactor.rgb * COLOR_0.rgb
  std::vector<glm::vec3> texelColor;   // linear RGB of the base color texture, as texelAlpha
  // The textures surfaceTransmittance() reads besides the base color.
  TexelMap transmission, thickness, diffuseTransmission, diffuseTransmissionColor;
  float volumeScale = 1.0f;  // the instance's (translucency.h)
};

float srgbToLinear(std::uint8_t value) {
  const float c = static_cast<float>(value) / 255.0f;
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

// GL's nearest-texel addressing: the integer texel, then the wrap mode on integers.
int wrapTexel(float coordinate, int size, int mode) {
  const double scaled = std::floor(static_cast<double>(coordinate) * size);
  if (!std::isfinite(scaled)) return 0;
  const long long i = static_cast<long long>(std::clamp(scaled, -1e15, 1e15));
  if (mode == kGlClampToEdge) return static_cast<int>(std::clamp<long long>(i, 0, size - 1));
  if (mode == kGlMirroredRepeat) {
    const long long period = 2LL * size;
    const long long j = ((i % period) + period) % period;
    return static_cast<int>(j < size ? j : period - 1 - j);
  }
  return static_cast<int>(((i % size) + size) % size);
}

// The base color (linear RGB only for translucent casters, else white) and alpha at
// barycentrics (u, v) of triangle `primitive`, with the texture's nearest texel.
glm::vec4 baseColorAt(const Cutout& c, unsigned primitive, float u, float v) {
  const std::uint32_t i0 = c.indices[3 * primitive], i1 = c.indices[3 * primitive + 1],
                      i2 = c.indices[3 * primitive + 2];
  const float w = 1.0f - u - v;
  glm::vec4 color(1.0f);
  color.a = w * c.vertexAlpha[i0] + u * c.vertexAlpha[i1] + v * c.vertexAlpha[i2];
  if (c.translucent)
    color =
        glm::vec4(w * c.vertexColor[i0] + u * c.vertexColor[i1] + v * c.vertexColor[i2], color.a);
  if (!c.uv.empty() && c.width > 0 && c.height > 0) {
    const glm::vec2 uv = w * c.uv[i0] + u * c.uv[i1] + v * c.uv[i2];
    const int x = wrapTexel(uv.x, c.width, c.wrapS);
    const int y = wrapTexel(uv.y, c.height, c.wrapT);
    const std::size_t texel = static_cast<std::size_t>(y) * c.width + x;
    color.a *= static_cast<float>(c.texelAlpha[texel]) / 255.0f;
    if (c.translucent) color = glm::vec4(glm::vec3(color) * c.texelColor[texel], color.a);
  }
  return color;
}

// A texel map's value at barycentrics (u, v) of triangle `primitive` (`fallback` without a
// texture): channel 0, or the RGB of a three-channel map.
glm::vec3 texelAt(const TexelMap& map, const Cutout& c, unsigned primitive, float u, float v,
                  glm::vec3 fallback) {
  if (map.width <= 0) return fallback;
  const std::uint32_t i0 = c.indices[3 * primitive], i1 = c.indices[3 * primitive + 1],
                      i2 = c.indices[3 * primitive + 2];
  const glm::vec2 uv = (1.0f - u - v) * map.uv[i0] + u * map.uv[i1] + v * map.uv[i2];
  const int x = wrapTexel(uv.x, map.width, map.wrapS);
  const int y = wrapTexel(uv.y, map.height, map.wrapT);
  const float* at = &map.values[(static_cast<std::size_t>(y) * map.width + x) * map.channels];
  return map.channels == 3 ? glm::vec3(at[0], at[1], at[2]) : glm::vec3(at[0]);
}

// Reads channel `channel` of `slot`'s texture (all of RGB, decoded from sRGB, with `srgbRgb`)
// into `map`; leaves it empty without a texture.
void addTexelMap(const Scene& scene, const Mesh& mesh, const TextureSlot& slot, int channel,
                 bool srgbRgb, TexelMap& map) {
  if (slot.texture < 0 || slot.texture >= static_cast<int>(scene.textures.size())) return;
  const Texture& texture = scene.textures[slot.texture];
  if (texture.image < 0 || texture.image >= static_cast<int>(scene.images.size())) return;
  const Image& image = scene.images[texture.image];
  const std::size_t texels = static_cast<std::size_t>(image.width) * image.height;
  if (image.width <= 0 || image.height <= 0 || image.rgba.size() < texels * 4) return;
  map.width = image.width;
  map.height = image.height;
  map.channels = srgbRgb ? 3 : 1;
  map.values.resize(texels * map.channels);
  for (std::size_t i = 0; i < texels; ++i) {
    if (srgbRgb) {
      for (int k = 0; k < 3; ++k) map.values[i * 3 + k] = srgbToLinear(image.rgba[i * 4 + k]);
    } else {
      map.values[i] = static_cast<float>(image.rgba[i * 4 + channel]) / 255.0f;
    }
  }
  map.wrapS = texture.sampler.wrapS;
  map.wrapT = texture.sampler.wrapT;
  const std::vector<glm::vec2>& uv = slot.texCoord == 1 ? mesh.uv1 : mesh.uv0;
  map.uv.assign(mesh.positions.size(), glm::vec2(0.0f));
  for (std::size_t i = 0; i < map.uv.size() && i < uv.size(); ++i)
    map.uv[i] = glm::vec2(slot.uvTransform * glm::vec3(uv[i], 1.0f));
}

// Whether the hit at barycentrics (u, v) of triangle `primitive` is opaque enough to cast.
bool castsAt(const Cutout& c, unsigned primitive, float u, float v) {
  return baseColorAt(c, primitive, u, v).a >= c.cutoff;  // the shadow pass discards below
}

void alphaFilter(const RTCFilterFunctionNArguments* args) {
  const Cutout& cutout = *static_cast<const Cutout*>(args->geometryUserPtr);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    if (!castsAt(cutout, RTCHitN_primID(args->hit, args->N, i), RTCHitN_u(args->hit, args->N, i),
                 RTCHitN_v(args->hit, args->N, i)))
      args->valid[i] = 0;
  }
}

Cutout makeCutout(const Scene& scene, const Mesh& mesh, const Material& material,
                  std::vector<std::uint32_t> indices, float volumeScale) {
  Cutout c;
  c.indices = std::move(indices);
  c.cutoff = material.alphaMode == AlphaMode::Mask ? material.alphaCutoff : 0.5f;
  c.vertexAlpha.assign(mesh.positions.size(), material.baseColorFactor.a);
  for (std::size_t i = 0; i < mesh.colors.size() && i < c.vertexAlpha.size(); ++i)
    c.vertexAlpha[i] *= mesh.colors[i].a;
  c.translucent = isTranslucentCaster(material);
  if (c.translucent) {
    c.material = material;
    c.vertexColor.assign(mesh.positions.size(), glm::vec3(material.baseColorFactor));
    for (std::size_t i = 0; i < mesh.colors.size() && i < c.vertexColor.size(); ++i)
      c.vertexColor[i] *= glm::vec3(mesh.colors[i]);
    addTexelMap(scene, mesh, material.transmissionTexture, 0, false, c.transmission);
    // As the lighting pass uploads them: only for what it draws (translucency.h).
    if (hasVolume(material))
      addTexelMap(scene, mesh, material.thicknessTexture, 1, false, c.thickness);
    if (hasDiffuseTransmission(material)) {
      addTexelMap(scene, mesh, material.diffuseTransmissionTexture, 3, false,
                  c.diffuseTransmission);
      addTexelMap(scene, mesh, material.diffuseTransmissionColorTexture, 0, true,
                  c.diffuseTransmissionColor);
    }
    c.volumeScale = volumeScale;
  }
  const TextureSlot& slot = material.baseColorTexture;
  if (slot.texture < 0 || slot.texture >= static_cast<int>(scene.textures.size())) return c;
  const Texture& texture = scene.textures[slot.texture];
  if (texture.image < 0 || texture.image >= static_cast<int>(scene.images.size())) return c;
  const Image& image = scene.images[texture.image];
  const std::size_t texels = static_cast<std::size_t>(image.width) * image.height;
  if (image.width <= 0 || image.height <= 0 || image.rgba.size() < texels * 4) return c;
  c.width = image.width;
  c.height = image.height;
  c.texelAlpha.resize(texels);
  for (std::size_t i = 0; i < texels; ++i) c.texelAlpha[i] = image.rgba[i * 4 + 3];
  if (c.translucent) {
    c.texelColor.resize(texels);
    for (std::size_t i = 0; i < texels; ++i)
      c.texelColor[i] = {srgbToLinear(image.rgba[i * 4]), srgbToLinear(image.rgba[i * 4 + 1]),
                         srgbToLinear(image.rgba[i * 4 + 2])};
  }
  c.wrapS = texture.sampler.wrapS;
  c.wrapT = texture.sampler.wrapT;
  // A missing set samples (0, 0), as an unbound vertex attribute does on the GPU.
  const std::vector<glm::vec2>& uv = slot.texCoord == 1 ? mesh.uv1 : mesh.uv0;
  c.uv = uv.size() == mesh.positions.size() ? uv : std::vector<glm::vec2>(mesh.positions.size());
  return c;
}

// Orthonormal tangents of a unit vector (Duff et al. 2017, "Building an Orthonormal Basis,
// Revisited").
void tangents(const glm::vec3& n, glm::vec3& t1, glm::vec3& t2) {
  const float sign = std::copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  const float b = n.x * n.y * a;
  t1 = {1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x};
  t2 = {b, sign + n.y * n.y * a, -n.y};
}

// Centers of an n x n grid on the unit square, mapped to the unit disk by Shirley and Chiu's
// concentric map, which keeps the strata compact and equal in area.
const std::vector<glm::vec2>& diskPattern(int n) {
  thread_local std::vector<glm::vec2> pattern;
  thread_local int patternSize = 0;
  if (patternSize == n) return pattern;
  pattern.clear();
  constexpr float kQuarterPi = 0.78539816339744831f;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const float a = 2.0f * (static_cast<float>(i) + 0.5f) / static_cast<float>(n) - 1.0f;
      const float b = 2.0f * (static_cast<float>(j) + 0.5f) / static_cast<float>(n) - 1.0f;
      if (a == 0.0f && b == 0.0f) {
        pattern.emplace_back(0.0f);
        continue;
      }
      float r, phi;
      if (std::abs(a) > std::abs(b)) {
        r = a;
        phi = kQuarterPi * (b / a);
      } else {
        r = b;
        phi = 2.0f * kQuarterPi - kQuarterPi * (a / b);
      }
      pattern.emplace_back(r * std::cos(phi), r * std::sin(phi));
    }
  patternSize = n;
  return pattern;
}

RTCRay makeRay(const glm::vec3& origin, const glm::vec3& direction, float tnear, float tfar,
               unsigned mask) {
  RTCRay ray{};
  ray.org_x = origin.x;
  ray.org_y = origin.y;
  ray.org_z = origin.z;
  ray.dir_x = direction.x;
  ray.dir_y = direction.y;
  ray.dir_z = direction.z;
  ray.tnear = tnear;
  ray.tfar = tfar;
  ray.mask = mask;
  ray.flags = 0;
  return ray;
}

}  // namespace

struct ShadowReference::Impl {
  const EmbreeApi* rtc = nullptr;  // set before anything below
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::vector<std::unique_ptr<Cutout>> cutouts;  // geometry user data; must outlive the scene
  std::string error;                             // the last message from Embree
  bool translucent = false;                      // the scene has translucent casters
  std::vector<std::uint8_t> unlit;               // per geometry ID: KHR_materials_unlit

  ~Impl() {
    if (scene) rtc->releaseScene(scene);
    if (device) rtc->releaseDevice(device);
  }

  std::optional<RTCRayHit> cast(const glm::vec3& origin, const glm::vec3& direction, float tnear,
                                float tfar, unsigned mask) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rayHit{};
    rayHit.ray = makeRay(origin, direction, tnear, tfar, mask);
    rayHit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rtc->intersect1(scene, &context, &rayHit);
    if (rayHit.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
    return rayHit;
  }
};

ShadowReference::ShadowReference(const Scene& scene) : impl_(std::make_unique<Impl>()) {
  Impl& impl = *impl_;
  impl.rtc = &embreeApi();  // throws where Embree cannot be loaded
  const EmbreeApi& rtc = *impl.rtc;
  impl.device = rtc.newDevice(nullptr);
  if (!impl.device)
    throw RenderError("Embree: cannot create a device (" +
                      std::to_string(static_cast<int>(rtc.getDeviceError(nullptr))) + ")");
  rtc.setDeviceErrorFunction(
      impl.device,
      [](void* user, RTCError, const char* message) {
        static_cast<Impl*>(user)->error = message ? message : "unknown error";
      },
      &impl);
  impl.scene = rtc.newScene(impl.device);
  // Robust traversal: a shadow ray through a shared edge must not slip between two triangles.
  rtc.setSceneFlags(impl.scene, RTC_SCENE_FLAG_ROBUST);
  rtc.setSceneBuildQuality(impl.scene, RTC_BUILD_QUALITY_HIGH);

  for (const MeshInstance& instance : scene.instances) {
    if (instance.mesh < 0 || instance.mesh >= static_cast<int>(scene.meshes.size())) continue;
    const Mesh& mesh = scene.meshes[instance.mesh];
    std::vector<std::uint32_t> indices;
    indices.reserve(mesh.indices.size());
    for (std::size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
      const std::uint32_t a = mesh.indices[i], b = mesh.indices[i + 1], c = mesh.indices[i + 2];
      if (a < mesh.positions.size() && b < mesh.positions.size() && c < mesh.positions.size())
        indices.insert(indices.end(), {a, b, c});
    }
    if (indices.empty()) continue;

    RTCGeometry geometry = rtc.newGeometry(impl.device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vertices = static_cast<float*>(
        rtc.setNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                 3 * sizeof(float), mesh.positions.size()));
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
      const glm::vec3 p = glm::vec3(instance.world * glm::vec4(mesh.positions[i], 1.0f));
      vertices[3 * i] = p.x;
      vertices[3 * i + 1] = p.y;
      vertices[3 * i + 2] = p.z;
    }
    auto* triangles = static_cast<std::uint32_t*>(
        rtc.setNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                 3 * sizeof(std::uint32_t), indices.size() / 3));
    std::copy(indices.begin(), indices.end(), triangles);

    const bool hasMaterial =
        mesh.material >= 0 && mesh.material < static_cast<int>(scene.materials.size());
    const AlphaMode mode =
        hasMaterial ? scene.materials[mesh.material].alphaMode : AlphaMode::Opaque;
    rtc.setGeometryMask(geometry, mode == AlphaMode::Blend ? kCastsShadow : kCastsShadow | kInAovs);
    const bool translucent = hasMaterial && isTranslucentCaster(scene.materials[mesh.material]);
    impl.translucent = impl.translucent || translucent;
    if (mode != AlphaMode::Opaque || translucent) {
      impl.cutouts.push_back(
          std::make_unique<Cutout>(makeCutout(scene, mesh, scene.materials[mesh.material],
                                              std::move(indices), volumeScale(instance.world))));
      rtc.setGeometryUserData(geometry, impl.cutouts.back().get());
      // Shadow rays of cut-out shadows (rtcOccluded1) see BLEND surfaces where alpha >= 0.5;
      // translucent shadow rays (rtcIntersect1) stop at every BLEND surface, whatever its alpha,
      // and weigh it (camera rays never see BLEND geometry: the mask keeps them out).
      if (mode != AlphaMode::Opaque) rtc.setGeometryOccludedFilterFunction(geometry, alphaFilter);
      if (mode == AlphaMode::Mask) rtc.setGeometryIntersectFilterFunction(geometry, alphaFilter);
    }
    rtc.commitGeometry(geometry);
    const unsigned id = rtc.attachGeometry(impl.scene, geometry);
    rtc.releaseGeometry(geometry);
    if (impl.unlit.size() <= id) impl.unlit.resize(id + 1, 0);
    impl.unlit[id] = hasMaterial && scene.materials[mesh.material].unlit ? 1 : 0;
  }
  rtc.commitScene(impl.scene);
  if (rtc.getDeviceError(impl.device) != RTC_ERROR_NONE)
    throw RenderError("Embree: cannot build the scene: " + impl.error);

  if (!scene.bounds.empty())
    epsilon_ = std::max(1e-4f * glm::length(scene.bounds.max - scene.bounds.min), 1e-30f);
}

ShadowReference::~ShadowReference() = default;

bool ShadowReference::occluded(const glm::vec3& origin, const glm::vec3& direction, float tnear,
                               float tfar) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay ray = makeRay(origin, direction, tnear, tfar, kCastsShadow);
  impl_->rtc->occluded1(impl_->scene, &context, &ray);
  // Embree marks an occluded ray by setting tfar to -inf.
  return ray.tfar < 0.0f;
}

std::optional<SurfaceHit> ShadowReference::intersect(const glm::vec3& origin,
                                                     const glm::vec3& direction, float tnear,
                                                     float tfar) const {
  const std::optional<RTCRayHit> hit = impl_->cast(origin, direction, tnear, tfar, kInAovs);
  if (!hit) return std::nullopt;
  const glm::vec3 n{hit->hit.Ng_x, hit->hit.Ng_y, hit->hit.Ng_z};
  const float length = glm::length(n);
  if (!(length > 0.0f)) return std::nullopt;
  const unsigned id = hit->hit.geomID;
  return SurfaceHit{hit->ray.tfar, n / length, id < impl_->unlit.size() && impl_->unlit[id] != 0};
}

glm::vec3 ShadowReference::rayTransmittance(const glm::vec3& origin, const glm::vec3& direction,
                                            float tnear, float tfar) const {
  glm::vec3 transmittance(1.0f);
  // Each crossing counts once: the next search starts just past the last hit, which also
  // steps over the twin hit of a ray through an edge two triangles share.
  const float step = 0.01f * epsilon_;
  for (int crossing = 0; crossing < kMaxTranslucentCrossings; ++crossing) {
    const std::optional<RTCRayHit> hit = impl_->cast(origin, direction, tnear, tfar, kCastsShadow);
    if (!hit) return transmittance;
    RTCGeometry geometry = impl_->rtc->getGeometry(impl_->scene, hit->hit.geomID);
    const auto* cutout = static_cast<const Cutout*>(impl_->rtc->getGeometryUserData(geometry));
    if (!cutout || !cutout->translucent) return glm::vec3(0.0f);
    const unsigned primitive = hit->hit.primID;
    const float u = hit->hit.u, v = hit->hit.v;
    SurfaceTexels texels;
    texels.baseColor = baseColorAt(*cutout, primitive, u, v);
    texels.transmission = texelAt(cutout->transmission, *cutout, primitive, u, v, glm::vec3(1)).x;
    texels.thickness = texelAt(cutout->thickness, *cutout, primitive, u, v, glm::vec3(1)).x;
    texels.diffuseTransmission =
        texelAt(cutout->diffuseTransmission, *cutout, primitive, u, v, glm::vec3(1)).x;
    texels.diffuseTransmissionColor =
        texelAt(cutout->diffuseTransmissionColor, *cutout, primitive, u, v, glm::vec3(1));
    transmittance *= surfaceTransmittance(cutout->material, texels, cutout->volumeScale);
    if (!(std::max({transmittance.r, transmittance.g, transmittance.b}) > 0.0f))
      return glm::vec3(0.0f);
    tnear = hit->ray.tfar + step;
  }
  return transmittance;
}

glm::vec3 ShadowReference::transmittance(const Light& light, const glm::vec3& point,
                                         const glm::vec3& normal, int sourceSamples) const {
  if (!impl_->translucent || !castsTranslucentShadows(light))
    return glm::vec3(visibility(light, point, normal, sourceSamples));
  const glm::vec3 origin = point + normal * epsilon_;
  const float radius = light.shadow.radius;
  const bool directional = light.type == LightType::Directional;
  constexpr float kInfinity = std::numeric_limits<float>::infinity();
  // Towards one point of the light (or one direction of the sun).
  const auto towards = [&](const glm::vec3& target) {
    const glm::vec3 d = target - origin;
    const float distance = glm::length(d);
    if (!(distance > epsilon_)) return glm::vec3(1.0f);
    return rayTransmittance(origin, d / distance, epsilon_, distance);
  };
  if (radius <= 0.0f) {
    if (directional) return rayTransmittance(origin, -light.direction, epsilon_, kInfinity);
    return towards(light.position);
  }
  const int n = std::max(1, static_cast<int>(std::lround(std::sqrt(std::max(sourceSamples, 1)))));
  const std::vector<glm::vec2>& pattern = diskPattern(n);
  glm::vec3 sum(0.0f), t1, t2;
  if (directional) {
    const glm::vec3 L = glm::normalize(-light.direction);
    tangents(L, t1, t2);
    const float spread = std::tan(std::min(radius, 1.5f));
    for (const glm::vec2& s : pattern)
      sum += rayTransmittance(origin, glm::normalize(L + spread * (s.x * t1 + s.y * t2)), epsilon_,
                              kInfinity);
  } else {
    const glm::vec3 axis = point - light.position;
    const float axisLength = glm::length(axis);
    tangents(axisLength > 0.0f ? axis / axisLength : glm::vec3(0.0f, 0.0f, 1.0f), t1, t2);
    for (const glm::vec2& s : pattern)
      sum += towards(light.position + radius * (s.x * t1 + s.y * t2));
  }
  return sum / static_cast<float>(pattern.size());
}

float ShadowReference::visibility(const Light& light, const glm::vec3& point,
                                  const glm::vec3& normal, int sourceSamples) const {
  if (impl_->translucent && castsTranslucentShadows(light)) {
    const glm::vec3 t = transmittance(light, point, normal, sourceSamples);
    return (t.r + t.g + t.b) / 3.0f;
  }
  const glm::vec3 origin = point + normal * epsilon_;
  const float radius = light.shadow.radius;
  const bool directional = light.type == LightType::Directional;
  constexpr float kInfinity = std::numeric_limits<float>::infinity();

  if (radius <= 0.0f) {
    if (directional) return occluded(origin, -light.direction, epsilon_, kInfinity) ? 0.0f : 1.0f;
    const glm::vec3 toLight = light.position - origin;
    const float distance = glm::length(toLight);
    if (!(distance > epsilon_)) return 1.0f;
    return occluded(origin, toLight / distance, epsilon_, distance) ? 0.0f : 1.0f;
  }

  const int n = std::max(1, static_cast<int>(std::lround(std::sqrt(std::max(sourceSamples, 1)))));
  const std::vector<glm::vec2>& pattern = diskPattern(n);
  int lit = 0;
  glm::vec3 t1, t2;
  if (directional) {
    // The sun seen as a disk of angular radius `radius`: directions through a disk at unit
    // distance of radius tan(radius).
    const glm::vec3 L = glm::normalize(-light.direction);
    tangents(L, t1, t2);
    const float spread = std::tan(std::min(radius, 1.5f));
    for (const glm::vec2& s : pattern) {
      const glm::vec3 d = glm::normalize(L + spread * (s.x * t1 + s.y * t2));
      lit += occluded(origin, d, epsilon_, kInfinity) ? 0 : 1;
    }
  } else {
    const glm::vec3 axis = point - light.position;
    const float axisLength = glm::length(axis);
    tangents(axisLength > 0.0f ? axis / axisLength : glm::vec3(0.0f, 0.0f, 1.0f), t1, t2);
    for (const glm::vec2& s : pattern) {
      const glm::vec3 target = light.position + radius * (s.x * t1 + s.y * t2);
      const glm::vec3 d = target - origin;
      const float distance = glm::length(d);
      if (!(distance > epsilon_)) {
        ++lit;
        continue;
      }
      lit += occluded(origin, d / distance, epsilon_, distance) ? 0 : 1;
    }
  }
  return static_cast<float>(lit) / static_cast<float>(pattern.size());
}

}  // namespace omnishadow
