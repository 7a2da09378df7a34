#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "renderer/output/image_writer.h"
#include "renderer/render/render_settings.h"
#include "renderer/scene/light.h"
#include "renderer/view/cube_distances.h"
#include "renderer/view/cube_faces.h"

namespace omnishadow {

// A point light's shadow map as the lighting pass sampled it.
struct ShadowMapDump {
  std::string light;
  float far = 0.0f;
  CubeDistances distances;
};

// A spot light's map or one directional cascade as the lighting pass sampled it.
struct PlanarShadowMapDump {
  std::string light;
  std::string planar;  // "spot" or "cascade<i>"
  int resolution = 0;
  float far = 0.0f;  // the distance the previews show as white
  // resolution^2 texels in GL rows (row 0 = t 0): distance along the map's view axis from the
  // light (spot) or from the map's near plane along the light (directional); +inf = nothing.
  std::vector<float> distances;
};

// The lit scene seen from one cube face of a point light, in GL texel layout like the dumps,
// or through a spot light's map or one directional cascade (`planar` names it: "spot",
// "cascade0", ...; empty for cube faces).
struct LightView {
  std::string light;
  CubeFace face;
  FloatImage beauty;
  std::string planar{};  // "spot" or "cascade<i>" for planar maps; empty for cube faces
};

// An 8-bit RGB picture, 3 bytes a pixel, first row = top.
struct Srgb8Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;
};

// What one render produces, read back to the CPU; first row = top of the picture.
struct Frame {
  // R,G,B,A: linear, premultiplied, A = coverage. Empty when srgb8 is set.
  FloatImage beauty;
  // Set when the lighting pass encoded the beauty (RenderSettings::srgb8Exposure): what
  // toSrgb8() makes of the float beauty with that exposure, byte for byte.
  std::optional<Srgb8Image> srgb8;
  // R,G,B,A, P.X,P.Y,P.Z, N.X,N.Y,N.Z, Z, visibility.<light> per light (README, "Outputs"),
  // then the requested layers.
  std::optional<FloatImage> aovs;
  // With RenderSettings::objectIds: one channel, "objectId", as the AOVs' objectId layer.
  std::optional<FloatImage> objectIds;
  std::vector<ShadowMapDump> shadowMaps;
  std::vector<PlanarShadowMapDump> planarShadowMaps;  // with shadowMaps: spot maps, cascades
  std::vector<LightView> lightViews;
  std::vector<std::string> warnings;
  // Shadowed lights whose maps were rendered for this frame, and those kept from the previous
  // render of the same scene (point and spot lights whose maps cannot have changed).
  int shadowMapsRendered = 0;
  int shadowMapsReused = 0;
  // Of the maps rendered, those drawn in the renderer's second GL context while the first drew
  // the others (RenderSettings::parallelShadowMaps).
  int shadowMapsInParallel = 0;
  // Over the maps rendered: flat casters left out of a light's map because they shadow no
  // receiver (a floor or wall with the whole scene on the light's side), counted per light.
  int flatCastersLeftOut = 0;
  // The beauty pass drew its depth pre-pass (renderer.cpp chooses per scene; the picture is
  // the same either way).
  bool depthPrepass = true;
};

// The fixed channels at the start of Frame::aovs: R G B A P.X P.Y P.Z N.X N.Y N.Z Z.
inline constexpr int kFixedAovChannels = 11;

// Channel names of Frame::aovs for these lights and layers, in order; last, the RGB shadow
// term transmittance.<light>.R/G/B of each light whose `translucent` entry is true (translucent
// shadows, README "Translucent shadows").
std::vector<std::string> aovChannels(const std::vector<Light>& lights, const AovLayers& layers,
                                     const std::vector<bool>& translucent = {});

// What annotation masks are made from: the AOVs (with their objectId layer) when the frame
// has them, else Frame::objectIds. Throws RenderError when it has neither.
const FloatImage& objectIdImage(const Frame& frame);

}  // namespace omnishadow
