#pragma once

#include <glm/glm.hpp>
#include <memory>
#include <string>
#include <vector>

#include "renderer/gl/gl_resources.h"
#include "renderer/passes/texture_cache.h"
#include "renderer/scene/scene.h"

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
  // First index of this draw's copy in the world-space caster stream (casterVertexArray()),
  // whose indices need no base vertex; -1 when it has none.
  GLint casterFirstIndex = -1;
};

// GL textures for one material; 0 where the material has no such texture. For a
// specular-glossiness material metallicRoughness holds its specularGlossinessTexture.
struct GpuMaterial {
  Material desc;
  GLuint baseColor = 0, metallicRoughness = 0, normal = 0, occlusion = 0, emissive = 0;
  GLuint baseColorSampler = 0, metallicRoughnessSampler = 0, normalSampler = 0,
         occlusionSampler = 0, emissiveSampler = 0;
  GLuint transmission = 0, transmissionSampler = 0;  // KHR_materials_transmission (shadows only)
};

// The static scene on the GPU: all meshes in one vertex buffer and one index buffer behind a
// single vertex array, textures (sRGB where glTF says so) with mipmaps, and sampler objects.
class GpuScene {
 public:
  // With `textures`, textures are taken from and added to that cache.
  explicit GpuScene(const Scene& scene, TextureCache* textures = nullptr);

  GLuint vertexArray() const { return vertexArray_.get(); }
  // Positions only (attribute 0), already in world space, with an index buffer of its own: the
  // shadow pass draws opaque casters from it without a transform per vertex. Holds a copy per
  // draw of each mesh drawn once, and of meshes small enough to copy for all their instances
  // (GpuDraw::casterFirstIndex); the other draws use vertexArray() and modelBuffer(). The
  // copies' triangles follow each other in draw order, their indices counted from the stream's
  // first vertex, so that consecutive draws are one range of indices: one draw call.
  GLuint casterVertexArray() const { return casterVertexArray_.get(); }
  // std430 array of mat4: draws()[i].world at index i.
  GLuint modelBuffer() const { return models_.get(); }
  const std::vector<GpuMeshRange>& meshes() const { return meshes_; }
  const std::vector<GpuDraw>& draws() const { return draws_; }
  const std::vector<GpuMaterial>& materials() const { return materials_; }
  // Images larger than this GL allows were halved until they fit; one line each.
  const std::vector<std::string>& warnings() const { return warnings_; }

 private:
  void uploadGeometry(const Scene& scene);
  void uploadCasterStream(const Scene& scene);
  void uploadMaterials(const Scene& scene);
  GLuint textureFor(const Scene& scene, const TextureSlot& slot, bool srgb);
  GLuint samplerFor(const Scene& scene, const TextureSlot& slot);

  gl::VertexArray vertexArray_, casterVertexArray_;
  gl::Buffer vertices_, indices_, models_, casterPositions_, casterIndices_;
  TextureCache* textureCache_;
  std::vector<std::shared_ptr<const gl::Texture>> textures_;  // indexed by 2 * image + srgb
  std::vector<gl::Sampler> samplers_;                         // indexed by texture
  std::vector<GpuMeshRange> meshes_;
  std::vector<GpuDraw> draws_;
  std::vector<GpuMaterial> materials_;
  std::vector<std::string> warnings_;
};

}  // namespace omnishadow
