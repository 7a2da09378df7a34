#pragma once

#include <glm/glm.hpp>
#include <vector>

#include "renderer/scene/light.h"
#include "renderer/scene/scene.h"

namespace omnishadow {

// Translucent shadow casters (README, "Translucent shadows"). A BLEND material lets through
// (1 - alpha) of the light, a KHR_materials_transmission one transmission x base color, a
// surface with both (1 - alpha) + alpha x transmission x base color. Every crossing of such a
// surface multiplies the light by its transmittance; opaque and cut-out surfaces block it.

// Whether the material's surfaces let light through partially (BLEND, or a transmission factor
// above 0), rather than blocking it (OPAQUE, MASK above the cutoff).
bool isTranslucentCaster(const Material& material);

// The light a translucent surface lets through, per RGB channel, where its base color
// (factor x texture x COLOR_0, linear) is `baseColor` and its transmission texture's R is
// `transmissionTexel` (1 without one). MASK texels below the cutoff are holes (all light
// passes); other modes take alpha as given by BLEND, else 1.
glm::vec3 surfaceTransmittance(const Material& material, const glm::vec4& baseColor,
                               float transmissionTexel = 1.0f);

// Whether any instance of the scene is drawn with a translucent material.
bool hasTranslucentCasters(const Scene& scene);

// Whether a light's shadow lets translucent casters tint it: shadowed, `translucentShadows` on
// and not vsm (whose moments have no transmittance; it keeps cut-out shadows).
bool castsTranslucentShadows(const Light& light);

// Per light of `lights`: castsTranslucentShadows() and the scene has translucent casters.
std::vector<bool> translucentShadowLights(const std::vector<Light>& lights, const Scene& scene);

}  // namespace omnishadow
