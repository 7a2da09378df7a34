#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <memory>
#include <optional>
#include <vector>

#include "renderer/gl/gl_resources.h"
#include "renderer/scene/bounds.h"
#include "renderer/scene/mesh_topology.h"
#include "renderer/scene/scene.h"
#include "renderer/scene/scene_fingerprint.h"

namespace omnishadow {

// Where one Mesh lives in the shared vertex and index buffers.
struct GpuMeshRange {
  GLint baseVertex = 0;
  GLsizei firstIndex = 0;  // in indices, not bytes
  GLsizei indexCount = 0;
  // Lines (pairs) and points follow the triangles in the index buffer; only the lighting pass
  // draws them.
  GLsizei lineIndexCount = 0;
  GLsizei pointIndexCount = 0;
  bool hasTangents = false;
  // The mesh bounds a solid (isClosedSolid): from a light outside it only front faces can be
  // nearest, so the shadow pass skips its back faces.
  bool closed = false;
  // Its copies in the world-space caster stream bound a solid: it is closed, or closed once
  // nearly equal positions are welded (checkSolid), which the copies are made from.
  bool closedInStream = false;
  // The plane its triangles lie in, when they are flat (flatMeshPlane): a floor or a wall.
  std::optional<MeshPlane> plane;
};

// A mesh instance ready to draw: its range, transform, material and world bounds.
struct GpuDraw {
  int mesh = -1;
  int material = -1;  // index into GpuScene::materials (the default material is appended)
  glm::mat4 world{1.0f};
  glm::mat3 normalMatrix{1.0f};
  bool mirrored = false;         // negative determinant: front faces are clockwise
  glm::vec3 boundsCenter{0.0f};  // world-space bounding sphere, for culling
  float boundsRadius = 0.0f;
  Bounds meshBounds;  // the mesh's box, which `world` places: tighter on screen than the sphere
  std::optional<MeshPlane> plane;  // world space, for flat meshes
  // First index of this draw's copy in the world-space caster stream (SceneVertexArrays::casters),
  // whose indices need no base vertex; -1 when it has none.
  GLint casterFirstIndex = -1;
  // Another draw of the same mesh and material with the same transform, bit for bit, comes
  // later / came earlier in the scene's order (markRepeatedDraws()). Its fragments are this
  // draw's, so a pass in which a surface drawn twice changes nothing (depths; opaque surfaces
  // that replace what they cover) draws only one of them. WhackAMole's seven mole nodes, for
  // one, all stand at the origin.
  bool repeatedLater = false;
  bool repeatsEarlier = false;
};

// Sets every draw's repeatedLater and repeatsEarlier.
void markRepeatedDraws(std::vector<GpuDraw>& draws);

// The two vertex arrays that read a GpuGeometry's buffers. Vertex arrays are not shared between
// GL contexts, so a second context (ShadowWorker) makes its own with makeVertexArrays().
struct SceneVertexArrays {
  gl::VertexArray scene;  // every attribute (GpuGeometry::vertexArray())
  // The world-space caster stream: positions only (attribute 0), already in world space, with an
  // index buffer of its own: the shadow pass draws opaque casters from it without a transform
  // per vertex. Holds a copy per draw of each mesh drawn once, and of meshes small enough to
  // copy for all their instances (GpuDraw::casterFirstIndex); the other draws use `scene` and
  // GpuGeometry::modelBuffer(). The copies follow each other along a Z-order curve through
  // their bounding spheres' centres, their indices counted from the stream's first vertex, so
  // that copies next to each other in the stream are one range of indices: one draw command.
  gl::VertexArray casters;
};

// A scene's meshes on the GPU: all of them in one vertex buffer and one index buffer behind a
// single vertex array, the draws (instances) with their world bounds, and the world-space
// caster stream of the shadow pass. Made from the meshes, the instances and the number of
// materials alone (geometryFingerprint()), so that renders of one scene can share it.
class GpuGeometry {
 public:
  explicit GpuGeometry(const Scene& scene);

  GLuint vertexArray() const { return vertexArrays_.scene.get(); }
  // Both vertex arrays, as made in the context that made this geometry.
  const SceneVertexArrays& vertexArrays() const { return vertexArrays_; }
  // New vertex arrays over this geometry's buffers, in the context current on the calling thread.
  SceneVertexArrays makeVertexArrays() const;
  // std430 array of mat4: draws()[i].world at index i.
  GLuint modelBuffer() const { return models_.get(); }
  const std::vector<GpuMeshRange>& meshes() const { return meshes_; }
  const std::vector<GpuDraw>& draws() const { return draws_; }
  // World-space box around every vertex of every draw: exact for the draws in the caster
  // stream, their mesh's box transformed for the others. Where shadows can be received.
  const Bounds& receiverBounds() const { return receiverBounds_; }

 private:
  // Returns, per mesh, the welded positions that close it where only welding does
  // (checkSolid()), for the caster stream's copies.
  std::vector<std::optional<std::vector<glm::vec3>>> uploadMeshes(const Scene& scene);
  void uploadCasterStream(const Scene& scene,
                          const std::vector<std::optional<std::vector<glm::vec3>>>& welded);

  gl::Buffer vertices_, indices_, models_, casterPositions_, casterIndices_;
  std::vector<GpuMeshRange> meshes_;
  std::vector<GpuDraw> draws_;
  Bounds receiverBounds_;
  SceneVertexArrays vertexArrays_;  // after the buffers, which they name
};

// The geometry of the last scene uploaded, kept for the next render: a scene rendered again
// (--repeat, frame sets, batch jobs of one scene, the Python module's renders) takes it instead
// of building its vertex buffers, closed-solid tests and caster stream again (the 250k-triangle
// bench room: about 25 ms a render). Found again when geometryFingerprint() matches; a scene
// posed in place or changed in memory between renders hashes differently and is uploaded anew.
class GeometryCache {
 public:
  // Needs the GL context the buffers belong to. `meshes`: the scene's meshDigests().
  std::shared_ptr<const GpuGeometry> find(const Scene& scene,
                                          const std::vector<MeshDigests>& meshes);

 private:
  std::uint64_t fingerprint_ = 0;
  std::shared_ptr<const GpuGeometry> geometry_;
};

}  // namespace omnishadow
