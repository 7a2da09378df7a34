#pragma once

#include <glm/glm.hpp>
#include <vector>

#include "renderer/scene/light.h"
#include "renderer/scene/scene.h"

namespace omnishadow {

// Translucent shadow casters (README, "Translucent shadows"). A BLEND material lets through
// (1 - alpha) of the light; a KHR_materials_transmission one transmission x base color, times,
// on a volume (KHR_materials_volume, as the lighting pass draws it: hasVolume), Beer's law over
// half its thickness (a ray through a closed volume crosses its boundary twice); a
// KHR_materials_diffuse_transmission one also (1 - transmission) x its fraction x its color.
// A surface with alpha and the others lets through (1 - alpha) + alpha x those. Every crossing
// of such a surface multiplies the light by its transmittance; opaque and cut-out surfaces
// block it.

// Whether the material's surfaces let light through partially (BLEND, or a transmission or
// diffuse transmission factor above 0), rather than blocking it (OPAQUE, MASK above the cutoff).
bool isTranslucentCaster(const Material& material);

// What a translucent surface's textures give at a point (each 1 without its texture).
struct SurfaceTexels {
  glm::vec4 baseColor{1.0f};                 // factor x texture x COLOR_0, linear
  float transmission = 1.0f;                 // transmissionTexture's R
  float thickness = 1.0f;                    // thicknessTexture's G
  float diffuseTransmission = 1.0f;          // diffuseTransmissionTexture's A
  glm::vec3 diffuseTransmissionColor{1.0f};  // diffuseTransmissionColorTexture's RGB, linear
};

// The exponent per unit of thickness texel of a volume's attenuation per crossing:
// ln(attenuationColor) x thicknessFactor x scale / (2 x attenuationDistance), per channel; 0
// for a material not drawn as a volume. `scale`: the instance's (volumeScale).
glm::vec3 volumeAttenuationExponent(const Material& material, float scale);

// How far an instance's world transform stretches thickness: the cube root of its linear
// part's determinant (1 for a rigid transform).
float volumeScale(const glm::mat4& world);

// The light a translucent surface lets through, per RGB channel. MASK texels below the cutoff
// are holes (all light passes); other modes take alpha as given by BLEND, else 1.
// `volumeScale`: that of the instance the surface belongs to.
glm::vec3 surfaceTransmittance(const Material& material, const SurfaceTexels& texels,
                               float volumeScale = 1.0f);

// Whether any instance of the scene is drawn with a translucent material.
bool hasTranslucentCasters(const Scene& scene);

// Whether a light's shadow lets translucent casters tint it: shadowed, `translucentShadows` on
// and not vsm (whose moments have no transmittance; it keeps cut-out shadows).
bool castsTranslucentShadows(const Light& light);

// Per light of `lights`: castsTranslucentShadows() and the scene has translucent casters.
std::vector<bool> translucentShadowLights(const std::vector<Light>& lights, const Scene& scene);

}  // namespace omnishadow
