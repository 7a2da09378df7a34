#include "renderer/scene/scene_fingerprint.h"

#include <cstring>

#include "renderer/scene/translucency.h"

namespace omnishadow {
namespace {

class Fnv1a {
 public:
  void bytes(const void* data, std::size_t size) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < size; ++i) hash_ = (hash_ ^ p[i]) * 0x100000001b3ull;
  }
  template <typename T>
  void value(const T& v) {
    bytes(&v, sizeof v);
  }
  template <typename T>
  void vector(const std::vector<T>& v) {
    value(v.size());
    if (!v.empty()) bytes(v.data(), v.size() * sizeof(T));
  }
  std::uint64_t get() const { return hash_; }

 private:
  std::uint64_t hash_ = 0xcbf29ce484222325ull;
};

}  // namespace

std::uint64_t shadowFingerprint(const Scene& scene) {
  Fnv1a h;
  h.value(scene.meshes.size());
  for (const Mesh& mesh : scene.meshes) {
    h.vector(mesh.positions);
    h.vector(mesh.indices);
    h.value(mesh.material);
    // Cut-out casters depend on their texture coordinates and vertex alpha too.
    const bool opaque =
        mesh.material < 0 || (scene.materials[mesh.material].alphaMode == AlphaMode::Opaque &&
                              !isTranslucentCaster(scene.materials[mesh.material]));
    if (!opaque) {
      h.vector(mesh.uv0);
      h.vector(mesh.uv1);
      h.vector(mesh.colors);
    }
  }
  h.value(scene.instances.size());
  for (const MeshInstance& instance : scene.instances) {
    h.value(instance.mesh);
    h.value(instance.world);
  }
  for (const Material& m : scene.materials) {
    h.value(m.alphaMode);
    h.value(m.alphaCutoff);
    h.value(m.doubleSided);
    h.value(m.baseColorFactor.a);
    // Translucent casters tint the transmittance layers with their color.
    h.value(m.transmissionFactor);
    h.value(m.transmissionTexture.texture);
    h.value(m.transmissionTexture.texCoord);
    h.value(m.transmissionTexture.uvTransform);
    if (m.transmissionTexture.texture >= 0) {
      const Texture& texture = scene.textures[m.transmissionTexture.texture];
      h.value(texture.sampler);
      if (texture.image >= 0) h.vector(scene.images[texture.image].rgba);
    }
    if (isTranslucentCaster(m)) h.value(glm::vec3(m.baseColorFactor));
    h.value(m.baseColorTexture.texture);
    h.value(m.baseColorTexture.texCoord);
    h.value(m.baseColorTexture.uvTransform);
    if ((m.alphaMode != AlphaMode::Opaque || isTranslucentCaster(m)) &&
        m.baseColorTexture.texture >= 0) {
      const Texture& texture = scene.textures[m.baseColorTexture.texture];
      h.value(texture.sampler);
      if (texture.image >= 0) h.vector(scene.images[texture.image].rgba);
    }
  }
  return h.get();
}

}  // namespace omnishadow
