#pragma once

// KHR_materials_sheen's BRDF on the CPU, as its specification's implementation notes write it:
// the "Charlie" distribution and visibility of Conty and Kulla (2017), and the directional
// albedo E(mu, roughness) that scales the base material beneath the sheen. The lighting shader
// (shaders/brdf.glsl) evaluates the same formulas per pixel; E is too costly there, so it reads a
// table of it that the build computes with sheenDirectionalAlbedo() (make_sheen_albedo_table).

namespace omnishadow {

// The table's grid: E at cos(theta) = i / (kSheenAlbedoCosines - 1) and sheen roughness
// j / (kSheenAlbedoRoughnesses - 1), cosine fastest. E varies fastest with the angle near grazing.
inline constexpr int kSheenAlbedoCosines = 32;
inline constexpr int kSheenAlbedoRoughnesses = 16;
inline constexpr int kSheenAlbedoEntries = kSheenAlbedoCosines * kSheenAlbedoRoughnesses;
// The integration steps per angle the table is made with.
inline constexpr int kSheenAlbedoSteps = 128;

// alpha_g = roughness^2 as the specification maps it, kept above this so that 1 / alpha_g stays
// finite (a roughness of 0 is allowed); the shader clamps the same way.
inline constexpr float kMinSheenAlpha = 1e-3f;

// The specification's sheen_distribution for NdotH and alpha_g.
double charlieDistribution(double NdotH, double alphaG);

// The specification's sheen_visibility (G / (4 NdotV NdotL)) for positive NdotV and NdotL.
double charlieVisibility(double NdotV, double NdotL, double alphaG);

// E(mu): the fraction of light arriving from every direction that the sheen of color 1 sends
// towards a direction at cos(theta) = mu from the normal (the BRDF times NdotL integrated over
// the hemisphere), for a sheen roughness in [0, 1]. A midpoint rule over `steps` x `steps`
// intervals of the incident direction's polar and azimuth angles.
double sheenDirectionalAlbedo(double mu, double roughness, int steps);

}  // namespace omnishadow
