#pragma once

#include <glm/glm.hpp>
#include <vector>

#include "renderer/scene/scene.h"

namespace omnishadow {

// Vertices of one deformed instance (scene_rig.h) in the file's vertex order.
struct DeformedVertices {
  std::vector<glm::vec3> positions, normals;
  std::vector<glm::vec4> tangents;
};

// Morph targets (glTF 3.7.2.2): each attribute plus the weighted sum of its targets'
// displacements; normals renormalized, tangent handedness kept.
DeformedVertices morph(const DeformedInstance& source, const std::vector<float>& weights);

// Linear blend skinning (glTF 3.7.3): each vertex by the weighted sum of its joints' matrices
// (joint world transform times inverse bind matrix), normals by the inverse transpose of those
// matrices, tangents by the matrices. Weights are divided by their sum; a vertex whose weights
// are all zero stays where `fallback` (the mesh node's world transform) puts it.
void skin(const DeformedInstance& source, const std::vector<glm::mat4>& jointMatrices,
          const glm::mat4& fallback, DeformedVertices& vertices);

// Writes the vertices into the instance's Scene mesh (in its vertex order), regenerating the
// flat normals or the tangents the loader generated, and updates the mesh bounds.
void writeDeformedMesh(const DeformedInstance& source, const DeformedVertices& vertices,
                       Mesh& mesh);

}  // namespace omnishadow
