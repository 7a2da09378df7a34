#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <optional>
#include <vector>

namespace omnishadow {

// Whether an indexed triangle list is the boundary of a solid with counter-clockwise front
// faces outside (glTF's winding). Seen from any point outside such a mesh, the nearest surface
// along every ray is a front face, so a shadow pass may skip its back faces without changing a
// depth (renderer/shadow_pass.cpp).
//
// True when, after welding bit-identical positions, every edge of a non-degenerate triangle is
// shared by exactly two triangles that run along it in opposite directions (a closed,
// consistently oriented surface), and every connected piece encloses a positive volume. Open
// meshes, inside-out pieces, flat two-sided sheets and meshes without triangles are not closed.
bool isClosedSolid(const std::vector<glm::vec3>& positions,
                   const std::vector<std::uint32_t>& indices);

// Positions where each one within `tolerance` (in every coordinate) of an earlier one, in
// vertex order, takes that one's exact value; the first of each group keeps its own.
std::vector<glm::vec3> weldedWithin(const std::vector<glm::vec3>& positions, float tolerance);

// One look at a mesh's edges gives two answers. `closed`: isClosedSolid's. `welded`, for a mesh
// that is not closed: the positions that close it once the corners of its open edges are welded
// (weldedWithin among themselves, a millionth of the mesh's extent; every vertex at such a
// corner's position moves with it), if any do; none for a mesh mostly of open corners (more
// than a quarter of its positions, and over 1,024), which is open by design. Generators and
// exporters compute a seam's two copies of a vertex, or a sphere's pole, by different float
// expressions (sin 2 pi is not 0 in float), which leaves the mesh open by an ulp. Drawn from
// the welded positions, whose shared corners are then the same bits after any transform, the
// mesh has no crack for a rasterizer's sample to fall through, and skipping its back faces
// changes no depth of the welded solid, which lies within the tolerance of the mesh.
struct SolidCheck {
  bool closed = false;
  std::optional<std::vector<glm::vec3>> welded;
};
SolidCheck checkSolid(const std::vector<glm::vec3>& positions,
                      const std::vector<std::uint32_t>& indices);

// The plane a flat mesh's triangles lie in: |dot(normal, p) + offset| <= thickness for every
// corner of a triangle. A flat caster can only shadow points strictly on its far side from the
// light, so a shadow pass may leave out a floor or a wall that has the whole scene on the
// light's side (renderer/view/caster_culling.h).
struct MeshPlane {
  glm::vec3 normal{0.0f, 0.0f, 1.0f};  // unit length
  float offset = 0.0f;
  float thickness = 0.0f;
};

// The plane of a mesh whose triangle corners all lie within 1e-5 of its extent of one plane
// (the plane of its largest triangle); none for meshes without a triangle of some area, or
// curved ones. Lines and points do not count.
std::optional<MeshPlane> flatMeshPlane(const std::vector<glm::vec3>& positions,
                                       const std::vector<std::uint32_t>& indices);

// A plane under an affine transform (none when it flattens the plane's normal direction): the
// same points, moved, within the transformed thickness.
std::optional<MeshPlane> transformedPlane(const MeshPlane& plane, const glm::mat4& transform);

}  // namespace omnishadow
