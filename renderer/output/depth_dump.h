#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "renderer/output/output_transaction.h"
#include "renderer/view/cube_distances.h"

namespace omnishadow {

// Writes a point light's shadow cube map for people and tools to look at (--dump-depth DIR).
// All files go through `transaction` (nothing appears unless the whole run succeeds):
//   <light>_<face>.exr   face px nx py ny pz nz, float32, channel "Z": distance to the light in
//                        world units (+inf where nothing was rendered); GL texel layout: file
//                        row r = texel row r (t grows downwards), column c = texel column (s).
//   <light>_<face>.png   8-bit grey preview of the same: distance / far, nearer = darker,
//                        nothing rendered = white.
//   <light>_cube.exr     OpenEXR cube map (envmap attribute ENVMAP_CUBE), width x 6*width,
//                        faces in OpenEXR's order and orientation (Imf::CubeMap), channel "Z".
//   <light>_cross.png    the six faces unfolded into a 4x3 horizontal cross as seen by a viewer
//                        at the light with +Y up: middle row +X, +Z, -X, -Z (each face's right
//                        neighbour is what the viewer sees turning right), +Y above and -Y
//                        below +Z; unused cells black. Same grey scale as the previews.
// `lightName` is used in file names as given (the caller makes it file-system safe).
void writePointShadowDump(const std::filesystem::path& folder, const std::string& lightName,
                          const CubeDistances& distances, float far,
                          OutputTransaction& transaction);

// Writes a spot light's map or one directional cascade (--dump-depth DIR) through
// `transaction`: <base>.exr (float32, channel "Z", the distances as given, GL texel rows) and
// <base>.png (8-bit grey preview, distance / far, nothing = white).
void writePlanarShadowDump(const std::filesystem::path& folder, const std::string& base,
                           int resolution, const std::vector<float>& distances, float far,
                           OutputTransaction& transaction);

// A light name made safe for a file name: characters other than letters, digits, '-', '_'
// and '.' become '_'; an empty result becomes "light".
std::string fileSafeName(const std::string& name);

}  // namespace omnishadow
