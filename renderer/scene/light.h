#pragma once

#include <filesystem>
#include <glm/glm.hpp>
#include <optional>
#include <string>
#include <vector>

#include "renderer/scene/bounds.h"

namespace omnishadow {

// Plain description of punctual lights, mirroring KHR_lights_punctual. Defaults here are the
// documented defaults of the lights file (README, "The lights file").

enum class LightType { Point, Spot, Directional };

enum class ShadowFilter {
  Hard,     // one comparison
  Pcf,      // hardware 2x2 comparison with linear filtering
  PcfDisk,  // 20 fixed offset directions, radius growing with distance to the camera
  Poisson,  // `samples` taps of a Vogel disk rotated per pixel by interleaved gradient noise
  Pcss,     // percentage-closer soft shadows: blocker search, penumbra from the light's radius
  Vsm,      // variance shadow map (filterable moments) with light-bleeding reduction
};

// Which faces the shadow pass culls.
enum class CullFace { None, Back, Front };

enum class DepthFormat { Float32, Fixed24 };

// Per-light shadow settings (lights file "shadow" object). Bias terms in "texels" are multiples
// of the world size of one shadow-map texel at the receiver, so they follow resolution and
// distance (README, "Shadow settings").
struct ShadowSettings {
  bool enabled = true;
  int resolution = 1024;    // texels per cube face or 2D map edge
  float near = 0.0f;        // world units (point, spot); 0 = from the light and scene scale
  float far = 0.0f;         // world units; 0 = the light's range, or the scene bounds if unlimited
  float bias = 0.0f;        // constant bias in world units
  float slopeBias = 2.0f;   // texels: max(slopeBias * tan(N, L), minBias), N.L floored at 0.05
  float minBias = 1.5f;     // texels, the slope term's floor
  float normalBias = 0.0f;  // texels: the receiver is moved this far along its normal
  float polygonOffsetFactor = 0.0f;  // glPolygonOffset in the shadow pass
  float polygonOffsetUnits = 0.0f;
  CullFace cullFace = CullFace::None;
  DepthFormat depthFormat = DepthFormat::Float32;
  ShadowFilter filter = ShadowFilter::Pcf;
  float filterRadius = 1.5f;    // texels (pcf-disk, poisson)
  int samples = 16;             // poisson taps; pcss blocker-search and filter taps
  float radius = 0.0f;          // world units: the light's size, for pcss penumbrae
  float bleedReduction = 0.2f;  // vsm: visibility below this is treated as shadow
  int cascades = 1;             // directional: 1..4 cascaded maps
  float cascadeSplit = 0.75f;   // directional: 0 = linear splits, 1 = logarithmic
  float distance = 0.0f;  // directional: shadows reach this far from the camera; 0 = scene bounds
  // Lights file "translucentShadows": translucent casters (translucency.h) tint the shadow;
  // false gives cut-out shadows (BLEND at alpha 0.5, transmission ignored).
  bool translucent = true;
};

struct Light {
  std::string name;  // unique within a render
  LightType type = LightType::Point;
  glm::vec3 position{0.0f};                    // world space (point, spot)
  glm::vec3 direction{0.0f, 0.0f, -1.0f};      // world space, normalized (spot, directional)
  glm::vec3 color{1.0f};                       // linear RGB
  float intensity = 1.0f;                      // candela (point, spot) or lux (directional)
  float range = 0.0f;                          // world units; 0 = unlimited
  float innerConeAngle = 0.0f;                 // radians (spot)
  float outerConeAngle = 0.7853981633974483f;  // radians (spot), pi/4
  ShadowSettings shadow{};
  std::string origin{};  // where it came from, for messages: a lights file path or "glTF"
};

// The lights file's "environment": light arriving from every direction, from an equirectangular
// (latitude-longitude) picture of linear radiance or, without one, the same from everywhere.
// It lights every surface's diffuse and specular reflection (image-based lighting) and casts no
// shadow; README, "Environment lighting".
struct EnvironmentLight {
  // Empty: a uniform environment of `color`. Otherwise read as the CLI reads images (OpenEXR,
  // Radiance HDR, PNG, anything OpenImageIO reads); relative to the lights file's folder.
  std::filesystem::path image;
  glm::vec3 color{1.0f};    // linear RGB, multiplies the image
  float intensity = 1.0f;   // multiplies the image
  float rotation = 0.0f;    // radians about +Y, counterclockwise seen from above
  bool background = false;  // the beauty shows it where no surface covers a pixel
  // The image's sun (extractSun(), renderer/view/environment_map.h) taken out of it and drawn
  // as a shadowed directional light named kEnvironmentSunName, unless a light has that name.
  bool sun = false;
  std::string origin{};  // the lights file, for messages
};

inline constexpr const char* kEnvironmentSunName = "environment-sun";

// The lights file's "ambient_occlusion": how much of the ambient and environment light reaching
// each surface its surroundings hide, estimated from the depth of what the camera sees
// (screen-space; renderer/passes/ambient_occlusion_pass.h). It darkens nothing the punctual
// lights give, which their shadows do. README, "Ambient occlusion".
struct AmbientOcclusion {
  // World units within which surfaces occlude; 0: kDefaultAmbientOcclusionShare of the
  // diagonal of the scene's bounds.
  float radius = 0.0f;
  // 0..1, as a glTF occlusion texture's strength: 1 + strength x (visible share - 1).
  float strength = 1.0f;
};
inline constexpr float kDefaultAmbientOcclusionShare = 0.05f;
// The radius a frame of a scene with `sceneBounds` uses (0 for an empty scene).
float effectiveRadius(const AmbientOcclusion& occlusion, const Bounds& sceneBounds);

struct LightSetup {
  // Linear RGB radiance multiplied by albedo. 0 by default when the file has an environment.
  glm::vec3 ambient{0.03f};
  std::optional<EnvironmentLight> environment;
  std::optional<AmbientOcclusion> ambientOcclusion;
  std::vector<Light> lights;
};

// What lights a frame besides its punctual lights: the constant ambient term and the
// environment, when there is one. From an ambient radiance alone, as most callers have.
struct Ambience {
  Ambience(const glm::vec3& ambientRadiance) : ambient(ambientRadiance) {}  // NOLINT: implicit
  explicit Ambience(const LightSetup& setup)
      : ambient(setup.ambient),
        environment(setup.environment),
        ambientOcclusion(setup.ambientOcclusion) {}
  glm::vec3 ambient{0.0f};
  std::optional<EnvironmentLight> environment;
  std::optional<AmbientOcclusion> ambientOcclusion;
};

const char* toString(LightType type);

// The lights of a render: the glTF's KHR_lights_punctual lights, then the lights file's. A file
// light named like a glTF light replaces it (to change its color or shadow settings, say).
// Names are unique within each list (the loaders ensure it), so they are unique in the result.
std::vector<Light> mergeLights(const std::vector<Light>& gltfLights,
                               const std::vector<Light>& fileLights);
const char* toString(ShadowFilter filter);
const char* toString(CullFace cull);
const char* toString(DepthFormat format);

}  // namespace omnishadow
