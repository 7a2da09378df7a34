#pragma once

#include "renderer/scene/scene.h"

namespace omnishadow {

// Fills mesh.normals with flat normals, as the glTF spec asks for primitives without NORMAL:
// the mesh is un-indexed (every triangle gets its own three vertices, all attributes copied)
// and each vertex takes its triangle's unit face normal (counter-clockwise = front).
void generateNormals(Mesh& mesh);

// Any unit vector perpendicular to the unit vector n (for tangents the UVs cannot define, or a
// frame around a normal); an axis where n is zero or NaN.
glm::vec3 anyPerpendicular(const glm::vec3& n);

// Fills mesh.tangents from positions, normals and the given UV set (per-triangle UV gradients
// accumulated per vertex, Gram-Schmidt orthogonalized, w = handedness). Needs normals and UVs.
void generateTangents(Mesh& mesh, const std::vector<glm::vec2>& uvs);

}  // namespace omnishadow
