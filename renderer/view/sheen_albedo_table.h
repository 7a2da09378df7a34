#pragma once

// The table of the sheen's directional albedo (sheen_brdf.h) that the build computed, and its
// lookup as the lighting shader does it.

#include <array>

#include "renderer/view/sheen_brdf.h"

namespace omnishadow {

// E at the grid of sheen_brdf.h, cosine fastest, each in [0, 1] (the Charlie visibility's fit
// gives more than 1 at grazing angles for roughnesses below 0.2; clamped, so that the base
// material's scaling 1 - max(sheen color) E stays at least 0).
const std::array<float, kSheenAlbedoEntries>& sheenAlbedoTable();

// E(mu, roughness) interpolated bilinearly in the table, both clamped to [0, 1]: what
// sheenAlbedo() in shaders/brdf.glsl computes.
float sheenAlbedo(float mu, float roughness);

}  // namespace omnishadow
