#pragma once

#include <glm/glm.hpp>
#include <memory>
#include <string>
#include <vector>

#include "renderer/gl/gl_resources.h"
#include "renderer/passes/gpu_geometry.h"
#include "renderer/passes/texture_cache.h"
#include "renderer/scene/scene.h"

namespace omnishadow {

// GL textures for one material; 0 where the material has no such texture. For a
// specular-glossiness material metallicRoughness holds its specularGlossinessTexture.
struct GpuMaterial {
  Material desc;
  GLuint baseColor = 0, metallicRoughness = 0, normal = 0, occlusion = 0, emissive = 0;
  GLuint baseColorSampler = 0, metallicRoughnessSampler = 0, normalSampler = 0,
         occlusionSampler = 0, emissiveSampler = 0;
  GLuint transmission = 0, transmissionSampler = 0;  // KHR_materials_transmission (shadows only)
  // KHR_materials_sheen: the sheen color texture (sRGB), whose A the roughness texture reads
  // when it is the same image; else the roughness texture alone. 0 without sheen.
  GLuint sheen = 0, sheenSampler = 0;
  // The sheen roughness texture when both sheen textures are given, on different images.
  GLuint sheenRoughness = 0, sheenRoughnessSampler = 0;
  // KHR_materials_specular's textures: the factor (linear, A) and the color (sRGB).
  GLuint specular = 0, specularSampler = 0;
  GLuint specularColor = 0, specularColorSampler = 0;
  // KHR_materials_clearcoat's textures (linear); 0 without a clearcoat.
  GLuint clearcoat = 0, clearcoatSampler = 0;
  GLuint clearcoatRoughness = 0, clearcoatRoughnessSampler = 0;
  GLuint clearcoatNormal = 0, clearcoatNormalSampler = 0;
  // KHR_materials_volume's thickness texture (linear, G); 0 unless drawn as a volume.
  GLuint thickness = 0, thicknessSampler = 0;
  // KHR_materials_anisotropy's texture (linear); 0 unless the material is anisotropic.
  GLuint anisotropy = 0, anisotropySampler = 0;
  // KHR_materials_iridescence's textures (linear); 0 unless the material has a film.
  GLuint iridescence = 0, iridescenceSampler = 0;
  GLuint iridescenceThickness = 0, iridescenceThicknessSampler = 0;
  // KHR_materials_diffuse_transmission's textures: the fraction (linear, A) and the color
  // (sRGB); 0 unless the material lets light through diffusely.
  GLuint diffuseTransmission = 0, diffuseTransmissionSampler = 0;
  GLuint diffuseTransmissionColor = 0, diffuseTransmissionColorSampler = 0;
};

// The static scene on the GPU: its geometry (gpu_geometry.h), textures (sRGB where glTF says
// so) with mipmaps, and sampler objects.
class GpuScene {
 public:
  // With `textures`, textures are taken from and added to that cache (`images`: the digests of
  // the scene's images as far as known, one per image, which the cache completes); with
  // `geometry`, the geometry is taken from that cache when it holds this scene's (`meshes`: the
  // scene's meshDigests(), found here when not given).
  explicit GpuScene(const Scene& scene, TextureCache* textures = nullptr,
                    GeometryCache* geometry = nullptr,
                    const std::vector<MeshDigests>* meshes = nullptr,
                    ImageDigests* images = nullptr);

  GLuint vertexArray() const { return geometry_->vertexArray(); }
  // GpuGeometry::vertexArrays() and makeVertexArrays().
  const SceneVertexArrays& vertexArrays() const { return geometry_->vertexArrays(); }
  SceneVertexArrays makeVertexArrays() const { return geometry_->makeVertexArrays(); }
  // std430 array of mat4: draws()[i].world at index i.
  GLuint modelBuffer() const { return geometry_->modelBuffer(); }
  const std::vector<GpuMeshRange>& meshes() const { return geometry_->meshes(); }
  const std::vector<GpuDraw>& draws() const { return geometry_->draws(); }
  const Bounds& receiverBounds() const { return geometry_->receiverBounds(); }
  const std::vector<GpuMaterial>& materials() const { return materials_; }
  // Images larger than this GL allows were halved until they fit; one line each.
  const std::vector<std::string>& warnings() const { return warnings_; }

 private:
  struct TextureUploads;  // the textures of one uploadMaterials() still waiting for mipmaps
  void uploadMaterials(const Scene& scene, ImageDigests* images);
  GLuint textureFor(const Scene& scene, const TextureSlot& slot, bool srgb, TextureUploads& uploads,
                    ImageDigests* images);
  void finishOldest(TextureUploads& uploads);  // puts in the levels of the oldest pending texture
  void finishLevels(TextureUploads& uploads);  // of every pending texture
  GLuint samplerFor(const Scene& scene, const TextureSlot& slot);

  std::shared_ptr<const GpuGeometry> geometry_;
  TextureCache* textureCache_;
  std::vector<std::shared_ptr<const gl::Texture>> textures_;  // indexed by 2 * image + srgb
  std::vector<gl::Sampler> samplers_;                         // indexed by texture
  std::vector<GpuMaterial> materials_;
  std::vector<std::string> warnings_;
};

}  // namespace omnishadow
