#pragma once

#include "renderer/scene.h"

namespace omnishadow {

// Fills mesh.normals with area-weighted vertex normals from the triangles.
void generateNormals(Mesh& mesh);

// Fills mesh.tangents from positions, normals and the given UV set (per-triangle UV gradients
// accumulated per vertex, Gram-Schmidt orthogonalized, w = handedness). Needs normals and UVs.
void generateTangents(Mesh& mesh, const std::vector<glm::vec2>& uvs);

}  // namespace omnishadow
